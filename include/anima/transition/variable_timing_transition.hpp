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
//      when either clip is space flight (Eq 13), with v and a measured at the
//      trigger; the vertical part is corrected linearly in t to land on B's
//      start height, so a flight path stays a parabola with the given gravity;
//   5. place B where the transition ends, heading aligned: no jump.
#pragma once

#include <anima/core/constants.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/resample.hpp>
#include <anima/rotation/lerp.hpp>
#include <anima/rotation/quaternion.hpp>
#include <anima/rotation/slerp.hpp>
#include <anima/rotation/squad.hpp>
#include <anima/transition/classify.hpp>
#include <anima/motion/joint_roles.hpp>
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

inline std::string_view to_string(interpolation m) {
    static constexpr std::string_view names[] = {"automatic", "lerp", "slerp", "squad"};
    return names[static_cast<int>(m)];
}

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
};

template <class T>
struct transition {
    clip<T> frames;       ///< the in-between frames (strictly between A's trigger and B's start)
    T duration = 0;       ///< s: T rounded to whole frames (frames.frames() + 1 steps)
    timing_result<T> timing;
    std::vector<interpolation> methods;  ///< per joint, as used
    easing parameter = easing::ease_in_out;
    motion_classification class_a, class_b;
    bool flight = false;                 ///< Eq 13 used for the root
    point_motion<T> root_at_trigger;     ///< v and a of Eq 12-13
    clip<T> placed_b;                    ///< B from its start frame, heading aligned, placed where the transition ends
};

/// The transition from frame `trigger` of a to frame `b_start` of b. The
/// clips must share a hierarchy (names, parents, position channels); bone
/// lengths may differ and the output uses A's skeleton. B is resampled to
/// A's frame time when they differ.
template <class T>
transition<T> make_transition(const clip<T>& a, std::size_t trigger, const clip<T>& b_in, std::size_t b_start = 0,
                              const transition_params& params = {}) {
    check_same_hierarchy(a.skeleton(), b_in.skeleton());
    if (trigger >= a.frames())
        throw invalid_argument("anima::make_transition: trigger frame " + std::to_string(trigger) +
                               " is outside clip A (" + std::to_string(a.frames()) + " frames)");
    if (b_start >= b_in.frames())
        throw invalid_argument("anima::make_transition: start frame " + std::to_string(b_start) +
                               " is outside clip B (" + std::to_string(b_in.frames()) + " frames)");
    if (!params.roles.empty() && params.roles.size() != a.joints())
        throw invalid_argument("anima::make_transition: " + std::to_string(params.roles.size()) + " roles for " +
                               std::to_string(a.joints()) + " joints");
    if (!params.methods.empty() && params.methods.size() != a.joints())
        throw invalid_argument("anima::make_transition: " + std::to_string(params.methods.size()) +
                               " interpolation methods for " + std::to_string(a.joints()) + " joints");
    if (!(params.large_angle >= 0) || !(params.gravity >= 0) || !std::isfinite(params.gravity_factor) ||
        !(params.root_window >= 0))
        throw invalid_argument("anima::make_transition: large_angle and gravity must be non-negative");
    const bool resampled = std::abs(b_in.frame_time() - a.frame_time()) > T(1e-9) * a.frame_time();
    const clip<T> b_resampled = resampled ? resample(b_in, a.frame_time()) : clip<T>();
    const clip<T>& b = resampled ? b_resampled : b_in;
    if (resampled) b_start = detail::resampled_frame(b_start, b_in.frame_time(), b);

    using vec3 = Eigen::Matrix<T, 3, 1>;
    using quat = Eigen::Quaternion<T>;
    transition<T> out;
    const auto roles = params.roles.empty() ? joint_roles(a.skeleton()) : params.roles;
    out.class_a = params.class_a ? *params.class_a : classify_motion(a, roles, params.classification);
    classify_params cb = params.classification;
    cb.up = out.class_a.up;  // one world for both clips
    cb.metres_per_unit = out.class_a.metres_per_unit;
    out.class_b = params.class_b ? *params.class_b : classify_motion(b, roles, cb);
    const signed_axis up = out.class_a.up;
    const vec3 up_vec = axis_vector<T>(up);
    const T dt = a.frame_time();
    const bool spot = out.class_a.type == motion_class::on_the_spot && out.class_b.type == motion_class::on_the_spot;
    out.flight = out.class_a.type == motion_class::space_flight || out.class_b.type == motion_class::space_flight;
    out.parameter = params.parameter ? *params.parameter : (spot ? easing::linear : easing::ease_in_out);

    // Heading and timing.
    const quat turn = heading_change(b.rotation(b_start, 0), a.rotation(trigger, 0), up);
    out.timing = variable_timing(a, trigger, b, b_start, roles, turn, params.timing);
    const auto steps = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(out.timing.duration / dt)));
    out.duration = dt * static_cast<T>(steps);

    // Root path (Eq 12 / Eq 13) and B's placement at its end.
    const bool translated = a.skeleton().translation_slot(0) >= 0;
    out.root_at_trigger = translated ? root_motion_at(a, trigger, static_cast<std::size_t>(std::lround(params.root_window / static_cast<double>(dt))) + 1) : point_motion<T>{};
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
    out.placed_b = place_clip(b, b_start, turn, end);

    // Per-joint methods.
    out.methods.resize(a.joints());
    for (std::size_t j = 0; j < a.joints(); ++j) {
        const interpolation chosen = params.methods.empty() ? interpolation::automatic : params.methods[j];
        if (chosen != interpolation::automatic) out.methods[j] = chosen;
        else if (roles[j] == joint_role::finger) out.methods[j] = interpolation::lerp;
        else if (out.timing.joints[j].angle >= static_cast<T>(params.large_angle)) out.methods[j] = interpolation::squad;
        else out.methods[j] = interpolation::slerp;
    }

    // The in-between frames.
    const clip<T>& pb = out.placed_b;
    out.frames = clip<T>(a.skeleton(), steps - 1, dt);
    std::vector<quat> s1(a.joints()), s2(a.joints());
    for (std::size_t j = 0; j < a.joints(); ++j) {
        if (out.methods[j] != interpolation::squad) continue;
        const quat& q1 = a.rotation(trigger, j);
        const quat& q2 = pb.rotation(0, j);
        const quat& before = a.rotation(trigger > 0 ? trigger - 1 : trigger, j);
        const quat& after = pb.rotation(pb.frames() > 1 ? 1 : 0, j);
        s1[j] = squad_control_point(before, q1, q2);
        s2[j] = squad_control_point(q1, q2, after);
    }
    for (std::size_t k = 1; k < steps; ++k) {
        const T t = dt * static_cast<T>(k);
        const T h = interpolation_parameter(t, out.duration, out.parameter);
        const T h_linear = interpolation_parameter(t, out.duration, easing::linear);
        for (std::size_t j = 0; j < a.joints(); ++j) {
            const quat& q1 = a.rotation(trigger, j);
            const quat q2 = align_hemisphere(pb.rotation(0, j), q1);
            quat q;
            switch (out.methods[j]) {
                case interpolation::lerp: q = anima::lerp(q1, q2, roles[j] == joint_role::finger ? h_linear : h); break;
                // B's rotation as it is: s2 was built on its side, and squad
                // moves the two together to q1's side.
                case interpolation::squad: q = squad(q1, pb.rotation(0, j), s1[j], s2[j], h); break;
                default: q = slerp(q1, q2, h); break;
            }
            out.frames.set_rotation(k - 1, j, q);
            if (j > 0 && a.skeleton().translation_slot(j) >= 0)
                out.frames.set_translation(k - 1, j, (T(1) - h) * a.translation(trigger, j) + h * pb.translation(0, j));
        }
        if (translated) {
            // Linear-in-t vertical correction: keeps Eq 13's second derivative.
            vec3 p = predicted(t);
            p += (t / out.duration) * (end_height - predicted_height) * up_vec;
            out.frames.set_root_position(k - 1, p);
        }
    }
    return out;
}

/// A clip made of two clips and the frames joining them.
template <class T>
struct joined_clip {
    clip<T> motion;
    std::size_t start_frame = 0;  ///< last frame of A in `motion`
    std::size_t end_frame = 0;    ///< first frame of (placed) B in `motion`
};

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
