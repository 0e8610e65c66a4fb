// A general graph for max-flow / min-cut with the Boykov-Kolmogorov
// algorithm: nodes, edges with a capacity in each direction, and terminal
// weights (capacities from the source and to the sink) per node, the form of
// the energies of vision and graphics ("graph cuts").
//
//   anima::flow_graph<int> g(3);
//   g.add_tweights(0, 5, 0);      // source -> 0
//   g.add_tweights(2, 0, 4);      // 2 -> sink
//   g.add_edge(0, 1, 3, 0);       // 0 -> 1
//   g.add_edge(1, 2, 6, 0);       // 1 -> 2
//   long long f = g.maxflow();    // 3
//   g.side(1);                    // cut_side::sink: the cut is the edge 0 -> 1
//
// The graph is stored the way the solver reads it (see detail/adjacency.hpp:
// the two arcs of an edge side by side, 32-bit ids, no per-node allocation),
// so maxflow() starts at once. maxflow() always solves the graph as it is:
// after changing capacities (set_edge, set_tweights...) or adding nodes and
// edges, calling it again solves the new graph from scratch.
//
// Capacities: see capacity.hpp (finite, >= 0, capacity_traits<Cap>::infinity()
// for hard constraints). Parallel edges are allowed and add up; self-loops
// are accepted and ignored (they never cross a cut).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/maxflow/capacity.hpp>
#include <anima/maxflow/detail/adjacency.hpp>
#include <anima/maxflow/detail/boykov_kolmogorov.hpp>
#include <anima/maxflow/min_cut.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace anima {

template <class Cap>
class flow_graph {
public:
    using capacity_type = Cap;
    using flow_type = typename capacity_traits<Cap>::flow_type;
    using traits = capacity_traits<Cap>;

    flow_graph() = default;

    /// A graph with `nodes` nodes (ids 0..nodes-1) and room for `edges` edges.
    explicit flow_graph(std::size_t nodes, std::size_t edges = 0) {
        add_nodes(nodes);
        arcs_.reserve(edges);
    }

    /// Adds `count` nodes without edges; returns the id of the first.
    std::size_t add_nodes(std::size_t count) {
        const std::size_t first = nodes();
        if (count > detail::bk_max_nodes - first)
            throw invalid_argument("flow_graph::add_nodes: " + std::to_string(first + count) +
                                   " nodes are more than the solver's 32-bit node ids can hold");
        source_.resize(first + count, Cap(0));
        sink_.resize(first + count, Cap(0));
        state_.resize(first + count);
        residual_.resize(first + count);
        arcs_.add_nodes(count);
        solved_ = false;
        return first;
    }
    std::size_t add_node() { return add_nodes(1); }

    std::size_t nodes() const noexcept { return source_.size(); }
    std::size_t edges() const noexcept { return arcs_.edges(); }
    void reserve_edges(std::size_t count) { arcs_.reserve(count); }

    /// Adds an edge with capacity `cap` from u to v and `rev_cap` from v to
    /// u; returns its id (0, 1, ... in order of addition).
    std::size_t add_edge(std::size_t u, std::size_t v, Cap cap, Cap rev_cap) {
        check_node(u, "add_edge");
        check_node(v, "add_edge");
        check_pair(cap, rev_cap, "add_edge");
        solved_ = false;
        return arcs_.add_edge(static_cast<detail::bk_index>(u), static_cast<detail::bk_index>(v), cap, rev_cap);
    }

    /// Replaces the capacities of edge e.
    void set_edge(std::size_t e, Cap cap, Cap rev_cap) {
        check_edge(e, "set_edge");
        check_pair(cap, rev_cap, "set_edge");
        solved_ = false;
        arcs_.set_edge(e, cap, rev_cap);
    }

    /// Adds capacity from the source to node i and from i to the sink (the
    /// "terminal weights"); several calls add up.
    void add_tweights(std::size_t i, Cap source_cap, Cap sink_cap) {
        check_node(i, "add_tweights");
        check_capacity(source_cap, "add_tweights");
        check_capacity(sink_cap, "add_tweights");
        if (!traits::sum_fits(source_[i], source_cap) || !traits::sum_fits(sink_[i], sink_cap))
            throw invalid_argument("flow_graph::add_tweights: the terminal capacities of node " + std::to_string(i) +
                                   " overflow the capacity type");
        source_[i] += source_cap;
        sink_[i] += sink_cap;
        solved_ = false;
    }

    /// Replaces node i's terminal capacities.
    void set_tweights(std::size_t i, Cap source_cap, Cap sink_cap) {
        check_node(i, "set_tweights");
        check_capacity(source_cap, "set_tweights");
        check_capacity(sink_cap, "set_tweights");
        source_[i] = source_cap;
        sink_[i] = sink_cap;
        solved_ = false;
    }

    /// Computes the maximum flow from the source to the sink (when the graph
    /// changed since the last call) and returns its value.
    flow_type maxflow() {
        if (solved_) return flow_;
        if (dirty_) arcs_.restore();  // set_edge writes both, so the originals are current
        dirty_ = true;
        const std::size_t n = nodes();
        flow_type flow = 0;
        for (std::size_t i = 0; i < n; ++i)
            flow = traits::add_flow(flow, detail::bk_terminal_init(residual_[i], source_[i], sink_[i]));
        detail::pair_layout<Cap> layout{arcs_.first(), arcs_.arcs()};
        detail::bk_solver<Cap, detail::pair_layout<Cap>> solver(layout, state_.data(), residual_.data(),
                                                                static_cast<detail::bk_index>(n), orphans_);
        flow_ = solver.run(flow);
        solved_ = true;
        return flow_;
    }

    /// The side of the minimum cut node i is on (after maxflow()).
    cut_side side(std::size_t i) const {
        check_solved("side");
        check_node(i, "side");
        return detail::bk_source_side(state_[i]) ? cut_side::source : cut_side::sink;
    }

    /// maxflow() and the side of every node.
    min_cut_result<flow_type> min_cut() {
        min_cut_result<flow_type> r;
        r.flow = maxflow();
        r.side.resize(nodes());
        for (std::size_t i = 0; i < nodes(); ++i)
            r.side[i] = detail::bk_source_side(state_[i]) ? cut_side::source : cut_side::sink;
        return r;
    }

    /// Net flow along edge e from u to v (negative: from v to u), after maxflow().
    Cap edge_flow(std::size_t e) const {
        check_solved("edge_flow");
        check_edge(e, "edge_flow");
        return arcs_.flow(e);
    }

    /// Flow from the source into node i, and from i to the sink, after maxflow().
    Cap source_flow(std::size_t i) const {
        check_solved("source_flow");
        check_node(i, "source_flow");
        return detail::bk_terminal_flow(source_[i], sink_[i], residual_[i], false);
    }
    Cap sink_flow(std::size_t i) const {
        check_solved("sink_flow");
        check_node(i, "sink_flow");
        return detail::bk_terminal_flow(source_[i], sink_[i], residual_[i], true);
    }

    /// Removes every node and edge, keeping the memory for the next graph.
    void clear() {
        source_.clear();
        sink_.clear();
        state_.clear();
        residual_.clear();
        arcs_.clear();
        dirty_ = solved_ = false;
    }

private:
    void check_node(std::size_t i, const char* fn) const {
        if (i >= nodes()) node_error(i, fn);
    }
    void check_edge(std::size_t e, const char* fn) const {
        if (e >= edges()) edge_error(e, fn);
    }
    [[noreturn]] void node_error(std::size_t i, const char* fn) const {
        throw invalid_argument(std::string("flow_graph::") + fn + ": node " + std::to_string(i) +
                               " out of range (the graph has " + std::to_string(nodes()) + " nodes)");
    }
    [[noreturn]] void edge_error(std::size_t e, const char* fn) const {
        throw invalid_argument(std::string("flow_graph::") + fn + ": edge " + std::to_string(e) +
                               " out of range (the graph has " + std::to_string(edges()) + " edges)");
    }
    // Checks inline, messages out of line: the checks sit on the building path.
    static void check_capacity(Cap c, const char* fn) {
        if (!traits::valid(c)) capacity_error(c, fn);
    }
    static void check_pair(Cap cap, Cap rev, const char* fn) {
        if (!(traits::valid(cap) && traits::valid(rev) && traits::sum_fits(cap, rev))) pair_error(cap, rev, fn);
    }
    [[noreturn]] static void capacity_error(Cap c, const char* fn) {
        throw invalid_argument(std::string("flow_graph::") + fn + ": capacity " + detail::argument_text(c) +
                               " is not finite and non-negative");
    }
    [[noreturn]] static void pair_error(Cap cap, Cap rev, const char* fn) {
        if (!traits::valid(cap)) capacity_error(cap, fn);
        if (!traits::valid(rev)) capacity_error(rev, fn);
        throw invalid_argument(std::string("flow_graph::") + fn + ": capacities " + detail::argument_text(cap) + " and " +
                               detail::argument_text(rev) + " overflow the capacity type when added");
    }
    void check_solved(const char* fn) const {
        if (!solved_)
            throw invalid_argument(std::string("flow_graph::") + fn +
                                   ": no flow yet; call maxflow() after the last change to the graph");
    }

    std::vector<Cap> source_, sink_;
    detail::pair_arcs<Cap> arcs_;
    std::vector<detail::bk_node> state_;
    std::vector<Cap> residual_;  ///< residual terminal capacities of the last solve
    std::vector<detail::bk_index> orphans_;
    flow_type flow_ = 0;
    bool dirty_ = false;   ///< arcs_ holds residuals of an earlier solve
    bool solved_ = false;  ///< state_ and flow_ answer the current graph
};

}  // namespace anima
