// Body model and inverse dynamics: de Leva masses sum to the body mass on
// both CMU layouts; a single body in free fall and in torque-free rotation
// (Euler's equations) needs no root force; on random trees and random
// spline motions the root residual equals the rate of change of momentum
// minus gravity (checked against momenta summed independently and
// differentiated numerically); momentum() agrees with that sum.
#include "flight_test_support.hpp"

#include <anima/flight/body_model.hpp>
#include <anima/flight/inverse_dynamics.hpp>
#include <anima/flight/key_trajectory.hpp>

#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <random>
#include <string>

namespace {

using namespace flight_test;

TEST_CASE_TEMPLATE("de Leva body model of the CMU skeletons: masses, centres, inertias", T, float, double) {
    const T tol = tolerance<T>(1e-12, 1e-4);
    for (const char* file : {"walk_cmu31_02_01.bvh", "run_cmu_09_01.bvh"}) {
        CAPTURE(file);
        const auto sk = anima::read_bvh<T>(bundled(file)).skeleton();
        for (anima::sex s : {anima::sex::male, anima::sex::female}) {
            anima::body_model_params<T> p;
            p.body_mass = T(63.5);
            p.sex = s;
            const auto model = anima::make_body_model(sk, p);
            REQUIRE(model.size() == sk.size());
            CHECK(std::abs(model.total_mass() - T(63.5)) < T(63.5) * tol);
            int massive = 0;
            for (std::size_t j = 0; j < model.size(); ++j) {
                if (model.masses[j] == T(0)) {
                    CHECK(model.inertias[j].norm() == T(0));
                    continue;
                }
                ++massive;
                Eigen::SelfAdjointEigenSolver<mat3<T>> es(model.inertias[j]);
                const auto ev = es.eigenvalues();
                CHECK(ev.minCoeff() > T(0));
                // A real body: each principal moment at most the sum of the other two.
                CHECK(ev[2] <= (ev[0] + ev[1]) * (T(1) + tol) + tol);
                CHECK(model.coms[j].norm() < T(0.5));  // metres: inside a human-sized segment
            }
            CHECK(massive == 16);
        }
        // The thigh is its de Leva share of the mass.
        const auto model = anima::make_body_model(sk, {});
        const auto thigh = sk.find("LeftUpLeg") ? *sk.find("LeftUpLeg") : *sk.find("lThigh");
        CHECK(std::abs(model.masses[thigh] - T(70 * 0.1416)) < T(70) * tol);
    }
}

TEST_CASE_TEMPLATE("body model arguments are checked by name", T, float, double) {
    const auto sk = cmu31_skeleton<T>();
    anima::body_model_params<T> p;
    p.body_mass = T(-1);
    CHECK(contains(invalid_argument_message([&] { anima::make_body_model(sk, p); }), "body_mass"));
    p.body_mass = T(70);
    p.segments = {{anima::segment_kind::thigh, "NoSuchJoint", ""}};
    CHECK(contains(invalid_argument_message([&] { anima::make_body_model(sk, p); }), "NoSuchJoint"));
    p.segments = {{anima::segment_kind::thigh, "LeftLeg", "LeftUpLeg"}};
    CHECK(contains(invalid_argument_message([&] { anima::make_body_model(sk, p); }), "not below"));
    anima::skeleton<T> other;
    other.add_joint("pelvis", -1, vec3<T>::Zero());
    CHECK(contains(invalid_argument_message([&] { anima::default_segment_map(other); }), "pelvis"));
    CHECK_THROWS_AS(anima::parse_segment_kind("wing"), anima::invalid_argument);
    anima::rigid_body_model<T> m;
    CHECK(contains(invalid_argument_message([&] { m.add_body("x", 0, vec3<T>::Zero(), T(1), vec3<T>::Zero(), mat3<T>::Identity()); }),
                   "parent"));
    mat3<T> skew = mat3<T>::Identity();
    skew(0, 1) = T(1);
    CHECK(contains(invalid_argument_message([&] { m.add_body("x", -1, vec3<T>::Zero(), T(1), vec3<T>::Zero(), skew); }),
                   "symmetric"));
}

// One body whose centre of mass sits off the joint.
template <class T>
anima::rigid_body_model<T> single_body(std::mt19937& rng) {
    anima::rigid_body_model<T> m;
    m.add_body("box", -1, vec3<T>::Zero(), T(3), vec3<T>(T(0.1), T(-0.2), T(0.05)), random_inertia<T>(rng, T(0.2)));
    return m;
}

TEST_CASE_TEMPLATE("a single body in free fall and in torque-free rotation has zero root residual", T, float, double) {
    std::mt19937 rng(7);
    const auto model = single_body<T>(rng);
    const vec3<T> g(T(0), T(-9.81), T(0));
    const T tol = tolerance<T>(1e-12, 2e-4);
    for (int trial = 0; trial < 20; ++trial) {
        auto x = anima::body_motion<T>::at_rest(1);
        const mat3<T> R = Eigen::Quaternion<T>::UnitRandom().toRotationMatrix();
        const vec3<T> w = vec3<T>::Random() * T(5);
        // Euler's equations in the body frame with no torque.
        const mat3<T> I = model.inertias[0];
        const vec3<T> wb = R.transpose() * w;
        const vec3<T> ab = -I.inverse() * wb.cross(I * wb);
        const vec3<T> a = R * ab;
        const vec3<T> rc = R * model.coms[0];
        x.rotations[0] = R;
        x.angular_velocities[0] = w;
        x.angular_accelerations[0] = a;
        x.root_position = vec3<T>::Random();
        x.root_velocity = vec3<T>::Random();
        // The joint accelerates so that the centre of mass falls freely.
        x.root_acceleration = g - a.cross(rc) - w.cross(w.cross(rc));
        const auto r = anima::inverse_dynamics(model, x, g);
        const T scale = model.masses[0] * T(10) + (I * wb).norm() * w.norm();
        CHECK(r.root_residual().norm() < tol * scale);
        // Not free fall: the residual is the missing force, m (a - g).
        x.root_acceleration += vec3<T>(T(1), T(0), T(0));
        const auto r2 = anima::inverse_dynamics(model, x, g);
        CHECK((r2.root_force - vec3<T>(model.masses[0], T(0), T(0))).norm() < tol * scale);
        CHECK((r2.root_moment - rc.cross(vec3<T>(model.masses[0], T(0), T(0)))).norm() < tol * scale);
    }
}

TEST_CASE_TEMPLATE("root residual = d(momentum)/dt - gravity on random spline motions (centroidal identity)", T, float,
                   double) {
    std::mt19937 rng(11);
    const vec3<T> g(T(0.3), T(-9.81), T(0.2));
    // Central differences: h balances truncation and rounding per precision.
    const T h = tolerance<T>(1e-5, 3e-3);
    const T tol = tolerance<T>(2e-6, 3e-2);
    for (int trial = 0; trial < 6; ++trial) {
        const auto model = random_model<T>(rng, 2 + static_cast<std::size_t>(trial) * 3);
        const auto keys = random_keys<T>(rng, model.size(), 6, T(2));
        const auto traj = anima::key_trajectory<T>::from_keys(keys);
        for (T t : {T(0.3), T(0.77), T(1.5)}) {
            const auto x = traj.at(t);
            const auto r = anima::inverse_dynamics(model, x, g);
            const auto lo = reference_momentum(model, traj.at(t - h)), hi = reference_momentum(model, traj.at(t + h));
            const auto mid = reference_momentum(model, x);
            const T M = model.total_mass();
            const vec3<T> dP = (hi.linear - lo.linear) / (T(2) * h);
            const vec3<T> dH = (hi.angular - lo.angular) / (T(2) * h);
            const vec3<T> force = dP - M * g;
            const vec3<T> moment_origin = dH - mid.first_moment.cross(g);
            const vec3<T> moment_root = moment_origin - x.root_position.cross(force);
            const T scale = T(1) + force.norm() + dH.norm();
            CHECK((r.root_force - force).norm() < tol * scale);
            CHECK((r.root_moment - moment_root).norm() < tol * scale);

            // anima::momentum agrees with the independent sum.
            const auto m = anima::momentum(model, x);
            const T mtol = tolerance<T>(1e-10, 1e-4);
            CHECK(std::abs(m.mass - M) < mtol * M);
            CHECK((m.centre_of_mass - mid.first_moment / M).norm() < mtol * (T(1) + m.centre_of_mass.norm()));
            CHECK((m.linear_momentum - mid.linear).norm() < mtol * (T(1) + mid.linear.norm()));
            const vec3<T> about_com = mid.angular - m.centre_of_mass.cross(mid.linear);
            CHECK((m.angular_momentum - about_com).norm() < mtol * (T(1) + mid.angular.norm() + M * m.centre_of_mass.norm() * mid.linear.norm()));
            CHECK((m.com_acceleration * M - dP).norm() < tol * scale);
        }
    }
}

TEST_CASE_TEMPLATE("joint torques balance each subtree's momentum change", T, float, double) {
    // For a chain root - a - b, the torque at a (about joint a) equals the rate
    // of change of the angular momentum of {a, b} about joint a's position
    // plus the moment of gravity and inertial terms; checked here by the
    // simplest case: a motionless pose under gravity is pure statics.
    anima::rigid_body_model<T> m;
    m.add_body("root", -1, vec3<T>::Zero(), T(1), vec3<T>::Zero(), mat3<T>::Identity() * T(0.01));
    m.add_body("arm", 0, vec3<T>(T(0), T(0), T(0)), T(2), vec3<T>(T(0.5), T(0), T(0)), mat3<T>::Identity() * T(0.01));
    m.add_body("hand", 1, vec3<T>(T(1), T(0), T(0)), T(1), vec3<T>(T(0.1), T(0), T(0)), mat3<T>::Identity() * T(0.01));
    const vec3<T> g(T(0), T(-10), T(0));
    const auto r = anima::inverse_dynamics(m, anima::body_motion<T>::at_rest(3), g);
    const T tol = tolerance<T>(1e-12, 1e-5);
    // Holding the arm horizontal: about the shoulder 2*10*0.5 + 1*10*1.1 = 21 N m about +Z.
    CHECK((r.joint_torques[1] - vec3<T>(T(0), T(0), T(21))).norm() < tol * T(21));
    CHECK((r.joint_torques[2] - vec3<T>(T(0), T(0), T(1))).norm() < tol * T(21));
    CHECK((r.root_force - vec3<T>(T(0), T(40), T(0))).norm() < tol * T(40));
}

TEST_CASE_TEMPLATE("inverse dynamics refuses malformed motions", T, float, double) {
    std::mt19937 rng(3);
    const auto model = random_model<T>(rng, 3);
    auto x = anima::body_motion<T>::at_rest(2);
    const vec3<T> g(T(0), T(-9.81), T(0));
    CHECK(contains(invalid_argument_message([&] { anima::inverse_dynamics(model, x, g); }), "3 bodies"));
    x = anima::body_motion<T>::at_rest(3);
    x.root_velocity[1] = std::numeric_limits<T>::quiet_NaN();
    CHECK(contains(invalid_argument_message([&] { anima::inverse_dynamics(model, x, g); }), "non-finite"));
    anima::rigid_body_model<T> massless;
    massless.add_body("x", -1, vec3<T>::Zero(), T(0), vec3<T>::Zero(), mat3<T>::Zero());
    CHECK(contains(invalid_argument_message([&] { anima::momentum(massless, anima::body_motion<T>::at_rest(1)); }),
                   "no mass"));
}

}  // namespace
