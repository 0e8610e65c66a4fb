// The paper's measures: normalised cross-correlation between predicted and
// true values of one parameter over a set of frames (Table 1), and PSNR
// between a synthesised and a real image over a region, grey levels 0-255
// (Eq 7).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace anima {

/// Normalised cross-correlation (Pearson's r) of two equally long
/// sequences, in [-1, 1]. Throws anima::invalid_argument for sizes that
/// differ, fewer than 2 values, a non-finite value, or a constant sequence
/// (r is undefined: the message names which).
template <class DerivedA, class DerivedB>
typename DerivedA::Scalar normalized_cross_correlation(const Eigen::MatrixBase<DerivedA>& a,
                                                       const Eigen::MatrixBase<DerivedB>& b) {
    using T = typename DerivedA::Scalar;
    const std::string who = "anima::normalized_cross_correlation";
    if (a.size() != b.size() || a.size() < 2)
        throw invalid_argument(who + ": needs two sequences of the same length >= 2, got " + std::to_string(a.size()) +
                               " and " + std::to_string(b.size()));
    if (!a.allFinite() || !b.allFinite()) throw invalid_argument(who + ": a value is not finite");
    const auto da = (a.array() - a.mean()).eval();
    const auto db = (b.template cast<T>().array() - static_cast<T>(b.mean())).eval();
    const T na = std::sqrt(da.square().sum()), nb = std::sqrt(db.square().sum());
    if (!(na > T(0))) throw invalid_argument(who + ": the first sequence is constant");
    if (!(nb > T(0))) throw invalid_argument(who + ": the second sequence is constant");
    const T r = (da * db).sum() / (na * nb);
    return std::max(T(-1), std::min(T(1), r));
}

/// Eq 7: 10 log10(peak^2 / MSE) over the pixels where `mask` is true (all
/// pixels when the mask is empty). Identical images give +infinity. Throws
/// anima::invalid_argument for sizes that differ, an empty region, a
/// non-finite value in the region or a non-positive peak.
template <class DerivedA, class DerivedB>
typename DerivedA::Scalar psnr(const Eigen::MatrixBase<DerivedA>& image, const Eigen::MatrixBase<DerivedB>& reference,
                               const Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>& mask = {},
                               typename DerivedA::Scalar peak = 255) {
    using T = typename DerivedA::Scalar;
    const std::string who = "anima::psnr";
    if (image.rows() != reference.rows() || image.cols() != reference.cols())
        throw invalid_argument(who + ": the images are " + std::to_string(image.rows()) + " x " +
                               std::to_string(image.cols()) + " and " + std::to_string(reference.rows()) + " x " +
                               std::to_string(reference.cols()));
    if (mask.size() != 0 && (mask.rows() != image.rows() || mask.cols() != image.cols()))
        throw invalid_argument(who + ": the mask is " + std::to_string(mask.rows()) + " x " +
                               std::to_string(mask.cols()) + ", the images " + std::to_string(image.rows()) + " x " +
                               std::to_string(image.cols()));
    check_positive(who, "peak", peak);
    double sum = 0;
    long count = 0;
    for (Eigen::Index x = 0; x < image.cols(); ++x)
        for (Eigen::Index y = 0; y < image.rows(); ++y) {
            if (mask.size() != 0 && !mask(y, x)) continue;
            const double d = static_cast<double>(image(y, x)) - static_cast<double>(reference(y, x));
            if (!std::isfinite(d))
                throw invalid_argument(who + ": pixel (x " + std::to_string(x) + ", y " + std::to_string(y) +
                                       ") is not finite");
            sum += d * d;
            ++count;
        }
    if (count == 0) throw invalid_argument(who + ": the region is empty");
    if (sum == 0) return std::numeric_limits<T>::infinity();
    const double p = static_cast<double>(peak);
    return static_cast<T>(10.0 * std::log10(p * p / (sum / static_cast<double>(count))));
}

}  // namespace anima
