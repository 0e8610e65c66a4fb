// The variable-timing hierarchical transition (sections 3-5 of the
// variable-timing paper, read as SPEC.md says):
//   1. classify both clips (on the spot / plane motion / space flight);
//   2. turn clip B to A's heading at the trigger and time the transition
//      (timing.hpp: T from the key joints' angles and angular speeds);
//   3. interpolate every joint with its own method: fingers by lerp with the
//      linear parameter, joints turning at least large_angle by squad with
//      control points from the neighbouring frames of A and B, the others by
//      slerp; the parameter eases in and out unless both clips are on the spot;
//   4. move the root along p0 + t v + t^2 a / 2 (Eq 12), or p0 + t v + k_g t^2 g
//      when the body is in the air at either end (Eq 13: A's trigger frame or
//      B's start frame in an airborne phase of a space-flight clip, not just
//      any frame of such a clip), with v and a measured at the trigger; the
//      vertical part is corrected linearly in t to land on B's start height,
//      so a flight path stays a parabola with the given gravity. On the
//      ground the path by default also meets B's root velocity where B
//      starts (a cubic Hermite through Eq 12's end point, a departure from
//      the paper: Eq 12 alone leaves the root's velocity jumping there);
//   5. place B where the transition ends, heading aligned: no jump.
// make_transition returns all of it with a placed copy of B; for a game loop,
// make_transition_into writes the same into storage the caller keeps (and
// says where B goes instead of copying it), with no allocation per call.
#pragma once

#include <anima/core/constants.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/joint_roles.hpp>
#include <anima/motion/resample.hpp>
#include <anima/rotation/quaternion.hpp>
#include <anima/rotation/slerp.hpp>
#include <anima/rotation/squad.hpp>
#include <anima/transition/classify.hpp>
#include <anima/transition/detail/blend_many.hpp>
#include <anima/transition/placement.hpp>
#include <anima/transition/timing.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace anima {

/// How one joint's rotation is interpolated through the transition.
enum class interpolation : unsigned char {
    automatic,  ///< the paper's rule (fingers lerp, large turns squad, others slerp)
    lerp,       ///< normalised linear blend (Eq 6; hemisphere-aligned first)
    slerp,      ///< Eq 7
    squad       ///< Eq 8-9, control points from the neighbouring frames
};

template <>
struct enum_names<interpolation> {
    static constexpr const char* what = "interpolation";
    static constexpr enum_entry<interpolation> entries[] = {{interpolation::automatic, "automatic"},
                                                            {interpolation::lerp, "lerp"},
                                                            {interpolation::slerp, "slerp"},
                                                            {interpolation::squad, "squad"}};
};

struct transition_params {
    classify_params classification;      ///< also gives the up axis and units
    /// Classes computed beforehand (classify_motion once per clip, offline):
    /// when set they are used as they are and the clips are not re-classified.
    std::optional<motion_classification> class_a, class_b;
    timing_params timing;
    std::vector<joint_role> roles;       ///< one per joint; empty: joint_roles(A's skeleton)
    std::vector<interpolation> methods;  ///< one per joint; empty or automatic: the paper's rule
    double large_angle = pi<double> / 6; ///< rad: at or above it a joint uses squad
    std::optional<easing> parameter;     ///< empty: linear for spot -> spot, ease-in-out otherwise
    double gravity = 9.81;               ///< m/s^2, along -up
    double gravity_factor = 0.5;         ///< k_g of Eq 13; 0.5 is free fall
    double root_window = 0.25;           ///< s of A fitted (quadratic) for the root's v and a at the trigger
    /// On the ground, the root path also meets placed B's root velocity at
    /// B's start (cubic Hermite from A's trigger position and velocity to
    /// Eq 12's end point and B's velocity). false: Eq 12 as printed, whose
    /// velocity jumps where B starts. Flight paths are Eq 13 either way.
    bool continuous_root = true;
    /// Bytes the in-between frames may take (1 GiB): a longer transition is
    /// refused before they are allocated. 0: no limit.
    double max_memory = 1024.0 * 1024.0 * 1024.0;
};

/// A transition without a copy of clip B: what make_transition_into writes
/// for a game loop, which plays B through `placement` instead.
template <class T>
struct transition_frames {
    clip<T> frames;       ///< the in-between frames (strictly between A's trigger and B's start)
    T duration = 0;       ///< s: T rounded to whole frames (frames.frames() + 1 steps)
    timing_result<T> timing;
    std::vector<interpolation> methods;  ///< per joint, as used
    easing parameter = easing::ease_in_out;
    motion_classification class_a, class_b;
    bool flight = false;                 ///< Eq 13 used for the root: the body is in the air at an end
    point_motion<T> root_at_trigger;     ///< v and a of Eq 12-13
    /// Placed B's root velocity at its start: the Hermite path's end
    /// velocity (zero when the path is Eq 12 or 13).
    Eigen::Matrix<T, 3, 1> root_velocity_at_b = Eigen::Matrix<T, 3, 1>::Zero();
    clip_placement<T> placement;         ///< where B goes: from its start frame, heading aligned, at the end
};

/// A transition and B placed where it ends: what make_transition returns.
template <class T>
struct transition : transition_frames<T> {
    clip<T> placed_b;  ///< B from its start frame, placed by `placement`
};

/// What make_transition_into keeps from call to call so that, once it has
/// seen a skeleton and a transition as long, it allocates nothing: keep one
/// per thread (or per character) and pass it to every call. The members are
/// scratch space, not results.
template <class T>
struct transition_workspace {
    skeleton<T> roles_of;                 ///< the skeleton `roles` were found for
    std::vector<joint_role> roles;        ///< joint_roles(roles_of)
    std::vector<T> h, h_linear;           ///< the interpolation parameter at each in-between frame
    detail::rates_scratch<T> rates;
    detail::root_fit<T> root_fit;
};

namespace detail {

/// joint_roles(sk), found again only when the names or roots differ from the
/// last skeleton's (the roles depend on nothing else).
template <class T>
const std::vector<joint_role>& cached_roles(const skeleton<T>& sk, transition_workspace<T>& ws) {
    bool same = ws.roles_of.size() == sk.size() && ws.roles.size() == sk.size();
    for (std::size_t j = 0; same && j < sk.size(); ++j)
        same = (sk[j].parent < 0) == (ws.roles_of[j].parent < 0) && sk[j].name == ws.roles_of[j].name;
    if (!same) {
        ws.roles = joint_roles(sk);
        ws.roles_of = sk;
    }
    return ws.roles;
}

/// make_transition's checks of its arguments; the errors name `who`.
template <class T>
void check_transition(const clip<T>& a, std::size_t trigger, const clip<T>& b, std::size_t b_start,
                      const transition_params& params, const char* who) {
    check_same_hierarchy(a.skeleton(), b.skeleton());
    if (a.joints() == 0) throw invalid_argument(std::string(who) + ": the clips have no joints");
    if (trigger >= a.frames())
        throw invalid_argument(std::string(who) + ": trigger frame " + std::to_string(trigger) +
                               " is outside clip A (" + std::to_string(a.frames()) + " frames)");
    if (b_start >= b.frames())
        throw invalid_argument(std::string(who) + ": start frame " + std::to_string(b_start) +
                               " is outside clip B (" + std::to_string(b.frames()) + " frames)");
    if (!params.roles.empty() && params.roles.size() != a.joints())
        throw invalid_argument(std::string(who) + ": " + std::to_string(params.roles.size()) + " roles for " +
                               std::to_string(a.joints()) + " joints");
    if (!params.methods.empty() && params.methods.size() != a.joints())
        throw invalid_argument(std::string(who) + ": " + std::to_string(params.methods.size()) +
                               " interpolation methods for " + std::to_string(a.joints()) + " joints");
    check_argument(params.large_angle >= 0, who, "transition_params::large_angle",
                   "non-negative (infinity: no joint uses squad)", params.large_angle);
    check_non_negative(who, "transition_params::gravity", params.gravity);
    check_finite(who, "transition_params::gravity_factor", params.gravity_factor);
    check_non_negative(who, "transition_params::root_window", params.root_window);
    check_classify_params(params.classification, who);
    check_timing_params(params.timing, who);
}

/// The transition's steps (in-between frames + 1) for its duration, counted
/// in double so that no duration overflows, refused when the in-between
/// frames would take more than params.max_memory.
template <class T>
std::size_t transition_steps(const clip<T>& a, T duration, const transition_params& params, const char* who) {
    const double steps = std::max(1.0, std::round(static_cast<double>(duration) / static_cast<double>(a.frame_time())));
    const double bytes = (steps - 1) * clip_frame_bytes(a.skeleton());
    if (params.max_memory > 0 && !(bytes <= params.max_memory))
        throw invalid_argument(std::string(who) + ": a transition of " + argument_text(duration) +
                               " s at a frame time of " + argument_text(a.frame_time()) + " s has " +
                               argument_text(steps - 1) + " in-between frames, about " +
                               argument_text(std::ceil(bytes / 1048576.0)) +
                               " MiB, more than transition_params::max_memory (" +
                               argument_text(params.max_memory / 1048576.0) +
                               " MiB): lower timing_params::max_duration");
    return static_cast<std::size_t>(steps);
}

/// Whether frame f of a clip with this classification is in an airborne
/// phase (only space-flight clips have them).
inline bool airborne_at(const motion_classification& m, std::size_t f) {
    if (m.type != motion_class::space_flight) return false;
    for (const auto& phase : m.airborne)
        if (f >= phase.first && f <= phase.last) return true;
    return false;
}

/// The root's velocity at frame f of c from the frames after it: the
/// one-sided second-order difference over steps of about 25 ms (first order,
/// or zero, when the clip ends sooner).
template <class T>
Eigen::Matrix<T, 3, 1> root_velocity_ahead(const clip<T>& c, std::size_t f) {
    const T dt = c.frame_time();
    const std::size_t left = c.frames() - 1 - f;
    std::size_t k = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(T(0.025) / dt)));
    if (2 * k <= left)
        return (T(-3) * c.root_position(f) + T(4) * c.root_position(f + k) - c.root_position(f + 2 * k)) /
               (T(2) * static_cast<T>(k) * dt);
    k = std::min(k, left);
    if (k == 0) return Eigen::Matrix<T, 3, 1>::Zero();
    return (c.root_position(f + k) - c.root_position(f)) / (static_cast<T>(k) * dt);
}

/// Whether b's frame time differs from a's (more than rounding).
template <class T>
bool other_frame_time(const clip<T>& a, const clip<T>& b) {
    return std::abs(b.frame_time() - a.frame_time()) > T(1e-9) * a.frame_time();
}

/// Each joint's method: the one given, else the paper's rule (fingers lerp,
/// a turn of large_angle or more squad, the rest slerp).
template <class T>
void choose_methods(const transition_params& params, const std::vector<joint_role>& roles,
                    const timing_result<T>& timing, std::vector<interpolation>& methods) {
    methods.resize(roles.size());
    for (std::size_t j = 0; j < roles.size(); ++j) {
        const interpolation chosen = params.methods.empty() ? interpolation::automatic : params.methods[j];
        if (chosen != interpolation::automatic) methods[j] = chosen;
        else if (roles[j] == joint_role::finger) methods[j] = interpolation::lerp;
        else if (timing.joints[j].angle >= static_cast<T>(params.large_angle)) methods[j] = interpolation::squad;
        else methods[j] = interpolation::slerp;
    }
}

/// The transition from checked arguments, B at A's frame time.
template <class T>
void make_transition_checked(const clip<T>& a, std::size_t trigger, const clip<T>& b, std::size_t b_start,
                             const transition_params& params, transition_frames<T>& out, transition_workspace<T>& ws,
                             const char* who) {
    const flush_denormals guard;  // float mocap's tiny angles would otherwise halve the speed
    using vec3 = Eigen::Matrix<T, 3, 1>;
    using quat = Eigen::Quaternion<T>;
    const std::size_t nj = a.joints();
    const std::vector<joint_role>& roles = params.roles.empty() ? cached_roles(a.skeleton(), ws) : params.roles;
    out.class_a = params.class_a ? *params.class_a : classify_motion(a, roles, params.classification);
    classify_params cb = params.classification;
    cb.up = out.class_a.up;  // one world for both clips
    cb.metres_per_unit = out.class_a.metres_per_unit;
    out.class_b = params.class_b ? *params.class_b : classify_motion(b, roles, cb);
    const signed_axis up = out.class_a.up;
    const vec3 up_vec = axis_vector<T>(up);
    const T dt = a.frame_time();
    const bool spot = out.class_a.type == motion_class::on_the_spot && out.class_b.type == motion_class::on_the_spot;
    out.flight = airborne_at(out.class_a, trigger) || airborne_at(out.class_b, b_start);
    out.parameter = params.parameter ? *params.parameter : (spot ? easing::linear : easing::ease_in_out);

    // Heading and timing.
    const quat turn = heading_change(b.rotation(b_start, 0), a.rotation(trigger, 0), up);
    variable_timing_into(a, trigger, b, b_start, roles, turn, params.timing, out.timing, ws.rates);
    const std::size_t steps = transition_steps(a, out.timing.duration, params, who);
    out.duration = dt * static_cast<T>(steps);

    // Root path (Eq 12 / Eq 13) and B's placement at its end.
    const bool translated = a.skeleton().translation_slot(0) >= 0;
    const auto root_frames = static_cast<std::size_t>(std::lround(params.root_window / static_cast<double>(dt))) + 1;
    out.root_at_trigger = translated ? root_motion_at(a, trigger, root_frames, ws.root_fit) : point_motion<T>{};
    const vec3 p0 = a.root_position(trigger);
    const vec3 v = out.root_at_trigger.velocity;
    const vec3 acc = out.flight ? vec3(T(2) * static_cast<T>(params.gravity_factor) *
                                       (-static_cast<T>(params.gravity / out.class_a.metres_per_unit)) * up_vec)
                                : out.root_at_trigger.acceleration;
    const auto predicted = [&](T t) { return vec3(p0 + t * v + T(0.5) * t * t * acc); };
    const vec3 b0 = b.root_position(b_start);
    vec3 end = predicted(out.duration);
    const T end_height = b0.dot(up_vec), predicted_height = end.dot(up_vec);
    end += (end_height - predicted_height) * up_vec;  // keep B's own height above its ground
    out.placement = clip_placement<T>{b_start, turn, b0, end};
    const bool hermite = translated && params.continuous_root && !out.flight;
    out.root_velocity_at_b = hermite ? vec3(turn * root_velocity_ahead(b, b_start)) : vec3::Zero();

    choose_methods(params, roles, out.timing, out.methods);

    // The in-between frames, in A's skeleton; the clip keeps its storage.
    if (out.frames.skeleton() != a.skeleton()) out.frames = clip<T>(a.skeleton(), 0, dt);
    out.frames.set_frame_time(dt);
    out.frames.resize(steps - 1);
    ws.h.resize(steps - 1);
    ws.h_linear.resize(steps - 1);
    for (std::size_t k = 1; k < steps; ++k) {
        const T t = dt * static_cast<T>(k);
        ws.h[k - 1] = interpolation_parameter(t, out.duration, out.parameter);
        ws.h_linear[k - 1] = interpolation_parameter(t, out.duration, easing::linear);
    }
    // Joint by joint: a joint blends the same two rotations in every frame.
    // Placed B differs from B only at the root. The blends write a joint's
    // frames straight into the clip, whose rows are frames (none when the
    // transition is one step: the clip's storage is then empty).
    const std::size_t next = b_start + 1 < b.frames() ? b_start + 1 : b_start;
    for (std::size_t j = 0; steps > 1 && j < nj; ++j) {
        const quat& q1 = a.rotation(trigger, j);
        const quat b_first = j == 0 ? out.placement.rotation(b.rotation(b_start, 0)) : b.rotation(b_start, j);
        const quat q2 = align_hemisphere(b_first, q1);
        quat* const column = clip_storage::rotations(out.frames) + j;  // frame k at column[k * nj]
        switch (out.methods[j]) {
            case interpolation::lerp: {
                const std::vector<T>& hs = roles[j] == joint_role::finger ? ws.h_linear : ws.h;
                // Not anima::nlerp or lerp: their side test and checks of t
                // cost 3-7 us a call here; q2 is on q1's side and hs are
                // finite by construction.
                lerp_many(q1, q2, hs.data(), steps - 1, column, nj);
                break;
            }
            case interpolation::squad: {
                // Control points from A's frame before the trigger and placed
                // B's second frame; B's rotation as it is: s2 was built on its
                // side, and squad moves the two together to q1's side.
                const quat& before = a.rotation(trigger > 0 ? trigger - 1 : trigger, j);
                const quat after = j == 0 ? out.placement.rotation(b.rotation(next, 0)) : b.rotation(next, j);
                const quat s1 = squad_control_point(before, q1, b_first), s2 = squad_control_point(q1, b_first, after);
                squad_many(q1, b_first, s1, s2, ws.h.data(), steps - 1, column, nj);
                break;
            }
            default:
                slerp_many(q1, q2, ws.h.data(), steps - 1, column, nj);
                break;
        }
        if (j > 0 && a.skeleton().translation_slot(j) >= 0) {
            const vec3 &from = a.translation(trigger, j), &to = b.translation(b_start, j);
            for (std::size_t k = 0; k + 1 < steps; ++k)
                out.frames.set_translation(k, j, (T(1) - ws.h[k]) * from + ws.h[k] * to);
        }
    }
    if (translated)
        for (std::size_t k = 1; k < steps; ++k) {
            const T t = dt * static_cast<T>(k);
            vec3 p;
            if (hermite) {
                const T s = t / out.duration, s2 = s * s, s3 = s2 * s;
                p = (T(2) * s3 - T(3) * s2 + T(1)) * p0 + (s3 - T(2) * s2 + s) * out.duration * v +
                    (T(-2) * s3 + T(3) * s2) * end + (s3 - s2) * out.duration * out.root_velocity_at_b;
            } else {
                // Linear-in-t vertical correction: keeps Eq 13's second derivative.
                p = predicted(t) + (t / out.duration) * (end_height - predicted_height) * up_vec;
            }
            out.frames.set_root_position(k - 1, p);
        }
}

}  // namespace detail

/// The transition from frame `trigger` of a to frame `b_start` of b written
/// into `out`, with `ws` as scratch: the per-call form of make_transition for
/// a game loop. The results are make_transition's, bit for bit, except that
/// B is not copied: out.placement says where B's frames go (the root turned
/// and moved, clip_placement::rotation and ::position; the other joints as
/// they are). Once `out` and `ws` have seen the skeleton and a transition at
/// least as long, a call allocates nothing, provided the clips' classes are
/// given (transition_params::class_a, class_b: classifying a clip allocates)
/// and root_window spans at most 64 frames (0.53 s at 120 Hz). B must have
/// A's frame time (resample it once, beforehand). Throws
/// anima::invalid_argument as make_transition does; `out` is then
/// unspecified.
template <class T>
void make_transition_into(const clip<T>& a, std::size_t trigger, const clip<T>& b, std::size_t b_start,
                          const transition_params& params, transition_frames<T>& out, transition_workspace<T>& ws) {
    detail::check_transition(a, trigger, b, b_start, params, "anima::make_transition_into");
    if (detail::other_frame_time(a, b))
        throw invalid_argument("anima::make_transition_into: clip B's frame time " +
                               detail::argument_text(b.frame_time()) + " s differs from clip A's " +
                               detail::argument_text(a.frame_time()) + " s: resample B first");
    detail::make_transition_checked(a, trigger, b, b_start, params, out, ws, "anima::make_transition_into");
}

/// The transition from frame `trigger` of a to frame `b_start` of b. The
/// clips must share a hierarchy (names, parents, position channels); bone
/// lengths may differ and the output uses A's skeleton. B is resampled to
/// A's frame time when they differ.
template <class T>
transition<T> make_transition(const clip<T>& a, std::size_t trigger, const clip<T>& b_in, std::size_t b_start = 0,
                              const transition_params& params = {}) {
    detail::check_transition(a, trigger, b_in, b_start, params, "anima::make_transition");
    const bool resampled = detail::other_frame_time(a, b_in);
    const clip<T> b_resampled = resampled ? resample(b_in, a.frame_time()) : clip<T>();
    const clip<T>& b = resampled ? b_resampled : b_in;
    if (resampled) b_start = detail::resampled_frame(b_start, b_in.frame_time(), b);
    transition<T> out;
    transition_workspace<T> ws;
    detail::make_transition_checked(a, trigger, b, b_start, params, out, ws, "anima::make_transition");
    out.placed_b = place_clip(b, b_start, out.placement.turn, out.placement.start);
    return out;
}

/// A clip made of two clips and the frames joining them.
template <class T>
struct joined_clip {
    clip<T> motion;
    std::size_t start_frame = 0;  ///< last frame of A in `motion`
    std::size_t end_frame = 0;    ///< first frame of (placed) B in `motion`
};

namespace detail {
/// start_frame <= end_frame < motion.frames(); the error names `who`.
template <class T>
void check_joined_window(const joined_clip<T>& joined, const char* who) {
    if (joined.start_frame > joined.end_frame || joined.end_frame >= joined.motion.frames())
        throw invalid_argument(std::string(who) + ": transition frames [" + std::to_string(joined.start_frame) +
                               ", " + std::to_string(joined.end_frame) + "] are not inside the clip (" +
                               std::to_string(joined.motion.frames()) + " frames)");
}
}  // namespace detail

/// A[0..trigger] + the transition's frames + the placed B.
template <class T>
joined_clip<T> join(const clip<T>& a, std::size_t trigger, const transition<T>& t) {
    if (trigger >= a.frames())
        throw invalid_argument("anima::join: trigger frame " + std::to_string(trigger) + " outside clip A (" +
                               std::to_string(a.frames()) + " frames)");
    joined_clip<T> out;
    out.motion = a.slice(0, trigger + 1);
    out.motion.append(t.frames);
    clip<T> b = clip<T>(a.skeleton(), t.placed_b.frames(), a.frame_time());
    for (std::size_t f = 0; f < b.frames(); ++f)
        for (std::size_t j = 0; j < b.joints(); ++j) {
            b.set_rotation(f, j, t.placed_b.rotation(f, j));
            if (b.skeleton().translation_slot(j) >= 0) b.set_translation(f, j, t.placed_b.translation(f, j));
        }
    out.motion.append(b);
    out.start_frame = trigger;
    out.end_frame = trigger + 1 + t.frames.frames();
    return out;
}

/// make_transition and join in one call.
template <class T>
joined_clip<T> transition_clips(const clip<T>& a, std::size_t trigger, const clip<T>& b, std::size_t b_start = 0,
                                const transition_params& params = {}) {
    return join(a, trigger, make_transition(a, trigger, b, b_start, params));
}

}  // namespace anima
