// Piecewise-affine warps between two shapes that share a triangulation:
// a point inside triangle t of one shape keeps its barycentric coordinates
// in triangle t of the other. Images are warped backwards (for each output
// pixel, where to sample the input) with bilinear sampling; the pixels an
// output shape covers, with their triangles and barycentric weights, are a
// `triangle_raster` that can be computed once and reused for every frame.
#pragma once

#include <anima/core/error.hpp>
#include <anima/image/bilinear.hpp>
#include <anima/sadm/delaunay.hpp>
#include <anima/sadm/landmarks.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace anima {

namespace detail {

template <class T>
void check_triangles(const std::vector<triangle_indices>& tris, Eigen::Index points, const std::string& who) {
    if (tris.empty()) throw invalid_argument(who + ": no triangles");
    for (std::size_t t = 0; t < tris.size(); ++t)
        for (int v : tris[t])
            if (v < 0 || v >= points)
                throw invalid_argument(who + ": triangle " + std::to_string(t) + " uses point " + std::to_string(v) +
                                       " of a shape with " + std::to_string(points));
}

/// Barycentric coordinates of (px, py) in triangle t of s; nullopt for a degenerate triangle.
template <class T>
std::optional<Eigen::Matrix<T, 1, 3>> barycentric(const landmark_set<T>& s, const triangle_indices& t, T px, T py) {
    const T x0 = s(t[0], 0), y0 = s(t[0], 1);
    const T e1x = s(t[1], 0) - x0, e1y = s(t[1], 1) - y0, e2x = s(t[2], 0) - x0, e2y = s(t[2], 1) - y0;
    const T det = e1x * e2y - e1y * e2x;
    if (!(std::abs(det) > T(0))) return std::nullopt;
    const T dx = px - x0, dy = py - y0;
    const T b1 = (dx * e2y - dy * e2x) / det, b2 = (e1x * dy - e1y * dx) / det;
    return Eigen::Matrix<T, 1, 3>(T(1) - b1 - b2, b1, b2);
}

template <class T>
constexpr T barycentric_slack() {
    return Eigen::NumTraits<T>::epsilon() * T(64);
}

}  // namespace detail

/// The map from one shape's triangulated region onto another's.
template <class T>
class piecewise_affine_warp {
public:
    using point = Eigen::Matrix<T, 1, 2>;

    /// Throws anima::invalid_argument when the shapes differ in size, a
    /// point is not finite or a triangle names a point the shapes lack.
    piecewise_affine_warp(landmark_set<T> from, landmark_set<T> to, std::vector<triangle_indices> triangles)
        : from_(std::move(from)), to_(std::move(to)), tris_(std::move(triangles)) {
        const std::string who = "anima::piecewise_affine_warp";
        if (from_.rows() != to_.rows())
            throw invalid_argument(who + ": the shapes have " + std::to_string(from_.rows()) + " and " +
                                   std::to_string(to_.rows()) + " points");
        check_finite_landmarks(from_, who, "from point");
        check_finite_landmarks(to_, who, "to point");
        detail::check_triangles<T>(tris_, from_.rows(), who);
    }

    /// Where p lands, or nullopt when p is outside every triangle of `from`
    /// (degenerate triangles are skipped).
    std::optional<point> apply(const point& p) const {
        for (const auto& t : tris_) {
            const auto w = detail::barycentric(from_, t, p(0), p(1));
            if (w && w->minCoeff() >= -detail::barycentric_slack<T>())
                return point((*w)(0) * to_.row(t[0]) + (*w)(1) * to_.row(t[1]) + (*w)(2) * to_.row(t[2]));
        }
        return std::nullopt;
    }

    const landmark_set<T>& from() const noexcept { return from_; }
    const landmark_set<T>& to() const noexcept { return to_; }
    const std::vector<triangle_indices>& triangles() const noexcept { return tris_; }

private:
    landmark_set<T> from_, to_;
    std::vector<triangle_indices> tris_;
};

/// The pixels of a rows x cols raster whose centres lie in a triangulated
/// shape, each with its triangle and barycentric weights. Pixel (y, x) has
/// its centre at (x, y). A pixel on an edge shared by two triangles belongs to
/// the first in the list.
template <class T>
struct triangle_raster {
    Eigen::Index rows = 0, cols = 0;
    std::vector<Eigen::Index> pixel;                  ///< y * cols + x, increasing
    std::vector<int> triangle;                        ///< index into the triangle list
    std::vector<Eigen::Matrix<T, 1, 3>> weights;      ///< barycentric weights of the pixel's centre

    std::size_t size() const noexcept { return pixel.size(); }
    Eigen::Index y(std::size_t k) const noexcept { return pixel[k] / cols; }
    Eigen::Index x(std::size_t k) const noexcept { return pixel[k] % cols; }
    /// rows x cols, true on covered pixels.
    Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> mask() const {
        Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> m = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>::Constant(rows, cols, false);
        for (std::size_t k = 0; k < size(); ++k) m(y(k), x(k)) = true;
        return m;
    }
};

/// The most pixels a triangle raster (and so a face model's reference frame)
/// may have: 2^23, about 2900 x 2900, which needs about 235 MB in double.
constexpr Eigen::Index max_raster_pixels = Eigen::Index{1} << 23;

/// The pixels of a rows x cols raster that `shape`'s triangles cover.
/// Throws anima::invalid_argument for a bad size, non-finite points or bad triangles.
template <class T>
triangle_raster<T> rasterize_triangles(const landmark_set<T>& shape, const std::vector<triangle_indices>& triangles,
                                       Eigen::Index rows, Eigen::Index cols) {
    const std::string who = "anima::rasterize_triangles";
    if (rows <= 0 || cols <= 0)
        throw invalid_argument(who + ": the raster is " + std::to_string(rows) + " x " + std::to_string(cols));
    if (rows > max_raster_pixels / cols)
        throw invalid_argument(who + ": the raster is " + std::to_string(rows) + " x " + std::to_string(cols) +
                               " pixels, more than the " + std::to_string(max_raster_pixels) +
                               " allowed (anima::max_raster_pixels)");
    check_finite_landmarks(shape, who, "point");
    detail::check_triangles<T>(triangles, shape.rows(), who);
    std::vector<int> owner(static_cast<std::size_t>(rows * cols), -1);
    std::vector<Eigen::Matrix<T, 1, 3>> w(owner.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto& tri = triangles[t];
        T lo_x = shape(tri[0], 0), hi_x = lo_x, lo_y = shape(tri[0], 1), hi_y = lo_y;
        for (int v : tri) {
            lo_x = std::min(lo_x, shape(v, 0)), hi_x = std::max(hi_x, shape(v, 0));
            lo_y = std::min(lo_y, shape(v, 1)), hi_y = std::max(hi_y, shape(v, 1));
        }
        const Eigen::Index x0 = std::max<Eigen::Index>(0, static_cast<Eigen::Index>(std::ceil(lo_x - T(1e-3))));
        const Eigen::Index x1 = std::min<Eigen::Index>(cols - 1, static_cast<Eigen::Index>(std::floor(hi_x + T(1e-3))));
        const Eigen::Index y0 = std::max<Eigen::Index>(0, static_cast<Eigen::Index>(std::ceil(lo_y - T(1e-3))));
        const Eigen::Index y1 = std::min<Eigen::Index>(rows - 1, static_cast<Eigen::Index>(std::floor(hi_y + T(1e-3))));
        for (Eigen::Index py = y0; py <= y1; ++py)
            for (Eigen::Index px = x0; px <= x1; ++px) {
                const std::size_t at = static_cast<std::size_t>(py * cols + px);
                if (owner[at] >= 0) continue;
                const auto b = detail::barycentric(shape, tri, static_cast<T>(px), static_cast<T>(py));
                if (b && b->minCoeff() >= -detail::barycentric_slack<T>()) {
                    owner[at] = static_cast<int>(t);
                    w[at] = *b;
                }
            }
    }
    triangle_raster<T> r;
    r.rows = rows;
    r.cols = cols;
    for (std::size_t at = 0; at < owner.size(); ++at)
        if (owner[at] >= 0) {
            r.pixel.push_back(static_cast<Eigen::Index>(at));
            r.triangle.push_back(owner[at]);
            r.weights.push_back(w[at]);
        }
    return r;
}

/// Where each raster pixel lands when the raster's shape is replaced by
/// `shape` (same triangles): one row (x, y) per pixel.
template <class T>
landmark_set<T> map_raster(const triangle_raster<T>& raster, const std::vector<triangle_indices>& triangles,
                           const landmark_set<T>& shape) {
    landmark_set<T> out(static_cast<Eigen::Index>(raster.size()), 2);
    for (std::size_t k = 0; k < raster.size(); ++k) {
        const auto& t = triangles[static_cast<std::size_t>(raster.triangle[k])];
        const auto& w = raster.weights[k];
        out.row(static_cast<Eigen::Index>(k)) = w(0) * shape.row(t[0]) + w(1) * shape.row(t[1]) + w(2) * shape.row(t[2]);
    }
    return out;
}

/// The image's grey levels at the raster's pixels after warping: pixel k of
/// the raster samples `img` (bilinearly) where it lands when the raster's
/// shape becomes `shape`. Throws anima::invalid_argument for an empty image,
/// a shape of the wrong size or a non-finite landmark.
template <class T, class Derived>
Eigen::Matrix<T, Eigen::Dynamic, 1> sample_warped(const triangle_raster<T>& raster,
                                                  const std::vector<triangle_indices>& triangles,
                                                  const landmark_set<T>& shape, const Eigen::MatrixBase<Derived>& img) {
    const std::string who = "anima::sample_warped";
    if (img.size() == 0) throw invalid_argument(who + ": the image is empty");
    check_finite_landmarks(shape, who);
    detail::check_triangles<T>(triangles, shape.rows(), who);
    const landmark_set<T> at = map_raster(raster, triangles, shape);
    Eigen::Matrix<T, Eigen::Dynamic, 1> g(at.rows());
    for (Eigen::Index k = 0; k < at.rows(); ++k) g(k) = sample_bilinear(img, at(k, 0), at(k, 1));
    return g;
}

/// Warps `img`, whose features sit at `from`, so that they sit at `to`, on a
/// rows x cols output. Pixels outside `to`'s triangles take `outside`.
/// Throws anima::invalid_argument as piecewise_affine_warp and rasterize_triangles do.
template <class T, class Derived>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> warp_image(const Eigen::MatrixBase<Derived>& img,
                                                            const landmark_set<T>& from, const landmark_set<T>& to,
                                                            const std::vector<triangle_indices>& triangles,
                                                            Eigen::Index rows, Eigen::Index cols, T outside = T(0)) {
    if (from.rows() != to.rows())
        throw invalid_argument("anima::warp_image: the shapes have " + std::to_string(from.rows()) + " and " +
                               std::to_string(to.rows()) + " points");
    const triangle_raster<T> raster = rasterize_triangles(to, triangles, rows, cols);
    const auto g = sample_warped(raster, triangles, from, img);
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> out = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>::Constant(rows, cols, outside);
    for (std::size_t k = 0; k < raster.size(); ++k) out(raster.y(k), raster.x(k)) = g(static_cast<Eigen::Index>(k));
    return out;
}

}  // namespace anima
