// Spherical quadrangle interpolation (Shoemake): a C1 curve through a sequence
// of orientations, built from slerps and one control point per key.
#pragma once

#include <anima/rotation/detail/angle_series.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>
#include <anima/rotation/slerp.hpp>

#include <cmath>
#include <type_traits>

namespace anima {

/// Control point s_i for key q_i with neighbours prev = q_{i-1}, next = q_{i+1}:
/// s_i = q_i exp(-(log(q_i^-1 q_{i+1}) + log(q_i^-1 q_{i-1})) / 4).
/// The neighbours are first moved to q_i's hemisphere, so the sign of the
/// inputs does not matter. At the ends of a sequence pass prev = q_i (or
/// next = q_i): the control point is then slerp(q_i, next, -1/4), a quarter
/// of the way back along the one real neighbour's arc, which starts the curve
/// towards that neighbour with the tangent of the segment.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
inline Q squad_control_point(const Q& prev, const Q& q, const Q& next) {
    using T = quat_scalar_t<Q>;
    const char* who = "anima::squad_control_point";
    const auto c_in = detail::load(q), p_in = detail::load(prev), n_in = detail::load(next);
    const detail::quat_lanes<T> lc = detail::to_lanes(c_in), lp = detail::to_lanes(p_in), ln = detail::to_lanes(n_in);
    T nc, np, nn, dp, dn, unused;
    detail::dot3_lanes(lc, lp, nc, np, dp);
    detail::dot3_lanes(ln, lc, nn, unused, dn);
    // The hemisphere test on the inputs as given, with the same dot product
    // as squad() uses for a segment: a key pair 180 degrees apart (a.b = 0 up
    // to rounding) then gets the same choice of arc in both places.
    const T sp = dp < T(0) ? T(-1) : T(1), sn = dn < T(0) ? T(-1) : T(1);
    detail::quat4<T> c, rp, rn;  // the key and the neighbours relative to it, unit, on its side
    if (std::abs(nc - T(1)) + std::abs(np - T(1)) + std::abs(nn - T(1)) <= detail::near_unit_tolerance<T>()) {
        // One Newton step on each length, applied to the products.
        const T gc = T(1.5) - T(0.5) * nc;
        c = c_in * gc;
        const auto ci = detail::conj4(c);
        rp = (ci * p_in) * ((T(1.5) - T(0.5) * np) * sp);
        rn = (ci * n_in) * ((T(1.5) - T(0.5) * nn) * sn);
    } else {
        c = detail::unit_or_throw(c_in, who);
        const auto ci = detail::conj4(c);
        rp = ci * (detail::unit_or_throw(p_in, who) * sp);
        rn = ci * (detail::unit_or_throw(n_in, who) * sn);
    }
    // Both relative rotations have w = c.n, c.p >= 0 and the sum of their logs
    // is at most pi in length: the polynomial log and exp of angle_series.hpp
    // cover them without an arc tangent, sine or cosine.
    T a[3], b[3];
    detail::log_unit_right_half_pair(rn, rp, a, b);
    const T k = T(-0.25);
    return detail::store<Q>(c * detail::exp_pure_eighth_turn(k * (a[0] + b[0]), k * (a[1] + b[1]), k * (a[2] + b[2])));
}

namespace detail {

/// squad4's general path, q2 and s2 already on q1's side: three slerps along
/// the arcs as given. Out of line, so that the fast path stays small.
template <class T>
ANIMA_COLD quat4<T> squad4_general(const quat4<T>& q1, const quat4<T>& q2, const quat4<T>& s1, const quat4<T>& s2,
                                   T t) {
    const char* who = "anima::squad";
    const quat4<T> a = slerp4(q1, q2, t, arc::as_given, who, false);
    const quat4<T> b = slerp4(s1, s2, t, arc::as_given, who, false);
    return slerp4(a, b, T(2) * t * (T(1) - t), arc::as_given, who);
}

/// Squad on 4-vectors. q2 is taken on q1's side (the shorter arc of the
/// segment) and s2 follows it: s2 was built on q2's side, so when q2 is
/// negated s2 is too. The blends then follow the arcs as given: a shortest-arc
/// choice of their own would send the curve the long way round when the
/// control points are more than 90 degrees (4-vector angle) apart, which
/// happens for keys more than 120 degrees apart.
template <class T>
inline quat4<T> squad4(const quat4<T>& q1, const quat4<T>& q2, const quat4<T>& s1, const quat4<T>& s2, T t) {
    const char* who = "anima::squad";
    const quat_lanes<T> lq1 = to_lanes(q1), lq2 = to_lanes(q2), ls1 = to_lanes(s1), ls2 = to_lanes(s2);
    T n1, n2, m1, m2, dq, ds_given;
    dot3_lanes(lq1, lq2, n1, n2, dq);
    dot3_lanes(ls1, ls2, m1, m2, ds_given);
    const T side = dq < T(0) ? T(-1) : T(1), ds = ds_given * side;
    // Fast path, one test: all four inputs near unit length, t in [0, 1], and
    // the control points' arc (on the keys' side) at most 90 degrees. The two
    // inner blends share t, so their four series run in the lanes together;
    // the series are exact down to a zero angle, so small angles need no
    // branch of their own.
    if (std::abs(n1 - T(1)) + std::abs(n2 - T(1)) + std::abs(m1 - T(1)) + std::abs(m2 - T(1)) <=
            near_unit_tolerance<T>() &&
        t * (T(1) - t) >= T(0) && ds >= T(0)) {
        const T g1 = T(1.5) - T(0.5) * n1, g2 = (T(1.5) - T(0.5) * n2) * side;
        const T h1 = T(1.5) - T(0.5) * m1, h2 = (T(1.5) - T(0.5) * m2) * side;
        T k0[2], k1[2];
        slerp_weights<T, 2>({dq * g1 * g2, ds * h1 * h2 * side}, t, k0, k1);
        const quat4<T> a = from_lanes(blend_lanes(lq1, k0[0] * g1, lq2, k1[0] * g2));
        const quat4<T> b = from_lanes(blend_lanes(ls1, k0[1] * h1, ls2, k1[1] * h2));
        return slerp4(a, b, T(2) * t * (T(1) - t), arc::as_given, who);
    }
    return squad4_general(q1, dq < T(0) ? -q2 : q2, s1, dq < T(0) ? -s2 : s2, t);
}

}  // namespace detail

/// Squad between keys q1 (t = 0) and q2 (t = 1) with control points s1, s2:
/// slerp(slerp(q1, q2, t), slerp(s1, s2, t), 2t(1 - t)), along the shorter
/// arc from q1 to q2 (q2 and s2 are negated together when q1.q2 < 0), with
/// the inner blends on the same side. Passes through q1 and q2 exactly; with
/// control points from squad_control_point consecutive segments join with
/// continuous angular velocity, and a segment of any angle up to 180 degrees
/// turns monotonically from q1 to q2. Inputs of any non-zero finite length
/// are normalised; throws anima::invalid_argument for a zero or non-finite
/// quaternion or t.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
inline Q squad(const Q& q1, const Q& q2, const Q& s1, const Q& s2, quat_scalar_t<Q> t) {
    return detail::store<Q>(
        detail::squad4(detail::load(q1), detail::load(q2), detail::load(s1), detail::load(s2), t));
}

}  // namespace anima
