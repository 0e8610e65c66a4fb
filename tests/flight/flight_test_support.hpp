// Models, motions and reference quantities shared by the flight tests.
#pragma once

#include "../test_support.hpp"

#include <anima/bvh/reader.hpp>
#include <anima/core/random.hpp>
#include <anima/flight/body_model.hpp>
#include <anima/flight/instances.hpp>  // compiled once when the build provides them
#include <anima/flight/inverse_dynamics.hpp>
#include <anima/flight/key_trajectory.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <random>
#include <string>
#include <vector>

namespace flight_test {

using anima_test::bundled;
using anima_test::contains;
using anima_test::invalid_argument_message;
using anima_test::tolerance;

template <class T>
using vec3 = Eigen::Matrix<T, 3, 1>;
template <class T>
using mat3 = Eigen::Matrix<T, 3, 3>;

/// The CMU 31-joint skeleton bundled in examples/data.
template <class T>
anima::skeleton<T> cmu31_skeleton() {
    return anima::read_bvh<T>(bundled("walk_cmu31_02_01.bvh")).skeleton();
}

/// A symmetric positive definite inertia with distinct principal moments
/// about a random axis frame.
template <class T>
mat3<T> random_inertia(std::mt19937& rng, T scale) {
    std::uniform_real_distribution<double> u(0.5, 1.5);
    const Eigen::Quaternion<T> q = Eigen::Quaternion<T>::UnitRandom();
    const vec3<T> d(T(u(rng)) * scale, T(u(rng)) * scale, T(u(rng)) * scale);
    // Triangle inequality for a physical body: each moment below the sum of the others.
    const mat3<T> r = q.toRotationMatrix();
    return r * d.asDiagonal() * r.transpose();
}

/// A random tree of `n` bodies (parents before children), masses 1..5 kg.
template <class T>
anima::rigid_body_model<T> random_model(std::mt19937& rng, std::size_t n) {
    std::uniform_real_distribution<double> u(-0.4, 0.4), m(1.0, 5.0);
    anima::rigid_body_model<T> model;
    for (std::size_t j = 0; j < n; ++j) {
        const int parent = j == 0 ? -1 : static_cast<int>(rng() % j);
        const vec3<T> offset = j == 0 ? vec3<T>::Zero() : vec3<T>(T(u(rng)), T(u(rng)), T(u(rng)));
        model.add_body("b" + std::to_string(j), parent, offset, T(m(rng)), vec3<T>(T(u(rng)), T(u(rng)), T(u(rng))),
                       random_inertia<T>(rng, T(0.05)));
    }
    return model;
}

/// Random keys for a model: n keys over [0, duration], rotations within
/// ~60 degrees of the previous key.
template <class T>
anima::flight_keys<T> random_keys(std::mt19937& rng, std::size_t joints, std::size_t n, T duration) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    anima::flight_keys<T> keys;
    for (std::size_t k = 0; k < n; ++k) {
        keys.times.push_back(duration * T(k) / T(n - 1) + (k > 0 && k + 1 < n ? T(0.2 * u(rng)) * duration / T(n) : T(0)));
        keys.root_positions.push_back(vec3<T>(T(u(rng)), T(u(rng)), T(u(rng))));
        keys.rotations.emplace_back();
        for (std::size_t j = 0; j < joints; ++j) {
            const vec3<T> axis = vec3<T>(T(u(rng)), T(u(rng)), T(u(rng))).normalized();
            const Eigen::Quaternion<T> step(Eigen::AngleAxis<T>(T(0.5 + 0.5 * u(rng)), axis));
            keys.rotations.back().push_back(k == 0 ? step : Eigen::Quaternion<T>(keys.rotations[k - 1][j] * step));
        }
    }
    return keys;
}

/// Angular momentum about the world origin, summed body by body (independent
/// of anima::momentum: uses its own forward kinematics and velocity sums).
template <class T>
struct momentum_about_origin {
    vec3<T> linear = vec3<T>::Zero();
    vec3<T> angular = vec3<T>::Zero();
    vec3<T> first_moment = vec3<T>::Zero();  // sum m c
};

template <class T>
momentum_about_origin<T> reference_momentum(const anima::rigid_body_model<T>& model, const anima::body_motion<T>& x) {
    const std::size_t n = model.size();
    std::vector<mat3<T>> R(n);
    std::vector<vec3<T>> p(n), v(n), w(n);
    momentum_about_origin<T> out;
    for (std::size_t j = 0; j < n; ++j) {
        const int par = model.parents[j];
        if (par < 0) {
            R[j] = x.rotations[j];
            p[j] = x.root_position;
            v[j] = x.root_velocity;
            w[j] = x.angular_velocities[j];
        } else {
            const auto q = static_cast<std::size_t>(par);
            R[j] = R[q] * x.rotations[j];
            p[j] = p[q] + R[q] * model.offsets[j];
            v[j] = v[q] + w[q].cross(R[q] * model.offsets[j]);
            w[j] = w[q] + R[q] * x.angular_velocities[j];
        }
        const vec3<T> c = p[j] + R[j] * model.coms[j];
        const vec3<T> vc = v[j] + w[j].cross(R[j] * model.coms[j]);
        out.linear += model.masses[j] * vc;
        out.first_moment += model.masses[j] * c;
        out.angular += R[j] * model.inertias[j] * R[j].transpose() * w[j] + model.masses[j] * c.cross(vc);
    }
    return out;
}

}  // namespace flight_test
