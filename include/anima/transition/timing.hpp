// Variable timing (section 4 of the variable-timing paper, as corrected in
// SPEC.md): the transition lasts as long as its slowest key joint needs to
// turn from the trigger pose of clip A to the first pose of clip B at the
// angular speed the joint had around the switch.
//
//   dtheta_i = 2 acos|q_A,i . q_B,i|   (the rotation angle; Eq 4 printed half of it)
//   velocity model:     t_i = dtheta_i / mean(|w_A,i|, |w_B,i|), each speed the
//                       mean over speed_window before the trigger / after B's start
//   acceleration model: t_i = sqrt(2 dtheta_i / (|dw_A,i| + |dw_B,i|))   (Eq 1-2)
//   T = clamp(max over key joints of t_i, min_duration, max_duration)   (Eq 5)
//
// Speeds and accelerations are floored (min_speed, min_acceleration) so a
// joint at rest does not ask for an infinite transition.
#pragma once

#include <anima/core/constants.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/rotation/angular_velocity.hpp>
#include <anima/rotation/quaternion.hpp>
#include <anima/motion/joint_roles.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace anima {

enum class timing_model : unsigned char { velocity, constant_acceleration };

/// How time maps to the interpolation parameter h.
enum class easing : unsigned char {
    linear,      ///< h = t / T (Eq 10)
    ease_in_out  ///< 2 (t/T)^2, then 1 - 2 (t/T - 1)^2 (Eq 11): accelerate, then decelerate
};

inline std::string_view to_string(easing e) { return e == easing::linear ? "linear" : "ease_in_out"; }

/// h(t) for t in [0, total], clamped to [0, 1].
template <class T>
T interpolation_parameter(T t, T total, easing e) {
    if (!(total > T(0))) return T(1);
    const T u = std::clamp(t / total, T(0), T(1));
    if (e == easing::linear) return u;
    return u < T(0.5) ? T(2) * u * u : T(1) - T(2) * (u - T(1)) * (u - T(1));
}

struct timing_params {
    timing_model model = timing_model::velocity;
    double min_duration = 0.1;      ///< s
    double max_duration = 1.2;      ///< s
    double min_speed = 0.5;         ///< rad/s, floor on the mean angular speed
    double min_acceleration = 2.0;  ///< rad/s^2, floor on the summed angular acceleration
    double speed_window = 0.1;      ///< s: speeds are averaged over this long before the trigger / after B's start
};

template <class T>
struct joint_timing {
    std::size_t joint = 0;
    joint_role role = joint_role::other;
    bool key = false;      ///< root, leg or foot: counts towards T
    T angle = 0;           ///< rad, from A's trigger pose to B's first pose
    T speed_a = 0, speed_b = 0;                ///< rad/s around the switch
    T acceleration_a = 0, acceleration_b = 0;  ///< rad/s^2 around the switch
    T time = 0;            ///< s, t_i (reported for every joint, key or not)
};

template <class T>
struct timing_result {
    T duration = 0;         ///< s, T after clamping
    T unclamped = 0;        ///< s, max t_i over the key joints
    std::size_t limiting_joint = 0;  ///< the key joint with the largest t_i
    std::vector<joint_timing<T>> joints;
};

namespace detail {

/// Mean |angular velocity| and mean |angular acceleration| of joint j's local
/// rotation over the one-frame steps in [first, last] (clamped to the clip).
/// Averaging over a short window rather than reading one instant keeps a
/// joint caught at the turning point of its swing from looking still.
template <class T>
void rotation_rates(const clip<T>& c, std::ptrdiff_t first, std::ptrdiff_t last, std::size_t j,
                    const Eigen::Quaternion<T>& turn, T& speed, T& accel) {
    speed = accel = T(0);
    const auto n = static_cast<std::ptrdiff_t>(c.frames());
    first = std::max<std::ptrdiff_t>(first, 0);
    last = std::min<std::ptrdiff_t>(last, n - 1);
    if (last - first < 1) {
        // One frame inside the window: widen to a neighbouring step if any.
        if (n < 2) return;
        first = std::min<std::ptrdiff_t>(first, n - 2);
        last = first + 1;
    }
    const T dt = c.frame_time();
    const auto q = [&](std::ptrdiff_t k) { return Eigen::Quaternion<T>(turn * c.rotation(static_cast<std::size_t>(k), j)); };
    Eigen::Matrix<T, 3, 1> previous = Eigen::Matrix<T, 3, 1>::Zero();
    T accel_sum = 0;
    for (std::ptrdiff_t k = first; k < last; ++k) {
        const Eigen::Matrix<T, 3, 1> w = angular_velocity(q(k), q(k + 1), dt);
        speed += w.norm();
        if (k > first) accel_sum += (w - previous).norm() / dt;
        previous = w;
    }
    speed /= static_cast<T>(last - first);
    if (last - first > 1) accel = accel_sum / static_cast<T>(last - first - 1);
}

}  // namespace detail

/// Per-joint t_i and the transition length T for switching from frame
/// `trigger` of a to frame `b_start` of b. `b_root_turn` is the heading turn
/// applied to b's root (so that root rotations are compared facing the same
/// way). `roles` has one entry per joint.
template <class T>
timing_result<T> variable_timing(const clip<T>& a, std::size_t trigger, const clip<T>& b, std::size_t b_start,
                                 const std::vector<joint_role>& roles, const Eigen::Quaternion<T>& b_root_turn,
                                 const timing_params& params = {}) {
    if (trigger >= a.frames() || b_start >= b.frames())
        throw invalid_argument("anima::variable_timing: trigger frame " + std::to_string(trigger) + " of " +
                               std::to_string(a.frames()) + " or start frame " + std::to_string(b_start) + " of " +
                               std::to_string(b.frames()) + " out of range");
    if (roles.size() != a.joints() || a.joints() != b.joints())
        throw invalid_argument("anima::variable_timing: roles, clip A and clip B must have the same joint count");
    if (!(params.min_duration >= 0) || !(params.max_duration >= params.min_duration) || !(params.min_speed > 0) ||
        !(params.min_acceleration > 0) || !(params.speed_window >= 0))
        throw invalid_argument("anima::variable_timing: need 0 <= min_duration <= max_duration and positive floors");
    timing_result<T> out;
    out.joints.resize(a.joints());
    T longest = -1;
    const Eigen::Quaternion<T> none = Eigen::Quaternion<T>::Identity();
    const auto window = std::max<std::ptrdiff_t>(
        1, static_cast<std::ptrdiff_t>(std::lround(params.speed_window / static_cast<double>(a.frame_time()))));
    for (std::size_t j = 0; j < a.joints(); ++j) {
        auto& jt = out.joints[j];
        jt.joint = j;
        jt.role = roles[j];
        jt.key = roles[j] == joint_role::root || roles[j] == joint_role::leg || roles[j] == joint_role::foot;
        const auto& turn = j == 0 ? b_root_turn : none;
        jt.angle = angle_between(a.rotation(trigger, j), Eigen::Quaternion<T>(turn * b.rotation(b_start, j)));
        detail::rotation_rates(a, static_cast<std::ptrdiff_t>(trigger) - window, static_cast<std::ptrdiff_t>(trigger), j,
                               none, jt.speed_a, jt.acceleration_a);
        detail::rotation_rates(b, static_cast<std::ptrdiff_t>(b_start), static_cast<std::ptrdiff_t>(b_start) + window, j,
                               turn, jt.speed_b, jt.acceleration_b);
        if (params.model == timing_model::velocity) {
            const T w = std::max(T(0.5) * (jt.speed_a + jt.speed_b), static_cast<T>(params.min_speed));
            jt.time = jt.angle / w;
        } else {
            const T alpha = std::max(jt.acceleration_a + jt.acceleration_b, static_cast<T>(params.min_acceleration));
            jt.time = std::sqrt(T(2) * jt.angle / alpha);
        }
        if (jt.key && jt.time > longest) {
            longest = jt.time;
            out.limiting_joint = j;
        }
    }
    out.unclamped = std::max(longest, T(0));
    out.duration = std::clamp(out.unclamped, static_cast<T>(params.min_duration), static_cast<T>(params.max_duration));
    return out;
}

}  // namespace anima
