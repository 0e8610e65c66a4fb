// Delaunay triangulation of a point set (Bowyer-Watson: insert points one at
// a time, remove the triangles whose circumcircle holds the new point, fan
// the hole from it). O(n^2) in the worst case, which is nothing for the 68
// landmarks of a face. The predicates run in double (long double for double
// input) whatever T is.
#pragma once

#include <anima/core/error.hpp>
#include <anima/sadm/landmarks.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace anima {

/// Three point indices, counter-clockwise for y up (positive signed area
/// (b - a) x (c - a)); on screen (y down) that is clockwise.
using triangle_indices = std::array<int, 3>;

namespace detail {

template <class T>
using predicate_real = std::conditional_t<std::is_same_v<T, float>, double, long double>;

template <class R>
R orient2(R ax, R ay, R bx, R by, R cx, R cy) {
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

/// > 0 when d lies strictly inside the circumcircle of the counter-clockwise triangle abc.
template <class R>
R in_circle(R ax, R ay, R bx, R by, R cx, R cy, R dx, R dy) {
    const R adx = ax - dx, ady = ay - dy, bdx = bx - dx, bdy = by - dy, cdx = cx - dx, cdy = cy - dy;
    const R a2 = adx * adx + ady * ady, b2 = bdx * bdx + bdy * bdy, c2 = cdx * cdx + cdy * cdy;
    return adx * (bdy * c2 - b2 * cdy) - ady * (bdx * c2 - b2 * cdx) + a2 * (bdx * cdy - bdy * cdx);
}

}  // namespace detail

/// The Delaunay triangulation of the points: triangles that cover their
/// convex hull, none with another point strictly inside its circumcircle.
/// Throws anima::invalid_argument for fewer than 3 points, a non-finite
/// point, two coincident points (naming both) or points all on one line.
template <class T>
std::vector<triangle_indices> delaunay_triangulation(const landmark_set<T>& points) {
    using R = detail::predicate_real<T>;
    const std::string who = "anima::delaunay_triangulation";
    const int n = static_cast<int>(points.rows());
    if (n < 3) throw invalid_argument(who + ": needs at least 3 points, got " + std::to_string(n));
    check_finite_landmarks(points, who, "point");
    std::vector<R> x(static_cast<std::size_t>(n) + 3), y(static_cast<std::size_t>(n) + 3);
    for (int k = 0; k < n; ++k) {
        x[static_cast<std::size_t>(k)] = static_cast<R>(points(k, 0));
        y[static_cast<std::size_t>(k)] = static_cast<R>(points(k, 1));
    }
    {  // coincident points make the triangulation undefined
        std::vector<int> order(static_cast<std::size_t>(n));
        for (int k = 0; k < n; ++k) order[static_cast<std::size_t>(k)] = k;
        const auto key = [&](int k) { return std::make_pair(x[static_cast<std::size_t>(k)], y[static_cast<std::size_t>(k)]); };
        std::sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
        for (std::size_t k = 1; k < order.size(); ++k)
            if (key(order[k]) == key(order[k - 1]))
                throw invalid_argument(who + ": points " + std::to_string(std::min(order[k], order[k - 1])) + " and " +
                                       std::to_string(std::max(order[k], order[k - 1])) + " coincide");
    }
    const R min_x = *std::min_element(x.begin(), x.begin() + n), max_x = *std::max_element(x.begin(), x.begin() + n);
    const R min_y = *std::min_element(y.begin(), y.begin() + n), max_y = *std::max_element(y.begin(), y.begin() + n);
    const R span = std::max(max_x - min_x, max_y - min_y);
    {  // all on one line: no triangle has positive area
        bool collinear = true;
        for (int k = 2; k < n && collinear; ++k)
            collinear = std::abs(detail::orient2(x[0], y[0], x[1], y[1], x[static_cast<std::size_t>(k)],
                                                 y[static_cast<std::size_t>(k)])) <= span * span * R(1e-12);
        if (collinear) throw invalid_argument(who + ": all " + std::to_string(n) + " points lie on one line");
    }
    // A super-triangle far outside the points holds every circumcircle that matters.
    const R cx = (min_x + max_x) / 2, cy = (min_y + max_y) / 2, far = span * R(1e4);
    x[static_cast<std::size_t>(n)] = cx - far, y[static_cast<std::size_t>(n)] = cy - far;
    x[static_cast<std::size_t>(n) + 1] = cx + far, y[static_cast<std::size_t>(n) + 1] = cy - far;
    x[static_cast<std::size_t>(n) + 2] = cx, y[static_cast<std::size_t>(n) + 2] = cy + far;
    const auto X = [&](int k) { return x[static_cast<std::size_t>(k)]; };
    const auto Y = [&](int k) { return y[static_cast<std::size_t>(k)]; };
    std::vector<triangle_indices> tris{{n, n + 1, n + 2}};
    for (int p = 0; p < n; ++p) {
        std::map<std::pair<int, int>, int> edges;  // boundary of the cavity: edges used once
        std::vector<triangle_indices> kept;
        kept.reserve(tris.size() + 2);
        for (const auto& t : tris) {
            if (detail::in_circle(X(t[0]), Y(t[0]), X(t[1]), Y(t[1]), X(t[2]), Y(t[2]), X(p), Y(p)) > R(0)) {
                for (int e = 0; e < 3; ++e) {
                    const int a = t[static_cast<std::size_t>(e)], b = t[static_cast<std::size_t>((e + 1) % 3)];
                    ++edges[{std::min(a, b), std::max(a, b)}];
                }
            } else {
                kept.push_back(t);
            }
        }
        // Re-create the cavity's directed boundary from the removed triangles' edges used once.
        for (const auto& t : tris) {
            if (!(detail::in_circle(X(t[0]), Y(t[0]), X(t[1]), Y(t[1]), X(t[2]), Y(t[2]), X(p), Y(p)) > R(0))) continue;
            for (int e = 0; e < 3; ++e) {
                const int a = t[static_cast<std::size_t>(e)], b = t[static_cast<std::size_t>((e + 1) % 3)];
                if (edges[{std::min(a, b), std::max(a, b)}] == 1) kept.push_back({a, b, p});
            }
        }
        tris = std::move(kept);
    }
    std::vector<triangle_indices> out;
    for (const auto& t : tris)
        if (t[0] < n && t[1] < n && t[2] < n) out.push_back(t);
    return out;
}

/// Signed area of a triangle of a landmark set (positive when counter-clockwise for y up).
template <class T>
T triangle_area(const landmark_set<T>& s, const triangle_indices& t) {
    return T(0.5) * ((s(t[1], 0) - s(t[0], 0)) * (s(t[2], 1) - s(t[0], 1)) -
                     (s(t[1], 1) - s(t[0], 1)) * (s(t[2], 0) - s(t[0], 0)));
}

}  // namespace anima
