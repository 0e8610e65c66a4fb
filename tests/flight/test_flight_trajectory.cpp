// Keyframe trajectories: the natural cubic spline interpolates, is C2 at the
// knots with zero end curvature and reproduces straight lines; the key
// trajectory passes through every key pose, its velocities and
// accelerations (root and angular) agree with central differences of the
// positions and rotations, angular velocity is continuous across keys, and
// glm and Eigen quaternion keys give the same motion.
#include "flight_test_support.hpp"

#include <anima/flight/cubic_spline.hpp>
#include <anima/flight/key_trajectory.hpp>

#include <doctest/doctest.h>

#include <glm/ext/quaternion_double.hpp>
#include <glm/ext/quaternion_float.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

namespace {

using namespace flight_test;

template <class T>
using dmatrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

TEST_CASE_TEMPLATE("natural cubic spline: interpolation, C2 knots, natural ends, exact on lines", T, float, double) {
    const std::vector<T> t{T(0), T(0.3), T(1.1), T(1.5), T(2.6)};
    dmatrix<T> y(5, 2);
    y << T(1), T(0), T(-2), T(1), T(0.5), T(3), T(4), T(-1), T(0), T(2);
    const anima::cubic_spline<T> s(t, y);
    const T tol = tolerance<T>(1e-12, 2e-5);
    typename anima::cubic_spline<T>::row v, d1, d2, v2, e1, e2;
    for (std::size_t k = 0; k < t.size(); ++k) {
        s.evaluate(t[k], v, d1, d2);
        CHECK((v - y.row(static_cast<Eigen::Index>(k))).norm() < tol * T(10));
    }
    s.evaluate(t.front(), v, d1, d2);
    CHECK(d2.norm() < tol * T(10));
    s.evaluate(t.back(), v, d1, d2);
    CHECK(d2.norm() < tol * T(10));
    // Continuity of value, slope and curvature across interior knots.
    const T eps = tolerance<T>(1e-9, 1e-4);
    for (std::size_t k = 1; k + 1 < t.size(); ++k) {
        s.evaluate(t[k] - eps, v, d1, d2);
        s.evaluate(t[k] + eps, v2, e1, e2);
        CHECK((d1 - e1).norm() < T(1e-3) * (T(1) + d1.norm()));
        CHECK((d2 - e2).norm() < T(1e-2) * (T(1) + d2.norm()));
    }
    // Samples of a line are reproduced exactly between the knots.
    dmatrix<T> line(5, 1);
    for (int k = 0; k < 5; ++k) line(k, 0) = T(3) * t[static_cast<std::size_t>(k)] - T(1);
    const anima::cubic_spline<T> ls(t, line);
    for (T x : {T(0.1), T(0.9), T(2.2)}) {
        ls.evaluate(x, v, d1, d2);
        CHECK(std::abs(v[0] - (T(3) * x - T(1))) < tol * T(10));
        CHECK(std::abs(d1[0] - T(3)) < tol * T(10));
        CHECK(std::abs(d2[0]) < tol * T(10));
    }
    CHECK(contains(invalid_argument_message([&] { anima::cubic_spline<T>({T(0), T(0)}, dmatrix<T>::Zero(2, 1)); }),
                   "increase strictly"));
    CHECK(contains(invalid_argument_message([&] { anima::cubic_spline<T>({T(0)}, dmatrix<T>::Zero(1, 1)); }),
                   "at least 2"));
}

TEST_CASE_TEMPLATE("cubic spline: keys a hair apart whose curvatures overflow are refused, naming the interval", T,
                   float, double) {
    // Curvatures go as 1 / h^2: 1e-20 s overflows float, 1e-160 s double.
    const T h = static_cast<T>(std::is_same_v<T, float> ? 1e-20 : 1e-160);
    dmatrix<T> y(4, 1);
    y << T(0), T(1), T(0), T(1);
    CHECK(contains(invalid_argument_message([&] { anima::cubic_spline<T>({T(0), h, T(2) * h, T(3) * h}, y); }),
                   "the spline's derivatives are not finite in this precision (shortest key interval " +
                       anima::detail::argument_text(h) + " s)"));
    // Two keys: the slope alone overflows.
    const T big = std::numeric_limits<T>::max() / T(2);
    dmatrix<T> steep(2, 1);
    steep << -big, big;
    CHECK(contains(invalid_argument_message([&] { anima::cubic_spline<T>({T(0), T(0.5)}, steep); }),
                   "shortest key interval 0.5 s"));
    dmatrix<T> bad = y;
    bad(2, 0) = std::numeric_limits<T>::quiet_NaN();
    CHECK(contains(invalid_argument_message([&] { anima::cubic_spline<T>({T(0), T(1), T(2), T(3)}, bad); }),
                   "value (2, 0) must be finite, got nan"));
    // An infinite last time still "increases": refused by name.
    CHECK(contains(invalid_argument_message([&] {
                       anima::cubic_spline<T>({T(0), T(1), T(2), std::numeric_limits<T>::infinity()}, y);
                   }),
                   "times must be finite; t[3] = inf"));
    // A wider spacing in the same precision still interpolates.
    const T wide = static_cast<T>(std::is_same_v<T, float> ? 1e-13 : 1e-150);
    const anima::cubic_spline<T> s({T(0), wide, T(2) * wide, T(3) * wide}, y);
    typename anima::cubic_spline<T>::row v, d1, d2;
    s.evaluate(T(1.5) * wide, v, d1, d2);
    CHECK(v.allFinite());
    CHECK(d1.allFinite());
    CHECK(d2.allFinite());
}

// Angular velocity w (parent frame) from rotations at t +- h: dR/dt R^T = [w]x.
template <class T>
vec3<T> finite_angular_velocity(const mat3<T>& lo, const mat3<T>& mid, const mat3<T>& hi, T h) {
    const mat3<T> W = (hi - lo) / (T(2) * h) * mid.transpose();
    return vec3<T>(W(2, 1) - W(1, 2), W(0, 2) - W(2, 0), W(1, 0) - W(0, 1)) / T(2);
}

TEST_CASE_TEMPLATE("key trajectory: keys reproduced, derivatives match central differences", T, float, double) {
    std::mt19937 rng(5);
    const auto keys = random_keys<T>(rng, 4, 7, T(1.6));
    const auto traj = anima::key_trajectory<T>::from_keys(keys);
    const T tol = tolerance<T>(1e-10, 1e-4);
    for (std::size_t k = 0; k < keys.size(); ++k) {
        const auto x = traj.at(keys.times[k]);
        CHECK((x.root_position - keys.root_positions[k]).norm() < tol * T(10));
        for (std::size_t j = 0; j < 4; ++j)
            CHECK((x.rotations[j] - keys.rotations[k][j].toRotationMatrix()).norm() < tol * T(10));
    }
    const T h = tolerance<T>(1e-5, 2e-3), dtol = tolerance<T>(1e-6, 2e-2);
    for (T t : {T(0.05), T(0.41), T(0.9), T(1.33)}) {
        const auto lo = traj.at(t - h), mid = traj.at(t), hi = traj.at(t + h);
        CHECK((mid.root_velocity - (hi.root_position - lo.root_position) / (T(2) * h)).norm() <
              dtol * (T(1) + mid.root_velocity.norm()));
        CHECK((mid.root_acceleration - (hi.root_velocity - lo.root_velocity) / (T(2) * h)).norm() <
              dtol * (T(1) + mid.root_acceleration.norm()));
        for (std::size_t j = 0; j < 4; ++j) {
            CHECK((mid.rotations[j] * mid.rotations[j].transpose() - mat3<T>::Identity()).norm() < tol * T(10));
            const vec3<T> w = finite_angular_velocity(lo.rotations[j], mid.rotations[j], hi.rotations[j], h);
            CHECK((mid.angular_velocities[j] - w).norm() < dtol * (T(1) + w.norm()));
            const vec3<T> a = (hi.angular_velocities[j] - lo.angular_velocities[j]) / (T(2) * h);
            CHECK((mid.angular_accelerations[j] - a).norm() < dtol * (T(1) + a.norm()));
        }
    }
    // Angular velocity is continuous across an interior key.
    const T e = tolerance<T>(1e-8, 1e-4);
    const auto before = traj.at(keys.times[3] - e), after = traj.at(keys.times[3] + e);
    for (std::size_t j = 0; j < 4; ++j)
        CHECK((before.angular_velocities[j] - after.angular_velocities[j]).norm() <
              T(1e-2) * (T(1) + before.angular_velocities[j].norm()));
    CHECK(contains(invalid_argument_message([&] { traj.at(T(2)); }), "outside"));
}

TEST_CASE_TEMPLATE("glm and Eigen quaternion keys give the same motion; opposite signs are one rotation", T, float,
                   double) {
    using gq = std::conditional_t<std::is_same_v<T, float>, glm::quat, glm::dquat>;
    std::mt19937 rng(9);
    auto keys = random_keys<T>(rng, 2, 4, T(1));
    auto flipped = keys;
    for (std::size_t k = 0; k < keys.size(); ++k) {
        const auto& q = keys.rotations[k][1];
        gq g;
        g.w = q.w();
        g.x = q.x();
        g.y = q.y();
        g.z = q.z();
        keys.set_rotation(k, 1, g);
        if (k % 2) flipped.rotations[k][1].coeffs() *= T(-1);
    }
    const auto a = anima::key_trajectory<T>::from_keys(keys), b = anima::key_trajectory<T>::from_keys(flipped);
    const T tol = tolerance<T>(1e-12, 1e-5);
    for (T t : {T(0.2), T(0.5), T(0.9)}) {
        const auto x = a.at(t), y = b.at(t);
        CHECK((x.rotations[1] - y.rotations[1]).norm() < tol);
        CHECK((x.angular_velocities[1] - y.angular_velocities[1]).norm() < tol * T(10));
    }
    CHECK_THROWS_AS(keys.set_rotation(9, 0, gq()), anima::invalid_argument);
    keys.times[2] = keys.times[1];
    CHECK(contains(invalid_argument_message([&] { anima::key_trajectory<T>::from_keys(keys); }), "increase strictly"));
}

}  // namespace
