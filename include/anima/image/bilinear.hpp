// Bilinear sampling of a grey image at real coordinates. Pixel (y, x) has
// its centre at the point (x, y); positions outside the image take the
// nearest border pixel's value (clamp to edge).
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace anima {

/// The image interpolated bilinearly at (x, y), clamped to the border. A
/// non-finite coordinate is clamped like any other (NaN to the first pixel),
/// so the result is always one of the image's convex combinations. The image
/// must not be empty.
template <class Derived, class T>
T sample_bilinear(const Eigen::MatrixBase<Derived>& img, T x, T y) {
    const T max_x = static_cast<T>(img.cols() - 1), max_y = static_cast<T>(img.rows() - 1);
    x = std::isnan(x) ? T(0) : std::clamp(x, T(0), max_x);
    y = std::isnan(y) ? T(0) : std::clamp(y, T(0), max_y);
    const Eigen::Index x0 = static_cast<Eigen::Index>(std::floor(x)), y0 = static_cast<Eigen::Index>(std::floor(y));
    const Eigen::Index x1 = std::min<Eigen::Index>(x0 + 1, img.cols() - 1), y1 = std::min<Eigen::Index>(y0 + 1, img.rows() - 1);
    const T fx = x - static_cast<T>(x0), fy = y - static_cast<T>(y0);
    const T top = (T(1) - fx) * static_cast<T>(img(y0, x0)) + fx * static_cast<T>(img(y0, x1));
    const T bottom = (T(1) - fx) * static_cast<T>(img(y1, x0)) + fx * static_cast<T>(img(y1, x1));
    return (T(1) - fy) * top + fy * bottom;
}

}  // namespace anima
