// The order in which a texton of several clips should pass through them:
// the loop whose seams cost least. Each junction's cost is the summed frame
// distance of its best overlap (clip i's last m frames over clip j's first
// m, as make_texton searches it), and the loop through all clips that
// costs least is found exactly (Held-Karp over subsets, O(K^2 2^K) for K
// clips, at most 16).
//
//   const auto order = anima::least_cost_clip_order(clips, params.texton);
//   std::vector<anima::clip<double>> ordered;
//   for (const std::size_t i : order.order) ordered.push_back(clips[i]);
//   const auto texton = anima::make_texton(ordered, params.texton);
#pragma once

#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/texture/overlap_search.hpp>
#include <anima/texture/seam_cost.hpp>
#include <anima/texture/texton.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace anima {

/// Clips the exact order search takes at most (2^16 subsets).
inline constexpr std::size_t max_ordered_clips = 16;

template <class T>
struct clip_order {
    /// Clip indices in loop order, starting with clip 0 (a loop has no first clip).
    std::vector<std::size_t> order;
    T cost = T(0);        ///< the loop's summed junction costs
    T given_cost = T(0);  ///< the same for the order given (0, 1, ..., K-1)
    /// costs(i, j): the summed frame distance of the best overlap of clip
    /// i's last m frames over clip j's first m (i != j); the diagonal is 0
    /// (a clip never follows itself in a loop of several).
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> costs;
};

namespace detail {

/// The cycle through every node of least summed costs(i, j) over its edges
/// i -> j, starting at node 0 (Held-Karp). n >= 1.
template <class T>
std::vector<std::size_t> least_cost_cycle(const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& costs) {
    const auto n = static_cast<std::size_t>(costs.rows());
    if (n <= 2) {
        std::vector<std::size_t> order(n);
        for (std::size_t i = 0; i < n; ++i) order[i] = i;
        return order;
    }
    // best[S][j]: least cost of a path from 0 through the nodes of S (a set
    // of nodes 1..n-1, bit j-1 for node j) ending at j in S.
    const std::size_t sets = std::size_t{1} << (n - 1);
    const T inf = std::numeric_limits<T>::infinity();
    std::vector<T> best(sets * n, inf);
    std::vector<std::uint8_t> from(sets * n, 0);
    const auto at = [n](std::size_t set, std::size_t j) { return set * n + j; };
    for (std::size_t j = 1; j < n; ++j) best[at(std::size_t{1} << (j - 1), j)] = costs(0, static_cast<Eigen::Index>(j));
    for (std::size_t set = 1; set < sets; ++set)
        for (std::size_t j = 1; j < n; ++j) {
            const std::size_t bit = std::size_t{1} << (j - 1);
            if (!(set & bit) || set == bit) continue;
            const std::size_t rest = set & ~bit;
            for (std::size_t i = 1; i < n; ++i) {
                if (!(rest & (std::size_t{1} << (i - 1)))) continue;
                const T c = best[at(rest, i)] + costs(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
                if (c < best[at(set, j)]) {
                    best[at(set, j)] = c;
                    from[at(set, j)] = static_cast<std::uint8_t>(i);
                }
            }
        }
    const std::size_t all = sets - 1;
    std::size_t last = 1;
    T least = inf;
    for (std::size_t j = 1; j < n; ++j) {
        const T c = best[at(all, j)] + costs(static_cast<Eigen::Index>(j), 0);
        if (c < least) {
            least = c;
            last = j;
        }
    }
    std::vector<std::size_t> order(n);
    std::size_t set = all;
    for (std::size_t k = n - 1; k >= 1; --k) {
        order[k] = last;
        const std::size_t previous = from[at(set, last)];
        set &= ~(std::size_t{1} << (last - 1));
        last = previous;
    }
    order[0] = 0;
    return order;
}

/// The summed costs(order[k], order[k + 1]) around the loop.
template <class T>
T cycle_cost(const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& costs, const std::vector<std::size_t>& order) {
    T sum = T(0);
    for (std::size_t k = 0; k < order.size() && order.size() > 1; ++k)
        sum += costs(static_cast<Eigen::Index>(order[k]), static_cast<Eigen::Index>(order[(k + 1) % order.size()]));
    return sum;
}

}  // namespace detail

/// The order of the clips whose loop costs least (see the top of this
/// file), with every junction's cost and the cost of the order given. The
/// clips are checked as make_texton checks them (and throws for);
/// anima::invalid_argument also for more than max_ordered_clips clips.
template <class T>
clip_order<T> least_cost_clip_order(const std::vector<clip<T>>& clips, const texton_params<T>& params = {}) {
    std::vector<const clip<T>*> pointers;
    for (const clip<T>& c : clips) pointers.push_back(&c);
    detail::check_texton_clips(pointers, params, "anima::least_cost_clip_order");
    const std::size_t K = clips.size();
    if (K > max_ordered_clips)
        throw invalid_argument("anima::least_cost_clip_order: " + std::to_string(K) + " clips; the exact search takes at most " +
                               std::to_string(max_ordered_clips));
    clip_order<T> out;
    out.costs = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>::Zero(static_cast<Eigen::Index>(K),
                                                                       static_cast<Eigen::Index>(K));
    const auto in = detail::texton_inputs_of(pointers, params);
    const auto M = static_cast<Eigen::Index>(params.m);
    for (std::size_t i = 0; i < K; ++i)
        for (std::size_t j = 0; j < K; ++j)
            if (i != j)
                out.costs(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
                    search_overlap(frame_pair_costs(in.x[i].bottomRows(M), in.x[j].topRows(M), in.distance),
                                   params.overlap)
                        .cost;
    out.order = detail::least_cost_cycle(out.costs);
    out.cost = detail::cycle_cost(out.costs, out.order);
    std::vector<std::size_t> given(K);
    for (std::size_t i = 0; i < K; ++i) given[i] = i;
    out.given_cost = detail::cycle_cost(out.costs, given);
    return out;
}

}  // namespace anima
