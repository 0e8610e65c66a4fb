// Spherical linear interpolation: constant angular speed along the shorter arc.
//
// How it is computed. For unit inputs at 4-vector angle theta (cos theta =
// a.b >= 0 after the shortest-arc flip) the result is k0 a + k1 b with
// k1 = sin(t theta) / sin(theta) and k0 the same with 1 - t. Both weights
// come from the power series of detail/angle_series.hpp, with no sine or arc
// cosine: when 1 - cos(theta) is below sqrt(epsilon), two terms of the
// series in cos(theta) - 1; below 0.3 (float, 8 terms) or 0.2 (double, 16
// terms), more terms of the same series (fewer for small angles: 2 or 3 in
// float, 4 or 7 in double below 1/1024 or 1/64); above, the series in
// cos(theta/4) - 1 (two half-angle square roots, one division, 5 or 10
// terms). Near theta = 0 the series are exact, so t is honoured at every
// angle and identical inputs need no special case. The series for t and
// 1 - t are evaluated side by side in the lanes of one vector, and the dot
// products (all three sharing one reduction) and the blend run on the
// quaternion as a vector (detail/lanes.hpp: GCC/Clang vector types, a plain
// array elsewhere). Outside the two-term range the result's length is
// corrected from the weights (|k0 a + k1 b|^2 = k0^2 + k1^2 + 2 k0 k1
// cos(theta)), by one Newton step; inside it the weights are exact to
// rounding and need no correction.
//
// The fast path takes inputs within sqrt(epsilon)/4 of unit length (one
// Newton step brings them to unit length inside the weights) and t in
// [0, 1], decided by one test on the sum of the two length errors and on
// t (1 - t) >= 0, which NaN and infinities fail. Anything else - extrapolation,
// quaternions far from unit length, zero or non-finite ones - goes to a
// general path that normalises with a scaled norm, uses sines, and throws
// anima::invalid_argument for inputs that are not rotations.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/rotation/detail/angle_series.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

namespace anima {
namespace detail {

/// Which of the two arcs between a and b a slerp follows.
enum class arc {
    shortest,  ///< b or -b, whichever is nearer a: the rotation's shorter way round
    as_given   ///< the great arc from a to b as they are (squad's inner blends)
};

/// What slerp_weights takes from the pairs alone (their a.b = d[m]), found
/// once for pairs blended at many parameters.
template <class T, int M>
struct slerp_weight_keys {
    bool direct = true;  ///< every 1 - d[m] within slerp_direct_limit: the series in d - 1
    /// Direct series only: the direct_series_tier of the largest 1 - d[m],
    /// for as few terms as suffice.
    int direct_tier = direct_series_tiers<T>;
    T y[M];              ///< d - 1 (direct), else c - 1 with c the cosine of a quarter of the angle
    T inverse[M];        ///< 1 (direct), else 1 / (c (2c^2 - 1)) = sin(phi) / sin(theta)
};

/// slerp_weights' part that depends on the pairs only.
template <class T, int M>
ANIMA_FORCE_INLINE slerp_weight_keys<T, M> prepare_slerp_weights(const T (&d)[M]) {
    slerp_weight_keys<T, M> k;
    k.direct_tier = 0;
    for (int m = 0; m < M; ++m) {
        k.direct = k.direct && T(1) - d[m] <= slerp_direct_limit<T>();  // NaN is not
        k.direct_tier = std::max(k.direct_tier, direct_series_tier(T(1) - d[m]));
    }
    for (int m = 0; m < M; ++m) {
        if (k.direct) {
            k.y[m] = d[m] - T(1);
            k.inverse[m] = T(1);
        } else {
            const T c = cos_quarter_angle(d[m]);
            k.y[m] = c - T(1);
            k.inverse[m] = T(1) / (c * (T(2) * c * c - T(1)));
        }
    }
    return k;
}

/// Slerp weights (k0[m] for a, k1[m] for b) of M pairs of unit quaternions
/// with a.b = d[m] in [0, 1] (a hair above 1 is fine), all at the same t in
/// [0, 1], from the pairs' keys (prepare_slerp_weights). The 2M series (t
/// and 1 - t for each pair) run side by side in the lanes of as few vectors
/// as hold them (one for up to two pairs of floats, one per pair of
/// doubles). When every 1 - d[m] is within slerp_direct_limit the series in
/// d - 1 itself is short enough: no square root or division. Otherwise the
/// angle is quartered first (two square roots and one division per pair, in
/// the keys). Exact as the angle tends to 0.
template <class T, int M>
ANIMA_FORCE_INLINE void slerp_weights(const slerp_weight_keys<T, M>& keys, T t, T (&k0)[M], T (&k1)[M]) {
    constexpr int width = lane_count<T>, vectors = (2 * M + width - 1) / width;
    T q[vectors * width]{}, y[vectors * width]{}, s[vectors * width]{};
    if (keys.direct) {
        const T t0 = T(1) - t;
        for (int m = 0; m < M; ++m) {
            q[2 * m] = t0 * t0;
            q[2 * m + 1] = t * t;
            y[2 * m] = y[2 * m + 1] = keys.y[m];
        }
        const auto series = [&](auto terms) {
            for (int v = 0; v < vectors; ++v) {
                const lanes<T> r =
                    angle_series_lanes<T, decltype(terms)::value>(load_lanes(q + v * width), load_lanes(y + v * width));
                for (int i = 0; i < width; ++i) s[v * width + i] = r[i];
            }
        };
        with_direct_series_terms<T>(keys.direct_tier, series);
        for (int m = 0; m < M; ++m) {
            k0[m] = t0 * s[2 * m];
            k1[m] = t * s[2 * m + 1];
        }
        return;
    }
    const T tau1 = T(4) * t, tau0 = T(4) - tau1;  // 4 - 4t is exact for t >= 1/2
    for (int m = 0; m < M; ++m) {
        q[2 * m] = tau0 * tau0;
        q[2 * m + 1] = tau1 * tau1;
        y[2 * m] = y[2 * m + 1] = keys.y[m];
    }
    for (int v = 0; v < vectors; ++v) {
        const lanes<T> r = angle_series_lanes<T>(load_lanes(q + v * width), load_lanes(y + v * width));
        for (int i = 0; i < width; ++i) s[v * width + i] = r[i];
    }
    for (int m = 0; m < M; ++m) {
        // k = tau sin(phi) S / sin(theta), sin(theta) / sin(phi) = 4c(2c^2 - 1), tau = 4t.
        k0[m] = (T(1) - t) * s[2 * m] * keys.inverse[m];
        k1[m] = t * s[2 * m + 1] * keys.inverse[m];
    }
}

/// slerp_weights of pairs blended once: the keys found on the way.
template <class T, int M>
ANIMA_FORCE_INLINE void slerp_weights(const T (&d)[M], T t, T (&k0)[M], T (&k1)[M]) {
    slerp_weights<T, M>(prepare_slerp_weights<T, M>(d), t, k0, k1);
}

/// Where 1 - cos(theta) is small enough for the two-term series of the weights.
template <class T>
constexpr T near_identity() {
    // A constexpr local: computed by the compiler, not by the square-root
    // loop on every call (which an unoptimised or -O1 build would run).
    constexpr T value = constexpr_sqrt(std::numeric_limits<T>::epsilon());
    return value;
}

/// Slerp weights for 1 - cos(theta) = -y at most near_identity: two terms
/// of the series in y itself, exact there (the third is under 2 y^2 / 15 <=
/// eps / 8). The factors of y depend on t alone, off the chain from the
/// inputs; the weights are exact to rounding and need no length correction.
template <class T>
ANIMA_FORCE_INLINE void near_identity_weights(T t, T y, T& k0, T& k1) {
    const T s = T(1) - t, p0 = s * (s * s - T(1)) * T(1.0L / 3), p1 = t * (t * t - T(1)) * T(1.0L / 3);
    k0 = s + p0 * y;
    k1 = t + p1 * y;
}

/// sin(k theta) / sin(theta), exact as theta -> 0 (where it tends to k).
template <class T>
T sin_ratio(T k, T theta) {
    if (theta < small_angle<T>()) return k * (T(1) + (T(1) - k * k) * theta * theta / T(6));
    return std::sin(k * theta) / std::sin(theta);
}

/// The general slerp: any t, inputs of any non-zero finite length (normalised
/// with a scaled norm), 4-vector angles up to pi for arc::as_given. Throws
/// anima::invalid_argument for a zero or non-finite quaternion or t.
template <class T>
quat4<T> slerp_general(const quat4<T>& a_in, const quat4<T>& b_in, T t, arc mode, const char* who) {
    if (!std::isfinite(t))
        throw invalid_argument(std::string(who) + ": t is not finite (" + detail::argument_text(t) + ")");
    const quat4<T> a = normalized_or_throw(a_in, who);
    quat4<T> b = normalized_or_throw(b_in, who);
    if (mode == arc::shortest && dot4(a, b) < T(0)) b = -b;
    // u = |a - b| = 2 sin(theta/2), v = |a + b| = 2 cos(theta/2): theta from
    // atan2 keeps full precision at both ends, and sin(theta) = uv/2.
    const T u = norm4(a - b), v = norm4(a + b);
    if (!(v > std::numeric_limits<T>::epsilon() * u)) return a;  // antipodal 4-vectors: the same rotation
    const T theta = T(2) * std::atan2(u, v);
    T k0, k1;
    if (theta < small_angle<T>()) {
        k0 = sin_ratio(T(1) - t, theta);
        k1 = sin_ratio(t, theta);
    } else {
        const T inv_sin = T(2) / (u * v);
        k0 = std::sin((T(1) - t) * theta) * inv_sin;
        k1 = std::sin(t * theta) * inv_sin;
    }
    const quat4<T> r = a * k0 + b * k1;
    return r * (T(1) / norm4(r));
}

/// slerp_general on inputs in lanes, which the fast path passes in
/// registers: the conversion back happens here, off the fast path.
template <class T>
ANIMA_COLD quat4<T> slerp_general_lanes(quat_lanes<T> a, quat_lanes<T> b, T t, arc mode, const char* who) {
    return slerp_general(from_lanes(a), from_lanes(b), t, mode, who);
}

/// Slerp of 4-vectors along the chosen arc. The result has unit length;
/// with `unit_result` false the fast path leaves it within a few epsilon of
/// it (enough for a caller that feeds it straight into another slerp, whose
/// Newton step on the inputs absorbs that).
template <class T>
ANIMA_FORCE_INLINE quat4<T> slerp4(const quat4<T>& a4, const quat4<T>& b4, T t, arc mode = arc::shortest,
                                   const char* who = "anima::slerp", bool unit_result = true) {
    constexpr T tolerance = near_unit_tolerance<T>();
    const quat_lanes<T> a = to_lanes(a4), b = to_lanes(b4);
    T na, nb, d;
    dot3_lanes(a, b, na, nb, d);
    // One test for the fast path: both inputs near unit length (NaN fails),
    // t in [0, 1] (t (1 - t) >= 0 fails for NaN and infinities too), and for
    // an arc as given an angle of at most 90 degrees.
    const T d_min = mode == arc::shortest ? T(-2) : T(0);
    if (!(std::abs(na - T(1)) + std::abs(nb - T(1)) <= tolerance && t * (T(1) - t) >= T(0) && d >= d_min))
        return slerp_general_lanes(a, b, t, mode, who);
    // One Newton step towards 1/|q| from 1: the inputs' length error drops
    // from at most sqrt(eps)/4 to below eps. It is folded into the weights.
    const T ga = T(1.5) - T(0.5) * na, gb = T(1.5) - T(0.5) * nb;
    // Shorter arc: -b when a.b < 0 (a select, not a branch).
    const T gbs = mode == arc::shortest && d < T(0) ? -gb : gb;
    const T cos_theta = std::abs(d) * ga * gb;
    T k0, k1;
    const T y = cos_theta - T(1);
    if (-y <= near_identity<T>()) {
        // theta below about eps^(1/4), nearly identical or nearly antipodal
        // inputs: no square root or division.
        near_identity_weights(t, y, k0, k1);
        return from_lanes(blend_lanes(a, k0 * ga, b, k1 * gbs));
    }
    T w0[1], w1[1];
    slerp_weights<T, 1>({cos_theta}, t, w0, w1);
    k0 = w0[0];
    k1 = w1[0];
    if (unit_result) {
        // |k0 a + k1 b|^2 for unit a, b, from the weights: one Newton step
        // towards its inverse square root takes out the weights' rounding
        // without a dot product of the result.
        const T g = T(1.5) - T(0.5) * (k0 * k0 + k1 * k1 + T(2) * k0 * k1 * cos_theta);
        k0 *= g;
        k1 *= g;
    }
    return from_lanes(blend_lanes(a, k0 * ga, b, k1 * gbs));
}

}  // namespace detail

/// Slerp from a (t = 0) to b (t = 1) along the shorter arc (b is negated when
/// a.b < 0). Accurate for identical and nearly identical inputs (t is
/// honoured at every angle: no early-out), finite for antipodal ones (which
/// are the same rotation). t outside [0, 1] extrapolates. Inputs of any
/// non-zero finite length are normalised first (a scaled norm, so 1e-200 or
/// 1e200 components work); the result is a unit quaternion. Throws
/// anima::invalid_argument for a zero or non-finite quaternion or t.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
inline Q slerp(const Q& a, const Q& b, quat_scalar_t<Q> t) {
    return detail::store<Q>(detail::slerp4(detail::load(a), detail::load(b), t));
}

}  // namespace anima
