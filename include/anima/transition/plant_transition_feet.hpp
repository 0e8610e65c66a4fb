// Feet planted through a transition, in two stages:
//   1. (on request) the root's horizontal path through the window is taken
//      from the feet on the ground (root_from_feet): each frame the root moves against the
//      motion of the feet in contact relative to it, so a foot on the ground
//      stays where it is; the frames after the window move with its end;
//   2. what the root could not take out (two feet that disagree, the ramps
//      at the window's ends) is taken out by IK on the legs: a foot on the
//      ground when A hands over and still on it in B (or in the frames
//      between) is held where it is, and the correction is released over
//      the swing that follows (ik/plant_feet.hpp).
// Works on any joined clip: the variable-timing transition and the cut,
// crossfade and inertialization baselines alike.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/ik/plant_feet.hpp>
#include <anima/motion/contacts.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/transition/variable_timing_transition.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

namespace anima {

template <class T>
struct transition_feet_params {
    plant_feet_params<T> planting;  ///< stage 2, the legs' IK (contacts by height alone)
    /// Stage 1: the root's horizontal path through the window from the feet
    /// on the ground. Off by default: it takes most of the skate out, but
    /// where the blended legs slow down toward B's pose while B's root moves
    /// on (a run, an ease-out) the root slows and speeds up again, and its
    /// peak acceleration can pass the clips' own (docs/transitions.md).
    /// false: the path as the transition made it, and the legs alone hold
    /// the feet.
    bool root_from_feet = false;
    /// The feet's root motion takes over from the transition's within this
    /// long of either end of the window (a smoothstep), but within no more
    /// than root_ramp_fraction of the window: the root's velocity turns from
    /// A's into the feet's and from there into B's without a jolt.
    T root_ramp_seconds = T(0.05);
    T root_ramp_fraction = T(0.125);
};

namespace detail {

/// Each step's horizontal root motion through the window (into frames
/// window.first + 1 .. window.last) as the feet on the ground give it:
/// against the motion, relative to the root, of each foot in contact, a
/// foot's motion that of its points weighted toward the lowest (softly, over
/// 1% of body height: a foot rolls from heel to toe), a foot counting fully
/// below height_on and not at all above height_off. What the feet do not
/// carry of a step is the recorded step.
template <class T>
std::vector<Eigen::Matrix<T, 3, 1>> steps_from_feet(const clip<T>& c, frame_interval window,
                                                    const contact_set<T>& contacts, const contact_params<T>& params) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    const auto& sk = c.skeleton();
    const auto axis = static_cast<Eigen::Index>(contacts.up.axis);
    const T sign = contacts.up.sign < 0 ? T(-1) : T(1), softness = T(0.01) * contacts.body_height;
    std::vector<std::vector<foot_point>> points(contacts.feet.size());
    for (std::size_t i = 0; i < points.size(); ++i) points[i] = foot_points_of(sk, contacts.feet[i].joint);
    global_pose<T> pose;
    const auto relative = [&](std::size_t f, std::vector<std::vector<vec3>>& out) {  // foot points - root
        forward_kinematics(c, f, pose);
        out.resize(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) {
            out[i].clear();
            for (const foot_point p : points[i]) out[i].push_back(foot_point_position(sk, pose, p) - pose.positions[0]);
        }
    };
    const auto weight = [&](std::size_t i, std::size_t f) {
        const T rise = contacts.feet[i].rise[f];
        return std::clamp((params.height_off - rise) / (params.height_off - params.height_on), T(0), T(1));
    };
    std::vector<vec3> steps;
    std::vector<std::vector<vec3>> before, now;
    relative(window.first, before);
    for (std::size_t f = window.first + 1; f <= window.last; ++f) {
        relative(f, now);
        vec3 moved = vec3::Zero();
        T carried = T(0);
        for (std::size_t i = 0; i < points.size(); ++i) {
            const T w = std::min(weight(i, f - 1), weight(i, f));
            if (!(w > T(0))) continue;
            T lowest = std::numeric_limits<T>::infinity();
            for (const vec3& p : before[i]) lowest = std::min(lowest, sign * p[axis]);
            vec3 foot = vec3::Zero();
            T total = T(0);
            for (std::size_t p = 0; p < before[i].size(); ++p) {
                const T k = std::exp(-(sign * before[i][p][axis] - lowest) / softness);
                foot += k * (now[i][p] - before[i][p]);
                total += k;
            }
            moved += w * foot / total;
            carried += w;
        }
        vec3 step = -moved / std::max(T(1), carried) +
                    std::max(T(0), T(1) - carried) * vec3(c.root_position(f) - c.root_position(f - 1));
        step[axis] = T(0);
        steps.push_back(step);
        std::swap(before, now);
    }
    return steps;
}

/// Stage 1 of plant_transition_feet on frames window.first .. window.last
/// (A's last and B's first) of c: the root's horizontal path from
/// steps_from_feet, ramped in and out (transition_feet_params), heights as
/// they are; the frames after the window move with its end.
template <class T>
void root_from_feet(clip<T>& c, frame_interval window, const contact_set<T>& contacts,
                    const transition_feet_params<T>& params) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    if (window.last <= window.first || window.last >= c.frames() || c.skeleton().translation_slot(0) < 0 ||
        contacts.feet.empty())
        return;
    const auto axis = static_cast<Eigen::Index>(contacts.up.axis);
    const std::vector<vec3> steps = steps_from_feet(c, window, contacts, params.planting.contacts);
    const T span = static_cast<T>(window.last - window.first);
    const T ramp = std::min(span * params.root_ramp_fraction, params.root_ramp_seconds / c.frame_time());
    vec3 root = c.root_position(window.first);
    std::vector<vec3> path;
    for (std::size_t f = window.first + 1; f <= window.last; ++f) {
        const T from_end = std::min(static_cast<T>(f - window.first) - T(0.5), static_cast<T>(window.last - f) + T(0.5));
        const T x = ramp > T(0) ? std::clamp(from_end / ramp, T(0), T(1)) : T(1), w = x * x * (T(3) - T(2) * x);
        vec3 recorded = c.root_position(f) - c.root_position(f - 1);
        recorded[axis] = T(0);
        root += w * steps[f - window.first - 1] + (T(1) - w) * recorded;
        root[axis] = c.root_position(f)[axis];
        path.push_back(root);
    }
    const vec3 shift = path.back() - c.root_position(window.last);
    for (std::size_t f = window.first + 1; f < window.last; ++f) c.set_root_position(f, path[f - window.first - 1]);
    for (std::size_t f = window.last; f < c.frames(); ++f) c.set_root_position(f, c.root_position(f) + shift);
}

}  // namespace detail

/// The joined clip with its feet planted through the transition (frames
/// start_frame..end_frame): the root's horizontal path from the feet on the
/// ground when params.root_from_feet asks for it, then the contact runs that reach the
/// window held by IK (params.planting, whose ranges are set here). Contacts
/// are found on the joined clip with params.planting.contacts (height alone
/// by default, so a foot sliding on the ground through the window counts as
/// planted). A figure without feet to plant (has_feet_to_plant) comes back
/// as it is.
template <class T>
joined_clip<T> plant_transition_feet(const joined_clip<T>& joined, transition_feet_params<T> params = {}) {
    check_non_negative("anima::plant_transition_feet", "root_ramp_seconds", params.root_ramp_seconds);
    check_in_range("anima::plant_transition_feet", "root_ramp_fraction", params.root_ramp_fraction, T(0), T(0.5));
    joined_clip<T> out = joined;
    const frame_interval window{joined.start_frame, joined.end_frame};
    if (!has_feet_to_plant(out.motion, params.planting)) return out;
    if (params.root_from_feet)
        detail::root_from_feet(out.motion, window, find_contacts(out.motion, params.planting.contacts), params);
    plant_feet_in_ranges(out.motion, {window}, std::move(params.planting), {});
    return out;
}

}  // namespace anima
