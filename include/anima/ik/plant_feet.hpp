// Foot planting: a foot in ground contact stops sliding. Over each stance
// (the frames of a contact run where the foot is not stepping: near the
// ground, a swing skims the floor) the foot is moved back by the horizontal
// distance its contact point (the stillest of its points near the ground:
// heel, ball or toe as the foot rolls) has slid since the stance began, so
// the roll of a step is kept and only the slide is taken out; after the
// stance the correction fades out over the swing, where a moved foot is not
// seen as skate. The legs are solved with clip-level IK
// (solve_clip_ik): warm-started frame to frame and pulled toward the
// recorded pose, so nothing but the legs of planted feet changes.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/ik/clip_ik.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/solve.hpp>
#include <anima/ik/step_rules.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/contacts.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/speed_limits.hpp>
#include <anima/rotation/quaternion.hpp>
#include <anima/rotation/slerp.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace anima {

template <class T>
struct plant_feet_params {
    /// How contacts are found when plant_feet is not given them. Height
    /// alone decides by default: a foot sliding on the ground is what is to
    /// be planted, and the speed test would call it lifted.
    contact_params<T> contacts = [] {
        contact_params<T> p;
        p.use_speed = false;
        return p;
    }();
    /// Plant only the contact runs that share a frame with one of these
    /// (a transition's window, the frames around a seam); empty: every run.
    std::vector<frame_interval> ranges;
    /// The correction left at the end of a run fades out over this much of
    /// the swing that follows (at most the whole gap to the foot's next run).
    T release_seconds = T(0.2);
    /// A foot is held at most this far (body heights) from where its
    /// recording puts it: past that it is dragged along, since a leg asked
    /// to reach further would straighten or flip instead.
    T max_correction = T(0.1);
    /// A foot that arrives sliding is caught over this long (the correction
    /// eases in), not in one frame, which would jerk the knee.
    T catch_seconds = T(0.05);
    /// A foot near the ground that moves faster than this fraction of the
    /// clip's fast foot speed (the 95th percentile of its foot points'
    /// speeds) is stepping, as a walk's swing skims the floor, not sliding:
    /// the plant ends there and starts again where the foot slows down.
    /// Holding it would drag the step back by max_correction.
    T slide_fraction = T(0.4);
    /// The fastest each joint may turn, rad/s, one entry per joint of the
    /// clip; empty: the clip's own fastest (clip_speed_limits). Where a leg
    /// solved for a held foot would turn faster (the body blended away over a
    /// planted foot at a seam), it follows at this speed instead, and the
    /// foot gives a little. Only joints that planting changed are limited:
    /// 0 keeps such a joint still, infinity leaves it free.
    std::vector<T> joint_speed_limits;
    /// Weight of the foot's recorded world orientation against its position
    /// (a length, in body heights): the foot keeps its roll.
    T orientation_weight = T(0.05);
    /// Per-frame settings of the damped least squares solve (adaptive
    /// damping: steady near the straight-leg singularity), pose pull, warm
    /// start. One solver only, so a texture or transition that plants feet
    /// does not compile every IK solver.
    clip_ik_params<T> ik;
};

template <class T>
struct plant_feet_result {
    clip<T> planted;            ///< the input with the planted feet's legs solved again
    contact_set<T> contacts;    ///< the contacts used
    std::size_t runs = 0;       ///< contact runs planted
    std::size_t frames = 0;     ///< frames solved (runs and releases)
    T largest_error = T(0);     ///< largest foot position error left by the IK (before the speed limits), file units
    T largest_correction = T(0);  ///< largest horizontal correction asked of a foot, file units
};

namespace detail {

/// A foot has a leg to move when it has a parent and a grandparent (knee
/// and hip, or whatever the skeleton calls them).
template <class T>
bool has_leg(const skeleton<T>& sk, std::size_t foot) {
    const int knee = sk[foot].parent;
    return knee >= 0 && sk[static_cast<std::size_t>(knee)].parent >= 0;
}

/// Whether run r shares a frame with any of the ranges (all when empty).
inline bool touches(const frame_interval& r, const std::vector<frame_interval>& ranges) {
    if (ranges.empty()) return true;
    for (const auto& g : ranges)
        if (r.first <= g.last && g.first <= r.last) return true;
    return false;
}

/// A tree whose only DOFs are the hips, knees and feet of the feet that
/// have a leg; everything else is fixed.
template <class T>
kinematic_tree<T> legs_tree(const skeleton<T>& sk, const contact_set<T>& contacts) {
    kinematic_tree<T> tree(sk);
    for (std::size_t j = 0; j < sk.size(); ++j)
        if (tree.kind(j) != ik_joint_kind::fixed) tree.set_fixed(j);
    for (const auto& foot : contacts.feet) {
        if (!has_leg(sk, foot.joint)) continue;
        const auto knee = static_cast<std::size_t>(sk[foot.joint].parent);
        const auto hip = static_cast<std::size_t>(sk[knee].parent);
        for (const std::size_t j : {hip, knee, foot.joint})
            if (sk.has_rotation_channels(j)) tree.set_ball(j);
    }
    return tree;
}

/// Per frame with a correction: each corrected foot's recorded position
/// moved by it (kept within the leg's reach) and its recorded orientation.
template <class T>
std::vector<frame_goals<T>> leg_goals(const skeleton<T>& sk, const contact_set<T>& contacts,
                                      const std::vector<global_pose<T>>& poses,
                                      const std::vector<std::vector<std::optional<Eigen::Matrix<T, 3, 1>>>>& correction,
                                      T orientation_weight) {
    using vector3 = Eigen::Matrix<T, 3, 1>;
    const T orientation_scale = orientation_weight * contacts.body_height;
    std::vector<frame_goals<T>> goals;
    for (std::size_t f = 0; f < poses.size(); ++f) {
        frame_goals<T> g{f, {}};
        for (std::size_t i = 0; i < contacts.feet.size(); ++i) {
            if (!correction[f][i]) continue;
            const std::size_t j = contacts.feet[i].joint;
            // A target the leg cannot reach is brought within reach along
            // the line from the hip: a leg asked past straight flips its knee.
            const auto knee = static_cast<std::size_t>(sk[j].parent);
            const auto hip = static_cast<std::size_t>(sk[knee].parent);
            const vector3& hip_at = poses[f].positions[hip];
            vector3 target = poses[f].positions[j] + *correction[f][i];
            const T reach_leg = std::max(T(0.98) * (sk[knee].offset.norm() + sk[j].offset.norm()),
                                         (poses[f].positions[j] - hip_at).norm());
            if ((target - hip_at).norm() > reach_leg)
                target = hip_at + (target - hip_at) * (reach_leg / (target - hip_at).norm());
            ik_goal<T> goal;
            goal.joint = j;
            goal.kind = orientation_scale > T(0) ? ik_goal_kind::pose : ik_goal_kind::position;
            goal.position = target;
            goal.orientation = poses[f].orientations[j];
            if (orientation_scale > T(0)) goal.orientation_scale = orientation_scale;
            g.goals.push_back(goal);
        }
        if (!g.goals.empty()) goals.push_back(std::move(g));
    }
    return goals;
}

/// The stillest of a foot's points near the ground in measured frame f:
/// the one carrying the weight (heel, ball or toe as the foot rolls), whose
/// slide foot_skate measures and plant_feet takes out. Its index and speed
/// (the largest finite value when no point is near the ground).
template <class T>
std::pair<std::size_t, T> weight_point(const foot_points<T>& fp, std::size_t f, T height_off) {
    const std::size_t row = f * fp.points;
    std::size_t best = 0;
    T best_speed = std::numeric_limits<T>::infinity();
    for (std::size_t q = 0; q < fp.points; ++q) {
        const T speed = fp.rise[row + q] <= height_off ? fp.speed[row + q] : std::numeric_limits<T>::max();
        if (speed < best_speed) {
            best_speed = speed;
            best = q;
        }
    }
    return {best, best_speed};
}

/// Smooth fade from 1 (s = 0) to 0 (s = 1).
template <class T>
T fade_out(T s) {
    s = std::clamp(s, T(0), T(1));
    return T(1) - s * s * (T(3) - T(2) * s);
}

/// Joints whose rotations planting changed turn no faster than `limits`
/// (rad/s): each frame's rotation moves from the previous frame's toward the
/// solved one by at most the limit's angle.
template <class T>
void limit_joint_speeds(clip<T>& planted, const clip<T>& recorded, const std::vector<T>& limits) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    for (std::size_t j = 0; j < planted.joints(); ++j) {
        bool changed = false;
        for (std::size_t f = 0; f < planted.frames() && !changed; ++f)
            changed = planted.rotation(f, j).coeffs() != recorded.rotation(f, j).coeffs();
        // A step at the limit itself is the recording's fastest: rounding in
        // limit * frame_time must not change it.
        const T step = limits[j] * planted.frame_time() * (T(1) + T(16) * std::numeric_limits<T>::epsilon());
        if (!changed || !(step < std::numeric_limits<T>::infinity())) continue;
        auto previous = planted.rotation(0, j);
        for (std::size_t f = 1; f < planted.frames(); ++f) {
            const auto target = planted.rotation(f, j);
            const T angle = angle_between(previous, target);
            if (angle > step) {
                previous = slerp(previous, target, step / angle);
                planted.set_rotation(f, j, previous);
            } else {
                previous = target;
            }
        }
    }
}

/// plant_feet's argument checks: settings in range, contacts of this clip.
template <class T>
void check_plant_feet(const clip<T>& c, const contact_set<T>& contacts, const plant_feet_params<T>& params) {
    const char* who = "anima::plant_feet";
    check_non_negative(who, "release_seconds", params.release_seconds);
    check_non_negative(who, "orientation_weight", params.orientation_weight);
    check_non_negative(who, "max_correction", params.max_correction);
    check_non_negative(who, "catch_seconds", params.catch_seconds);
    check_positive(who, "slide_fraction", params.slide_fraction);
    if (!params.joint_speed_limits.empty()) {
        if (params.joint_speed_limits.size() != c.joints())
            throw invalid_argument(std::string(who) + ": joint_speed_limits has " +
                                   std::to_string(params.joint_speed_limits.size()) + " entries, the clip " +
                                   std::to_string(c.joints()) + " joints");
        for (const T limit : params.joint_speed_limits)
            check_argument(limit >= T(0), who, "a joint speed limit", "at least 0 (infinity: free)", limit);
    }
    for (const auto& foot : contacts.feet) {
        if (foot.in_contact.size() != c.frames())
            throw invalid_argument(std::string(who) + ": the contacts of foot '" + foot.name + "' cover " +
                                   std::to_string(foot.in_contact.size()) + " frames, the clip has " +
                                   std::to_string(c.frames()));
        if (foot.joint >= c.joints())
            throw invalid_argument(std::string(who) + ": foot '" + foot.name + "' is joint " +
                                   std::to_string(foot.joint) + ", the skeleton has " + std::to_string(c.joints()));
    }
}

/// A clip whose measured frames lie within one foot-speed window (+-1/60 s
/// around the middle frame reaches both ends) cannot tell a stance from a
/// step: every point's speed is its mean over the clip. When a run would be
/// planted, that is an error (a frame time in the wrong unit, most often),
/// not a silent "nothing to plant". A clip of fewer than 8 measured frames
/// is short at any frame time and passes as before: there the window says
/// more about the clip's length than about its frame time.
template <class T>
void check_speed_window(const clip<T>& c, const contact_set<T>& contacts, const std::vector<frame_interval>& ranges) {
    const std::size_t measured = c.frames() - std::min(c.frames(), contacts.lead_in);
    const std::size_t half = speed_half_window(c.frame_time());
    if (measured < 8 || 2 * half < measured - 1) return;
    for (const auto& foot : contacts.feet) {
        if (!has_leg(c.skeleton(), foot.joint)) continue;
        for (const auto& run : foot.contacts)
            if (touches(run, ranges))
                fail_argument("anima::plant_feet", "the clip's frame time",
                              "long enough that its " + std::to_string(measured) +
                                  " measured frames outlast the +-1/60 s foot-speed window (a stance cannot be "
                                  "told from a step within one; is the frame time in seconds?)",
                              c.frame_time());
    }
}

/// plant_feet on checked arguments. `given`: measure_feet of the contacts'
/// feet from their lead-in on, when the caller has it (find_contacts
/// measures them too), else null.
template <class T>
plant_feet_result<T> plant_feet_checked(const clip<T>& c, const contact_set<T>& contacts,
                                        const plant_feet_params<T>& params, const std::vector<foot_points<T>>* given) {
    using vector3 = Eigen::Matrix<T, 3, 1>;
    const auto& sk = c.skeleton();
    const std::size_t frames = c.frames();
    plant_feet_result<T> out{c, contacts, 0, 0, T(0), T(0)};
    if (frames < 2 || contacts.feet.empty()) return out;
    check_speed_window(c, contacts, params.ranges);

    // Recorded world positions of every joint and End Site, and orientations.
    std::vector<std::vector<vector3>> points(frames);
    std::vector<global_pose<T>> poses(frames);
    for (std::size_t f = 0; f < frames; ++f) {
        forward_kinematics(c, f, poses[f]);
        points[f] = end_site_positions(sk, poses[f]);
    }
    const auto up = static_cast<Eigen::Index>(contacts.up.axis);
    const auto flat = [&](vector3 v) {
        v[up] = T(0);
        return v;
    };
    // A foot point is the joint's position or its End Site's.
    const auto point = [&](std::size_t f, foot_point p) -> const vector3& {
        return p.end_site ? points[f][p.joint] : poses[f].positions[p.joint];
    };
    const T reach = params.max_correction * contacts.body_height;
    const std::size_t catching = detail::frames_spanning(params.catch_seconds, c.frame_time(), T(1e-6));
    const std::size_t release = detail::frames_spanning(params.release_seconds, c.frame_time(), T(1e-6));

    // Per frame, per foot: the horizontal correction asked (empty: none).
    std::vector<std::vector<std::optional<vector3>>> correction(
        frames, std::vector<std::optional<vector3>>(contacts.feet.size()));
    // The foot's points as foot_skate sees them: each point's rise above its
    // own standing height and its speed, to pick the one that carries the
    // weight in each frame.
    std::vector<foot_points<T>> own;
    if (!given) {
        std::vector<std::size_t> foot_joints;
        for (const auto& foot : contacts.feet) foot_joints.push_back(foot.joint);
        own = detail::measure_feet(c, foot_joints, contacts.lead_in, contacts, params.contacts);
        given = &own;
    }
    const std::vector<foot_points<T>>& measured = *given;
    const T slide_speed = params.slide_fraction * detail::fast_foot_speed(measured);
    for (std::size_t i = 0; i < contacts.feet.size(); ++i) {
        const auto& foot = contacts.feet[i];
        if (!detail::has_leg(sk, foot.joint)) continue;
        const auto foot_points = foot_points_of(sk, foot.joint);  // in measure_feet's order
        const auto& fp = measured[i];
        // The stretches of the touched runs where the foot is not stepping,
        // and in each of their frames the point that carries the weight.
        std::vector<frame_interval> stances;
        std::vector<std::size_t> carrier(frames);
        for (const auto& run : foot.contacts) {
            if (!detail::touches(run, params.ranges)) continue;
            ++out.runs;
            std::vector<bool> slow(run.last - run.first + 1);
            for (std::size_t f = std::max(run.first, contacts.lead_in); f <= run.last; ++f) {
                const auto [q, speed] = detail::weight_point(fp, f - contacts.lead_in, params.contacts.height_off);
                carrier[f] = q;
                slow[f - run.first] = speed < slide_speed;
            }
            for (const auto& s : true_runs(slow)) stances.push_back({run.first + s.first, run.first + s.last});
        }
        for (std::size_t r = 0; r < stances.size(); ++r) {
            vector3 slid = vector3::Zero();
            correction[stances[r].first][i] = vector3::Zero();
            for (std::size_t f = stances[r].first + 1; f <= stances[r].last; ++f) {
                const foot_point bearing = foot_points[carrier[f]];
                slid += flat(point(f, bearing) - point(f - 1, bearing));
                if (slid.norm() > reach) slid *= reach / slid.norm();
                const std::size_t k = f - stances[r].first;
                const T ease = k >= catching ? T(1) : T(1) - detail::fade_out(static_cast<T>(k) / static_cast<T>(catching));
                correction[f][i] = vector3(-slid * ease);
                out.largest_correction = std::max(out.largest_correction, slid.norm());
            }
            // Fade the last correction out over the swing to the next stance.
            const std::size_t next = r + 1 < stances.size() ? stances[r + 1].first : frames;
            const std::size_t span = std::min(release, next - stances[r].last - 1);
            for (std::size_t k = 1; k <= span; ++k)
                correction[stances[r].last + k][i] =
                    vector3(-slid * detail::fade_out(static_cast<T>(k) / static_cast<T>(span + 1)));
        }
    }

    const kinematic_tree<T> tree = detail::legs_tree(sk, contacts);
    const auto goals = detail::leg_goals(sk, contacts, poses, correction, params.orientation_weight);
    if (goals.empty()) return out;
    typename damped_least_squares<T>::params dls;
    dls.adaptive = true;
    const damped_least_squares<T> rule(dls);
    auto solved = solve_clip_ik(
        tree, c, goals,
        [&rule](const kinematic_tree<T>& t, const std::vector<ik_goal<T>>& gs, const ik_vector<T>& start,
                const ik_params<T>& p) { return solve_ik(t, gs, start, rule, p); },
        params.ik);
    out.planted = std::move(solved.edited);
    detail::limit_joint_speeds(out.planted, c,
                               params.joint_speed_limits.empty() ? clip_speed_limits(c).joint : params.joint_speed_limits);
    out.frames = solved.frames.size();
    out.largest_error = solved.largest_error;
    return out;
}

}  // namespace detail

/// The clip with feet in contact planted, using the given contacts (found on
/// this clip, or built by the caller). A foot too close to the root to have
/// a leg (it needs a parent and a grandparent) is left as it is. Throws
/// anima::invalid_argument for contacts of another clip (frame count or
/// joints) or bad parameters, and for a clip of 8 or more frames whose
/// frame time puts them all within one +-1/60 s foot-speed window, where a
/// stance cannot be told from a step (a frame time in the wrong unit).
template <class T>
plant_feet_result<T> plant_feet(const clip<T>& c, const contact_set<T>& contacts, const plant_feet_params<T>& params) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    detail::check_plant_feet(c, contacts, params);
    return detail::plant_feet_checked(c, contacts, params, static_cast<const std::vector<detail::foot_points<T>>*>(nullptr));
}

/// The clip with feet in contact planted, contacts found on the clip with
/// params.contacts (find_contacts' errors: no feet, no height). The feet
/// are measured once, for both.
template <class T>
plant_feet_result<T> plant_feet(const clip<T>& c, const plant_feet_params<T>& params = {}) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    std::vector<detail::foot_points<T>> measured;
    const contact_set<T> contacts = detail::find_contacts_measured(c, params.contacts, measured);
    detail::check_plant_feet(c, contacts, params);
    return detail::plant_feet_checked(c, contacts, params, &measured);
}

/// Whether plant_feet(c, params) finds feet to plant: the clip has frames,
/// its figure a height along the up axis, and feet (named in
/// params.contacts.feet, or found by find_feet). For pipelines that plant
/// by default and must pass over a prop or a figure without legs.
template <class T>
bool has_feet_to_plant(const clip<T>& c, const plant_feet_params<T>& params = {}) {
    if (c.frames() < 2 || !has_feet(c, params.contacts)) return false;
    if (!params.contacts.feet.empty()) return true;
    const signed_axis up = params.contacts.up ? *params.contacts.up : guess_up_axis(c.skeleton()).up;
    for (const std::size_t j : find_feet(c.skeleton(), up))
        if (detail::has_leg(c.skeleton(), j)) return true;
    return false;
}

/// plant_feet on the contact runs of `c` that reach `ranges` (in place of
/// params.ranges), the legs within `limits` when params sets none: the
/// speeds of the clip that `c` was made from (a texture's or a played
/// stream's source), which the stitched clip's own fastest, slide included,
/// would overstate. `c` is left as it is, and 0 returned, when there are no
/// ranges or no feet to plant; otherwise the number of runs planted.
template <class T>
std::size_t plant_feet_in_ranges(clip<T>& c, std::vector<frame_interval> ranges, plant_feet_params<T> params,
                                 const std::vector<T>& limits) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    params.ranges = std::move(ranges);
    if (params.ranges.empty() || !has_feet_to_plant(c, params)) return 0;
    if (params.joint_speed_limits.empty()) params.joint_speed_limits = limits;
    auto planted = plant_feet(c, params);
    c = std::move(planted.planted);
    return planted.runs;
}

}  // namespace anima
