// Adjacency for the general max-flow graph: each edge is a pair of arcs
// stored next to each other (arc 2k from u to v, arc 2k + 1 back), so an
// arc's reverse is its id with the last bit flipped and needs no storage, and
// the arcs leaving a node form a singly linked list through `next`. Adding
// an edge is two appends and two list insertions: the graph is ready to solve
// as it is built, with 12 bytes per arc for int capacities.
#pragma once

#include <anima/core/error.hpp>
#include <anima/maxflow/detail/boykov_kolmogorov.hpp>

#include <algorithm>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace anima::detail {

template <class Cap>
struct pair_arc {
    bk_index head;
    bk_index next;  ///< next arc leaving the same node; bk_none ends the list, bk_orphan: not linked
    Cap cap;        ///< residual capacity
};

/// The arcs of a graph. Arc ids start at `base` (even, so that flipping the
/// last bit of an id still gives the reverse arc): arc a is arcs()[a - base].
/// Storage grows by doubling, like a vector, but is written only once per
/// arc (no value-initialisation, no temporaries): adding edges is the hot
/// path of building a graph.
template <class Cap>
class pair_arcs {
public:
    bk_index base = 0;

    void add_nodes(std::size_t count) { first_.resize(first_.size() + count, bk_none); }
    std::size_t edges() const noexcept { return edges_; }
    void reserve(std::size_t edges) {
        if (edges > room_) grow(edges);
    }

    /// Appends edge u - v; returns its id. Self-loops stay out of the lists
    /// (they never cross a cut), and so do edges without capacity until they
    /// get some.
    std::size_t add_edge(bk_index u, bk_index v, Cap cap, Cap rev) {
        const std::size_t e = edges_;
        if (e == room_) grow(e + 1);
        pair_arc<Cap>* p = arcs_.get() + 2 * e;
        Cap* o = original_.get() + 2 * e;
        o[0] = cap;
        o[1] = rev;
        p[0].head = v;
        p[0].cap = cap;
        p[1].head = u;
        p[1].cap = rev;
        ++edges_;
        if (u != v && (cap != Cap(0) || rev != Cap(0))) {
            link(e);
        } else {
            p[0].next = bk_orphan;
            p[1].next = bk_orphan;
        }
        return e;
    }

    void set_edge(std::size_t e, Cap cap, Cap rev) {
        pair_arc<Cap>* p = arcs_.get() + 2 * e;
        p[0].cap = original_[2 * e] = cap;
        p[1].cap = original_[2 * e + 1] = rev;
        if (p[0].next == bk_orphan && p[0].head != p[1].head && (cap != Cap(0) || rev != Cap(0))) link(e);
    }

    /// Puts the capacities as given back into the arcs (after a solve).
    void restore() {
        for (std::size_t a = 0; a < 2 * edges_; ++a) arcs_[a].cap = original_[a];
    }

    /// Net flow from u to v along edge e.
    Cap flow(std::size_t e) const { return original_[2 * e] - arcs_[2 * e].cap; }

    void clear() {
        edges_ = 0;
        first_.clear();
    }

    const bk_index* first() const noexcept { return first_.data(); }
    bool has_first() const noexcept { return !first_.empty(); }
    pair_arc<Cap>* arcs() const noexcept { return arcs_.get(); }

private:
    void link(std::size_t e) {
        pair_arc<Cap>* p = arcs_.get() + 2 * e;
        const auto id = static_cast<bk_index>(base + 2 * e);
        p[0].next = first_[p[1].head];
        first_[p[1].head] = id;
        p[1].next = first_[p[0].head];
        first_[p[0].head] = id + 1;
    }

    void grow(std::size_t edges) {
        const std::size_t limit = (bk_max_index - base) / 2;
        if (edges > limit)
            throw invalid_argument("max-flow graph: more than " + std::to_string(limit) +
                                   " edges, the most the solver's 32-bit arc ids can hold");
        const std::size_t room = std::min(limit, std::max({edges, 2 * room_, std::size_t(16)}));
        std::unique_ptr<pair_arc<Cap>[]> arcs(new pair_arc<Cap>[2 * room]);
        std::unique_ptr<Cap[]> original(new Cap[2 * room]);
        std::copy(arcs_.get(), arcs_.get() + 2 * edges_, arcs.get());
        std::copy(original_.get(), original_.get() + 2 * edges_, original.get());
        arcs_ = std::move(arcs);
        original_ = std::move(original);
        room_ = room;
    }

    std::unique_ptr<pair_arc<Cap>[]> arcs_;  ///< 2 per edge; written once each
    std::unique_ptr<Cap[]> original_;        ///< capacities as given, per arc
    std::size_t edges_ = 0, room_ = 0;
    std::vector<bk_index> first_;  ///< per node: its first arc, bk_none when it has none
};

/// The layout of a general graph for bk_solver.
template <class Cap>
struct pair_layout {
    const bk_index* first;
    pair_arc<Cap>* arcs;

    bk_index head(bk_index a) const noexcept { return arcs[a].head; }
    static bk_index sister(bk_index a) noexcept { return a ^ 1u; }
    Cap& cap(bk_index a) const noexcept { return arcs[a].cap; }
    template <class F>
    void for_each_arc(bk_index i, F&& f) const {
        for (bk_index a = first[i]; a != bk_none; a = arcs[a].next)
            if (f(a, arcs[a].head, a ^ 1u)) return;
    }
};

}  // namespace anima::detail
