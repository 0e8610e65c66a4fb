// Euler angles for the six Tait-Bryan orders, checked against products of
// Eigen::AngleAxis, plus order parsing.
#include "rotation_test_util.hpp"

#include <anima/core/error.hpp>
#include <anima/rotation/euler.hpp>
#include <anima/rotation/quaternion.hpp>

#include <algorithm>
#include <string>
#include <vector>

using namespace rt;

namespace {
constexpr anima::euler_order orders[] = {anima::euler_order::xyz, anima::euler_order::xzy,
                                         anima::euler_order::yxz, anima::euler_order::yzx,
                                         anima::euler_order::zxy, anima::euler_order::zyx};

/// R_axis0(a0) * R_axis1(a1) * R_axis2(a2) built from Eigen::AngleAxis.
template <class T>
Eigen::Quaternion<T> eigen_euler(T a0, T a1, T a2, anima::euler_order order) {
    using V = Eigen::Matrix<T, 3, 1>;
    const auto ax = anima::axes_of(order);
    return Eigen::AngleAxis<T>(a0, V::Unit(int(ax[0]))) * Eigen::AngleAxis<T>(a1, V::Unit(int(ax[1]))) *
           Eigen::AngleAxis<T>(a2, V::Unit(int(ax[2])));
}
/// Difference of two angles modulo 2 pi, in [-pi, pi].
ld angle_diff(ld a, ld b) { return std::remainder(a - b, 2 * pi); }
/// pi rounded to T: what atan2 returns for a half turn.
template <class T>
T pi_t() {
    return std::atan2(T(0), T(-1));
}
template <class Q>
ld euler_round_trip_error(const Q& q, anima::euler_order order) {
    const auto e = anima::to_euler(q, order);
    CHECK(std::isfinite(e[0]));
    CHECK(std::isfinite(e[1]));
    CHECK(std::isfinite(e[2]));
    return angle_between(to_lq(q), to_lq(anima::from_euler<Q>(e[0], e[1], e[2], order)));
}
}  // namespace

TEST_CASE_TEMPLATE("from_euler is the product of the three axis rotations", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    rng r(41);
    for (anima::euler_order order : orders) {
        CAPTURE(anima::to_string(order));
        for (int i = 0; i < 50; ++i) {
            const T a0 = T(r.uniform(-7, 7)), a1 = T(r.uniform(-7, 7)), a2 = T(r.uniform(-7, 7));
            const Q q = anima::from_euler<Q>(a0, a1, a2, order);
            CHECK(diff(q, eigen_euler(a0, a1, a2, order)) <= 8 * e);
            CHECK(norm_error(q) <= 4 * e);
        }
    }
    // BVH "Zrotation Xrotation Yrotation": v' = Rz(a0) Rx(a1) Ry(a2) v, so y is turned about y first.
    const Q q = anima::from_euler<Q>(T(pi / 2), T(pi / 2), T(0.3), anima::euler_order::zxy);
    CHECK(vdiff(anima::rotate(q, std::array<T, 3>{0, 1, 0}), vec{0, 0, 1}) <= 4 * e);
    CHECK(vdiff(anima::rotate(q, std::array<T, 3>{1, 0, 0}),
                vec{-std::sin(ld(T(0.3))), std::cos(ld(T(0.3))), 0}) <= 4 * e);
}

TEST_CASE_TEMPLATE("to_euler inverts from_euler away from gimbal lock", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    rng r(42);
    for (anima::euler_order order : orders) {
        CAPTURE(anima::to_string(order));
        for (int i = 0; i < 200; ++i) {
            const T a0 = T(r.uniform(-pi, pi)), a1 = T(r.uniform(-pi / 2 + 0.01, pi / 2 - 0.01)),
                    a2 = T(r.uniform(-pi, pi));
            CAPTURE(a1);
            const Q q = anima::from_euler<Q>(a0, a1, a2, order);
            const auto got = anima::to_euler(q, order);
            const ld tol = 16 * e / std::cos(ld(a1));  // a0 and a2 get harder to separate as |a1| -> pi/2
            CHECK(std::abs(angle_diff(got[0], a0)) <= tol);
            CHECK(std::abs(got[1] - ld(a1)) <= 8 * e);
            CHECK(std::abs(angle_diff(got[2], a2)) <= tol);
            CHECK(got[0] > -pi_t<T>());
            CHECK(got[0] <= pi_t<T>());
            CHECK(got[2] > -pi_t<T>());
            CHECK(got[2] <= pi_t<T>());
            // Normalises its input, and q and -q give the same angles.
            const auto scaled = anima::to_euler(
                make<Q>(3 * to_lq(q).w, 3 * to_lq(q).x, 3 * to_lq(q).y, 3 * to_lq(q).z), order);
            CHECK(std::abs(angle_diff(scaled[0], got[0])) <= tol);
            const auto negated = anima::to_euler(neg(q), order);
            CHECK(vdiff(negated, got) == 0);
        }
    }
    CHECK_THROWS_AS(anima::to_euler(make<Q>(0, 0, 0, 0), anima::euler_order::xyz), anima::invalid_argument);
}

TEST_CASE_TEMPLATE("to_euler at gimbal lock reproduces the rotation", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const ld tol = sizeof(T) == sizeof(double) ? 1e-7L : 1e-5L;
    rng r(43);
    for (anima::euler_order order : orders) {
        CAPTURE(anima::to_string(order));
        for (ld a1 : {pi / 2, -pi / 2, pi / 2 - 1e-9L, -(pi / 2 - 1e-9L)}) {
            for (int i = 0; i < 20; ++i) {
                const Q q = anima::from_euler<Q>(T(r.uniform(-pi, pi)), T(a1), T(r.uniform(-pi, pi)), order);
                CAPTURE(a1);
                CHECK(euler_round_trip_error(q, order) <= tol);
                CHECK(std::abs(anima::to_euler(q, order)[1] - a1) <= 1e-8L + 8 * eps<T>());
            }
        }
    }
}

// HEADER BUG (detail::matrix_to_euler, euler.hpp): below cos(a1) = sqrt(eps)
// it sets a2 = 0 and reads a0 from the matrix, which misplaces the rotation by
// about cos(a1) * |a2|; just above, a0 and a2 come from entries of size
// cos(a1) and lose precision as eps / cos(a1). Either way the round trip is off
// by ~sqrt(eps): 1e-3 rad in float, 4e-8 rad in double. Reading a2 from the
// residual R_a1^T R_a0^T R instead keeps it within a few eps for every a1.
TEST_CASE_TEMPLATE("to_euler round trip stays within a few ulps as a1 approaches +-pi/2", Q,
                   ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    rng r(44);
    for (anima::euler_order order : orders) {
        ld worst = 0, worst_d = 0;
        for (int i = 0; i <= 120; ++i) {
            const ld d = std::pow(10.0L, -12 + 11.0L * i / 120);  // distance from gimbal lock
            const ld a1 = (i % 2 ? 1 : -1) * (pi / 2 - d);
            const Q q = anima::from_euler<Q>(T(r.uniform(-pi, pi)), T(a1), T(r.uniform(-pi, pi)), order);
            const ld err = euler_round_trip_error(q, order);
            if (err > worst) worst = err, worst_d = d;
        }
        CAPTURE(anima::to_string(order));
        CAPTURE(worst_d);
        CHECK(worst <= 64 * eps<T>());
    }
}

// HEADER BUG (detail::matrix_to_euler, euler.hpp): a0 and a2 are documented in
// (-pi, pi], but atan2(-0.0, negative) returns -pi: a half turn about x gives
// to_euler((0, 1, 0, 0), xyz) = (-pi, 0, 0). The rotation is right, the range
// is not; e.g. map a result of -pi to +pi before returning.
TEST_CASE_TEMPLATE("to_euler keeps a0 and a2 in (-pi, pi] for exact half turns", Q, ANIMA_QUAT_TYPES) {
    for (anima::euler_order order : orders) {
        CAPTURE(anima::to_string(order));
        for (const Q& q : {make<Q>(0, 1, 0, 0), make<Q>(0, 0, 1, 0), make<Q>(0, 0, 0, 1),
                           make<Q>(0, -1, 0, 0), make<Q>(0, 0, -1, 0), make<Q>(0, 0, 0, -1)}) {
            const auto got = anima::to_euler(q, order);
            CAPTURE(got[0]);
            CAPTURE(got[2]);
            CHECK(got[0] > -pi_t<scalar<Q>>());
            CHECK(got[2] > -pi_t<scalar<Q>>());
            CHECK(euler_round_trip_error(q, order) <= 4 * eps<scalar<Q>>());
        }
    }
}

TEST_CASE("euler orders parse case-insensitively and print as upper case") {
    for (anima::euler_order order : orders) {
        const std::string name = anima::to_string(order);
        CHECK(name.size() == 3);
        CHECK(anima::parse_euler_order(name) == order);
        std::string lower = name;
        for (char& c : lower) c = char(c - 'X' + 'x');
        CHECK(anima::parse_euler_order(lower) == order);
        const auto ax = anima::axes_of(order);
        CHECK(anima::euler_order_of(ax[0], ax[1], ax[2]) == order);
        for (int i = 0; i < 3; ++i) CHECK(name[i] == char('X' + int(ax[i])));
    }
    CHECK(anima::parse_euler_order("zxy") == anima::euler_order::zxy);
    CHECK(anima::parse_euler_order("ZXY") == anima::euler_order::zxy);
    CHECK(anima::parse_euler_order("zXy") == anima::euler_order::zxy);
    CHECK(anima::to_string(anima::euler_order::zxy) == "ZXY");
    // The names a tool offers are the ones to_string prints.
    const std::vector<std::string> names = anima::enum_name_list<anima::euler_order>();
    CHECK(names.size() == 6);
    for (anima::euler_order order : orders)
        CHECK(std::find(names.begin(), names.end(), anima::to_string(order)) != names.end());
    CHECK_THROWS_WITH(anima::parse_euler_order("zxz"),
                      "anima::parse_euler_order: 'zxz' is not a rotation order: use XYZ, XZY, YXZ, YZX, ZXY or ZYX");
    for (const char* bad : {"zxz", "xxy", "abc", "xy", "", "xyzx", "x y", "XYW"}) {
        CAPTURE(bad);
        CHECK_THROWS_AS(anima::parse_euler_order(bad), anima::invalid_argument);
    }
    CHECK_THROWS_AS(anima::euler_order_of(anima::axis::z, anima::axis::x, anima::axis::z),
                    anima::invalid_argument);
}
