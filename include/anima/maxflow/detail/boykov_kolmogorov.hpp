// The Boykov-Kolmogorov max-flow algorithm (Boykov and Kolmogorov, "An
// experimental comparison of min-cut/max-flow algorithms for energy
// minimization in vision", TPAMI 26(9), 2004), written once for every graph
// layout.
//
// Two search trees grow through arcs with residual capacity: S from the
// source, T towards the sink. When they touch, the path through the touching
// arc is augmented. The arcs it saturates cut nodes off their trees
// ("orphans"); an orphan looks for a new parent in its own tree, preferring
// the one closest to the terminal (distance labels, trusted when stamped with
// the current time), or becomes free. The trees survive from one
// augmentation to the next instead of being rebuilt, which is what makes the
// method fast on the many short paths of image-like grids.
//
// A layout supplies, for arc ids below bk_max_index:
//   head(a)            the node arc a points to
//   sister(a)          the reverse arc
//   cap(a)             the residual capacity of a (a reference)
//   for_each_arc(i, f) calls f(a, head(a), sister(a)) for the arcs leaving
//                      node i, in order, until f returns true
// Every arc has a sister; self-loops are not arcs.
//
// Memory: the search reads a node's tree, parent and label for every arc it
// scans, so those live in 16 bytes per node (the tree flag in the top bit of
// the distance label); the residual terminal capacities, read only at the
// ends of a path, are a separate array.
#pragma once

#include <anima/maxflow/capacity.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace anima::detail {

using bk_index = std::uint32_t;
inline constexpr bk_index bk_none = 0xFFFFFFFFu;      ///< parent: free node; next: not active
inline constexpr bk_index bk_terminal = 0xFFFFFFFEu;  ///< parent: the terminal itself
inline constexpr bk_index bk_orphan = 0xFFFFFFFDu;    ///< parent: lost, adoption pending
/// Arc ids stay below the markers.
inline constexpr std::size_t bk_max_index = 0xFFFFFFF0u;
/// Node ids too, and distances (at most the node count) below the tree bit.
inline constexpr std::size_t bk_max_nodes = 0x7FFFFFF0u;
inline constexpr bk_index bk_sink_bit = 0x80000000u;

struct bk_node {
    bk_index parent;  ///< arc from this node to its parent, or bk_terminal / bk_orphan / bk_none
    bk_index next;    ///< next in the active queue; bk_none when not active, itself when last
    bk_index stamp;   ///< the time at which the distance was last known to be exact
    bk_index label;   ///< distance to the terminal along the tree (1 for a terminal's child), | bk_sink_bit in T
};

/// A node's residual terminal capacity from its source and sink capacities:
/// the common part flows straight through (returned), the rest stays as one
/// signed residual, > 0 from the source, < 0 to the sink.
template <class Cap>
Cap bk_terminal_init(Cap& residual, Cap source, Cap sink) noexcept {
    residual = source - sink;
    return source < sink ? source : sink;
}

/// Flow on a node's source edge (to_sink false) or sink edge after a run,
/// from its capacities and final residual: the residual only moves towards
/// zero, from source - sink.
template <class Cap>
Cap bk_terminal_flow(Cap source, Cap sink, Cap residual, bool to_sink) noexcept {
    const Cap common = source < sink ? source : sink;
    const Cap start = source - sink;
    if (to_sink) return start < Cap(0) ? common + (residual - start) : common;
    return start > Cap(0) ? common + (start - residual) : common;
}

/// Source-side membership after a run: nodes reachable from the source in
/// the residual graph (the source tree); free nodes are on the sink side.
inline bool bk_source_side(const bk_node& n) noexcept {
    return n.parent != bk_none && !(n.label & bk_sink_bit);
}

template <class Cap, class Layout>
class bk_solver {
public:
    using flow_type = typename capacity_traits<Cap>::flow_type;

    /// `residual` holds each node's residual terminal capacity (see
    /// bk_terminal_init); the nodes are initialised by run(). `orphans` is
    /// workspace, kept by the caller to reuse its memory.
    bk_solver(Layout& layout, bk_node* nodes, Cap* residual, bk_index count, std::vector<bk_index>& orphans)
        : g_(layout), node_(nodes), tr_(residual), n_(count), orphans_(orphans) {}

    /// Pushes the maximum flow; returns `flow` plus what was pushed.
    flow_type run(flow_type flow) {
        orphans_.clear();
        for (bk_index i = 0; i < n_; ++i) {
            bk_node& v = node_[i];
            v.next = bk_none;
            v.stamp = 0;
            if (tr_[i] != Cap(0)) {
                v.label = tr_[i] < Cap(0) ? (1u | bk_sink_bit) : 1u;
                v.parent = bk_terminal;
                activate(i);
            } else {
                v.label = 1u;
                v.parent = bk_none;
            }
        }

        bk_index current = bk_none;
        for (;;) {
            bk_index i = current;
            if (i != bk_none) {
                node_[i].next = bk_none;
                if (node_[i].parent == bk_none) i = bk_none;
            }
            if (i == bk_none) {
                i = pop_active();
                if (i == bk_none) break;
            }

            bk_index mid = bk_none, u = i, v = i;
            if (node_[i].label & bk_sink_bit)
                grow<true>(i, mid, u);
            else
                grow<false>(i, mid, v);

            if (++time_ == bk_none) restart_clock();
            if (mid != bk_none) {
                // i may touch the other tree through more arcs: keep it, marked
                // active so that it is not queued a second time meanwhile.
                node_[i].next = i;
                current = i;
                flow = augment(mid, u, v, flow);
                adopt_orphans();
            } else {
                current = bk_none;
            }
        }
        return flow;
    }

private:
    void activate(bk_index i) {
        bk_node& v = node_[i];
        if (v.next != bk_none) return;
        v.next = i;
        if (last_ != bk_none)
            node_[last_].next = i;
        else
            first_ = i;
        last_ = i;
    }

    bk_index pop_active() {
        while (first_ != bk_none) {
            const bk_index i = first_;
            bk_node& v = node_[i];
            first_ = v.next == i ? bk_none : v.next;
            if (first_ == bk_none) last_ = bk_none;
            v.next = bk_none;
            if (v.parent != bk_none) return i;  // freed nodes stay queued until popped
        }
        return bk_none;
    }

    void restart_clock() {
        for (bk_index k = 0; k < n_; ++k) node_[k].stamp = 0;
        time_ = 1;
    }

    /// Grows i's tree through i's arcs. On meeting the other tree sets mid to
    /// the arc from the source side to the sink side and `other` to the node
    /// of the other tree.
    template <bool Sink>
    void grow(bk_index i, bk_index& mid, bk_index& other) {
        // i's label does not change while its arcs are scanned (no self-loops).
        // Labels of one tree compare as distances: they share the tree bit.
        const bk_index stamp = node_[i].stamp, label = node_[i].label;
        g_.for_each_arc(i, [&](bk_index a, bk_index j, bk_index s) {
            // Residual capacity away from the terminal: i -> j in S, j -> i in T.
            if (!(g_.cap(Sink ? s : a) > Cap(0))) return false;
            bk_node& nj = node_[j];
            if (nj.parent == bk_none) {
                set_parent(nj, s, stamp, label + 1);  // joins i's tree
                activate(j);
            } else if (((nj.label & bk_sink_bit) != 0) != Sink) {
                mid = Sink ? s : a;
                other = j;
                return true;
            } else if (nj.stamp <= stamp && nj.label > label) {
                set_parent(nj, s, stamp, label + 1);  // a shorter way to the terminal
            }
            return false;
        });
    }

    static void set_parent(bk_node& n, bk_index arc_to_parent, bk_index stamp, bk_index label) {
        n.parent = arc_to_parent;
        n.stamp = stamp;
        n.label = label;
    }

    void orphan(bk_index i) {
        node_[i].parent = bk_orphan;
        orphans_.push_back(i);
    }

    flow_type augment(bk_index mid, bk_index u, bk_index v, flow_type flow) {
        // Bottleneck: the middle arc, the source-side path (parent -> child
        // arcs), the sink-side path (child -> parent arcs), the two terminals.
        Cap b = g_.cap(mid);
        bk_index i = u;
        for (bk_index p; (p = node_[i].parent) != bk_terminal; i = g_.head(p)) {
            const Cap c = g_.cap(g_.sister(p));
            if (c < b) b = c;
        }
        if (tr_[i] < b) b = tr_[i];
        for (i = v;;) {
            const bk_index p = node_[i].parent;
            if (p == bk_terminal) break;
            const Cap c = g_.cap(p);
            if (c < b) b = c;
            i = g_.head(p);
        }
        if (-tr_[i] < b) b = -tr_[i];

        g_.cap(g_.sister(mid)) += b;
        g_.cap(mid) -= b;
        for (i = u;;) {
            const bk_index p = node_[i].parent;
            if (p == bk_terminal) {
                tr_[i] -= b;
                if (tr_[i] == Cap(0)) orphan(i);
                break;
            }
            g_.cap(p) += b;
            Cap& down = g_.cap(g_.sister(p));
            down -= b;
            if (down == Cap(0)) orphan(i);
            i = g_.head(p);
        }
        for (i = v;;) {
            const bk_index p = node_[i].parent;
            if (p == bk_terminal) {
                tr_[i] += b;
                if (tr_[i] == Cap(0)) orphan(i);
                break;
            }
            g_.cap(g_.sister(p)) += b;
            Cap& up = g_.cap(p);
            up -= b;
            if (up == Cap(0)) orphan(i);
            i = g_.head(p);
        }
        return capacity_traits<Cap>::add_flow(flow, b);
    }

    void adopt_orphans() {
        // The path's orphans are taken from the terminals inwards, sink side
        // first; orphans found while processing join the end of the list.
        // The clock is copied: node stores could alias the member.
        std::reverse(orphans_.begin(), orphans_.end());
        const bk_index now = time_;
        for (std::size_t k = 0; k < orphans_.size(); ++k) {
            const bk_index i = orphans_[k];
            if (node_[i].label & bk_sink_bit)
                process_orphan<true>(i, now);
            else
                process_orphan<false>(i, now);
        }
        orphans_.clear();
    }

    /// Arcs from j to its terminal along its tree, or bk_none when the way
    /// passes through an orphan. Stamps the nodes on the way with their
    /// distances, so later searches in this adoption stop early.
    bk_index root_distance(bk_index j, bk_index now, bk_index tree) {
        bk_index d = 0;
        for (bk_index k = j;;) {
            bk_node& n = node_[k];
            if (n.stamp == now) {
                d += n.label & ~bk_sink_bit;
                break;
            }
            const bk_index p = n.parent;
            ++d;
            if (p == bk_terminal) {
                n.stamp = now;
                n.label = 1u | tree;
                break;
            }
            if (p == bk_orphan) return bk_none;
            k = g_.head(p);
        }
        bk_index e = d;
        for (bk_index k = j; node_[k].stamp != now; k = g_.head(node_[k].parent)) {
            node_[k].stamp = now;
            node_[k].label = e-- | tree;
        }
        return d;
    }

    template <bool Sink>
    void process_orphan(bk_index i, bk_index now) {
        constexpr bk_index tree = Sink ? bk_sink_bit : 0u;
        bk_index best = bk_none, best_d = bk_none;
        // A parent j must be in i's tree with residual capacity on the tree
        // direction: j -> i in the source tree, i -> j in the sink tree.
        g_.for_each_arc(i, [&](bk_index a, bk_index j, bk_index s) {
            if (!(g_.cap(Sink ? a : s) > Cap(0))) return false;
            const bk_node& nj = node_[j];
            if (nj.parent == bk_none || (nj.label & bk_sink_bit) != tree) return false;
            const bk_index d = root_distance(j, now, tree);
            if (d < best_d) {
                best_d = d;
                best = a;
            }
            return false;
        });
        bk_node& ni = node_[i];
        if (best != bk_none) {
            set_parent(ni, best, now, (best_d + 1) | tree);
            return;
        }
        // No parent: i becomes free. Neighbours that could grow into it again
        // become active; its children become orphans.
        g_.for_each_arc(i, [&](bk_index a, bk_index j, bk_index s) {
            bk_node& nj = node_[j];
            const bk_index p = nj.parent;
            if (p == bk_none || (nj.label & bk_sink_bit) != tree) return false;
            if (g_.cap(Sink ? a : s) > Cap(0)) activate(j);
            if (p != bk_terminal && p != bk_orphan && g_.head(p) == i) orphan(j);
            return false;
        });
        ni.parent = bk_none;
    }

    Layout& g_;
    bk_node* node_;
    Cap* tr_;
    bk_index n_;
    std::vector<bk_index>& orphans_;
    bk_index first_ = bk_none, last_ = bk_none;
    bk_index time_ = 0;
};

}  // namespace anima::detail
