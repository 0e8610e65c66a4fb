// Angular velocity of a quaternion curve by finite differences.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/exp_log.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

namespace anima {

/// The frame an angular velocity is expressed in. For a joint's local
/// rotation, `parent` is the parent joint's frame (world for the root) and
/// `local` is the joint's own rotating frame.
enum class angular_frame : unsigned char { parent, local };

namespace detail {
template <class T>
void check_time_step(T dt, const char* who) {
    check_positive(who, "time step", dt);
}
}  // namespace detail

/// Constant angular velocity (radians per unit time, axis * rate) that turns
/// q0 into q1 in time dt along the shorter arc: rotation vector of q1 q0^-1
/// (parent frame) or of q0^-1 q1 (local frame), divided by dt.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
quat_vector3_t<Q> angular_velocity(const Q& q0, const Q& q1, quat_scalar_t<Q> dt,
                                   angular_frame frame = angular_frame::parent) {
    using T = quat_scalar_t<Q>;
    detail::check_time_step(dt, "anima::angular_velocity");
    const auto a = detail::load(q0), b = detail::load(q1);
    const auto d = frame == angular_frame::parent ? b * detail::conj4(a) : detail::conj4(a) * b;
    auto v = to_rotation_vector(detail::store<Q>(d));
    const T inv = T(1) / dt;
    return quat_traits<Q>::make_vector(v[0] * inv, v[1] * inv, v[2] * inv);
}

/// Angular velocity at every sample of a curve sampled every dt: central
/// differences inside, one-sided at the ends; a single sample has zero
/// velocity and an empty curve gives an empty result. `curve` is any random
/// access range of quaternions (std::vector<Q>, a span...).
template <class Range, class Q = std::decay_t<decltype(std::declval<const Range&>()[0])>,
          std::enable_if_t<is_quaternion_v<Q>, int> = 0>
std::vector<quat_vector3_t<Q>> angular_velocities(const Range& curve, quat_scalar_t<Q> dt,
                                                  angular_frame frame = angular_frame::parent) {
    using T = quat_scalar_t<Q>;
    detail::check_time_step(dt, "anima::angular_velocities");
    const std::size_t n = curve.size();
    std::vector<quat_vector3_t<Q>> out;
    out.reserve(n);
    if (n == 1) out.push_back(quat_traits<Q>::make_vector(T(0), T(0), T(0)));
    if (n < 2) return out;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t lo = i == 0 ? 0 : i - 1;
        const std::size_t hi = i + 1 == n ? n - 1 : i + 1;
        out.push_back(angular_velocity(curve[lo], curve[hi], dt * static_cast<T>(hi - lo), frame));
    }
    return out;
}

}  // namespace anima
