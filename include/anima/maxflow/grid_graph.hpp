// Max-flow / min-cut on a rows x cols lattice: each node (r, c) has edges to
// its right (r, c+1) and lower (r+1, c) neighbours, terminal weights, and
// optionally extra edges to any other node. That is the 4-connected grid of
// image segmentation, and the (DOF x frame) lattice of a motion-texture seam,
// where each DOF row is tied frame by frame to the rows of neighbouring
// joints (extra edges, or set_down for adjacent rows).
//
//   anima::grid_flow_graph<int> g(rows, cols);
//   g.set_right(r, c, cap, rev_cap);   // (r, c) -> (r, c+1) and back
//   g.set_down(r, c, cap, rev_cap);    // (r, c) -> (r+1, c) and back
//   g.add_edge(g.node(r1, c), g.node(r2, c), cap, rev_cap);
//   g.set_tweights(r, c, source_cap, sink_cap);
//   g.maxflow(); g.side(r, c);
//
// The solver is the same Boykov-Kolmogorov code as flow_graph's, on an
// implicit layout: the four neighbour arcs of a node are slots 4p .. 4p+3 of
// one capacity array and their heads and reverse arcs are computed from the
// index, so a grid arc costs one capacity and no pointers. The lattice is
// padded with a column on the right and a row above and below, so every
// neighbour index exists (padding nodes have no capacity and never join a
// search tree). Extra edges are laid out as in flow_graph after the grid
// arcs.
//
// Node ids are row-major: node(r, c) = r * cols + c. Capacities: see
// capacity.hpp. Unset grid edges have capacity 0 (no edge).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/maxflow/capacity.hpp>
#include <anima/maxflow/detail/adjacency.hpp>
#include <anima/maxflow/detail/boykov_kolmogorov.hpp>
#include <anima/maxflow/min_cut.hpp>

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace anima {
namespace detail {

/// bk_solver layout of a padded grid with padded width w: arc 4p + k leaves
/// node p towards p + 1, p - 1, p + w, p - w for k = 0, 1, 2, 3. Arc ids from
/// `grid_arcs` on are the extra edges' (when Extra).
template <class Cap, bool Extra>
struct grid_layout {
    Cap* rcap;
    bk_index step[4];    ///< head - tail per slot, modulo 2^32
    bk_index jump[4];    ///< sister - arc per slot, modulo 2^32
    bk_index grid_arcs;  ///< 4 x padded nodes
    const bk_index* xfirst;
    pair_arc<Cap>* xarcs;  ///< indexed by arc id - grid_arcs

    bk_index head(bk_index a) const noexcept {
        if constexpr (Extra)
            if (a >= grid_arcs) return xarcs[a - grid_arcs].head;
        return (a >> 2) + step[a & 3];
    }
    bk_index sister(bk_index a) const noexcept {
        if constexpr (Extra)
            if (a >= grid_arcs) return a ^ 1u;
        return a + jump[a & 3];
    }
    Cap& cap(bk_index a) const noexcept {
        if constexpr (Extra)
            if (a >= grid_arcs) return xarcs[a - grid_arcs].cap;
        return rcap[a];
    }
    template <class F>
    void for_each_arc(bk_index i, F&& f) const {
        // Unrolled: each slot's head and sister offsets are then known per call.
        const bk_index a = i << 2;
        if (f(a, i + step[0], a + jump[0]) || f(a + 1, i + step[1], a + 1 + jump[1]) ||
            f(a + 2, i + step[2], a + 2 + jump[2]) || f(a + 3, i + step[3], a + 3 + jump[3]))
            return;
        if constexpr (Extra)
            for (bk_index x = xfirst[i]; x != bk_none; x = xarcs[x - grid_arcs].next)
                if (f(x, xarcs[x - grid_arcs].head, x ^ 1u)) return;
    }
};

}  // namespace detail

template <class Cap>
class grid_flow_graph {
public:
    using capacity_type = Cap;
    using flow_type = typename capacity_traits<Cap>::flow_type;
    using traits = capacity_traits<Cap>;

    /// A rows x cols lattice with no edges (rows, cols >= 1).
    grid_flow_graph(std::size_t rows, std::size_t cols) : rows_(rows), cols_(cols), width_(cols + 1) {
        if (rows == 0 || cols == 0)
            throw invalid_argument("grid_flow_graph: the grid must have at least one row and one column, not " +
                                   std::to_string(rows) + " x " + std::to_string(cols));
        if (cols >= detail::bk_max_nodes || rows >= detail::bk_max_nodes ||
            (rows + 2) > detail::bk_max_index / 4 / width_)
            throw invalid_argument("grid_flow_graph: a " + std::to_string(rows) + " x " + std::to_string(cols) +
                                   " grid is more than the solver's 32-bit arc ids can hold");
        padded_ = (rows + 2) * width_;
        // Everything the solver needs is allocated here, while building.
        cap_.assign(4 * padded_, Cap(0));
        rcap_.assign(4 * padded_, Cap(0));
        state_.resize(padded_);
        residual_.resize(padded_);
        xarcs_.base = static_cast<detail::bk_index>(4 * padded_);
        source_.assign(rows * cols, Cap(0));
        sink_.assign(rows * cols, Cap(0));
    }

    std::size_t rows() const noexcept { return rows_; }
    std::size_t cols() const noexcept { return cols_; }
    std::size_t nodes() const noexcept { return rows_ * cols_; }
    std::size_t extra_edges() const noexcept { return xarcs_.edges(); }

    /// The id of node (r, c): r * cols + c.
    std::size_t node(std::size_t r, std::size_t c) const {
        check_cell(r, c, "node");
        return r * cols_ + c;
    }

    /// Sets the edge between (r, c) and (r, c+1): `cap` rightwards, `rev_cap` back.
    void set_right(std::size_t r, std::size_t c, Cap cap, Cap rev_cap) {
        if (r >= rows_ || c + 1 >= cols_)
            cell_error(r, c, "set_right", r < rows_ && c + 1 == cols_ ? "is in the last column" : "is outside the grid");
        check_pair(cap, rev_cap, "set_right");
        const std::size_t p = padded(r, c);
        rcap_[4 * p] = cap_[4 * p] = cap;
        rcap_[4 * (p + 1) + 1] = cap_[4 * (p + 1) + 1] = rev_cap;
        solved_ = false;
    }

    /// Sets the edge between (r, c) and (r+1, c): `cap` downwards, `rev_cap` back.
    void set_down(std::size_t r, std::size_t c, Cap cap, Cap rev_cap) {
        if (r + 1 >= rows_ || c >= cols_)
            cell_error(r, c, "set_down", c < cols_ && r + 1 == rows_ ? "is in the last row" : "is outside the grid");
        check_pair(cap, rev_cap, "set_down");
        const std::size_t p = padded(r, c);
        rcap_[4 * p + 2] = cap_[4 * p + 2] = cap;
        rcap_[4 * (p + width_) + 3] = cap_[4 * (p + width_) + 3] = rev_cap;
        solved_ = false;
    }

    /// Adds an edge between any two nodes (ids from node()): `cap` from u to
    /// v, `rev_cap` back; returns its id among the extra edges. Parallel
    /// edges add up; self-loops are ignored.
    std::size_t add_edge(std::size_t u, std::size_t v, Cap cap, Cap rev_cap) {
        check_node(u, "add_edge");
        check_node(v, "add_edge");
        check_pair(cap, rev_cap, "add_edge");
        if (!xarcs_.has_first()) xarcs_.add_nodes(padded_);
        solved_ = false;
        return xarcs_.add_edge(static_cast<detail::bk_index>(padded(u / cols_, u % cols_)),
                               static_cast<detail::bk_index>(padded(v / cols_, v % cols_)), cap, rev_cap);
    }

    /// Replaces the capacities of extra edge e.
    void set_edge(std::size_t e, Cap cap, Cap rev_cap) {
        check_edge(e, "set_edge");
        check_pair(cap, rev_cap, "set_edge");
        xarcs_.set_edge(e, cap, rev_cap);
        solved_ = false;
    }

    /// Adds capacity from the source to (r, c) and from (r, c) to the sink.
    void add_tweights(std::size_t r, std::size_t c, Cap source_cap, Cap sink_cap) {
        check_cell(r, c, "add_tweights");
        check_capacity(source_cap, "add_tweights");
        check_capacity(sink_cap, "add_tweights");
        const std::size_t i = r * cols_ + c;
        if (!traits::sum_fits(source_[i], source_cap) || !traits::sum_fits(sink_[i], sink_cap))
            throw invalid_argument("grid_flow_graph::add_tweights: the terminal capacities of (" + std::to_string(r) +
                                   ", " + std::to_string(c) + ") overflow the capacity type");
        source_[i] += source_cap;
        sink_[i] += sink_cap;
        solved_ = false;
    }

    /// Replaces the terminal capacities of (r, c).
    void set_tweights(std::size_t r, std::size_t c, Cap source_cap, Cap sink_cap) {
        check_cell(r, c, "set_tweights");
        check_capacity(source_cap, "set_tweights");
        check_capacity(sink_cap, "set_tweights");
        source_[r * cols_ + c] = source_cap;
        sink_[r * cols_ + c] = sink_cap;
        solved_ = false;
    }

    /// Computes the maximum flow (when the graph changed since the last call)
    /// and returns its value.
    flow_type maxflow() {
        if (solved_) return flow_;
        // Setters write the capacities and the residuals, so until a solve
        // changes them the residuals need no copy.
        if (dirty_) {
            std::copy(cap_.begin(), cap_.end(), rcap_.begin());
            xarcs_.restore();
        }
        dirty_ = true;
        const bool extra = xarcs_.edges() > 0;
        Cap* node = residual_.data();
        for (std::size_t p = 0; p < width_; ++p) node[p] = node[padded_ - 1 - p] = Cap(0);
        flow_type flow = 0;
        const Cap* source = source_.data();
        const Cap* sink = sink_.data();
        for (std::size_t r = 0; r < rows_; ++r) {
            node += width_;
            for (std::size_t c = 0; c < cols_; ++c)
                flow = traits::add_flow(flow, detail::bk_terminal_init(node[c], *source++, *sink++));
            node[cols_] = Cap(0);
        }
        flow_ = extra ? run<true>(flow) : run<false>(flow);
        solved_ = true;
        return flow_;
    }

    cut_side side(std::size_t r, std::size_t c) const {
        check_solved("side");
        check_cell(r, c, "side");
        return detail::bk_source_side(state_[padded(r, c)]) ? cut_side::source : cut_side::sink;
    }
    /// The side of node id i (= r * cols + c).
    cut_side side(std::size_t i) const {
        check_node(i, "side");
        return side(i / cols_, i % cols_);
    }

    /// maxflow() and the side of every node, in row-major order.
    min_cut_result<flow_type> min_cut() {
        min_cut_result<flow_type> result;
        result.flow = maxflow();
        result.side.resize(nodes());
        for (std::size_t r = 0; r < rows_; ++r)
            for (std::size_t c = 0; c < cols_; ++c)
                result.side[r * cols_ + c] =
                    detail::bk_source_side(state_[padded(r, c)]) ? cut_side::source : cut_side::sink;
        return result;
    }

    /// Net flow from (r, c) to (r, c+1) / to (r+1, c) (negative: backwards), after maxflow().
    Cap right_flow(std::size_t r, std::size_t c) const {
        check_solved("right_flow");
        check_cell(r, c, "right_flow");
        const std::size_t a = 4 * padded(r, c);
        return c + 1 < cols_ ? cap_[a] - rcap_[a] : Cap(0);
    }
    Cap down_flow(std::size_t r, std::size_t c) const {
        check_solved("down_flow");
        check_cell(r, c, "down_flow");
        const std::size_t a = 4 * padded(r, c) + 2;
        return r + 1 < rows_ ? cap_[a] - rcap_[a] : Cap(0);
    }
    /// Net flow along extra edge e from u to v, after maxflow().
    Cap edge_flow(std::size_t e) const {
        check_solved("edge_flow");
        check_edge(e, "edge_flow");
        return xarcs_.flow(e);
    }
    /// Flow from the source into (r, c), and from (r, c) to the sink, after maxflow().
    Cap source_flow(std::size_t r, std::size_t c) const {
        check_solved("source_flow");
        check_cell(r, c, "source_flow");
        const std::size_t i = r * cols_ + c;
        return detail::bk_terminal_flow(source_[i], sink_[i], residual_[padded(r, c)], false);
    }
    Cap sink_flow(std::size_t r, std::size_t c) const {
        check_solved("sink_flow");
        check_cell(r, c, "sink_flow");
        const std::size_t i = r * cols_ + c;
        return detail::bk_terminal_flow(source_[i], sink_[i], residual_[padded(r, c)], true);
    }

private:
    std::size_t padded(std::size_t r, std::size_t c) const noexcept { return (r + 1) * width_ + c; }

    template <bool Extra>
    flow_type run(flow_type flow) {
        const auto w = static_cast<detail::bk_index>(width_);
        detail::grid_layout<Cap, Extra> layout{rcap_.data(),
                                               {1u, 0u - 1u, w, 0u - w},
                                               {5u, 0u - 5u, 4u * w + 1u, 0u - (4u * w + 1u)},
                                               static_cast<detail::bk_index>(4 * padded_),
                                               Extra ? xarcs_.first() : nullptr, Extra ? xarcs_.arcs() : nullptr};
        detail::bk_solver<Cap, detail::grid_layout<Cap, Extra>> solver(
            layout, state_.data(), residual_.data(), static_cast<detail::bk_index>(padded_), orphans_);
        return solver.run(flow);
    }

    void check_cell(std::size_t r, std::size_t c, const char* fn) const {
        if (r >= rows_ || c >= cols_) cell_error(r, c, fn, "is outside the grid");
    }
    void check_node(std::size_t i, const char* fn) const {
        if (i >= nodes())
            throw invalid_argument(std::string("grid_flow_graph::") + fn + ": node " + std::to_string(i) +
                                   " out of range (the grid has " + std::to_string(nodes()) + " nodes)");
    }
    void check_edge(std::size_t e, const char* fn) const {
        if (e >= extra_edges())
            throw invalid_argument(std::string("grid_flow_graph::") + fn + ": extra edge " + std::to_string(e) +
                                   " out of range (the grid has " + std::to_string(extra_edges()) + ")");
    }
    [[noreturn]] void cell_error(std::size_t r, std::size_t c, const char* fn, const char* what) const {
        throw invalid_argument(std::string("grid_flow_graph::") + fn + ": (" + std::to_string(r) + ", " +
                               std::to_string(c) + ") " + what + " (" + std::to_string(rows_) + " x " +
                               std::to_string(cols_) + ")");
    }
    // Checks inline, messages out of line: the checks sit on the building path.
    static void check_capacity(Cap c, const char* fn) {
        if (!traits::valid(c)) capacity_error(c, fn);
    }
    static void check_pair(Cap cap, Cap rev, const char* fn) {
        if (!(traits::valid(cap) && traits::valid(rev) && traits::sum_fits(cap, rev))) pair_error(cap, rev, fn);
    }
    [[noreturn]] static void capacity_error(Cap c, const char* fn) {
        throw invalid_argument(std::string("grid_flow_graph::") + fn + ": capacity " + detail::argument_text(c) +
                               " is not finite and non-negative");
    }
    [[noreturn]] static void pair_error(Cap cap, Cap rev, const char* fn) {
        if (!traits::valid(cap)) capacity_error(cap, fn);
        if (!traits::valid(rev)) capacity_error(rev, fn);
        throw invalid_argument(std::string("grid_flow_graph::") + fn + ": capacities " + detail::argument_text(cap) + " and " +
                               detail::argument_text(rev) + " overflow the capacity type when added");
    }
    void check_solved(const char* fn) const {
        if (!solved_)
            throw invalid_argument(std::string("grid_flow_graph::") + fn +
                                   ": no flow yet; call maxflow() after the last change to the graph");
    }

    std::size_t rows_, cols_, width_, padded_ = 0;
    std::vector<Cap> cap_;   ///< grid arc capacities as set, 4 per padded node
    std::vector<Cap> rcap_;  ///< residual capacities of the last solve
    std::vector<Cap> source_, sink_;
    detail::pair_arcs<Cap> xarcs_;  ///< extra edges, arc ids after the grid's
    std::vector<detail::bk_node> state_;
    std::vector<Cap> residual_;  ///< residual terminal capacities, per padded node
    std::vector<detail::bk_index> orphans_;
    flow_type flow_ = 0;
    bool dirty_ = false;  ///< rcap_ holds residuals of an earlier solve
    bool solved_ = false;
};

}  // namespace anima
