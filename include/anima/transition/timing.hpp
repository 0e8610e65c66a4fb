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

#include <anima/core/check_argument.hpp>
#include <anima/core/constants.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/joint_roles.hpp>
#include <anima/rotation/detail/angle_series.hpp>
#include <anima/rotation/detail/lanes.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/exp_log.hpp>
#include <anima/rotation/quaternion.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace anima {

enum class timing_model : unsigned char { velocity, constant_acceleration };

template <>
struct enum_names<timing_model> {
    static constexpr const char* what = "timing model";
    static constexpr enum_entry<timing_model> entries[] = {{timing_model::velocity, "velocity"},
                                                           {timing_model::constant_acceleration, "acceleration"},
                                                           {timing_model::constant_acceleration, "constant_acceleration"}};
};

/// How time maps to the interpolation parameter h.
enum class easing : unsigned char {
    linear,      ///< h = t / T (Eq 10)
    ease_in_out  ///< 2 (t/T)^2, then 1 - 2 (t/T - 1)^2 (Eq 11): accelerate, then decelerate
};

template <>
struct enum_names<easing> {
    static constexpr const char* what = "easing";
    static constexpr enum_entry<easing> entries[] = {{easing::linear, "linear"}, {easing::ease_in_out, "ease_in_out"}};
};

/// h(t) for t in [0, total], clamped to [0, 1]; 1 when total <= 0. Throws
/// anima::invalid_argument for a NaN t or total.
template <class T>
T interpolation_parameter(T t, T total, easing e) {
    if (std::isnan(t) || std::isnan(total))
        throw invalid_argument("anima::interpolation_parameter: t and total must not be NaN, got " +
                               detail::argument_text(t) + " and " + detail::argument_text(total));
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
    /// Measure the angular speeds, accelerations and t_i of every joint, as
    /// reports show them. false: only of the key joints, which alone decide
    /// T (the others' speed, acceleration and time are then NaN, their angle
    /// is still measured): the same T for a fraction of the work, what a
    /// game loop wants.
    bool every_joint = true;
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

/// Whether a joint of this role is a key joint of the timing (root, leg
/// or foot): one that counts towards the transition's length.
constexpr bool key_joint_role(joint_role r) {
    return r == joint_role::root || r == joint_role::leg || r == joint_role::foot;
}

namespace detail {

/// phi / sin(phi) for every y = cos(phi) - 1 of a fixed-size array: the
/// series of angle_series at tau = 0 with `terms` terms, by the same Horner's
/// rule over pairs of terms.
template <int terms, class A>
A half_angle_ratio(const A& y) {
    using T = typename A::Scalar;
    static constexpr angle_series_coefficients<T, terms> s{};
    A r = A::Constant(T(1));
    for (int i = (terms % 2 == 0 ? terms - 1 : terms); i >= 1; i -= 2) {
        const A w = y * (-s.v[i]);
        if (i + 1 <= terms)
            r = T(1) + w + (w * (y * (-s.v[i + 1]))) * r;
        else
            r = T(1) + w;
    }
    return r;
}

/// Memory of joint_rates, kept from call to call.
template <class T>
struct rates_scratch {
    std::vector<T> q[4];  ///< window frames by component (w, x, y, z): q[c][f * joints + j]
    std::vector<T> w[3];  ///< angular velocity of each step: w[c][k * joints + j]
    std::vector<T> speed, change;  ///< |w| of each step; |w - the same joint's w a step before|
    std::vector<T> mean_speed, mean_acceleration;  ///< per measured joint: the results
    std::vector<std::size_t> picked;  ///< the joints measured, when not all
};

/// joint_rates' steps that the series does not cover (over 73 degrees, or of
/// quaternions not near unit length), as angular_velocity computes them,
/// and the speeds again where any was replaced.
template <class T>
void step_rates_outside_series(rates_scratch<T>& s, std::size_t count, std::size_t nj, T dt, T off_unit, T largest) {
    using array = Eigen::Array<T, Eigen::Dynamic, 1>;
    // Constants of the series' range, folded at compile time (near_unit_tolerance is a square root).
    constexpr T unit_tolerance = near_unit_tolerance<T>(), series_limit = direct_series_limit<T>();
    if (!(off_unit > unit_tolerance || largest > series_limit)) return;
    for (std::size_t i = 0; i < count; ++i) {
        const quat4<T> a{s.q[0][i], s.q[1][i], s.q[2][i], s.q[3][i]};
        const quat4<T> b{s.q[0][i + nj], s.q[1][i + nj], s.q[2][i + nj], s.q[3][i + nj]};
        const quat4<T> e = b * conj4(a);
        const T n2 = dot4(e, e);
        if (std::abs(n2 - T(1)) <= unit_tolerance && T(1) - std::abs(e.w) * (T(1.5) - T(0.5) * n2) <= series_limit)
            continue;
        const auto v = to_rotation_vector(store<Eigen::Quaternion<T>>(e));
        for (std::size_t m = 0; m < 3; ++m) s.w[m][i] = v[static_cast<int>(m)] * (T(1) / dt);
    }
    const auto size = static_cast<Eigen::Index>(count);
    const auto velocity = [&](int m) { return Eigen::Map<array>(s.w[static_cast<std::size_t>(m)].data(), size); };
    Eigen::Map<array>(s.speed.data(), size) = (velocity(0).square() + velocity(1).square() + velocity(2).square()).sqrt();
}

/// |w - the same joint's w a step before|, from the second step on; then
/// the means per joint (a row of the tables).
template <class T>
void mean_rates(rates_scratch<T>& s, std::size_t count, std::size_t nj, std::size_t steps, T dt) {
    using array = Eigen::Array<T, Eigen::Dynamic, 1>;
    using table = Eigen::Array<T, Eigen::Dynamic, Eigen::Dynamic>;
    const auto size = static_cast<Eigen::Index>(count), joints = static_cast<Eigen::Index>(nj);
    const auto velocity = [&](int m) { return Eigen::Map<array>(s.w[static_cast<std::size_t>(m)].data(), size); };
    const auto later = size - joints;
    s.change.resize(count);
    const auto difference = [&](int m) { return velocity(m).tail(later) - velocity(m).head(later); };
    Eigen::Map<array>(s.change.data(), later) =
        (difference(0).square() + difference(1).square() + difference(2).square()).sqrt();
    Eigen::Map<array>(s.mean_speed.data(), joints) =
        Eigen::Map<const table>(s.speed.data(), joints, static_cast<Eigen::Index>(steps)).rowwise().sum() /
        static_cast<T>(steps);
    if (steps > 1)
        Eigen::Map<array>(s.mean_acceleration.data(), joints) =
            Eigen::Map<const table>(s.change.data(), joints, static_cast<Eigen::Index>(steps - 1)).rowwise().sum() /
            dt / static_cast<T>(steps - 1);
}

/// Mean |angular velocity| and mean |angular acceleration| of every joint's
/// local rotation over the one-frame steps in [first, last] (clamped to the
/// clip), the root's rotations first turned by root_turn when it is given;
/// into s.mean_speed and s.mean_acceleration. With `picked`, only of the
/// joints it lists, in increasing order (the results in its order). Averaging over a short window
/// rather than reading one instant keeps a joint caught at the turning point
/// of its swing from looking still.
///
/// A step's angular velocity is angular_velocity's, the rotation vector of
/// q_(k+1) q_k^-1 over dt, here for all joints and steps at once in Eigen's
/// vectorised fixed-size arrays: with (w, v) the step's quaternion, w >= 0
/// (one Newton step brings it to unit length), the rotation vector is
/// 2 (phi / sin(phi)) v, phi / sin(phi) the series of angle_series.hpp in
/// y = w - 1: exact to rounding, with no arc tangent, square root or
/// division, and few terms for the small steps of 120 Hz motion (the number
/// is chosen once for all steps, from the largest). Steps over 73 degrees,
/// or of quaternions not near unit length, take angular_velocity's own path.
template <class T>
void joint_rates(const clip<T>& c, std::ptrdiff_t first, std::ptrdiff_t last, const Eigen::Quaternion<T>* root_turn,
                 const std::vector<std::size_t>* picked, rates_scratch<T>& s) {
    constexpr int width = 2 * lane_count<T>;  // steps at a time: two vectors
    using chunk = Eigen::Array<T, width, 1>;
    const std::size_t stride = c.joints(), nj = picked ? picked->size() : stride;
    s.mean_speed.assign(nj, T(0));
    s.mean_acceleration.assign(nj, T(0));
    const auto n = static_cast<std::ptrdiff_t>(c.frames());
    first = std::max<std::ptrdiff_t>(first, 0);
    last = std::min<std::ptrdiff_t>(last, n - 1);
    if (last - first < 1) {
        // One frame inside the window: widen to a neighbouring step if any.
        if (n < 2) return;
        first = std::min<std::ptrdiff_t>(first, n - 2);
        last = first + 1;
    }
    const auto steps = static_cast<std::size_t>(last - first);
    const std::size_t count = steps * nj, padded = (count + width - 1) / width * width;
    const T dt = c.frame_time(), scale = T(2) / dt;
    // The frames by component, the joints of a frame together as the clip
    // stores them; identities past the end, so that a last partial group of
    // steps is finite.
    for (auto& v : s.q) v.resize(padded + nj);
    const Eigen::Quaternion<T>* r = c.rotations().data() + static_cast<std::size_t>(first) * stride;
    const auto put = [&](std::size_t i, const Eigen::Quaternion<T>& q) {
        s.q[0][i] = q.w();
        s.q[1][i] = q.x();
        s.q[2][i] = q.y();
        s.q[3][i] = q.z();
    };
    if (!picked)
        for (std::size_t i = 0; i < count + nj; ++i) put(i, r[i]);
    else
        for (std::size_t f = 0, i = 0; f <= steps; ++f)
            for (std::size_t k = 0; k < nj; ++k, ++i) put(i, r[f * stride + (*picked)[k]]);
    for (std::size_t i = count + nj; i < padded + nj; ++i) put(i, Eigen::Quaternion<T>::Identity());
    // The root's rotations turned, where the root is measured.
    const std::size_t root =
        picked ? static_cast<std::size_t>(std::find(picked->begin(), picked->end(), 0) - picked->begin()) : 0;
    if (root_turn && root < nj)
        for (std::size_t f = 0; f <= steps; ++f) put(f * nj + root, *root_turn * r[f * stride]);
    // First pass: each step's quaternion e = b conj(a), its Newton factor
    // towards unit length, negated when e.w < 0 (the shorter way round), and
    // y = w - 1 of the unit step. e's vector part goes to w, y to speed, the
    // factor (times 2 / dt) to change, for the second pass.
    for (auto& v : s.w) v.resize(padded);
    s.speed.resize(padded);
    s.change.resize(padded);
    const auto at = [](const std::vector<T>& v, std::size_t from) { return Eigen::Map<const chunk>(v.data() + from); };
    const auto to = [](std::vector<T>& v, std::size_t from) { return Eigen::Map<chunk>(v.data() + from); };
    chunk off_unit = chunk::Zero(), lowest = chunk::Zero();
    for (std::size_t i = 0; i < padded; i += width) {
        const chunk aw = at(s.q[0], i), ax = at(s.q[1], i), ay = at(s.q[2], i), az = at(s.q[3], i);
        const chunk bw = at(s.q[0], i + nj), bx = at(s.q[1], i + nj), by = at(s.q[2], i + nj), bz = at(s.q[3], i + nj);
        // quat4's product, written out with its order of operations.
        const chunk ew = bw * aw + bx * ax + by * ay + bz * az, ex = bx * aw - bw * ax - by * az + bz * ay,
                    ey = bx * az - bw * ay + by * aw - bz * ax, ez = by * ax - (bw * az + bx * ay) + bz * aw;
        const chunk n2 = ew * ew + ex * ex + ey * ey + ez * ez;
        off_unit = off_unit.max((n2 - T(1)).abs());
        chunk g = T(1.5) - T(0.5) * n2;
        g = (ew < T(0)).select(-g, g);
        const chunk y = ew * g - T(1);
        lowest = lowest.min(y);
        to(s.w[0], i) = ex;
        to(s.w[1], i) = ey;
        to(s.w[2], i) = ez;
        to(s.speed, i) = y;
        to(s.change, i) = g * scale;
    }
    // Second pass, with as many terms as the largest step needs (steps up to
    // 5 degrees: 4 terms in double, 2 in float; direct_series_bounds gives
    // the other tiers): w = 2 (phi / sin(phi)) v / dt, and |w|.
    const T largest = -lowest.minCoeff();
    const auto finish = [&](auto terms) {
        for (std::size_t i = 0; i < padded; i += width) {
            const chunk h = half_angle_ratio<decltype(terms)::value>(chunk(at(s.speed, i))) * at(s.change, i);
            const chunk wx = h * at(s.w[0], i), wy = h * at(s.w[1], i), wz = h * at(s.w[2], i);
            to(s.w[0], i) = wx;
            to(s.w[1], i) = wy;
            to(s.w[2], i) = wz;
            to(s.speed, i) = (wx * wx + wy * wy + wz * wz).sqrt();
        }
    };
    with_direct_series_terms<T>(direct_series_tier(largest), finish);
    step_rates_outside_series(s, count, nj, dt, off_unit.maxCoeff(), largest);
    mean_rates(s, count, nj, steps, dt);
}

/// The checks of timing_params; the errors name `who`.
inline void check_timing_params(const timing_params& p, const char* who) {
    check_non_negative(who, "timing_params::min_duration", p.min_duration);
    if (!(p.max_duration >= p.min_duration) || !std::isfinite(p.max_duration))
        fail_argument(who, "timing_params::max_duration",
                      "finite and at least min_duration (" + argument_text(p.min_duration) + ")", p.max_duration);
    check_positive(who, "timing_params::min_speed", p.min_speed);
    check_positive(who, "timing_params::min_acceleration", p.min_acceleration);
    check_non_negative(who, "timing_params::speed_window", p.speed_window);
}

/// variable_timing into `out`, whose joint vector is reused, with `scratch`
/// kept from call to call.
template <class T>
void variable_timing_into(const clip<T>& a, std::size_t trigger, const clip<T>& b, std::size_t b_start,
                          const std::vector<joint_role>& roles, const Eigen::Quaternion<T>& b_root_turn,
                          const timing_params& params, timing_result<T>& out, rates_scratch<T>& scratch) {
    if (trigger >= a.frames() || b_start >= b.frames())
        throw invalid_argument("anima::variable_timing: trigger frame " + std::to_string(trigger) + " of " +
                               std::to_string(a.frames()) + " or start frame " + std::to_string(b_start) + " of " +
                               std::to_string(b.frames()) + " out of range");
    if (roles.size() != a.joints() || a.joints() != b.joints())
        throw invalid_argument("anima::variable_timing: roles, clip A and clip B must have the same joint count");
    check_timing_params(params, "anima::variable_timing");
    const auto turn = store<Eigen::Quaternion<T>>(normalized_or_throw(load(b_root_turn), "anima::variable_timing: b_root_turn"));
    const std::size_t nj = a.joints();
    out.joints.resize(nj);
    out.limiting_joint = 0;
    const auto window = std::max<std::ptrdiff_t>(
        1, static_cast<std::ptrdiff_t>(std::lround(params.speed_window / static_cast<double>(a.frame_time()))));
    const std::vector<std::size_t>* picked = nullptr;
    if (!params.every_joint) {
        scratch.picked.clear();
        for (std::size_t j = 0; j < nj; ++j)
            if (key_joint_role(roles[j])) scratch.picked.push_back(j);
        picked = &scratch.picked;
    }
    // The speeds of joint j (all joints) or of the k-th picked joint, NaN
    // for a joint not measured.
    constexpr T unmeasured = std::numeric_limits<T>::quiet_NaN();
    for (auto& jt : out.joints) jt.speed_a = jt.speed_b = jt.acceleration_a = jt.acceleration_b = unmeasured;
    const auto joint_of = [&](std::size_t k) { return picked ? (*picked)[k] : k; };
    const std::size_t measured = picked ? picked->size() : nj;
    joint_rates(a, static_cast<std::ptrdiff_t>(trigger) - window, static_cast<std::ptrdiff_t>(trigger),
                static_cast<const Eigen::Quaternion<T>*>(nullptr), picked, scratch);
    for (std::size_t k = 0; k < measured; ++k) {
        out.joints[joint_of(k)].speed_a = scratch.mean_speed[k];
        out.joints[joint_of(k)].acceleration_a = scratch.mean_acceleration[k];
    }
    joint_rates(b, static_cast<std::ptrdiff_t>(b_start), static_cast<std::ptrdiff_t>(b_start) + window, &turn,
                picked, scratch);
    for (std::size_t k = 0; k < measured; ++k) {
        out.joints[joint_of(k)].speed_b = scratch.mean_speed[k];
        out.joints[joint_of(k)].acceleration_b = scratch.mean_acceleration[k];
    }
    T longest = -1;
    for (std::size_t j = 0; j < nj; ++j) {
        auto& jt = out.joints[j];
        jt.joint = j;
        jt.role = roles[j];
        jt.key = key_joint_role(roles[j]);
        // Only the root is turned.
        const Eigen::Quaternion<T>& b_pose = b.rotation(b_start, j);
        jt.angle = angle_between(a.rotation(trigger, j), j == 0 ? Eigen::Quaternion<T>(turn * b_pose) : b_pose);
        if (!params.every_joint && !jt.key) {
            jt.time = unmeasured;
        } else if (params.model == timing_model::velocity) {
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
    const flush_denormals guard;  // see make_transition_into
    timing_result<T> out;
    detail::rates_scratch<T> scratch;
    detail::variable_timing_into(a, trigger, b, b_start, roles, b_root_turn, params, out, scratch);
    return out;
}

}  // namespace anima
