// Foot contacts and airborne phases of a clip, and the foot skate measure.
//
// A foot is a joint (LeftFoot, lFoot, l_ankle...) with its descendants and
// their End Sites: its heel, ball and toe tips. A foot is in contact when one
// of those points is near its standing height *and* nearly still on the
// ground plane. Both thresholds are in body heights (per second for speeds),
// so they hold for any unit and for a frame time that is wrong by a constant
// factor (speeds then scale, heights do not, and height is the stricter
// cue). Hysteresis (enter below the lower thresholds, leave above the upper
// ones) and a minimum duration keep marker noise from flickering a contact.
// The standing height of each point is a low percentile of its own height
// over the clip, so the ground need not be at zero and feet need not rest
// flat. The airborne frames are those where no foot is in contact.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/core/text.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/rest_pose.hpp>
#include <anima/motion/skeleton.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace anima {

/// Frames first..last, both included.
struct frame_interval {
    std::size_t first = 0, last = 0;
    std::size_t frames() const noexcept { return last - first + 1; }
    friend bool operator==(frame_interval a, frame_interval b) { return a.first == b.first && a.last == b.last; }
};

/// The runs of true in a per-frame flag vector.
inline std::vector<frame_interval> true_runs(const std::vector<bool>& flags) {
    std::vector<frame_interval> runs;
    for (std::size_t f = 0; f < flags.size(); ++f) {
        if (!flags[f]) continue;
        if (runs.empty() || runs.back().last + 1 != f) runs.push_back({f, f});
        else runs.back().last = f;
    }
    return runs;
}

template <class T>
struct contact_params {
    std::optional<signed_axis> up;    ///< guessed from the skeleton when empty
    std::vector<std::string> feet;    ///< foot joints by name; empty: found (see find_feet)
    T height_on = T(0.03);            ///< a point enters contact below this rise (body heights)
    T height_off = T(0.05);           ///< and leaves above this one
    /// Horizontal speed to enter contact, body heights per second: at most
    /// speed_on, and lower for a clip whose feet move slowly (or whose frame
    /// time is too long): relative_speed times the 95th percentile of its feet
    /// speeds, but not under speed_floor.
    T speed_on = T(0.3);
    T relative_speed = T(0.15);
    T speed_floor = T(0.15);
    T speed_off = T(0.6);             ///< to leave, scaled with speed_on the same way
    T min_contact_seconds = T(0.05);  ///< shorter contacts are dropped
    T min_gap_seconds = T(0.025);     ///< shorter gaps in a contact (and airborne phases) are closed
    T standing_quantile = T(0.05);    ///< of a point's heights: its standing height
    /// The standing height is taken over +-this many seconds around each
    /// frame (floors are not level, markers drift), but never more than
    /// 0.05 body heights above the whole clip's.
    T standing_window_seconds = T(1);
    /// false: height alone decides. To measure the skate of a motion that
    /// may slide, whose sliding feet the speed test would call lifted.
    bool use_speed = true;
    /// Leave out the frames a converter put before the capture (a T-pose at
    /// frame 0, see rest_pose_lead_in): they are neither contact nor airborne.
    bool skip_rest_pose = true;
};

/// One foot over the clip.
template <class T>
struct foot_contact {
    std::string name;                     ///< the foot joint's name
    std::size_t joint = 0;                ///< its index
    std::vector<bool> in_contact;         ///< per frame
    std::vector<frame_interval> contacts; ///< the runs of in_contact
    std::vector<T> rise;                  ///< lowest point above its standing height, body heights
    /// Horizontal speed, body heights per second, of the stillest point
    /// within height_off of the ground (of the lowest point when none is):
    /// a planted foot rolls over heel, ball and toe, and slides only if even
    /// its stillest point moves.
    std::vector<T> speed;
};

template <class T>
struct contact_set {
    signed_axis up;                              ///< the up axis used
    T body_height = T(0);                        ///< rest-pose height along up, file units
    T frame_time = T(0);
    std::size_t lead_in = 0;                     ///< frames left out at the start (skip_rest_pose)
    T speed_on = T(0);                           ///< the entering speed used, body heights per second
    /// The 95th percentile of the feet's point speeds, body heights per
    /// second: the scale that tells a stepping foot from a still or sliding one.
    T fast_foot_speed = T(0);
    std::vector<foot_contact<T>> feet;
    std::vector<bool> airborne;                  ///< per frame: no foot in contact
    std::vector<frame_interval> airborne_phases; ///< the runs of airborne
};

namespace detail {

inline bool is_foot_name(const std::string& name) {
    const std::string n = ascii_lower(name);
    return n.find("foot") != std::string::npos || n.find("ankle") != std::string::npos;
}

/// The joint and every joint below it.
template <class T>
std::vector<std::size_t> subtree(const skeleton<T>& sk, std::size_t root) {
    std::vector<bool> inside(sk.size(), false);
    inside[root] = true;
    std::vector<std::size_t> out{root};
    for (std::size_t j = root + 1; j < sk.size(); ++j)  // parents come first
        if (sk[j].parent >= 0 && inside[static_cast<std::size_t>(sk[j].parent)]) {
            inside[j] = true;
            out.push_back(j);
        }
    return out;
}

}  // namespace detail

/// One of a foot's points: a joint of its subtree or that joint's End Site.
struct foot_point {
    std::size_t joint = 0;
    bool end_site = false;  ///< the joint's End Site rather than the joint
};

/// The points that make up the foot at joint `foot`, the ones contacts are
/// measured on (the lowest of them touches the ground): every joint of its
/// subtree, each followed by its End Site if it has one, parents first.
/// Throws anima::invalid_argument for a joint outside the skeleton.
template <class T>
std::vector<foot_point> foot_points_of(const skeleton<T>& sk, std::size_t foot) {
    if (foot >= sk.size())
        throw invalid_argument("anima::foot_points_of: joint " + std::to_string(foot) + " is outside the skeleton (" +
                               std::to_string(sk.size()) + " joints)");
    std::vector<foot_point> out;
    for (const std::size_t j : detail::subtree(sk, foot)) {
        out.push_back({j, false});
        if (sk[j].end_site) out.push_back({j, true});
    }
    return out;
}

namespace detail {

/// Where a foot point is in a pose.
template <class T>
Eigen::Matrix<T, 3, 1> foot_point_position(const skeleton<T>& sk, const global_pose<T>& pose, foot_point p) {
    return p.end_site ? Eigen::Matrix<T, 3, 1>(pose.positions[p.joint] + pose.orientations[p.joint] * *sk[p.joint].end_site)
                      : pose.positions[p.joint];
}

template <class T>
T quantile(std::vector<T> values, T q) {
    if (values.empty()) return T(0);
    const auto k = static_cast<std::size_t>(std::floor(q * static_cast<T>(values.size() - 1)));
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
    return values[k];
}

/// Per frame, the q-quantile of the values within +-window frames, capped at
/// the whole series' quantile + cap. Sampled every window/8 frames and held
/// in between: the standing height changes slowly.
template <class T>
std::vector<T> windowed_quantile(const std::vector<T>& values, std::size_t window, T q, T cap) {
    const std::size_t n = values.size();
    const T limit = quantile(values, q) + cap;
    std::vector<T> out(n, limit);
    const std::size_t step = std::max<std::size_t>(1, window / 8);
    for (std::size_t f = 0; f < n; f += step) {
        const std::size_t mid = std::min(n - 1, f + step / 2);
        const std::size_t a = mid >= window ? mid - window : 0, b = std::min(n - 1, mid + window);
        const T local = std::min(limit, quantile(std::vector<T>(values.begin() + static_cast<std::ptrdiff_t>(a),
                                                                values.begin() + static_cast<std::ptrdiff_t>(b) + 1),
                                                 q));
        for (std::size_t k = f; k < std::min(n, f + step); ++k) out[k] = local;
    }
    return out;
}

/// Closes false runs shorter than `gap` between true runs, then drops true
/// runs shorter than `least` (none in a series shorter than that: a clip
/// too short to tell keeps what it shows).
inline void clean_runs(std::vector<bool>& flags, std::size_t least, std::size_t gap) {
    const auto runs = true_runs(flags);
    for (std::size_t r = 1; r < runs.size(); ++r)
        if (runs[r].first - runs[r - 1].last - 1 < gap)
            for (std::size_t f = runs[r - 1].last + 1; f < runs[r].first; ++f) flags[f] = true;
    if (flags.size() < least) return;
    for (const auto& run : true_runs(flags))
        if (run.frames() < least)
            for (std::size_t f = run.first; f <= run.last; ++f) flags[f] = false;
}

}  // namespace detail

/// The feet of a skeleton: joints named *foot* or *ankle* whose parent is not
/// one (LeftFoot, lFoot, l_ankle; not LeftToeBase under LeftFoot). Without
/// such names, the leaves whose rest-pose tip is within 10% of the body
/// height of the lowest point. Empty when neither finds any.
template <class T>
std::vector<std::size_t> find_feet(const skeleton<T>& sk, signed_axis up) {
    std::vector<std::size_t> feet;
    for (std::size_t j = 0; j < sk.size(); ++j)
        if (detail::is_foot_name(sk[j].name) && !(sk[j].parent >= 0 && detail::is_foot_name(sk[static_cast<std::size_t>(sk[j].parent)].name)))
            feet.push_back(j);
    if (!feet.empty() || sk.empty()) return feet;
    const auto rest = rest_positions(sk).first;
    const auto k = static_cast<Eigen::Index>(up.axis);
    const T sign = up.sign < 0 ? T(-1) : T(1);
    std::vector<bool> has_child(sk.size(), false);
    for (std::size_t j = 0; j < sk.size(); ++j)
        if (sk[j].parent >= 0) has_child[static_cast<std::size_t>(sk[j].parent)] = true;
    std::vector<T> tip(sk.size());
    T lowest = std::numeric_limits<T>::max();
    for (std::size_t j = 0; j < sk.size(); ++j) {
        tip[j] = sign * (sk[j].end_site ? T(rest[j][k] + (*sk[j].end_site)[k]) : rest[j][k]);
        lowest = std::min(lowest, tip[j]);
    }
    const T height = figure_height(sk, up);
    for (std::size_t j = 0; j < sk.size(); ++j)
        if (!has_child[j] && tip[j] <= lowest + T(0.1) * height) feet.push_back(j);
    return feet;
}

namespace detail {

template <class T>
void check_contact_params(const contact_params<T>& params) {
    const char* who = "anima::find_contacts";
    check_positive(who, "height_on", params.height_on);
    check_argument(params.height_off >= params.height_on, who, "height_off", "at least height_on", params.height_off);
    check_positive(who, "speed_on", params.speed_on);
    check_argument(params.speed_off >= params.speed_on, who, "speed_off", "at least speed_on", params.speed_off);
    check_non_negative(who, "relative_speed", params.relative_speed);
    check_non_negative(who, "speed_floor", params.speed_floor);
    check_non_negative(who, "min_contact_seconds", params.min_contact_seconds);
    check_non_negative(who, "min_gap_seconds", params.min_gap_seconds);
    check_in_range(who, "standing_quantile", params.standing_quantile, T(0), T(1));
    check_non_negative(who, "standing_window_seconds", params.standing_window_seconds);
}

/// One foot's points (its joints and their End Sites) over frames
/// first..frames-1: rise above the standing height (body heights) and
/// horizontal speed (body heights per second), [frame * points + point].
template <class T>
struct foot_points {
    std::size_t points = 0;
    std::vector<T> rise, speed;
};

/// A whole number of frames as a count, capped at 1e15 (no clip is that
/// long), 0 for a NaN or a negative: a tiny frame time or a huge duration
/// must not overflow the conversion (undefined behaviour).
template <class T>
std::size_t capped_frame_count(T frames) {
    if (!(frames > T(0))) return 0;
    return frames < T(1e15) ? static_cast<std::size_t>(frames) : std::size_t(1e15);
}

/// The frames `seconds` spans at `frame_time`: ceil(seconds / frame_time -
/// slack), capped.
template <class T>
std::size_t frames_spanning(T seconds, T frame_time, T slack = T(0)) {
    return capped_frame_count(std::ceil(seconds / frame_time - slack));
}

/// Foot speeds are central differences over +-1/60 s, this many frames
/// each side (at least 1): a difference over one frame at 120 Hz would turn
/// millimetre marker noise into centimetres per second.
template <class T>
std::size_t speed_half_window(T frame_time) {
    return std::max<std::size_t>(1, capped_frame_count(std::round(1.0 / (60.0 * static_cast<double>(frame_time)))));
}

template <class T>
std::vector<foot_points<T>> measure_feet(const clip<T>& c, const std::vector<std::size_t>& feet, std::size_t first,
                                         const contact_set<T>& out, const contact_params<T>& params) {
    using vector3 = Eigen::Matrix<T, 3, 1>;
    const auto& sk = c.skeleton();
    const std::size_t n = c.frames() - first;
    const auto axis = static_cast<Eigen::Index>(out.up.axis);
    const T sign = out.up.sign < 0 ? T(-1) : T(1), h = out.body_height;
    const std::size_t window = frames_spanning(params.standing_window_seconds, c.frame_time());
    const std::size_t half = speed_half_window(c.frame_time());
    std::vector<std::vector<foot_point>> points(feet.size());
    for (std::size_t i = 0; i < feet.size(); ++i) points[i] = foot_points_of(sk, feet[i]);
    std::vector<std::vector<vector3>> where(feet.size());  // [foot][frame * points + p]
    global_pose<T> pose;
    for (std::size_t f = first; f < c.frames(); ++f) {
        forward_kinematics(c, f, pose);
        for (std::size_t i = 0; i < feet.size(); ++i)
            for (const foot_point p : points[i]) where[i].push_back(foot_point_position(sk, pose, p));
    }
    std::vector<foot_points<T>> out_points(feet.size());
    for (std::size_t i = 0; i < feet.size(); ++i) {
        const std::size_t np = points[i].size();
        const auto at = [&](std::size_t f, std::size_t p) -> const vector3& { return where[i][f * np + p]; };
        foot_points<T>& fp = out_points[i];
        fp.points = np;
        fp.rise.resize(n * np);
        fp.speed.resize(n * np);
        for (std::size_t p = 0; p < np; ++p) {
            std::vector<T> heights(n);
            for (std::size_t f = 0; f < n; ++f) heights[f] = sign * at(f, p)[axis];
            const auto standing = windowed_quantile(heights, window, params.standing_quantile, T(0.05) * h);
            for (std::size_t f = 0; f < n; ++f) {
                fp.rise[f * np + p] = (heights[f] - standing[f]) / h;
                const std::size_t a = f >= half ? f - half : 0, b = std::min(n - 1, f + half);
                vector3 d = at(b, p) - at(a, p);
                d[axis] = T(0);
                fp.speed[f * np + p] = b > a ? d.norm() / (h * static_cast<T>(b - a) * c.frame_time()) : T(0);
            }
        }
    }
    return out_points;
}

/// The hysteresis over one foot's points: in contact from a frame where a
/// point is below the entering thresholds until no point is below the
/// leaving ones. Fills the foot's rise and speed from frame `first` on.
/// The clip's fast foot speed: the 95th percentile of every measured foot
/// point's speed, body heights per second. The scale that tells a stepping
/// foot from a still or sliding one, whatever the gait and frame time.
template <class T>
T fast_foot_speed(const std::vector<foot_points<T>>& measured) {
    std::vector<T> all;
    for (const auto& fp : measured) all.insert(all.end(), fp.speed.begin(), fp.speed.end());
    return quantile(std::move(all), T(0.95));
}

template <class T>
std::vector<bool> follow_foot(const foot_points<T>& fp, std::size_t first, const contact_params<T>& params,
                              T speed_on, T speed_off, foot_contact<T>& foot) {
    const std::size_t np = fp.points, n = np ? fp.rise.size() / np : 0;
    std::vector<bool> in_contact(n, false);
    bool on = false;
    for (std::size_t f = 0; f < n; ++f) {
        bool enter = false, hold = false;
        std::size_t lowest = 0, planted = np;  // the lowest point; the stillest one near the ground
        for (std::size_t p = 0; p < np; ++p) {
            const T r = fp.rise[f * np + p], v = fp.speed[f * np + p];
            enter = enter || (r < params.height_on && (!params.use_speed || v < speed_on));
            hold = hold || (r < params.height_off && (!params.use_speed || v < speed_off));
            if (r < fp.rise[f * np + lowest]) lowest = p;
            if (r < params.height_off && (planted == np || v < fp.speed[f * np + planted])) planted = p;
        }
        on = on ? hold : enter;
        in_contact[f] = on;
        foot.rise[first + f] = fp.rise[f * np + lowest];
        foot.speed[first + f] = fp.speed[f * np + (planted < np ? planted : lowest)];
    }
    return in_contact;
}

}  // namespace detail

/// Whether find_contacts(c, params) has feet to look at: a figure with a
/// height along the up axis, and feet named in params.feet or found by
/// find_feet. For measures that must pass over a prop or a single joint.
template <class T>
bool has_feet(const clip<T>& c, const contact_params<T>& params = {}) {
    if (c.joints() == 0) return false;
    const signed_axis up = params.up ? *params.up : guess_up_axis(c.skeleton()).up;
    if (!(figure_height(c.skeleton(), up) > T(0))) return false;
    return !params.feet.empty() || !find_feet(c.skeleton(), up).empty();
}

namespace detail {

/// find_contacts, and the feet's points as it measured them (measure_feet
/// of its feet from its lead-in on), for a caller that needs both.
template <class T>
contact_set<T> find_contacts_measured(const clip<T>& c, const contact_params<T>& params,
                                      std::vector<foot_points<T>>& measured) {
    const std::string who = "anima::find_contacts";
    detail::check_contact_params(params);
    const auto& sk = c.skeleton();
    contact_set<T> out;
    out.up = params.up ? *params.up : guess_up_axis(sk).up;
    out.body_height = figure_height(sk, out.up);
    out.frame_time = c.frame_time();
    if (!(out.body_height > T(0))) throw invalid_argument(who + ": the figure has no height along its up axis");
    std::vector<std::size_t> feet;
    for (const auto& name : params.feet) {
        const auto j = sk.find(name);
        if (!j) throw invalid_argument(who + ": the skeleton has no joint '" + name + "'");
        feet.push_back(*j);
    }
    if (params.feet.empty()) feet = find_feet(sk, out.up);
    if (feet.empty())
        throw invalid_argument(who + ": no foot joints found by name or as lowest leaves; name them in "
                                     "contact_params::feet");

    const std::size_t frames = c.frames();
    const std::size_t first = params.skip_rest_pose && frames > 2 ? rest_pose_lead_in(c) : 0;
    out.lead_in = first;
    const std::size_t n = frames - first;  // the frames looked at: first..frames-1
    const auto frames_of = [&](T seconds) { return detail::frames_spanning(seconds, c.frame_time(), T(1e-6)); };
    measured = detail::measure_feet(c, feet, first, out, params);
    out.fast_foot_speed = detail::fast_foot_speed(measured);
    out.speed_on = std::min(params.speed_on, std::max(params.speed_floor, params.relative_speed * out.fast_foot_speed));
    const T speed_off = out.speed_on * (params.speed_off / params.speed_on);

    std::vector<bool> airborne(n, true);
    for (std::size_t i = 0; i < feet.size(); ++i) {
        foot_contact<T> foot;
        foot.name = sk[feet[i]].name;
        foot.joint = feet[i];
        foot.rise.assign(frames, T(0));
        foot.speed.assign(frames, T(0));
        std::vector<bool> in_contact = detail::follow_foot(measured[i], first, params, out.speed_on, speed_off, foot);
        detail::clean_runs(in_contact, frames_of(params.min_contact_seconds), frames_of(params.min_gap_seconds));
        for (std::size_t f = 0; f < n; ++f)
            if (in_contact[f]) airborne[f] = false;
        foot.in_contact.assign(first, false);
        foot.in_contact.insert(foot.in_contact.end(), in_contact.begin(), in_contact.end());
        foot.contacts = true_runs(foot.in_contact);
        out.feet.push_back(std::move(foot));
    }
    for (const auto& foot : out.feet)  // e.g. float positions near 1e30, whose differences overflow
        for (std::size_t f = 0; f < frames; ++f)
            if (!std::isfinite(foot.speed[f]) || !std::isfinite(foot.rise[f]))
                throw invalid_argument(who + ": foot '" + foot.name + "' at frame " + std::to_string(f) +
                                       ": its height or speed overflows the scalar type; scale the clip down "
                                       "(scale_clip)");
    // An airborne phase shorter than the gap that closes contacts is noise.
    detail::clean_runs(airborne, frames_of(params.min_gap_seconds), 0);
    out.airborne.assign(first, false);
    out.airborne.insert(out.airborne.end(), airborne.begin(), airborne.end());
    out.airborne_phases = true_runs(out.airborne);
    return out;
}

}  // namespace detail

/// Contacts and airborne phases of a clip. Throws anima::invalid_argument for
/// a foot name the skeleton does not have, a skeleton without feet (name
/// them in params.feet; has_feet tells beforehand), a figure of zero height
/// or bad thresholds.
template <class T>
contact_set<T> find_contacts(const clip<T>& c, const contact_params<T>& params = {}) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    std::vector<detail::foot_points<T>> measured;
    return detail::find_contacts_measured(c, params, measured);
}

/// Foot skate: the horizontal speed of feet in contact, in body heights per
/// second, over the contact frames of frames first..last.
template <class T>
struct skate_summary {
    T median = T(0);
    T mean = T(0);
    T max = T(0);
    std::size_t samples = 0;  ///< (foot, frame) pairs in contact
};

namespace detail {
template <class T>
skate_summary<T> summarise_skate(std::vector<T> speeds) {
    skate_summary<T> out;
    out.samples = speeds.size();
    if (speeds.empty()) return out;
    T sum = T(0);
    for (const T s : speeds) {
        sum += s;
        out.max = std::max(out.max, s);
    }
    out.mean = sum / static_cast<T>(speeds.size());
    out.median = quantile(std::move(speeds), T(0.5));
    return out;
}
}  // namespace detail

/// The skate of one foot over its contact frames in first..last.
template <class T>
skate_summary<T> foot_skate(const foot_contact<T>& foot, std::size_t first = 0,
                            std::size_t last = std::numeric_limits<std::size_t>::max()) {
    std::vector<T> speeds;
    for (std::size_t f = first; f <= last && f < foot.in_contact.size(); ++f)
        if (foot.in_contact[f]) speeds.push_back(foot.speed[f]);
    return detail::summarise_skate(std::move(speeds));
}

namespace detail {
template <class T>
void append_contact_speeds(const contact_set<T>& contacts, std::size_t first, std::size_t last, std::vector<T>& speeds) {
    for (const auto& foot : contacts.feet)
        for (std::size_t f = first; f <= last && f < foot.in_contact.size(); ++f)
            if (foot.in_contact[f]) speeds.push_back(foot.speed[f]);
}
}  // namespace detail

/// The skate of every foot together over frames first..last.
template <class T>
skate_summary<T> foot_skate(const contact_set<T>& contacts, std::size_t first = 0,
                            std::size_t last = std::numeric_limits<std::size_t>::max()) {
    std::vector<T> speeds;
    detail::append_contact_speeds(contacts, first, last, speeds);
    return detail::summarise_skate(std::move(speeds));
}

namespace detail {
template <class T>
skate_summary<T> clip_foot_skate(const std::vector<const clip<T>*>& clips, std::optional<signed_axis> up) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    contact_params<T> p;
    p.up = up;
    p.use_speed = false;
    p.skip_rest_pose = false;
    std::vector<T> speeds;
    for (const clip<T>* c : clips)
        if (has_feet(*c, p)) append_contact_speeds(find_contacts(*c, p), 0, c->frames(), speeds);
    return summarise_skate(std::move(speeds));
}
}  // namespace detail

/// The foot skate of a whole clip as the texture, playback and transition
/// evaluations compare it: every foot on the ground by height alone (a
/// speed test would leave out the sliding that is to be measured), rest
/// pose frames included. Zero samples for a figure without feet. `up`:
/// guessed from the skeleton when empty.
template <class T>
skate_summary<T> clip_foot_skate(const clip<T>& c, std::optional<signed_axis> up = std::nullopt) {
    return detail::clip_foot_skate(std::vector<const clip<T>*>{&c}, up);
}

/// clip_foot_skate of several clips together: every contact frame of each.
template <class T>
skate_summary<T> clip_foot_skate(const std::vector<clip<T>>& clips, std::optional<signed_axis> up = std::nullopt) {
    std::vector<const clip<T>*> pointers;
    for (const clip<T>& c : clips) pointers.push_back(&c);
    return detail::clip_foot_skate(pointers, up);
}

}  // namespace anima
