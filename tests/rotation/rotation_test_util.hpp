// Shared helpers for the rotation tests: the four quaternion types under test,
// seeded random rotations, and a long double reference quaternion that is
// independent of anima's own code.
#pragma once

#include <anima/rotation/quat_traits.hpp>

#include <doctest/doctest.h>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <random>

#define ANIMA_QUAT_TYPES \
    glm::qua<float>, glm::qua<double>, Eigen::Quaternion<float>, Eigen::Quaternion<double>

TYPE_TO_STRING(glm::qua<float>);
TYPE_TO_STRING(glm::qua<double>);
TYPE_TO_STRING(Eigen::Quaternion<float>);
TYPE_TO_STRING(Eigen::Quaternion<double>);

namespace rt {

using ld = long double;
using vec = std::array<ld, 3>;
template <class Q>
using scalar = anima::quat_scalar_t<Q>;
template <class Q>
using vector3 = anima::quat_vector3_t<Q>;

const ld pi = 3.141592653589793238462643383279502884L;

template <class T>
constexpr T eps() {
    return std::numeric_limits<T>::epsilon();
}

/// Reference quaternion in long double.
struct lq {
    ld w, x, y, z;
};
inline lq operator*(const lq& a, const lq& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
inline lq conj(const lq& a) { return {a.w, -a.x, -a.y, -a.z}; }
inline lq scale(const lq& a, ld s) { return {s * a.w, s * a.x, s * a.y, s * a.z}; }
inline lq operator+(const lq& a, const lq& b) { return {a.w + b.w, a.x + b.x, a.y + b.y, a.z + b.z}; }
inline lq unit(const lq& a) { return scale(a, 1 / std::sqrt(a.w * a.w + a.x * a.x + a.y * a.y + a.z * a.z)); }
inline ld vnorm(const vec& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
/// Rotation by `angle` about `axis` (normalised here).
inline lq rot(ld angle, const vec& axis) {
    const ld s = std::sin(angle / 2) / vnorm(axis);
    return {std::cos(angle / 2), s * axis[0], s * axis[1], s * axis[2]};
}
/// Angle in [0, pi] between the orientations a and b.
inline ld angle_between(const lq& a, const lq& b) {
    const lq d = conj(a) * b;
    return 2 * std::atan2(std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z), std::abs(d.w));
}
/// v rotated by the unit quaternion q (q v q*).
inline vec rotate(const lq& q, const vec& v) {
    const lq r = q * lq{0, v[0], v[1], v[2]} * conj(q);
    return {r.x, r.y, r.z};
}

template <class Q>
lq to_lq(const Q& q) {
    using tr = anima::quat_traits<Q>;
    return {tr::w(q), tr::x(q), tr::y(q), tr::z(q)};
}
inline lq to_lq(const lq& q) { return q; }
template <class Q>
Q make(ld w, ld x, ld y, ld z) {
    using T = scalar<Q>;
    return anima::quat_traits<Q>::make(T(w), T(x), T(y), T(z));
}
template <class Q>
Q from_lq(const lq& q) {
    return make<Q>(q.w, q.x, q.y, q.z);
}
template <class Q>
Q neg(const Q& q) {
    const lq p = to_lq(q);
    return make<Q>(-p.w, -p.x, -p.y, -p.z);
}
template <class V>
vec to_vec(const V& v) {
    return {ld(v[0]), ld(v[1]), ld(v[2])};
}
template <class Q>
vector3<Q> make_vec(const vec& v) {
    using T = scalar<Q>;
    return anima::quat_traits<Q>::make_vector(T(v[0]), T(v[1]), T(v[2]));
}
template <class Q>
glm::qua<scalar<Q>> to_glm(const Q& q) {
    return from_lq<glm::qua<scalar<Q>>>(to_lq(q));
}
template <class Q>
Eigen::Quaternion<scalar<Q>> to_eigen(const Q& q) {
    return from_lq<Eigen::Quaternion<scalar<Q>>>(to_lq(q));
}

/// Largest component difference.
inline ld diff(const lq& a, const lq& b) {
    return std::max({std::abs(a.w - b.w), std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
}
template <class A, class B>
ld diff(const A& a, const B& b) {
    return diff(to_lq(a), to_lq(b));
}
/// Largest component difference between a and +-b, whichever sign is closer.
template <class A, class B>
ld diff_up_to_sign(const A& a, const B& b) {
    const lq p = to_lq(b);
    return std::min(diff(to_lq(a), p), diff(to_lq(a), lq{-p.w, -p.x, -p.y, -p.z}));
}
template <class A, class B>
ld vdiff(const A& a, const B& b) {
    return std::max(
        {std::abs(ld(a[0]) - ld(b[0])), std::abs(ld(a[1]) - ld(b[1])), std::abs(ld(a[2]) - ld(b[2]))});
}
template <class Q>
bool finite(const Q& q) {
    const lq p = to_lq(q);
    return std::isfinite(p.w) && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}
template <class Q>
ld norm_error(const Q& q) {
    const lq p = to_lq(q);
    return std::abs(std::sqrt(p.w * p.w + p.x * p.x + p.y * p.y + p.z * p.z) - 1);
}

/// Scale factors whose squares over- or underflow T: 1e-200, 1e200 and the
/// smallest normal number (denormal components) in double, their float
/// counterparts, and 1 for comparison.
template <class T>
std::array<T, 5> awkward_scales() {
    using lim = std::numeric_limits<T>;
    return {T(1), std::ldexp(T(1), -(lim::max_exponent * 2) / 3), std::ldexp(T(1), (lim::max_exponent * 2) / 3),
            lim::min(), lim::max() / T(4)};
}
template <class Q>
Q scaled(const Q& q, scalar<Q> s) {
    const lq p = to_lq(q);
    using T = scalar<Q>;
    return anima::quat_traits<Q>::make(T(p.w) * s, T(p.x) * s, T(p.y) * s, T(p.z) * s);
}

/// Slerp in long double along the arc as given (no hemisphere flip): a (a^-1 b)^t.
inline lq ref_slerp_as_given(const lq& a, const lq& b, ld t) {
    const lq d = conj(a) * b;
    const ld s = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    if (s == 0) return a;
    const ld half = std::atan2(s, d.w), k = std::sin(t * half) / s;
    return a * lq{std::cos(t * half), k * d.x, k * d.y, k * d.z};
}
/// Slerp in long double along the shorter arc, from the relative rotation.
inline lq ref_slerp(const lq& a, lq b, ld t) {
    if (a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z < 0) b = scale(b, -1);
    return ref_slerp_as_given(a, b, t);
}

/// Seeded random numbers, vectors and rotations.
struct rng {
    std::mt19937 gen;
    explicit rng(unsigned seed) : gen(seed) {}
    ld uniform(ld lo, ld hi) { return std::uniform_real_distribution<double>(double(lo), double(hi))(gen); }
    vec unit_vector() {
        std::normal_distribution<double> n;
        vec v{n(gen), n(gen), n(gen)};
        const ld l = vnorm(v);
        return {v[0] / l, v[1] / l, v[2] / l};
    }
    lq unit_lq() {
        std::normal_distribution<double> n;
        lq q{n(gen), n(gen), n(gen), n(gen)};
        const ld l = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
        return {q.w / l, q.x / l, q.y / l, q.z / l};
    }
    /// A uniformly distributed unit quaternion (either sign of w).
    template <class Q>
    Q unit() {
        return from_lq<Q>(unit_lq());
    }
    /// A quaternion of norm in [0.5, 2].
    template <class Q>
    Q any() {
        const lq u = unit_lq();
        const ld s = uniform(0.5, 2);
        return make<Q>(s * u.w, s * u.x, s * u.y, s * u.z);
    }
};

/// The partner of a in the i-th pair of the mixed slerp inputs, by i mod 4:
/// uniformly random, 1e-6 rad apart, nearly antipodal 4-vectors (the same
/// rotation up to 1e-6 rad), rotations 150 to 180 degrees apart.
inline lq mixed_partner(rng& r, const lq& a, std::size_t i) {
    switch (i % 4) {
    case 0: return r.unit_lq();
    case 1: return a * rot(1e-6L, r.unit_vector());
    case 2: return scale(a * rot(1e-6L, r.unit_vector()), -1);
    default: return a * rot(r.uniform(150, 180) * pi / 180, r.unit_vector());
    }
}

}  // namespace rt
