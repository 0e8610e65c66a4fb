// Internal plain quaternion used by the rotation toolkit. Public functions load
// the user's type into quat4, compute, and store back through quat_traits, so
// the maths is written once for every quaternion type. The algebra, exp_pure
// and log_unit also run on automatic-derivative scalars
// (Eigen::AutoDiffScalar): the flight objective and IK use them so, with
// derivatives that exist at the identity (series in squared norms there,
// chosen by the scalar's value).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/inline.hpp>
#include <anima/core/scalar_value.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>
#include <type_traits>

namespace anima::detail {

template <class T>
struct quat4 {
    T w, x, y, z;

    friend ANIMA_FORCE_INLINE quat4 operator*(const quat4& a, const quat4& b) {
        return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
                a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
    }
    friend ANIMA_FORCE_INLINE quat4 operator*(const quat4& a, T s) { return {a.w * s, a.x * s, a.y * s, a.z * s}; }
    friend ANIMA_FORCE_INLINE quat4 operator+(const quat4& a, const quat4& b) {
        return {a.w + b.w, a.x + b.x, a.y + b.y, a.z + b.z};
    }
    friend ANIMA_FORCE_INLINE quat4 operator-(const quat4& a, const quat4& b) {
        return {a.w - b.w, a.x - b.x, a.y - b.y, a.z - b.z};
    }
    quat4 operator-() const { return {-w, -x, -y, -z}; }
};

template <class T>
ANIMA_FORCE_INLINE T dot4(const quat4<T>& a, const quat4<T>& b) {
    return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
T norm4(const quat4<T>& q) {
    return std::sqrt(dot4(q, q));
}
template <class T>
ANIMA_FORCE_INLINE quat4<T> conj4(const quat4<T>& q) {
    return {q.w, -q.x, -q.y, -q.z};
}
template <class T>
T vector_norm(const quat4<T>& q) {
    return std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
}

template <class Q>
quat4<quat_scalar_t<Q>> load(const Q& q) {
    using tr = quat_traits<Q>;
    return {tr::w(q), tr::x(q), tr::y(q), tr::z(q)};
}
template <class Q, class T>
Q store(const quat4<T>& q) {
    return quat_traits<Q>::make(q.w, q.x, q.y, q.z);
}

/// Square root by Newton's method, for compile-time constants.
template <class T>
constexpr T constexpr_sqrt(T x) {
    T r = x > T(1) ? x : T(1);
    for (int i = 0; i < 200; ++i) r = T(0.5) * (r + x / r);
    return r;
}

/// Below this angle (radians) a 4th-order Taylor series of sin(x)/x is exact to
/// machine precision: x^4/120 <= epsilon. A constant, so hot loops pay nothing.
template <class T>
constexpr T small_angle() {
    constexpr T value = constexpr_sqrt(constexpr_sqrt(T(120) * std::numeric_limits<T>::epsilon()));
    return value;
}

/// Largest component magnitude; NaN when a component is NaN.
template <class T>
T max_abs4(const quat4<T>& q) {
    T m = std::abs(q.w);
    for (const T c : {q.x, q.y, q.z}) {
        const T a = std::abs(c);
        if (a > m || std::isnan(a)) m = a;  // a NaN, once taken, stays
    }
    return m;
}

/// |q| without overflow or underflow: for components far from 1 (1e-200,
/// 1e200, denormals) the squares are formed after dividing by the largest
/// component. Infinite for an infinite component, NaN for a NaN one.
template <class T>
T scaled_norm4(const quat4<T>& q) {
    constexpr T lo = std::numeric_limits<T>::min() / std::numeric_limits<T>::epsilon();
    constexpr T hi = std::numeric_limits<T>::max() / T(8);
    const T n2 = dot4(q, q);
    if (n2 >= lo && n2 <= hi) return std::sqrt(n2);
    const T m = max_abs4(q);
    if (!(m > T(0)) || !(m <= std::numeric_limits<T>::max())) return m;  // 0, inf or NaN
    const quat4<T> s{q.w / m, q.x / m, q.y / m, q.z / m};
    return m * norm4(s);
}

/// Unit quaternion q / |q| and ln|q|, computed without overflow or underflow
/// for any finite non-zero q; throws anima::invalid_argument naming the
/// caller for a zero or non-finite quaternion.
template <class T>
quat4<T> normalized_or_throw(const quat4<T>& q, const char* who, T* log_norm = nullptr) {
    constexpr T lo = std::numeric_limits<T>::min() / std::numeric_limits<T>::epsilon();
    constexpr T hi = std::numeric_limits<T>::max() / T(8);
    const T n2 = dot4(q, q);
    if (n2 >= lo && n2 <= hi) {  // the common case: the squares neither overflow nor underflow
        const T n = std::sqrt(n2);
        if (log_norm) *log_norm = std::log(n);
        return q * (T(1) / n);
    }
    const T m = max_abs4(q);
    if (!(m > T(0)) || !(m <= std::numeric_limits<T>::max()))
        throw invalid_argument(std::string(who) + ": quaternion has zero or non-finite norm (largest component " +
                               detail::argument_text(m) + ")");
    const quat4<T> s{q.w / m, q.x / m, q.y / m, q.z / m};  // largest component exactly +-1
    const T n = norm4(s);
    if (log_norm) *log_norm = std::log(m) + std::log(n);
    return s * (T(1) / n);
}

/// Inputs whose squared norm is within this of 1 count as unit quaternions
/// up to one Newton step: 1.5 - n2/2 approximates 1/|q| with an error of
/// 3/8 (n2 - 1)^2, below epsilon / 40 here.
template <class T>
constexpr T near_unit_tolerance() {
    constexpr T value = constexpr_sqrt(std::numeric_limits<T>::epsilon()) / T(4);  // by the compiler
    return value;
}

/// Like normalized_or_throw, cheaper for inputs already near unit length
/// (stored unit quaternions): one Newton step, no square root or division.
template <class T>
quat4<T> unit_or_throw(const quat4<T>& q, const char* who) {
    const T n2 = dot4(q, q);
    if (std::abs(n2 - T(1)) <= near_unit_tolerance<T>()) return q * (T(1.5) - T(0.5) * n2);
    return normalized_or_throw(q, who);
}

/// Row-major rotation matrix of a unit quaternion, for any scalar (the flight
/// objective runs it on AutoDiff scalars).
template <class T>
std::array<std::array<T, 3>, 3> to_matrix(const quat4<T>& q) {
    const T xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    const T xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    const T wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    return {{{T(1) - T(2) * (yy + zz), T(2) * (xy - wz), T(2) * (xz + wy)},
             {T(2) * (xy + wz), T(1) - T(2) * (xx + zz), T(2) * (yz - wx)},
             {T(2) * (xz - wy), T(2) * (yz + wx), T(1) - T(2) * (xx + yy)}}};
}

/// cos(a) and sin(a)/a from a^2, for any scalar S including
/// automatic-derivative ones. Below small_angle both are series in a^2 (three
/// terms: the next is below epsilon there, and the derivatives stay
/// accurate), which also avoids the square root whose derivative is infinite
/// at 0. The branch goes through select_less (core/scalar_value.hpp).
template <class S>
void cos_and_sinc(const S& a2, S& c, S& k) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    using R = real_scalar_t<S>;
    constexpr R limit = small_angle<R>() * small_angle<R>();
    const std::array<S, 2> r = select_less(
        a2, S(limit),
        [&] { return std::array<S, 2>{S(S(1) - a2 / S(2) + a2 * a2 / S(24)), S(S(1) - a2 / S(6) + a2 * a2 / S(120))}; },
        [&] {
            const S a = sqrt(a2);
            return std::array<S, 2>{S(cos(a)), S(sin(a) / a)};
        });
    c = r[0];
    k = r[1];
}

/// exp of a pure quaternion (0, v): (cos|v|, sin|v| v/|v|), for any scalar S.
template <class S>
quat4<S> exp_pure(const S& vx, const S& vy, const S& vz) {
    S c, k;
    cos_and_sinc(S(vx * vx + vy * vy + vz * vz), c, k);
    return {c, k * vx, k * vy, k * vz};
}

/// "(x, y, z)" for a message, each in its shortest exact form.
template <class T>
std::string vector_text(T x, T y, T z) {
    return "(" + argument_text(x) + ", " + argument_text(y) + ", " + argument_text(z) + ")";
}

/// Divides (x, y, z) by its length, found after scaling by the largest
/// component so that lengths whose squares over- or underflow work; throws
/// "who: what must be non-zero and finite, got (x, y, z)" otherwise.
template <class T>
void normalize3_or_throw(T& x, T& y, T& z, const char* who, const char* what) {
    const T m = std::max({std::abs(x), std::abs(y), std::abs(z)});
    if (!(m > T(0)) || !(m <= std::numeric_limits<T>::max()) || std::isnan(x + y + z))
        throw invalid_argument(std::string(who) + ": " + what + " must be non-zero and finite, got " +
                               vector_text(x, y, z));
    x /= m;
    y /= m;
    z /= m;
    const T n = std::sqrt(x * x + y * y + z * z);
    x /= n;
    y /= n;
    z /= n;
}

/// exp_pure for the public entry points: refuses a non-finite vector (naming
/// `what`), and stays exact when |v|^2 overflows though |v| does not (|v|
/// above about 1.8e19 in float): cos and sin of the length found by scaling.
template <class T>
quat4<T> exp_pure_checked(T vx, T vy, T vz, const char* who, const char* what) {
    if (!std::isfinite(vx) || !std::isfinite(vy) || !std::isfinite(vz))
        throw invalid_argument(std::string(who) + ": " + what + " must be finite, got " + vector_text(vx, vy, vz));
    if (vx * vx + vy * vy + vz * vz <= std::numeric_limits<T>::max()) return exp_pure(vx, vy, vz);
    const T m = std::max({std::abs(vx), std::abs(vy), std::abs(vz)});
    const T a = vx / m, b = vy / m, c = vz / m;  // the largest is exactly +-1
    const T r = std::sqrt(a * a + b * b + c * c);
    const T n = m * r;
    if (!std::isfinite(n))
        throw invalid_argument(std::string(who) + ": the length of " + what + " overflows, largest component " +
                               argument_text(m));
    const T s = std::sin(n);
    return {std::cos(n), s * (a / r), s * (b / r), s * (c / r)};
}

/// Vector part of log of a unit quaternion: theta * axis where q = (cos theta, sin theta axis),
/// theta in [0, pi], for any scalar S. atan2 keeps full precision at both ends.
template <class S>
void log_unit(const quat4<S>& q, S& vx, S& vy, S& vz) {
    using std::atan2;
    using std::sqrt;
    using R = real_scalar_t<S>;
    constexpr R small2 = small_angle<R>() * small_angle<R>();
    const S s2 = q.x * q.x + q.y * q.y + q.z * q.z;
    if (scalar_value(s2) == 0.0 && !(scalar_value(q.w) > 0.0)) {
        // q = -1: the identity reached the long way round (angle 2 pi); the
        // axis is undefined, x is chosen so the result is finite.
        vx = atan2(S(0), q.w);
        vy = S(0);
        vz = S(0);
        return;
    }
    // theta / sin(theta) = atan2(s, w) / s; when s is tiny and w > 0 the ratio
    // is a series in r^2 = s^2 / w^2, free of the square root.
    const auto series = [&] {
        // atan(r)/r = 1 - r^2/3 + r^4/5 - ...; the r^4 term matters at this
        // cut-off (small_angle is where x^4 / 120 drops below epsilon).
        const S r2 = s2 / (q.w * q.w);
        return S((S(1) - r2 / S(3) + r2 * r2 / S(5)) / q.w);
    };
    const auto closed = [&] {
        const S s = sqrt(s2);
        return S(atan2(s, q.w) / s);
    };
    const auto below_cut_off = [&] { return select_less(s2, S(S(small2) * q.w * q.w), series, closed); };
    const S k = select_less(S(0), q.w, below_cut_off, closed);
    vx = k * q.x;
    vy = k * q.y;
    vz = k * q.z;
}

}  // namespace anima::detail
