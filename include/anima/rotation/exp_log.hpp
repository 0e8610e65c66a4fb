// Quaternion exponential, logarithm and power, and the rotation vector
// (exponential map) that turns a rotation into three unconstrained numbers.
// All are exact near the identity (Taylor branches) and finite at q = -1.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <cmath>
#include <type_traits>

namespace anima {

/// exp(q) = e^w (cos|v|, sin|v| v/|v|) for any quaternion q = (w, v).
/// Throws anima::invalid_argument for a non-finite q, or when e^w overflows.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q exp(const Q& q) {
    const auto p = detail::load(q);
    check_finite("anima::exp", "q.w", p.w);
    const auto e = std::exp(p.w);
    check_argument(std::isfinite(e), "anima::exp", "q.w", "small enough that e^w is finite", p.w);
    return detail::store<Q>(detail::exp_pure_checked(p.x, p.y, p.z, "anima::exp", "the vector part of q") * e);
}

/// log(q) = (ln|q|, atan2(|v|, w) v/|v|). For a unit quaternion the scalar part
/// is 0 and the vector part is (half the rotation angle) * axis. log(-1) is
/// (0, pi, 0, 0): the axis of a 2 pi turn is arbitrary, x is chosen.
/// Throws anima::invalid_argument for a zero or non-finite quaternion.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q log(const Q& q) {
    using T = quat_scalar_t<Q>;
    T log_norm;
    const auto u = detail::normalized_or_throw(detail::load(q), "anima::log", &log_norm);
    T vx, vy, vz;
    detail::log_unit(u, vx, vy, vz);
    return quat_traits<Q>::make(log_norm, vx, vy, vz);
}

/// q^t = exp(t log q) for a unit quaternion: the rotation scaled to t times its
/// angle about the same axis (taken on q's side of the double cover).
/// Throws anima::invalid_argument for a zero or non-finite q or a non-finite t.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q pow(const Q& q, quat_scalar_t<Q> t) {
    using T = quat_scalar_t<Q>;
    const auto u = detail::normalized_or_throw(detail::load(q), "anima::pow");
    check_finite("anima::pow", "t", t);
    T vx, vy, vz;
    detail::log_unit(u, vx, vy, vz);
    return detail::store<Q>(detail::exp_pure_checked(t * vx, t * vy, t * vz, "anima::pow", "t * log(q)"));
}

/// Rotation vector (axis * angle, angle in [0, pi]) of a unit quaternion: the
/// exponential map's inverse, taken on the w >= 0 side so it is unique.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
quat_vector3_t<Q> to_rotation_vector(const Q& q) {
    using T = quat_scalar_t<Q>;
    auto u = detail::normalized_or_throw(detail::load(q), "anima::to_rotation_vector");
    if (u.w < T(0)) u = -u;
    T vx, vy, vz;
    detail::log_unit(u, vx, vy, vz);
    return quat_traits<Q>::make_vector(T(2) * vx, T(2) * vy, T(2) * vz);
}

/// Unit quaternion of the rotation vector v (axis * angle); v is anything
/// indexable by [0..2]. The zero vector gives the identity. Throws
/// anima::invalid_argument for a non-finite v.
template <class Q, class V, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q from_rotation_vector(const V& v) {
    using T = quat_scalar_t<Q>;
    return detail::store<Q>(detail::exp_pure_checked(static_cast<T>(v[0]) / T(2), static_cast<T>(v[1]) / T(2),
                                                     static_cast<T>(v[2]) / T(2), "anima::from_rotation_vector",
                                                     "the rotation vector"));
}

}  // namespace anima
