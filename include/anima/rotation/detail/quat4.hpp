// Internal plain quaternion used by the rotation toolkit. Public functions load
// the user's type into quat4, compute, and store back through quat_traits, so
// the maths is written once for every quaternion type.
#pragma once

#include <anima/core/error.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>
#include <type_traits>

namespace anima::detail {

template <class T>
struct quat4 {
    static_assert(std::is_floating_point_v<T>, "anima quaternions need a floating-point scalar");
    T w, x, y, z;

    friend quat4 operator*(const quat4& a, const quat4& b) {
        return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
                a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
    }
    friend quat4 operator*(const quat4& a, T s) { return {a.w * s, a.x * s, a.y * s, a.z * s}; }
    friend quat4 operator+(const quat4& a, const quat4& b) {
        return {a.w + b.w, a.x + b.x, a.y + b.y, a.z + b.z};
    }
    friend quat4 operator-(const quat4& a, const quat4& b) {
        return {a.w - b.w, a.x - b.x, a.y - b.y, a.z - b.z};
    }
    quat4 operator-() const { return {-w, -x, -y, -z}; }
};

template <class T>
T dot4(const quat4<T>& a, const quat4<T>& b) {
    return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
T norm4(const quat4<T>& q) {
    return std::sqrt(dot4(q, q));
}
template <class T>
quat4<T> conj4(const quat4<T>& q) {
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

/// sin(x)/x, exact near 0.
template <class T>
T sinc(T x) {
    if (std::abs(x) < small_angle<T>()) return T(1) - x * x / T(6);
    return std::sin(x) / x;
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
                               std::to_string(static_cast<double>(m)) + ")");
    const quat4<T> s{q.w / m, q.x / m, q.y / m, q.z / m};  // largest component exactly +-1
    const T n = norm4(s);
    if (log_norm) *log_norm = std::log(m) + std::log(n);
    return s * (T(1) / n);
}

/// exp of a pure quaternion (0, v): (cos|v|, sin|v| v/|v|).
template <class T>
quat4<T> exp_pure(T vx, T vy, T vz) {
    const T a = std::sqrt(vx * vx + vy * vy + vz * vz);
    const T s = sinc(a);
    return {std::cos(a), s * vx, s * vy, s * vz};
}

/// Vector part of log of a unit quaternion: theta * axis where q = (cos theta, sin theta axis),
/// theta in [0, pi]. atan2 keeps full precision at both ends.
template <class T>
void log_unit(const quat4<T>& q, T& vx, T& vy, T& vz) {
    const T s = vector_norm(q);
    const T theta = std::atan2(s, q.w);
    // theta / sin(theta) written as theta / s; when s is tiny and w > 0 the ratio -> 1/w.
    T k;
    if (s < small_angle<T>() * std::abs(q.w)) {
        if (q.w > T(0)) {
            // atan(r)/r = 1 - r^2/3 + r^4/5 - ..., r = s/w; the r^4 term matters
            // at this cut-off (chosen for sinc, whose next term is r^4/120).
            const T r2 = s * s / (q.w * q.w);
            k = (T(1) - r2 / T(3) + r2 * r2 / T(5)) / q.w;
        } else {
            // q ~ -1: the rotation is the identity reached the long way round (angle 2 pi).
            // The axis is undefined when s == 0; choose x so the result is finite.
            if (s == T(0)) {
                vx = theta;
                vy = T(0);
                vz = T(0);
                return;
            }
            k = theta / s;
        }
    } else {
        k = theta / s;
    }
    vx = k * q.x;
    vy = k * q.y;
    vz = k * q.z;
}

}  // namespace anima::detail
