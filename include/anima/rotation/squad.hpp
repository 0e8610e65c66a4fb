// Spherical quadrangle interpolation (Shoemake): a C1 curve through a sequence
// of orientations, built from slerps and one control point per key.
#pragma once

#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>
#include <anima/rotation/slerp.hpp>

#include <type_traits>

namespace anima {

/// Control point s_i for key q_i with neighbours prev = q_{i-1}, next = q_{i+1}:
/// s_i = q_i exp(-(log(q_i^-1 q_{i+1}) + log(q_i^-1 q_{i-1})) / 4).
/// The neighbours are first moved to q_i's hemisphere, so the sign of the
/// inputs does not matter. At the ends of a sequence pass prev = q_i (or
/// next = q_i): the control point is then slerp(q_i, next, -1/4), a quarter
/// of the way back along the one real neighbour's arc, which starts the curve
/// towards that neighbour with the tangent of the segment.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q squad_control_point(const Q& prev, const Q& q, const Q& next) {
    using T = quat_scalar_t<Q>;
    const auto c = detail::normalized_or_throw(detail::load(q), "anima::squad_control_point");
    auto p = detail::normalized_or_throw(detail::load(prev), "anima::squad_control_point");
    auto n = detail::normalized_or_throw(detail::load(next), "anima::squad_control_point");
    if (detail::dot4(c, p) < T(0)) p = -p;
    if (detail::dot4(c, n) < T(0)) n = -n;
    const auto ci = detail::conj4(c);
    T ax, ay, az, bx, by, bz;
    detail::log_unit(ci * n, ax, ay, az);
    detail::log_unit(ci * p, bx, by, bz);
    const T k = T(-0.25);
    return detail::store<Q>(c * detail::exp_pure(k * (ax + bx), k * (ay + by), k * (az + bz)));
}

/// Squad between keys q1 (t = 0) and q2 (t = 1) with control points s1, s2:
/// slerp(slerp(q1, q2, t), slerp(s1, s2, t), 2t(1 - t)). Passes through q1 and
/// q2 exactly; with control points from squad_control_point consecutive
/// segments join with continuous angular velocity.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q squad(const Q& q1, const Q& q2, const Q& s1, const Q& s2, quat_scalar_t<Q> t) {
    using T = quat_scalar_t<Q>;
    const auto a = detail::slerp4(detail::load(q1), detail::load(q2), t, false);
    const auto b = detail::slerp4(detail::load(s1), detail::load(s2), t, false);
    return detail::store<Q>(detail::slerp4(a, b, T(2) * t * (T(1) - t)));
}

}  // namespace anima
