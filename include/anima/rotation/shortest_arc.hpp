// The shortest-arc rotation taking one direction onto another.
#pragma once

#include <anima/core/error.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace anima {

/// The rotation by the smallest angle that turns the direction of `from`
/// onto the direction of `to` (both anything indexable by [0..2], any
/// non-zero length). Its axis is from x to; for opposite directions, where
/// every axis perpendicular to `from` is as short, it is the one nearest to
/// the coordinate axis `from` is least aligned with. Throws
/// anima::invalid_argument for a zero or non-finite vector.
///
/// Closed form, no decomposition: with unit a, b, c = a x b and d = a.b, the
/// quaternion is (1 + d, c) normalised. Two rewrites keep it accurate where
/// the directions nearly coincide or nearly oppose: c is a x (b - a) or
/// a x (b + a), whose difference vector is small and exact, so c stays
/// perpendicular to a; and for d < 0, 1 + d is |c|^2 / (1 - d), which does not
/// cancel. (Eigen's FromTwoVectors uses an SVD for opposite directions.)
template <class Q, class A, class B, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q shortest_arc(const A& from, const B& to) {
    using T = quat_scalar_t<Q>;
    T a[3] = {static_cast<T>(from[0]), static_cast<T>(from[1]), static_cast<T>(from[2])};
    T b[3] = {static_cast<T>(to[0]), static_cast<T>(to[1]), static_cast<T>(to[2])};
    // Scaled by the largest component first, so that lengths whose squares
    // over- or underflow T still give their direction.
    detail::normalize3_or_throw(a[0], a[1], a[2], "anima::shortest_arc", "from");
    detail::normalize3_or_throw(b[0], b[1], b[2], "anima::shortest_arc", "to");
    const T d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const T sign = d >= T(0) ? T(-1) : T(1);
    const T s[3] = {b[0] + sign * a[0], b[1] + sign * a[1], b[2] + sign * a[2]};
    const T c[3] = {a[1] * s[2] - a[2] * s[1], a[2] * s[0] - a[0] * s[2], a[0] * s[1] - a[1] * s[0]};
    const T cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    // Exactly (or, within rounding, indistinguishably) opposite: no axis from c.
    if (d < T(0) && cc <= std::numeric_limits<T>::min()) {
        int k = 0;  // the coordinate axis a is least aligned with
        for (int i = 1; i < 3; ++i)
            if (std::abs(a[i]) < std::abs(a[k])) k = i;
        T e[3] = {T(0), T(0), T(0)};
        e[k] = T(1);
        T axis[3] = {a[1] * e[2] - a[2] * e[1], a[2] * e[0] - a[0] * e[2], a[0] * e[1] - a[1] * e[0]};
        const T n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
        return quat_traits<Q>::make(T(0), axis[0] / n, axis[1] / n, axis[2] / n);
    }
    const T w = d >= T(0) ? T(1) + d : cc / (T(1) - d);
    const T n = std::sqrt(w * w + cc);
    return quat_traits<Q>::make(w / n, c[0] / n, c[1] / n, c[2] / n);
}

}  // namespace anima
