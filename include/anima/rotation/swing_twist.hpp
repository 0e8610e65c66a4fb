// Swing-twist decomposition: q = swing * twist, where twist turns about a
// given axis and swing about an axis perpendicular to it. The twist about the
// up axis of a root orientation is the character's heading.
#pragma once

#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

namespace anima {

/// {swing, twist} of the unit quaternion q about `axis` (anything indexable
/// by [0..2], normalised here). When q is a pure half turn perpendicular to
/// the axis the twist is undefined and the identity is returned.
template <class Q, class V, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
std::pair<Q, Q> swing_twist(const Q& q, const V& axis) {
    using T = quat_scalar_t<Q>;
    const auto p = detail::normalized_or_throw(detail::load(q), "anima::swing_twist");
    T ax = static_cast<T>(axis[0]), ay = static_cast<T>(axis[1]), az = static_cast<T>(axis[2]);
    detail::normalize3_or_throw(ax, ay, az, "anima::swing_twist", "axis");
    const T d = p.x * ax + p.y * ay + p.z * az;
    detail::quat4<T> twist{p.w, d * ax, d * ay, d * az};
    const T n = detail::norm4(twist);
    if (n < std::numeric_limits<T>::epsilon()) twist = {T(1), T(0), T(0), T(0)};
    else twist = twist * (T(1) / n);
    const auto swing = p * detail::conj4(twist);
    return {detail::store<Q>(swing), detail::store<Q>(twist)};
}

/// Signed angle (radians, in (-pi, pi]) of q's twist about `axis`.
template <class Q, class V, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
quat_scalar_t<Q> twist_angle(const Q& q, const V& axis) {
    using T = quat_scalar_t<Q>;
    const auto tw = detail::load(swing_twist(q, axis).second);
    const T an = std::sqrt(T(axis[0]) * T(axis[0]) + T(axis[1]) * T(axis[1]) + T(axis[2]) * T(axis[2]));
    const T s = (tw.x * T(axis[0]) + tw.y * T(axis[1]) + tw.z * T(axis[2])) / an;
    return std::remainder(T(2) * std::atan2(s, tw.w), T(2) * T(3.141592653589793238462643383279502884L));
}

}  // namespace anima
