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

template <class T>
quat4<T> slerp4(const quat4<T>& a, quat4<T> b, T t) {
    if (dot4(a, b) < T(0)) b = -b;  // shortest arc: q and -q are the same rotation
    // Angle between the 4-vectors from |a-b| and |a+b|: accurate at both ends,
    // where acos(a.b) loses half the digits.
    const T theta = T(2) * std::atan2(norm4(a - b), norm4(a + b));
    const quat4<T> r = a * sin_ratio(T(1) - t, theta) + b * sin_ratio(t, theta);
    // Inputs a hair off unit length would drift; renormalising keeps |r| = 1.
    return r * (T(1) / norm4(r));
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
