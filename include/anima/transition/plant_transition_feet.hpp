// Feet planted through a transition, in two stages:
//   1. the root's horizontal path through the window is taken from the feet
//      on the ground (root_from_feet): each frame the root moves against the
//      motion of the feet in contact relative to it, so a foot on the ground
//      stays where it is, but never accelerating beyond the clips' own; the
//      frames after the window move with its end;
//   2. what the root could not take out (two feet that disagree, the ramps
//      at the window's ends, the acceleration limit) is taken out by IK on
//      the legs: a foot on the
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
    /// on the ground. false: the path as the transition made it, and the
    /// legs alone hold the feet.
    bool root_from_feet = true;
    /// The feet's root motion takes over from the transition's within this
    /// long of either end of the window (a smoothstep), but within no more
    /// than root_ramp_fraction of the window: the root's velocity turns from
    /// A's into the feet's and from there into B's without a jolt.
    T root_ramp_seconds = T(0.05);
    T root_ramp_fraction = T(0.125);
    /// The root's horizontal acceleration through the window stays within
    /// this quantile of the joined clip's own outside it (after any rest-pose
    /// lead-in), on each horizontal axis: where the blended legs slow down
    /// toward B's pose while B's root moves on, the feet would have the root
    /// stop and start again; the legs' IK takes the rest.
    T root_acceleration_quantile = T(0.95);
    /// A band for the root's horizontal speed through the window: along the
    /// way A's last step and B's first both travel (when within 60 degrees
    /// of each other) at least band x the slower end's speed, and overall at
    /// most the faster end's / band; the legs' IK takes the rest. The blended
    /// legs step slower than a runner moves, and the feet alone stall it
    /// mid-stride: without a band the root's slowest speed in the window was
    /// 0.08-0.2 of the slower end's on runs and walks into runs and walks
    /// (measure_transition's root_speed_ratio). The default, 0.5 (chosen on
    /// the evaluation's tuning pairs, docs/transitions.md), keeps it about
    /// half; the price is skate where the legs cannot keep up (run_cmu_02_03
    /// into a walk: 0.14x to 1.49x the clips' own). 0: no band, the feet first.
    T root_speed_band = T(0.5);
};

namespace detail {

/// Each step's horizontal root motion through the window (into frames
/// window.first + 1 .. window.last) as the feet on the ground give it:
/// against the motion, relative to the root, of each foot in contact, a
/// foot's motion that of its points weighted toward the lowest (softly, over
/// 1% of body height: a foot rolls from heel to toe), a foot counting fully
/// below height_on and not at all above height_off. Two feet that disagree
/// share the difference, but a foot d faster than the slowest low foot (a
/// swing that skims the floor, or a foot the blend drags; horizontal speeds
/// in body heights per second) counts at most slide_speed / (2 d) as much:
/// an equal share would drag the slowest at about d / 2, and past
/// slide_speed the legs' IK takes a foot for stepping and lets it go. What
/// the feet do not carry of a step is the recorded step.
template <class T>
std::vector<Eigen::Matrix<T, 3, 1>> steps_from_feet(const clip<T>& c, frame_interval window,
                                                    const contact_set<T>& contacts, const contact_params<T>& params,
                                                    T slide_speed) {
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
    const T band = params.height_off - params.height_on;  // may be 0: a foot is then down or up
    const auto low = [&](std::size_t i, std::size_t f) {
        const T rise = contacts.feet[i].rise[f];
        if (!(band > T(0))) return rise <= params.height_on ? T(1) : T(0);
        return std::clamp((params.height_off - rise) / band, T(0), T(1));
    };
    const auto foot_motion = [&](const std::vector<vec3>& from, const std::vector<vec3>& to) {
        T lowest = std::numeric_limits<T>::infinity();
        for (const vec3& p : from) lowest = std::min(lowest, sign * p[axis]);
        vec3 foot = vec3::Zero();
        T total = T(0);
        for (std::size_t p = 0; p < from.size(); ++p) {
            const T k = std::exp(-(sign * from[p][axis] - lowest) / softness);
            foot += k * (to[p] - from[p]);
            total += k;
        }
        return vec3(foot / total);
    };
    std::vector<T> weights(points.size());
    std::vector<vec3> motion(points.size());
    std::vector<vec3> steps;
    std::vector<std::vector<vec3>> before, now;
    relative(window.first, before);
    for (std::size_t f = window.first + 1; f <= window.last; ++f) {
        relative(f, now);
        std::size_t slowest = points.size();
        for (std::size_t i = 0; i < points.size(); ++i) {
            weights[i] = std::min(low(i, f - 1), low(i, f));
            if (!(weights[i] > T(0))) continue;
            motion[i] = foot_motion(before[i], now[i]);
            if (slowest == points.size() || contacts.feet[i].speed[f] < contacts.feet[slowest].speed[f]) slowest = i;
        }
        // A foot d faster than the slowest low foot counts at most
        // slide_speed / (2 d) as much.
        for (std::size_t i = 0; i < points.size(); ++i) {
            if (!(weights[i] > T(0))) continue;  // then there is a slowest
            const T faster = contacts.feet[i].speed[f] - contacts.feet[slowest].speed[f];
            if (faster > T(0)) weights[i] *= std::min(T(1), slide_speed / (T(2) * faster));
        }
        vec3 moved = vec3::Zero();
        T carried = T(0);
        for (std::size_t i = 0; i < points.size(); ++i)
            if (weights[i] > T(0)) {
                moved += weights[i] * motion[i];
                carried += weights[i];
            }
        vec3 step = -moved / std::max(T(1), carried) +
                    std::max(T(0), T(1) - carried) * vec3(c.root_position(f) - c.root_position(f - 1));
        step[axis] = T(0);
        steps.push_back(step);
        std::swap(before, now);
    }
    return steps;
}

/// The largest change of a horizontal step from one frame to the next (file
/// units per frame, per axis) that keeps the root's acceleration within the
/// q-quantile of c's own outside the window and after its first `skip`
/// frames (a rest-pose lead-in). Infinity when there is nothing to measure.
template <class T>
T root_step_change_limit(const clip<T>& c, frame_interval window, std::size_t skip, signed_axis up, T q) {
    const auto axis = static_cast<Eigen::Index>(up.axis);
    std::vector<T> changes;
    for (std::size_t f = skip + 2; f < c.frames(); ++f) {
        if (f + 1 >= window.first && f <= window.last + 1) continue;
        Eigen::Matrix<T, 3, 1> d = c.root_position(f) - T(2) * c.root_position(f - 1) + c.root_position(f - 2);
        d[axis] = T(0);
        changes.push_back(d.norm());
    }
    if (changes.empty()) return std::numeric_limits<T>::infinity();
    return quantile(std::move(changes), q) / std::sqrt(T(2));
}

/// Stage 1 of plant_transition_feet on frames window.first .. window.last
/// (A's last and B's first) of c: the root's horizontal path from
/// steps_from_feet, ramped in and out (transition_feet_params), each step
/// differing from the one before by at most `limit` on each horizontal axis
/// (forward from A's last step, then back from B's first), heights as they
/// are; the frames after the window move with its end.
template <class T>
void root_from_feet(clip<T>& c, frame_interval window, const contact_set<T>& contacts,
                    const transition_feet_params<T>& params, T limit) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    if (window.last <= window.first || window.last >= c.frames() || c.skeleton().translation_slot(0) < 0 ||
        contacts.feet.empty())
        return;
    const auto axis = static_cast<Eigen::Index>(contacts.up.axis);
    const auto recorded = [&](std::size_t f) {
        vec3 s = c.root_position(f) - c.root_position(f - 1);
        s[axis] = T(0);
        return s;
    };
    const T slide_speed = params.planting.slide_fraction * contacts.fast_foot_speed;
    std::vector<vec3> steps = steps_from_feet(c, window, contacts, params.planting.contacts, slide_speed);
    const T span = static_cast<T>(window.last - window.first);
    const T ramp = std::min(span * params.root_ramp_fraction, params.root_ramp_seconds / c.frame_time());
    for (std::size_t f = window.first + 1; f <= window.last; ++f) {
        const T from_end = std::min(static_cast<T>(f - window.first) - T(0.5), static_cast<T>(window.last - f) + T(0.5));
        const T w = T(1) - fade_out(ramp > T(0) ? from_end / ramp : T(1));  // eased in, as plant_feet catches a foot
        vec3& step = steps[f - window.first - 1];
        step = w * step + (T(1) - w) * recorded(f);
    }
    const vec3 before = window.first >= 1 ? recorded(window.first) : steps.front();
    const vec3 after = window.last + 1 < c.frames() ? recorded(window.last + 1) : steps.back();
    if (params.root_speed_band > T(0)) {
        // Speed along the way the two ends travel, at least band x the slower
        // end's; overall at most the faster end's / band.
        const T slow = params.root_speed_band * std::min(before.norm(), after.norm());
        const T fast = std::max(before.norm(), after.norm()) / params.root_speed_band;
        // The floor only where both ends travel the same way (within 60
        // degrees): a turn or a start from a dance has no one way to keep.
        const T agree = before.normalized().dot(after.normalized());
        const vec3 way = before.normalized() + after.normalized();
        const vec3 along = agree > T(0.5) ? vec3(way.normalized()) : vec3::Zero();
        for (vec3& s : steps) {
            const T ahead = s.dot(along);
            if (ahead < slow) s += (slow - ahead) * along;
            const T n = s.norm();
            if (n > fast) s *= fast / n;
        }
    }
    if (std::isfinite(limit)) {
        for (Eigen::Index k = 0; k < 3; ++k) {
            if (k == axis) continue;
            T last = before[k];
            for (vec3& s : steps) last = s[k] = std::clamp(s[k], last - limit, last + limit);
            last = after[k];
            for (auto s = steps.rbegin(); s != steps.rend(); ++s) last = (*s)[k] = std::clamp((*s)[k], last - limit, last + limit);
        }
    }
    vec3 root = c.root_position(window.first);
    std::vector<vec3> path;
    for (std::size_t f = window.first + 1; f <= window.last; ++f) {
        root += steps[f - window.first - 1];
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
/// ground (params.root_from_feet), then the contact runs that reach the
/// window held by IK (params.planting, whose ranges are set here). Contacts
/// are found on the joined clip with params.planting.contacts (height alone
/// by default, so a foot sliding on the ground through the window counts as
/// planted). A figure without feet to plant (has_feet_to_plant) comes back
/// as it is.
template <class T>
joined_clip<T> plant_transition_feet(const joined_clip<T>& joined, transition_feet_params<T> params = {}) {
    detail::check_joined_window(joined, "anima::plant_transition_feet");
    check_non_negative("anima::plant_transition_feet", "root_ramp_seconds", params.root_ramp_seconds);
    check_in_range("anima::plant_transition_feet", "root_ramp_fraction", params.root_ramp_fraction, T(0), T(0.5));
    check_in_range("anima::plant_transition_feet", "root_acceleration_quantile", params.root_acceleration_quantile, T(0),
                   T(1));
    check_in_range("anima::plant_transition_feet", "root_speed_band", params.root_speed_band, T(0), T(1));
    joined_clip<T> out = joined;
    const frame_interval window{joined.start_frame, joined.end_frame};
    if (!has_feet_to_plant(out.motion, params.planting)) return out;
    if (params.root_from_feet) {
        const auto contacts = find_contacts(out.motion, params.planting.contacts);
        const T limit = detail::root_step_change_limit(out.motion, window, contacts.lead_in, contacts.up,
                                                       params.root_acceleration_quantile);
        detail::root_from_feet(out.motion, window, contacts, params, limit);
    }
    plant_feet_in_ranges(out.motion, {window}, std::move(params.planting), {});
    return out;
}

}  // namespace anima
