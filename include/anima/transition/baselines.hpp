// Transitions the variable-timing method is compared with:
//   direct_cut     B starts on the frame after A's trigger (no transition);
//   crossfade      A keeps playing while B fades in over a fixed time;
//   inertialize    B starts at once, and the difference between A and B at the
//                  switch (pose offset and its velocity) decays to zero with a
//                  critically damped spring, as game engines do.
// All place B with its heading turned to A's and its root continuing A's
// root, like the variable-timing transition, and return a joined_clip.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/core/nondeduced.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/resample.hpp>
#include <anima/rotation/exp_log.hpp>
#include <anima/rotation/slerp.hpp>
#include <anima/transition/classify.hpp>
#include <anima/transition/placement.hpp>
#include <anima/transition/variable_timing_transition.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace anima {
namespace detail {

/// Checks shared by the baselines; resamples B to A's frame time if needed
/// and places it so that its start frame is at A's trigger root position,
/// moved on by one frame of A's root velocity, heading aligned. The up axis
/// is guessed from A's skeleton unless given.
template <class T>
clip<T> place_after(const clip<T>& a, std::size_t trigger, const clip<T>& b_in, std::size_t b_start,
                    std::optional<signed_axis> up_axis, const char* who) {
    check_same_hierarchy(a.skeleton(), b_in.skeleton());
    if (a.joints() == 0) throw invalid_argument(std::string(who) + ": the clips have no joints");
    if (trigger >= a.frames() || b_start >= b_in.frames())
        throw invalid_argument(std::string(who) + ": trigger frame " + std::to_string(trigger) + " of " +
                               std::to_string(a.frames()) + " or start frame " + std::to_string(b_start) + " of " +
                               std::to_string(b_in.frames()) + " out of range");
    clip<T> b = b_in;
    if (std::abs(b.frame_time() - a.frame_time()) > T(1e-9) * a.frame_time()) {
        b = resample(b_in, a.frame_time());
        b_start = resampled_frame(b_start, b_in.frame_time(), b);
    }
    const signed_axis up = up_axis ? *up_axis : guess_up_axis(a.skeleton()).up;
    const Eigen::Matrix<T, 3, 1> u = axis_vector<T>(up);
    const Eigen::Quaternion<T> turn = heading_change(b.rotation(b_start, 0), a.rotation(trigger, 0), up);
    Eigen::Matrix<T, 3, 1> start = a.root_position(trigger);
    if (a.skeleton().translation_slot(0) >= 0 && trigger > 0)
        start += a.root_position(trigger) - a.root_position(trigger - 1);
    // Keep B's own height above its ground.
    start += (b.root_position(b_start).dot(u) - start.dot(u)) * u;
    clip<T> placed = place_clip(b, b_start, turn, start);
    clip<T> out(a.skeleton(), placed.frames(), a.frame_time());
    for (std::size_t f = 0; f < placed.frames(); ++f)
        for (std::size_t j = 0; j < placed.joints(); ++j) {
            out.set_rotation(f, j, placed.rotation(f, j));
            if (out.skeleton().translation_slot(j) >= 0) out.set_translation(f, j, placed.translation(f, j));
        }
    return out;
}

}  // namespace detail

/// A[0..trigger] followed at once by the placed B.
template <class T>
joined_clip<T> direct_cut(const clip<T>& a, std::size_t trigger, const clip<T>& b, std::size_t b_start = 0,
                          std::optional<signed_axis> up = std::nullopt) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    const clip<T> pb = detail::place_after(a, trigger, b, b_start, up, "anima::direct_cut");
    joined_clip<T> out;
    out.motion = a.slice(0, trigger + 1);
    out.motion.append(pb);
    out.start_frame = trigger;
    out.end_frame = trigger + 1;
    return out;
}

/// A[0..trigger], then `duration` seconds in which A (continuing past the
/// trigger, holding its last frame if it ends) and the placed B play together
/// with B's weight rising linearly, then the rest of B. Rotations blend by
/// slerp, translations linearly.
template <class T>
joined_clip<T> crossfade(const clip<T>& a, std::size_t trigger, const clip<T>& b, std::size_t b_start,
                         nondeduced_t<T> duration,
                         std::optional<signed_axis> up = std::nullopt) {
    check_non_negative("anima::crossfade", "duration", duration);
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    const clip<T> pb = detail::place_after(a, trigger, b, b_start, up, "anima::crossfade");
    // Steps of the blend, counted in T: a long duration need not fit a size_t.
    const T steps = std::max(T(1), std::round(duration / a.frame_time()));
    joined_clip<T> out;
    out.motion = a.slice(0, trigger + 1);
    // At least one frame of B must follow the blend: it is where B takes over.
    const std::size_t blended = steps - T(1) < static_cast<T>(pb.frames() - 1)
                                    ? static_cast<std::size_t>(steps) - 1
                                    : pb.frames() - 1;
    clip<T> blend(a.skeleton(), blended, a.frame_time());
    // A continues from its own root path; B was placed one frame ahead of the
    // trigger, so B's frame k - 1 lines up with A's frame trigger + k.
    for (std::size_t k = 1; k <= blend.frames(); ++k) {
        const T w = static_cast<T>(k) / steps;
        const std::size_t fa = std::min(trigger + k, a.frames() - 1), fb = k - 1;
        for (std::size_t j = 0; j < a.joints(); ++j) {
            blend.set_rotation(k - 1, j, slerp(a.rotation(fa, j), pb.rotation(fb, j), w));
            if (a.skeleton().translation_slot(j) >= 0)
                blend.set_translation(k - 1, j, (T(1) - w) * a.translation(fa, j) + w * pb.translation(fb, j));
        }
    }
    out.motion.append(blend);
    if (blend.frames() < pb.frames()) out.motion.append(pb.slice(blend.frames(), pb.frames()));
    out.start_frame = trigger;
    out.end_frame = trigger + 1 + blend.frames();
    return out;
}

/// Critically damped decay of an offset x0 with velocity v0 towards zero:
/// x(t) = (x0 + (v0 + y x0) t) e^(-y t), y = 2 ln 2 / halflife. Written with
/// y t so that a half-life far below t (y overflowing y x0) decays to 0
/// rather than to inf * 0.
template <class V, class T>
V spring_decay(const V& x0, const V& v0, T halflife, T t) {
    const T yt = T(2) * T(0.69314718055994530942) / halflife * t;
    const T decay = std::exp(-yt);
    if (decay == T(0)) return x0 * T(0);
    return (x0 + v0 * t + x0 * yt) * decay;
}

/// A[0..trigger] followed at once by the placed B, corrected by offsets that
/// start at (A - B) at the switch, with velocity (A's - B's), and decay with a
/// critically damped spring of the given half-life. Rotation offsets are
/// rotation vectors in the parent frame, q = exp(offset / 2) * q_B. The
/// transition ends (end_frame) when the rotation offsets have all fallen below
/// 1% of the largest one at the switch, and the root offset below 1% of its own.
template <class T>
joined_clip<T> inertialize(const clip<T>& a, std::size_t trigger, const clip<T>& b, std::size_t b_start,
                           nondeduced_t<T> halflife,
                           std::optional<signed_axis> up = std::nullopt) {
    // Normal: a subnormal half-life would overflow 1 / halflife.
    check_argument(halflife >= std::numeric_limits<T>::min() && std::isfinite(halflife), "anima::inertialize",
                   "halflife", "positive, normal and finite", halflife);
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    using vec3 = Eigen::Matrix<T, 3, 1>;
    using quat = Eigen::Quaternion<T>;
    const clip<T> pb = detail::place_after(a, trigger, b, b_start, up, "anima::inertialize");
    const T dt = a.frame_time();
    const std::size_t nj = a.joints();
    // Offsets at the switch: B's frame 0 stands where A's next frame would be.
    std::vector<vec3> x0(nj), v0(nj);
    const std::size_t prev = trigger > 0 ? trigger - 1 : trigger;
    for (std::size_t j = 0; j < nj; ++j) {
        // A extrapolated one frame: q_A(t+1) ~ q_A(t) (q_A(t-1)^-1 q_A(t)).
        const quat qa = a.rotation(trigger, j);
        const quat step = a.rotation(prev, j).conjugate() * qa;
        const quat qa_next = qa * step;
        x0[j] = to_rotation_vector(quat(qa_next * pb.rotation(0, j).conjugate()));
        const quat pb1 = pb.rotation(pb.frames() > 1 ? 1 : 0, j);
        const vec3 x1 = to_rotation_vector(quat(qa_next * step * pb1.conjugate()));
        v0[j] = (x1 - x0[j]) / dt;
    }
    vec3 root_x0 = vec3::Zero(), root_v0 = vec3::Zero();
    const bool translated = a.skeleton().translation_slot(0) >= 0;
    if (translated && trigger > 0 && pb.frames() > 1) {
        const vec3 va = a.root_position(trigger) - a.root_position(prev);
        const vec3 a_next = a.root_position(trigger) + va;
        root_x0 = a_next - pb.root_position(0);
        root_v0 = ((a_next + va) - pb.root_position(1) - root_x0) / dt;
    }
    // Rotations (rad) and the root (length units) settle separately.
    T largest_rotation = 0;
    for (const auto& x : x0) largest_rotation = std::max(largest_rotation, x.norm());
    const T largest_root = root_x0.norm();

    joined_clip<T> out;
    out.motion = a.slice(0, trigger + 1);
    clip<T> tail = pb;
    std::size_t settled = pb.frames();
    for (std::size_t f = 0; f < pb.frames(); ++f) {
        const T t = dt * static_cast<T>(f);
        T rotation_left = 0, root_left = 0;
        for (std::size_t j = 0; j < nj; ++j) {
            const vec3 x = spring_decay(x0[j], v0[j], halflife, t);
            rotation_left = std::max(rotation_left, x.norm());
            tail.set_rotation(f, j, quat(from_rotation_vector<quat>(x) * pb.rotation(f, j)));
        }
        if (translated) {
            const vec3 x = spring_decay(root_x0, root_v0, halflife, t);
            root_left = x.norm();
            tail.set_root_position(f, pb.root_position(f) + x);
        }
        if (settled == pb.frames() && rotation_left <= T(0.01) * largest_rotation && root_left <= T(0.01) * largest_root)
            settled = f;
    }
    out.motion.append(tail);
    out.start_frame = trigger;
    out.end_frame = trigger + 1 + std::min(settled, pb.frames() - 1);
    return out;
}

}  // namespace anima
