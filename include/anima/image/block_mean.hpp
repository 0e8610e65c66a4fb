// Resampling a matrix (an image, a distance matrix) to another size by the
// means of the blocks its pixels cover.
#pragma once

#include <anima/core/error.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace anima {

/// `m` resampled to rows x cols: pixel (r, c) is the mean of the block of
/// `m` it covers, rows [r R / rows, (r + 1) R / rows) and columns likewise
/// (R the rows of `m`), at least one of each: shrinking averages blocks,
/// enlarging repeats values. Throws anima::invalid_argument for an empty `m`
/// or a size below 1.
template <class Derived>
Eigen::Matrix<typename Derived::Scalar, Eigen::Dynamic, Eigen::Dynamic> block_mean_resample(
    const Eigen::MatrixBase<Derived>& m, Eigen::Index rows, Eigen::Index cols) {
    if (m.size() == 0 || rows < 1 || cols < 1)
        throw invalid_argument("anima::block_mean_resample: a " + std::to_string(m.rows()) + " x " +
                               std::to_string(m.cols()) + " matrix to " + std::to_string(rows) + " x " +
                               std::to_string(cols));
    // Pixel p of n covers [p size / n, (p + 1) size / n), at least one.
    const auto spans = [](Eigen::Index size, Eigen::Index n) {
        std::vector<std::pair<Eigen::Index, Eigen::Index>> out;  // first, count
        for (Eigen::Index p = 0; p < n; ++p) {
            const Eigen::Index first = p * size / n;
            out.emplace_back(first, std::max(first + 1, (p + 1) * size / n) - first);
        }
        return out;
    };
    const auto ys = spans(m.rows(), rows), xs = spans(m.cols(), cols);
    Eigen::Matrix<typename Derived::Scalar, Eigen::Dynamic, Eigen::Dynamic> out(rows, cols);
    for (Eigen::Index r = 0; r < rows; ++r)
        for (Eigen::Index c = 0; c < cols; ++c) {
            const auto [y, h] = ys[static_cast<std::size_t>(r)];
            const auto [x, w] = xs[static_cast<std::size_t>(c)];
            out(r, c) = m.block(y, x, h, w).mean();
        }
    return out;
}

}  // namespace anima
