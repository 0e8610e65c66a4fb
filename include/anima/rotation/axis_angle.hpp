// Axis-angle <-> quaternion.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <cmath>
#include <string>
#include <type_traits>

namespace anima {

/// An axis (unit length) and an angle in radians.
template <class V, class T>
struct axis_angle {
    V axis;
    T angle;
};

/// Rotation by `angle` radians about `axis` (anything indexable by [0..2]; it
/// is normalised here). Throws anima::invalid_argument for a zero or non-finite axis.
template <class Q, class V, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q from_axis_angle(const V& axis, quat_scalar_t<Q> angle) {
    using T = quat_scalar_t<Q>;
    T x = static_cast<T>(axis[0]), y = static_cast<T>(axis[1]), z = static_cast<T>(axis[2]);
    detail::normalize3_or_throw(x, y, z, "anima::from_axis_angle", "axis");
    check_finite("anima::from_axis_angle", "angle", angle);
    const T s = std::sin(angle / T(2));
    return quat_traits<Q>::make(std::cos(angle / T(2)), s * x, s * y, s * z);
}

/// Axis and angle (in [0, pi]) of a unit quaternion. For the identity the
/// axis is undefined and (1, 0, 0) is returned with angle 0.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
axis_angle<quat_vector3_t<Q>, quat_scalar_t<Q>> to_axis_angle(const Q& q) {
    using T = quat_scalar_t<Q>;
    auto u = detail::normalized_or_throw(detail::load(q), "anima::to_axis_angle");
    if (u.w < T(0)) u = -u;
    const T s = detail::vector_norm(u);
    if (s == T(0)) return {quat_traits<Q>::make_vector(T(1), T(0), T(0)), T(0)};
    return {quat_traits<Q>::make_vector(u.x / s, u.y / s, u.z / s), T(2) * std::atan2(s, u.w)};
}

}  // namespace anima
