// The seam itself: every row of the overlap lattice (a joint, the root's
// translation) switches from A (M2) to B (M1) at its own frame, chosen by a
// minimum cut of the (row x overlap frame) graph:
//   - edges along each row carry the Eq 8-9 capacity forwards and an
//     infinite one backwards, so a row switches exactly once (A...A B...B);
//   - edges between neighbouring rows (a joint and its parent, a joint's
//     translation and rotation) at the same frame carry the same capacity
//     times `neighbour_weight`, so related joints switch at nearby frames;
//   - the first overlap column is tied to the source (A) and the last to
//     the sink (B) with max-flow's infinity.
// The cut's capacity is the maximum flow.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/maxflow/capacity.hpp>
#include <anima/maxflow/grid_graph.hpp>
#include <anima/maxflow/min_cut.hpp>
#include <anima/texture/seam_cost.hpp>

#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace anima {

template <class T>
struct seam_cut_params {
    seam_cost_params<T> cost;
    /// Capacity of an edge between neighbouring rows relative to an edge
    /// along a row with the same mismatch (0: rows are cut independently).
    T neighbour_weight = T(0.5);
};

template <class T>
struct seam_cut_result {
    /// Per row: the first overlap frame taken from B, in 1..frames-1.
    std::vector<std::size_t> seam;
    /// Per row: the capacity of its cut edge (Eq 8-9).
    std::vector<T> row_cost;
    /// Summed capacity of the cut edges between neighbouring rows.
    T neighbour_cost = T(0);
    /// The cut's capacity: row costs plus neighbour cost.
    T cost = T(0);
    /// The maximum flow the solver found (equal to `cost` up to rounding).
    typename capacity_traits<T>::flow_type flow = 0;
};

/// Cuts the lattice of `cost` (rows x overlap frames). `neighbours` lists
/// pairs of distinct rows to tie. Throws anima::invalid_argument for a row
/// index out of range, a pair of equal rows, or a negative or non-finite
/// neighbour weight.
template <class T>
seam_cut_result<T> cut_seams(const seam_cost<T>& cost, const std::vector<std::pair<std::size_t, std::size_t>>& neighbours,
                             T neighbour_weight = T(0.5)) {
    const std::size_t rows = cost.rows(), frames = cost.frames();
    if (!(neighbour_weight >= T(0)) || !std::isfinite(neighbour_weight))
        throw invalid_argument("anima::cut_seams: the neighbour weight must be finite and >= 0, got " +
                               detail::argument_text(neighbour_weight));
    for (const auto& [r1, r2] : neighbours)
        if (r1 >= rows || r2 >= rows || r1 == r2)
            throw invalid_argument("anima::cut_seams: neighbour pair (" + std::to_string(r1) + ", " + std::to_string(r2) +
                                   ") is not two distinct rows of " + std::to_string(rows));
    const T inf = max_flow_infinity<T>();
    grid_flow_graph<T> g(rows, frames);
    for (std::size_t r = 0; r < rows; ++r) {
        for (std::size_t t = 0; t + 1 < frames; ++t) g.set_right(r, t, detail::seam_edge(cost, r, t, r, t + 1), inf);
        g.set_tweights(r, 0, inf, T(0));
        g.set_tweights(r, frames - 1, T(0), inf);
    }
    if (neighbour_weight > T(0))
        for (const auto& [r1, r2] : neighbours)
            for (std::size_t t = 0; t < frames; ++t) {
                const T c = neighbour_weight * detail::seam_edge(cost, r1, t, r2, t);
                g.add_edge(g.node(r1, t), g.node(r2, t), c, c);
            }
    const auto cut = g.min_cut();

    seam_cut_result<T> out;
    out.flow = cut.flow;
    out.seam.resize(rows);
    out.row_cost.resize(rows);
    const auto on_b = [&](std::size_t r, std::size_t t) { return cut.side[r * frames + t] == cut_side::sink; };
    for (std::size_t r = 0; r < rows; ++r) {
        std::size_t s = 1;
        while (s + 1 < frames && !on_b(r, s)) ++s;
        out.seam[r] = s;
        out.row_cost[r] = detail::seam_edge(cost, r, s - 1, r, s);
        out.cost += out.row_cost[r];
    }
    if (neighbour_weight > T(0))
        for (const auto& [r1, r2] : neighbours) {
            const std::size_t lo = std::min(out.seam[r1], out.seam[r2]), hi = std::max(out.seam[r1], out.seam[r2]);
            for (std::size_t t = lo; t < hi; ++t) out.neighbour_cost += neighbour_weight * detail::seam_edge(cost, r1, t, r2, t);
        }
    out.cost += out.neighbour_cost;
    return out;
}

}  // namespace anima
