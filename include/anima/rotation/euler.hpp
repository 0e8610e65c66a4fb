// Euler (Tait-Bryan) angles <-> quaternions for all six axis orders.
//
// Convention: order "zxy" with angles (a0, a1, a2) is the rotation
// Rz(a0) * Rx(a1) * Ry(a2) acting on column vectors: the axes are applied
// right to left, or equivalently intrinsically in the order written. This is
// what a BVH line "CHANNELS 3 Zrotation Xrotation Yrotation" means.
// Angles are in radians.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>

namespace anima {

/// A rotation axis of the local frame.
enum class axis : unsigned char { x = 0, y = 1, z = 2 };

/// The six Tait-Bryan orders; the letters give the axes of a0, a1, a2.
enum class euler_order : unsigned char { xyz, xzy, yxz, yzx, zxy, zyx };

/// The three axes of an order, in the order the angles are given.
inline constexpr std::array<axis, 3> axes_of(euler_order order) {
    switch (order) {
        case euler_order::xyz: return {axis::x, axis::y, axis::z};
        case euler_order::xzy: return {axis::x, axis::z, axis::y};
        case euler_order::yxz: return {axis::y, axis::x, axis::z};
        case euler_order::yzx: return {axis::y, axis::z, axis::x};
        case euler_order::zxy: return {axis::z, axis::x, axis::y};
        case euler_order::zyx: return {axis::z, axis::y, axis::x};
    }
    return {axis::x, axis::y, axis::z};
}

/// The order whose axes are a0, a1, a2. Throws anima::invalid_argument when an
/// axis repeats (proper Euler angles such as zxz are not Tait-Bryan).
inline euler_order euler_order_of(axis a0, axis a1, axis a2) {
    for (euler_order o : {euler_order::xyz, euler_order::xzy, euler_order::yxz, euler_order::yzx,
                          euler_order::zxy, euler_order::zyx}) {
        const auto ax = axes_of(o);
        if (ax[0] == a0 && ax[1] == a1 && ax[2] == a2) return o;
    }
    throw invalid_argument("anima::euler_order_of: the three axes must be distinct");
}

template <>
struct enum_names<euler_order> {
    static constexpr const char* what = "rotation order";
    static constexpr enum_entry<euler_order> entries[] = {
        {euler_order::xyz, "XYZ"}, {euler_order::xzy, "XZY"}, {euler_order::yxz, "YXZ"},
        {euler_order::yzx, "YZX"}, {euler_order::zxy, "ZXY"}, {euler_order::zyx, "ZYX"}};
};

/// "XYZ", "zxy"... (case-insensitive) to an order; throws anima::invalid_argument
/// naming the choices otherwise.
inline euler_order parse_euler_order(std::string_view s) {
    return parse_enum<euler_order>(s, "anima::parse_euler_order");
}

/// "XYZ" etc.
inline std::string to_string(euler_order order) {
    std::string s;
    for (axis a : axes_of(order)) s += static_cast<char>('X' + static_cast<int>(a));
    return s;
}

namespace detail {

template <class T>
quat4<T> axis_rotation(axis a, T angle) {
    const T h = angle / T(2);
    quat4<T> q{std::cos(h), T(0), T(0), T(0)};
    const T s = std::sin(h);
    if (a == axis::x) q.x = s;
    else if (a == axis::y) q.y = s;
    else q.z = s;
    return q;
}

/// atan2 mapped to (-pi, pi]: atan2(-0, negative) is -pi.
template <class T>
T atan2_half_open(T y, T x) {
    const T a = std::atan2(y, x);
    return a <= -T(3.141592653589793238462643383279502884L) ? -a : a;
}

template <class T>
std::array<T, 3> matrix_to_euler(const std::array<std::array<T, 3>, 3>& R, euler_order order) {
    const auto ax = axes_of(order);
    const int i = static_cast<int>(ax[0]), j = static_cast<int>(ax[1]), k = static_cast<int>(ax[2]);
    // +1 for the cyclic orders (xyz, yzx, zxy), -1 for the others.
    const T sign = ((j - i + 3) % 3 == 1) ? T(1) : T(-1);
    const T cb = std::sqrt(R[i][i] * R[i][i] + R[i][j] * R[i][j]);
    const T b = std::atan2(sign * R[i][k], cb);
    if (cb < std::numeric_limits<T>::epsilon()) {
        // Gimbal lock: only a0 + a2 (or a0 - a2) is defined; put it all in a0.
        return {atan2_half_open(sign * R[k][j], R[j][j]), b, T(0)};
    }
    const T a = atan2_half_open(-sign * R[j][k], R[k][k]);
    // a2 from what is left once a0 is undone, R_i(-a0) R = R_j(a1) R_k(a2):
    // exact for whatever a0 came out, so precision holds right up to gimbal
    // lock, where a0 itself becomes ill-conditioned.
    const T ca = std::cos(a), sa = std::sin(a);
    const T rji = ca * R[j][i] + sign * sa * R[k][i];
    const T rjj = ca * R[j][j] + sign * sa * R[k][j];
    return {a, b, atan2_half_open(sign * rji, rjj)};
}

}  // namespace detail

/// Quaternion of the rotation R_{a0 axis}(a0) * R_{a1 axis}(a1) * R_{a2 axis}(a2).
/// Throws anima::invalid_argument for a non-finite angle.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q from_euler(quat_scalar_t<Q> a0, quat_scalar_t<Q> a1, quat_scalar_t<Q> a2, euler_order order) {
    check_finite("anima::from_euler", "a0", a0);
    check_finite("anima::from_euler", "a1", a1);
    check_finite("anima::from_euler", "a2", a2);
    const auto ax = axes_of(order);
    return detail::store<Q>(detail::axis_rotation(ax[0], a0) * detail::axis_rotation(ax[1], a1) *
                            detail::axis_rotation(ax[2], a2));
}

/// Angles (a0, a1, a2) of a unit quaternion in the given order, with a0, a2 in
/// (-pi, pi] and a1 in [-pi/2, pi/2]. At gimbal lock (|a1| = pi/2, where only
/// a0 + a2 or a0 - a2 is defined) a2 is set to 0.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
std::array<quat_scalar_t<Q>, 3> to_euler(const Q& q, euler_order order) {
    return detail::matrix_to_euler(
        detail::to_matrix(detail::normalized_or_throw(detail::load(q), "anima::to_euler")), order);
}

}  // namespace anima
