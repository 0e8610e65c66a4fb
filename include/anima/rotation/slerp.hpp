// Spherical linear interpolation: constant angular speed along the shorter arc.
#pragma once

#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <cmath>
#include <type_traits>

namespace anima {
namespace detail {

/// sin(k theta) / sin(theta), exact as theta -> 0 (where it tends to k).
template <class T>
T sin_ratio(T k, T theta) {
    if (theta < small_angle<T>()) return k * (T(1) + (T(1) - k * k) * theta * theta / T(6));
    return std::sin(k * theta) / std::sin(theta);
}

/// Slerp of 4-vectors; `renormalize` = false skips the final rescaling where a
/// caller feeds the result straight into another slerp.
template <class T>
quat4<T> slerp4(const quat4<T>& a, quat4<T> b, T t, bool renormalize = true) {
    if (dot4(a, b) < T(0)) b = -b;  // shortest arc: q and -q are the same rotation
    // With u = |a-b| = 2 sin(theta/2) and v = |a+b| = 2 cos(theta/2) (for unit
    // inputs), the angle comes from asin(u / |(u, v)|), well conditioned since
    // u <= v after the flip, and 1/sin(theta) = (u^2 + v^2) / 2uv needs no
    // further sine. acos(a.b) would lose half the digits near 0.
    const T u = norm4(a - b), v = norm4(a + b), h2 = u * u + v * v;
    const T theta = T(2) * std::asin(u / std::sqrt(h2));
    T k0, k1;
    if (theta < small_angle<T>()) {
        k0 = sin_ratio(T(1) - t, theta);
        k1 = sin_ratio(t, theta);
    } else {
        const T inv_sin = h2 / (T(2) * u * v);
        k0 = std::sin((T(1) - t) * theta) * inv_sin;
        k1 = std::sin(t * theta) * inv_sin;
    }
    const quat4<T> r = a * k0 + b * k1;
    // Inputs a hair off unit length would drift; renormalising keeps |r| = 1.
    return renormalize ? r * (T(1) / norm4(r)) : r;
}

}  // namespace detail

/// Slerp from a (t = 0) to b (t = 1) along the shorter arc (b is negated when
/// a.b < 0). Exact for identical and nearly identical inputs (a Taylor branch,
/// not an early-out: t is honoured at every angle), finite for antipodal ones
/// (which are the same rotation). t outside [0, 1] extrapolates. Inputs are
/// expected to be unit quaternions; the result is normalised.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q slerp(const Q& a, const Q& b, quat_scalar_t<Q> t) {
    return detail::store<Q>(detail::slerp4(detail::load(a), detail::load(b), t));
}

}  // namespace anima
