// Non-negative values (distances, errors) as an 8-bit grey image: 0 black,
// a percentile of the values and everything above it white, so that a few
// extreme values do not leave everything else black.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace anima {

/// The grey levels and the value drawn white.
template <class T>
struct grey_levels {
    std::vector<unsigned char> bytes;  ///< row by row, top to bottom
    T white = T(0);                    ///< the percentile; 0 when every value is 0
};

/// Each value v of `values` as round(255 * min(1, v / white)), white being
/// the `percentile`-th percentile of the values (the element at index
/// floor((n - 1) * percentile / 100) of them sorted; 100: the largest).
/// All black when white is 0. Throws anima::invalid_argument for an empty
/// matrix, a percentile outside [0, 100] or a value that is negative or not
/// finite (naming its row and column).
template <class Derived>
grey_levels<typename Derived::Scalar> percentile_grey(const Eigen::MatrixBase<Derived>& values, double percentile) {
    using T = typename Derived::Scalar;
    check_argument(percentile >= 0 && percentile <= 100, "anima::percentile_grey", "percentile", "in [0, 100]",
                   percentile);
    if (values.size() == 0) throw invalid_argument("anima::percentile_grey: the matrix is empty");
    std::vector<T> sorted;
    sorted.reserve(static_cast<std::size_t>(values.size()));
    for (Eigen::Index y = 0; y < values.rows(); ++y)
        for (Eigen::Index x = 0; x < values.cols(); ++x) {
            const T v = values(y, x);
            if (!(v >= T(0)) || !std::isfinite(v))
                throw invalid_argument("anima::percentile_grey: value (row " + std::to_string(y) + ", column " +
                                       std::to_string(x) + ") is " + detail::argument_text(v) +
                                       ", not a finite value >= 0");
            sorted.push_back(v);
        }
    const auto q = sorted.begin() + static_cast<std::ptrdiff_t>(
                                        std::floor(static_cast<double>(sorted.size() - 1) * percentile / 100));
    std::nth_element(sorted.begin(), q, sorted.end());
    grey_levels<T> out;
    out.white = *q;
    out.bytes.reserve(sorted.size());
    const double white = static_cast<double>(out.white);
    for (Eigen::Index y = 0; y < values.rows(); ++y)
        for (Eigen::Index x = 0; x < values.cols(); ++x) {
            const double g = white > 0 ? std::min(1.0, static_cast<double>(values(y, x)) / white) : 0.0;
            out.bytes.push_back(static_cast<unsigned char>(std::lround(255 * g)));
        }
    return out;
}

}  // namespace anima
