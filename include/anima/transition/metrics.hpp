// Measures of how smooth a transition is, for comparing methods on the same
// clips: its length, the peaks of joint angular acceleration and jerk and of
// root acceleration around it, and how much the supporting foot slides
// (and how much feet in contact skate there, against the clips' own skate).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/contacts.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/finite_difference.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/rotation/angular_velocity.hpp>
#include <anima/motion/joint_roles.hpp>
#include <anima/transition/variable_timing_transition.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace anima {

template <class T>
struct transition_quality {
    T length = 0;                     ///< s, from the last frame of A to the first of B
    T peak_angular_acceleration = 0;  ///< rad/s^2, over all non-finger joints
    T peak_angular_jerk = 0;          ///< rad/s^3
    T peak_root_acceleration = 0;     ///< m/s^2
    T foot_slide = 0;                 ///< m/s, mean horizontal speed of the lowest foot joint
    /// Foot skate (motion/contacts.hpp, contacts by height alone so that a
    /// sliding foot counts): median horizontal speed of feet in contact, body
    /// heights per second, over the measured frames and over the rest of the
    /// joined clip (the clips' own), and their ratio (0 when either has no
    /// contact, or the figure no feet).
    T foot_skate_window = 0, foot_skate_clips = 0, foot_skate_ratio = 0;
    /// The root's ground speed (m/s, the up component left out): the slowest
    /// over the transition's frames, the slower of its first and last
    /// frame's, and their ratio (0 when the ends stand still). A ratio well
    /// under 1 is a stall: a runner slowing mid-stride, as following planted
    /// feet can (transition_feet_params::root_speed_band bounds it).
    T root_speed_min = 0, root_speed_ends = 0, root_speed_ratio = 0;
};

/// Measures a joined clip over its transition plus `margin` frames on each
/// side (so that a jump at either end is counted). Derivatives are finite
/// differences at the clip's frame rate; lengths are converted to metres with
/// metres_per_unit.
template <class T>
transition_quality<T> measure_transition(const joined_clip<T>& joined, const std::vector<joint_role>& roles,
                                         signed_axis up, double metres_per_unit, std::size_t margin = 12) {
    const clip<T>& c = joined.motion;
    if (roles.size() != c.joints())
        throw invalid_argument("anima::measure_transition: " + std::to_string(roles.size()) + " roles for " +
                               std::to_string(c.joints()) + " joints");
    detail::check_joined_window(joined, "anima::measure_transition");
    check_positive("anima::measure_transition", "metres_per_unit", metres_per_unit);
    transition_quality<T> q;
    const T dt = c.frame_time();
    const T m = static_cast<T>(metres_per_unit);
    q.length = dt * static_cast<T>(joined.end_frame - joined.start_frame);
    const std::size_t first = joined.start_frame > margin ? joined.start_frame - margin : 0;
    const std::size_t last = std::min(joined.end_frame + margin, c.frames() - 1);
    const auto n = static_cast<Eigen::Index>(last - first + 1);
    if (n < 4) return q;

    // Angular velocity per one-frame step, then differences of it.
    for (std::size_t j = 0; j < c.joints(); ++j) {
        if (roles[j] == joint_role::finger) continue;
        Eigen::Matrix<T, Eigen::Dynamic, 3> w(n - 1, 3);
        for (Eigen::Index k = 0; k + 1 < n; ++k)
            w.row(k) = angular_velocity(c.rotation(first + static_cast<std::size_t>(k), j),
                                        c.rotation(first + static_cast<std::size_t>(k) + 1, j), dt)
                           .transpose();
        const Eigen::Matrix<T, Eigen::Dynamic, 3> alpha = (w.bottomRows(n - 2) - w.topRows(n - 2)) / dt;
        const Eigen::Matrix<T, Eigen::Dynamic, 3> jerk = (alpha.bottomRows(n - 3) - alpha.topRows(n - 3)) / dt;
        q.peak_angular_acceleration = std::max(q.peak_angular_acceleration, alpha.rowwise().norm().maxCoeff());
        q.peak_angular_jerk = std::max(q.peak_angular_jerk, jerk.rowwise().norm().maxCoeff());
    }

    const auto P = global_positions(c.slice(first, last + 1));
    const auto V = time_derivative(P, dt);
    const auto A = time_derivative(V.leftCols(3).eval(), dt);
    q.peak_root_acceleration = A.rowwise().norm().maxCoeff() * m;
    const auto ground_speed = [&](std::size_t f) {
        Eigen::Matrix<T, 3, 1> v = V.row(static_cast<Eigen::Index>(f - first)).template head<3>().transpose();
        v[static_cast<int>(up.axis)] = T(0);
        return v.norm() * m;
    };
    q.root_speed_ends = std::min(ground_speed(joined.start_frame), ground_speed(joined.end_frame));
    q.root_speed_min = q.root_speed_ends;
    for (std::size_t f = joined.start_frame + 1; f < joined.end_frame; ++f)
        q.root_speed_min = std::min(q.root_speed_min, ground_speed(f));
    q.root_speed_ratio = q.root_speed_ends > T(0) ? q.root_speed_min / q.root_speed_ends : T(0);

    std::vector<std::size_t> feet;
    for (std::size_t j = 0; j < roles.size(); ++j)
        if (roles[j] == joint_role::foot) feet.push_back(j);
    if (!feet.empty()) {
        const int k = static_cast<int>(up.axis);
        T sum = 0;
        for (Eigen::Index f = 0; f < n; ++f) {
            std::size_t lowest = feet[0];
            for (std::size_t j : feet)
                if (up.sign * P(f, static_cast<Eigen::Index>(3 * j) + k) <
                    up.sign * P(f, static_cast<Eigen::Index>(3 * lowest) + k))
                    lowest = j;
            Eigen::Matrix<T, 3, 1> v = V.row(f).template segment<3>(static_cast<Eigen::Index>(3 * lowest)).transpose();
            v[k] = 0;
            sum += v.norm();
        }
        q.foot_slide = sum / static_cast<T>(n) * m;
    }

    contact_params<T> cp;
    cp.up = up;
    cp.use_speed = false;
    if (!has_feet(c, cp)) return q;  // a figure without feet has no skate
    const auto contacts = find_contacts(c, cp);
    std::vector<T> inside, outside;
    for (const auto& foot : contacts.feet)
        for (std::size_t f = 0; f < c.frames(); ++f)
            if (foot.in_contact[f]) (f >= first && f <= last ? inside : outside).push_back(foot.speed[f]);
    q.foot_skate_window = detail::summarise_skate(std::move(inside)).median;
    q.foot_skate_clips = detail::summarise_skate(std::move(outside)).median;
    q.foot_skate_ratio = q.foot_skate_window > 0 && q.foot_skate_clips > 0 ? q.foot_skate_window / q.foot_skate_clips : T(0);
    return q;
}

}  // namespace anima
