// Where two motions overlap best: the (i, j) loop of the paper. Motion A
// (the clip's last m frames, M2) is laid over motion B (its first m
// frames, M1) so that A's frames i .. i+n-1 coincide with B's frames
// j .. j+n-1 (n = the overlap); the offsets (i, j) with the least summed
// frame-pair cost win.
//
// Summing every window directly costs O(offsets^2 * n) pair look-ups. Each
// window lies on one diagonal of the pair-cost matrix P(i, j), so prefix
// sums along the diagonals give every window in O(1): O(|A| |B| D) for P
// (D DOFs) and O(|A| |B|) for the windows.
#pragma once

#include <anima/core/error.hpp>
#include <anima/motion/frame_distance.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace anima {

template <class T>
struct overlap_search_result {
    std::size_t first_a = 0;  ///< A's first overlap frame (i)
    std::size_t first_b = 0;  ///< B's first overlap frame (j)
    T cost = T(0);            ///< summed pair cost of that window
    /// Cost of every window: (|A| - n + 1) x (|B| - n + 1), indexed (i, j).
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> costs;
};

/// P(i, j) = distance(A frame i, B frame j) for frames x DOF matrices with
/// the same DOFs (e.g. anima::frame_features rows and a distance from
/// anima::make_frame_distance). Throws anima::invalid_argument for
/// different DOF counts or a distance made for another DOF count.
template <class DA, class DB, class T = typename DA::Scalar>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> frame_pair_costs(const Eigen::MatrixBase<DA>& a,
                                                                  const Eigen::MatrixBase<DB>& b,
                                                                  const frame_distance<T>& distance) {
    if (a.cols() != b.cols())
        throw invalid_argument("anima::frame_pair_costs: the motions have " + std::to_string(a.cols()) + " and " +
                               std::to_string(b.cols()) + " DOFs");
    if (distance.metric == frame_metric::mahalanobis && distance.precision.size() != a.cols())
        throw invalid_argument("anima::frame_pair_costs: the distance has " + std::to_string(distance.precision.size()) +
                               " DOF weights, the motions " + std::to_string(a.cols()) + " DOFs");
    if (distance.metric == frame_metric::l2 && (distance.block_size < 1 || a.cols() % distance.block_size != 0))
        throw invalid_argument("anima::frame_pair_costs: L2 block size " + std::to_string(distance.block_size) +
                               " does not divide the " + std::to_string(a.cols()) + " DOFs");
    // Frames as contiguous columns: each pair reads two of them.
    const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> fa = a.transpose(), fb = b.transpose();
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> p(fa.cols(), fb.cols());
    for (Eigen::Index j = 0; j < fb.cols(); ++j)
        for (Eigen::Index i = 0; i < fa.cols(); ++i) p(i, j) = distance(fa.col(i), fb.col(j));
    return p;
}

/// The overlap offsets (i, j) minimising sum_{t < n} P(i + t, j + t) for a
/// pair-cost matrix P (|A| x |B|, finite, >= 0) and an overlap of n frames,
/// among the windows with i - j >= min_shift (every window by default; a
/// texton uses it to keep its loop long enough). Ties go to the smallest i,
/// then the smallest j. Throws anima::invalid_argument for n = 0, n longer
/// than either motion, a negative or non-finite cost, window sums that
/// overflow the scalar type (finite costs near its largest value), or a
/// min_shift that no window meets.
template <class Derived>
overlap_search_result<typename Derived::Scalar> search_overlap(
    const Eigen::MatrixBase<Derived>& pair_costs, std::size_t overlap,
    std::ptrdiff_t min_shift = std::numeric_limits<std::ptrdiff_t>::min()) {
    using T = typename Derived::Scalar;
    // Prefix sums subtract large partial sums: keep them at least in double.
    using acc = std::common_type_t<T, double>;
    const Eigen::Index na = pair_costs.rows(), nb = pair_costs.cols();
    // Compared as sizes first: a huge overlap must not wrap to a negative index.
    if (overlap == 0 || overlap > static_cast<std::size_t>(na) || overlap > static_cast<std::size_t>(nb))
        throw invalid_argument("anima::search_overlap: an overlap of " + std::to_string(overlap) +
                               " frames does not fit motions of " + std::to_string(na) + " and " + std::to_string(nb) +
                               " frames (it needs 1..the shorter length)");
    for (Eigen::Index j = 0; j < nb; ++j)
        for (Eigen::Index i = 0; i < na; ++i)
            if (!(pair_costs(i, j) >= T(0)) || !std::isfinite(pair_costs(i, j)))
                throw invalid_argument("anima::search_overlap: pair cost (" + std::to_string(i) + ", " +
                                       std::to_string(j) + ") is negative or not finite");
    const auto n = static_cast<Eigen::Index>(overlap);
    overlap_search_result<T> out;
    out.costs.resize(na - n + 1, nb - n + 1);
    std::vector<acc> prefix(static_cast<std::size_t>(std::min(na, nb)) + 1);
    // Diagonal d = j - i, from -(na-1) to nb-1; only those holding a window.
    for (Eigen::Index d = -(na - n); d <= nb - n; ++d) {
        const Eigen::Index i0 = d < 0 ? -d : 0, j0 = d < 0 ? 0 : d;
        const Eigen::Index len = std::min(na - i0, nb - j0);
        prefix[0] = 0;
        for (Eigen::Index k = 0; k < len; ++k)
            prefix[static_cast<std::size_t>(k + 1)] = prefix[static_cast<std::size_t>(k)] + acc(pair_costs(i0 + k, j0 + k));
        for (Eigen::Index k = 0; k + n <= len; ++k) {
            const acc window = prefix[static_cast<std::size_t>(k + n)] - prefix[static_cast<std::size_t>(k)];
            out.costs(i0 + k, j0 + k) = static_cast<T>(std::max(window, acc(0)));
        }
    }
    // Finite costs can still sum past T's range (a window of float max()).
    if (!out.costs.allFinite())
        throw invalid_argument("anima::search_overlap: the summed costs of " + std::to_string(overlap) +
                               " frames overflow the scalar type; scale the DOFs down");
    const Eigen::Index rows = out.costs.rows();
    if (min_shift > static_cast<std::ptrdiff_t>(rows - 1))
        throw invalid_argument("anima::search_overlap: no window has i - j >= " + std::to_string(min_shift) +
                               " (i is at most " + std::to_string(rows - 1) + ")");
    Eigen::Index bi = -1, bj = -1;
    for (Eigen::Index i = 0; i < rows; ++i)
        for (Eigen::Index j = 0; j < out.costs.cols() && static_cast<std::ptrdiff_t>(i - j) >= min_shift; ++j)
            if (bi < 0 || out.costs(i, j) < out.costs(bi, bj)) {
                bi = i;
                bj = j;
            }
    out.first_a = static_cast<std::size_t>(bi);
    out.first_b = static_cast<std::size_t>(bj);
    out.cost = out.costs(bi, bj);
    return out;
}

}  // namespace anima
