// Quaternion algebra for any type with quat_traits (glm::qua, Eigen::Quaternion):
// dot, conjugate, inverse, normalize, multiply, rotate, hemisphere alignment,
// and the angle of a rotation or between two orientations.
//
// Convention: q = (w, x, y, z) = (cos(a/2), sin(a/2) axis) rotates by angle a
// about axis; q and -q are the same rotation (the "double cover").
// Call these qualified (anima::dot): GLM declares functions of the same names.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

namespace anima {

/// Four-dimensional dot product a.b; |a.b| = cos(half the angle between a and b).
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
quat_scalar_t<Q> dot(const Q& a, const Q& b) {
    return detail::dot4(detail::load(a), detail::load(b));
}

/// Euclidean norm of the four components, without overflow or underflow of
/// the squares (finite for components like 1e200, non-zero for 1e-200).
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
quat_scalar_t<Q> norm(const Q& q) {
    return detail::scaled_norm4(detail::load(q));
}

/// (w, -x, -y, -z): the inverse rotation of a unit quaternion.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q conjugate(const Q& q) {
    return detail::store<Q>(detail::conj4(detail::load(q)));
}

/// conj(q) / |q|^2. Throws anima::invalid_argument for a zero or non-finite
/// quaternion, or one whose inverse is not representable (|q| below about
/// 1 / the largest finite value).
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q inverse(const Q& q) {
    using T = quat_scalar_t<Q>;
    const auto p = detail::load(q);
    const T n = detail::scaled_norm4(p);
    if (!(n > T(0)) || !(n <= std::numeric_limits<T>::max()))
        throw invalid_argument("anima::inverse: quaternion has zero or non-finite norm");
    const auto r = detail::conj4(p * (T(1) / n)) * (T(1) / n);  // |q| divided out twice: no overflow of |q|^2
    if (!std::isfinite(r.w) || !std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.z))
        throw invalid_argument("anima::inverse: the inverse of a quaternion of norm " +
                               detail::argument_text(n) + " is not representable");
    return detail::store<Q>(r);
}

/// q / |q|. Throws anima::invalid_argument for a zero or non-finite quaternion.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q normalize(const Q& q) {
    return detail::store<Q>(detail::normalized_or_throw(detail::load(q), "anima::normalize"));
}

/// Hamilton product a*b: apply b first, then a.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q multiply(const Q& a, const Q& b) {
    return detail::store<Q>(detail::load(a) * detail::load(b));
}

/// Rotates the 3-vector v (anything indexable by [0..2]) by the unit quaternion q.
/// Returns quat_vector3_t<Q>.
template <class Q, class V, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
quat_vector3_t<Q> rotate(const Q& q, const V& v) {
    using T = quat_scalar_t<Q>;
    const auto p = detail::load(q);
    const T vx = static_cast<T>(v[0]), vy = static_cast<T>(v[1]), vz = static_cast<T>(v[2]);
    // v' = v + 2w (u x v) + 2 u x (u x v), u the vector part: 15 multiplies, no matrix.
    const T tx = T(2) * (p.y * vz - p.z * vy);
    const T ty = T(2) * (p.z * vx - p.x * vz);
    const T tz = T(2) * (p.x * vy - p.y * vx);
    return quat_traits<Q>::make_vector(vx + p.w * tx + (p.y * tz - p.z * ty),
                                       vy + p.w * ty + (p.z * tx - p.x * tz),
                                       vz + p.w * tz + (p.x * ty - p.y * tx));
}

/// q or -q, whichever lies in the same hemisphere as ref (q.ref >= 0). Use it
/// before blending a sequence so neighbours take the short way round.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q align_hemisphere(const Q& q, const Q& ref) {
    const auto p = detail::load(q);
    return detail::dot4(p, detail::load(ref)) < 0 ? detail::store<Q>(-p) : q;
}

/// The representative with w >= 0 (the rotation angle then lies in [0, pi]).
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q canonicalize(const Q& q) {
    const auto p = detail::load(q);
    return p.w < 0 ? detail::store<Q>(-p) : q;
}

/// Rotation angle of a unit quaternion, in [0, pi]: 2 atan2(|v|, |w|), which
/// unlike 2 acos(w) keeps full precision near 0.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
quat_scalar_t<Q> angle(const Q& q) {
    using T = quat_scalar_t<Q>;
    const auto p = detail::load(q);
    return T(2) * std::atan2(detail::vector_norm(p), std::abs(p.w));
}

/// Angle in [0, pi] of the rotation that takes orientation a to orientation b:
/// 2 acos(|a.b|) for unit inputs, computed from the relative rotation so that
/// it is accurate for nearly identical and nearly opposite orientations.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
quat_scalar_t<Q> angle_between(const Q& a, const Q& b) {
    using T = quat_scalar_t<Q>;
    const auto d = detail::conj4(detail::load(a)) * detail::load(b);
    return T(2) * std::atan2(detail::vector_norm(d), std::abs(d.w));
}

/// q as another quaternion type, component for component (GLM <-> Eigen,
/// float <-> double), not normalised: what moves a clip's Eigen rotations
/// into a GLM engine and back. (Not glm::quat_cast, which takes a matrix.)
template <class To, class From,
          std::enable_if_t<is_quaternion_v<To> && is_quaternion_v<From>, int> = 0>
To quaternion_cast(const From& q) {
    using T = quat_scalar_t<To>;
    const auto p = detail::load(q);
    return quat_traits<To>::make(static_cast<T>(p.w), static_cast<T>(p.x), static_cast<T>(p.y), static_cast<T>(p.z));
}

/// Identity rotation of type Q.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q identity() {
    using T = quat_scalar_t<Q>;
    return quat_traits<Q>::make(T(1), T(0), T(0), T(0));
}

}  // namespace anima
