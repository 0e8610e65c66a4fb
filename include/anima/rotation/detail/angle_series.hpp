// Polynomial replacements for the trigonometric functions of slerp, log and
// exp on the angles squad and slerp meet (4-vector angles up to about 90
// degrees), so that the hot paths call no sine, cosine or arc tangent.
//
// With theta an angle of cosine d, phi = theta / 4 and c = cos(phi) (two
// half-angle square roots of d), sin(theta) / sin(phi) is the polynomial
// 4c(2c^2 - 1), and sin(tau phi) / (tau sin(phi)) is a power series in
// y = c - 1 whose coefficients follow from the Chebyshev differential
// equation (the idea of Eberly's "A Fast and Accurate Algorithm for
// Computing SLERP", with two halvings of the angle instead of one so that
// few terms suffice): with u_i = 1/(i(2i+1)) and v_i = i/(2i+1),
//   sin(tau phi) / (tau sin(phi)) = 1 + w_1 (1 + w_2 (1 + ...)),  w_i = (tau^2 u_i - v_i) y.
// For theta <= pi/2, |y| <= 1 - cos(pi/8) and each term is about 26 times
// smaller than the one before when tau <= 4: 5 terms reach float precision,
// 10 double precision. tau = 0 gives phi / sin(phi), hence theta / sin(theta),
// the factor of a quaternion logarithm. Near theta = 0 the series is exact.
// For small angles the series in cos(theta) - 1 itself is short enough and
// needs no square root (direct_series_terms). The series are evaluated in
// the lanes of a vector (detail/lanes.hpp), several at once.
#pragma once

#include <anima/rotation/detail/lanes.hpp>
#include <anima/rotation/detail/quat4.hpp>

#include <cmath>
#include <limits>
#include <type_traits>

namespace anima::detail {

/// The same series taken directly in y = cos(theta) - 1 (no halving of the
/// angle, tau = t in [0, 1] or 0 for a logarithm) needs no square root or
/// division. Term i is at most v_1 ... v_i |y|^i (|tau^2 u_i - v_i| <= v_i),
/// so with these many terms and -y up to direct_series_limit the first
/// omitted one is below epsilon / 8: float 8 terms to 1 - cos(theta) = 0.3
/// (4-vector angles up to 45.6 degrees, rotations up to 91: squad's key
/// steps of up to 90 degrees take no square root, and its branch does not
/// depend on the step), double 16 terms to 0.2 (36.8 and 73.7 degrees),
/// wider scalars 16 terms to 0.1.
template <class T>
constexpr int direct_series_terms() {
    return std::numeric_limits<T>::digits <= 24 ? 8 : 16;
}
template <class T>
constexpr T direct_series_limit() {
    constexpr int digits = std::numeric_limits<T>::digits;
    return digits <= 24 ? T(0.3) : digits <= 53 ? T(0.2) : T(0.1);
}

/// Where slerp's weights take the direct series rather than the quartered
/// angle's (two square roots and a division, then angle_series_terms: 10
/// terms in double, 5 in float). In double that is the third tier, 1/16:
/// beyond it the direct series needs 13 to 16 terms, more than the roots
/// cost, and a pair blended at many parameters pays them only once. In
/// float direct_series_limit: its 8 terms cost less than the roots.
template <class T>
constexpr T slerp_direct_limit() {
    return std::numeric_limits<T>::digits <= 24 ? direct_series_limit<T>() : T(1) / T(16);
}

/// Terms of the direct series (tau in [0, 1] or 0) that leave the first
/// omitted one, at most v_1 ... v_(n+1) bound^(n+1), below epsilon / 8 for
/// -y <= bound: fewer than direct_series_terms for small angles, the usual
/// case of neighbouring frames and of slerps between nearby poses.
template <class T>
constexpr int direct_series_terms_within(T bound) {
    T term = 1;
    int n = 0;
    for (;; ++n) {
        term *= bound * T(n + 1) / T(2 * n + 3);
        if (term < std::numeric_limits<T>::epsilon() / 8) return n;
    }
}

/// The bounds on -y = 1 - cos(theta) under which the direct series is cut
/// short, the tiers of direct_series_tier: 4-vector angles up to 2.5, 10.1,
/// 20.4 and 29.0 degrees (rotations up to 5, 20, 41 and 58 degrees); 4, 7,
/// 10 and 13 terms in double. Float uses the first two (2 and 3 terms): its
/// full series has only 8, and more tiers cost more in mispredicted
/// branches on mixed angles than they save. Beyond the last, up to
/// direct_series_limit, direct_series_terms.
template <class T>
inline constexpr T direct_series_bounds[4] = {T(1) / T(1024), T(1) / T(64), T(1) / T(16), T(1) / T(8)};
template <class T>
inline constexpr int direct_series_tiers = std::numeric_limits<T>::digits <= 24 ? 2 : 4;

/// The first tier whose bound -y is within (NaN: none), or
/// direct_series_tiers when it is beyond all.
template <class T>
int direct_series_tier(T minus_y) {
    int tier = 0;  // the bounds it is beyond, counted without branches
    for (int k = 0; k < direct_series_tiers<T>; ++k) tier += !(minus_y <= direct_series_bounds<T>[k]);
    return tier;
}

/// f(std::integral_constant<int, n>{}) with n the terms of the direct
/// series that a tier needs: one instance of the series per tier.
template <class T, int K = 0, class F>
ANIMA_FORCE_INLINE void with_direct_series_terms(int tier, F&& f) {
    if constexpr (K < direct_series_tiers<T>) {
        if (tier == K)
            f(std::integral_constant<int, direct_series_terms_within<T>(direct_series_bounds<T>[K])>{});
        else
            with_direct_series_terms<T, K + 1>(tier, f);
    } else {
        f(std::integral_constant<int, direct_series_terms<T>()>{});
    }
}

/// Number of series terms for tau <= 4, theta <= pi/2 that leaves the
/// truncation error below the scalar's rounding error.
template <class T>
constexpr int angle_series_terms() {
    constexpr int digits = std::numeric_limits<T>::digits;
    return digits <= 24 ? 5 : digits <= 53 ? 10 : 14;
}

/// u_i and v_i of the series, i = 1..N (index 0 unused).
template <class T, int N>
struct angle_series_coefficients {
    T u[N + 1]{};
    T v[N + 1]{};
    constexpr angle_series_coefficients() {
        for (int i = 1; i <= N; ++i) {
            u[i] = T(1) / T(i * (2 * i + 1));
            v[i] = T(i) / T(2 * i + 1);
        }
    }
};

/// cos(theta / 4) from d = cos(theta), d in [-1, 1] (a hair beyond is fine).
template <class T>
ANIMA_FORCE_INLINE T cos_quarter_angle(T d) {
    const T c2 = std::sqrt(T(0.5) + T(0.5) * d);  // cos(theta / 2)
    return std::sqrt(T(0.5) + T(0.5) * c2);
}

/// cos_quarter_angle in every lane (the square roots through sqrt_lanes).
template <class T>
ANIMA_FORCE_INLINE lanes<T> cos_quarter_angle_lanes(const lanes<T>& d) {
    const lanes<T> c2 = sqrt_lanes<T>(T(0.5) + d * T(0.5));
    return sqrt_lanes<T>(T(0.5) + c2 * T(0.5));
}

/// sin(tau phi) / (tau sin(phi)) for tau^2 = sq and y = cos(phi) - 1, by
/// Horner's rule over pairs of terms, 1 + w1 + w1 w2 (1 + w3 + w3 w4 (...)),
/// which halves the dependency chain.
template <class T>
T angle_series(T sq, T y) {
    constexpr int n = angle_series_terms<T>();
    static constexpr angle_series_coefficients<T, n> s{};
    T w[n + 2];
    for (int i = 1; i <= n; ++i) w[i] = (sq * s.u[i] - s.v[i]) * y;
    w[n + 1] = T(0);
    T a = T(1);
    for (int i = (n % 2 == 0 ? n - 1 : n); i >= 1; i -= 2) a = T(1) + w[i] + (w[i] * w[i + 1]) * a;
    return a;
}

/// The coefficients u_i, v_i of angle_series in every lane of a vector.
template <class T, int N>
struct angle_series_lane_coefficients {
    lanes<T> u[N + 1]{};
    lanes<T> v[N + 1]{};
    constexpr angle_series_lane_coefficients() {
        for (int i = 1; i <= N; ++i) {
            u[i] = splat(T(1) / T(i * (2 * i + 1)));
            v[i] = splat(T(i) / T(2 * i + 1));
        }
    }
};

/// The series of angle_series in every lane at once: tau^2 = q per lane, y
/// one scalar for all lanes (Y = T) or one per lane (Y = lanes<T>). Horner's
/// rule over pairs of terms, as in angle_series.
template <class T, int n = angle_series_terms<T>(), class Y>
ANIMA_FORCE_INLINE lanes<T> angle_series_lanes(const lanes<T>& q, const Y& y) {
    using L = lanes<T>;
    static constexpr angle_series_lane_coefficients<T, n> s{};
    L a = splat(T(1));
    for (int i = (n % 2 == 0 ? n - 1 : n); i >= 1; i -= 2) {
        const L w = (q * s.u[i] - s.v[i]) * y;
        if (i + 1 <= n)
            a = T(1) + w + (w * ((q * s.u[i + 1] - s.v[i + 1]) * y)) * a;
        else
            a = T(1) + w;
    }
    return a;
}

/// Vector parts of the logarithms of two unit quaternions p, q with w >= 0
/// (rotation angles at most 180 degrees; w a hair below 0 is fine): theta *
/// axis, theta = atan2(|v|, w) <= pi/2, without an arc tangent. theta /
/// sin(theta) is the series at tau = 0, for both quaternions in the lanes of
/// one vector: in w - 1 itself when both 1 - w are below
/// direct_series_limit (no square root or division), otherwise in
/// cos(theta/4) - 1 divided by sin(theta) / sin(theta/4) = 4c(2c^2 - 1).
template <class T>
ANIMA_FORCE_INLINE void log_unit_right_half_pair(const quat4<T>& p, const quat4<T>& q, T (&vp)[3], T (&vq)[3]) {
    using L = lanes<T>;
    T kp, kq;
    if constexpr (lane_count<T> >= 2) {
        L k;
        if (T(1) - p.w <= direct_series_limit<T>() && T(1) - q.w <= direct_series_limit<T>()) {
            const L y{p.w - T(1), q.w - T(1)};
            k = angle_series_lanes<T, direct_series_terms<T>()>(y * T(0), y);
        } else {
            const L c{cos_quarter_angle(p.w), cos_quarter_angle(q.w)};
            k = angle_series_lanes<T>(c * T(0), c - T(1)) / (c * (T(2) * c * c - T(1)));
        }
        kp = k[0];
        kq = k[1];
    } else {
        const T cp = cos_quarter_angle(p.w), cq = cos_quarter_angle(q.w);
        kp = angle_series(T(0), cp - T(1)) / (cp * (T(2) * cp * cp - T(1)));
        kq = angle_series(T(0), cq - T(1)) / (cq * (T(2) * cq * cq - T(1)));
    }
    vp[0] = kp * p.x;
    vp[1] = kp * p.y;
    vp[2] = kp * p.z;
    vq[0] = kq * q.x;
    vq[1] = kq * q.y;
    vq[2] = kq * q.z;
}

/// Taylor coefficients of cos a and sin(a)/a in x = a^2, in lanes 0 and 1:
/// cos a = sum c_i x^i, c_i = (-1)^i / (2i)!, and sin(a)/a with (2i + 1)!.
template <class T, int N>
struct cos_sinc_coefficients {
    lanes<T> c[N]{};
    constexpr cos_sinc_coefficients() {
        T cos_i = T(1), sinc_i = T(1);
        for (int i = 0; i < N; ++i) {
            if constexpr (lane_count<T> == 4)
                c[i] = lanes<T>{cos_i, sinc_i, cos_i, sinc_i};
            else if constexpr (lane_count<T> == 2)
                c[i] = lanes<T>{cos_i, sinc_i};
            cos_i = -cos_i / T((2 * i + 1) * (2 * i + 2));
            sinc_i = -sinc_i / T((2 * i + 2) * (2 * i + 3));
        }
    }
};

/// sum_{i < N} c[B + i] x^i by Estrin's scheme, with powers = (x, x^2, x^4,
/// x^8): the lower half of the terms plus the upper half times x^H, H the
/// largest power of two below N, recursively (unrolled at compile time).
template <class T, int B, int N, class L, int M>
ANIMA_FORCE_INLINE L estrin(const L (&c)[M], const T (&powers)[4]) {
    static_assert(N >= 1 && B + N <= M && N <= 16, "up to 16 terms");
    if constexpr (N == 1) {
        return c[B];
    } else {
        constexpr int h = N > 8 ? 8 : N > 4 ? 4 : N > 2 ? 2 : 1;
        constexpr int level = h == 8 ? 3 : h == 4 ? 2 : h == 2 ? 1 : 0;
        return estrin<T, B, h>(c, powers) + estrin<T, B + h, N - h>(c, powers) * powers[level];
    }
}

/// exp of a pure quaternion (0, v) with |v| <= pi/4, the largest argument
/// squad_control_point meets, by Taylor polynomials in x = |v|^2 (float: 5
/// terms, double: 9; the first omitted term is below epsilon / 4 at pi/4).
/// cos and sin(a)/a run side by side in two lanes, by Estrin's scheme (the
/// terms paired, then pairs of pairs, with x, x^2, x^4, ...), whose chain of
/// dependent operations grows with log2 of the degree instead of the degree.
/// Larger |v| go to exp_pure.
template <class T>
ANIMA_FORCE_INLINE quat4<T> exp_pure_eighth_turn(T vx, T vy, T vz) {
    constexpr int n = std::numeric_limits<T>::digits <= 24 ? 5 : std::numeric_limits<T>::digits <= 53 ? 9 : 12;
    const T a2 = vx * vx + vy * vy + vz * vz;
    if (!(a2 <= T(0.61685027506808491)))  // (pi/4)^2
        return exp_pure(vx, vy, vz);
    T c = T(1), k = T(1);
    if constexpr (lane_count<T> >= 2) {
        static constexpr cos_sinc_coefficients<T, n> s{};
        const T a4 = a2 * a2, a8 = a4 * a4;
        const T powers[4] = {a2, a4, a8, a8 * a8};
        const lanes<T> p = estrin<T, 0, n>(s.c, powers);
        c = p[0];
        k = p[1];
    } else {
        for (int i = n - 1; i >= 1; --i) {
            c = T(1) - a2 * (T(1) / T((2 * i - 1) * (2 * i))) * c;
            k = T(1) - a2 * (T(1) / T((2 * i) * (2 * i + 1))) * k;
        }
    }
    return {c, k * vx, k * vy, k * vz};
}

}  // namespace anima::detail
