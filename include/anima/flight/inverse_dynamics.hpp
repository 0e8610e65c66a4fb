// Recursive Newton-Euler inverse dynamics of a floating-base tree of rigid
// bodies with ball joints, rotations given as rotation matrices (built from
// quaternions: no Euler-angle singularity). An outward pass carries angular
// velocity and acceleration and the linear acceleration of every joint and
// centre of mass down the tree; an inward pass sums the Newton-Euler force
// and moment each body needs back towards the root. What reaches the root is
// the six generalised forces F1..F6 (the force and the moment about the root
// joint, world frame) that something would have to apply to the root for the
// motion to happen. In flight nothing but gravity acts, so they should vanish.
//
// All vectors are world-frame 3-vectors (the world-frame form of the
// spatial-vector recursion); every function is templated on the scalar so
// the same code runs on Eigen's AutoDiffScalar for exact derivatives.
#pragma once

#include <anima/core/error.hpp>
#include <anima/flight/body_model.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace anima {

/// The state of the tree at one instant. Joint j's local rotation Q_j is
/// relative to its parent (the root's is its world orientation); its
/// angular velocity and acceleration relative to the parent are expressed in
/// the parent's frame (the root's in the world), so that dQ/dt = [w]x Q.
template <class S>
struct body_motion {
    using vector3 = Eigen::Matrix<S, 3, 1>;
    using matrix3 = Eigen::Matrix<S, 3, 3>;
    vector3 root_position = vector3::Zero(), root_velocity = vector3::Zero(), root_acceleration = vector3::Zero();
    std::vector<matrix3> rotations;
    std::vector<vector3> angular_velocities;
    std::vector<vector3> angular_accelerations;

    /// n joints at rest (identity rotations, no motion).
    static body_motion at_rest(std::size_t n) {
        body_motion m;
        m.rotations.assign(n, matrix3::Identity());
        m.angular_velocities.assign(n, vector3::Zero());
        m.angular_accelerations.assign(n, vector3::Zero());
        return m;
    }
};

template <class S>
struct inverse_dynamics_result {
    using vector3 = Eigen::Matrix<S, 3, 1>;
    vector3 root_force = vector3::Zero();   ///< F1..F3, world frame, N
    vector3 root_moment = vector3::Zero();  ///< F4..F6 about the root joint, world frame, N m
    /// Moment the parent applies to joint j through the ball joint, in the
    /// parent's frame (the root's entry is root_moment).
    std::vector<vector3> joint_torques;

    /// (F1..F6): what must vanish in flight.
    Eigen::Matrix<S, 6, 1> root_residual() const {
        Eigen::Matrix<S, 6, 1> r;
        r << root_force, root_moment;
        return r;
    }
};

/// Centre of mass, linear momentum and angular momentum about the centre of
/// mass, world frame.
template <class S>
struct momentum_state {
    using vector3 = Eigen::Matrix<S, 3, 1>;
    S mass = S(0);
    vector3 centre_of_mass = vector3::Zero();
    vector3 com_velocity = vector3::Zero();
    vector3 com_acceleration = vector3::Zero();
    vector3 linear_momentum = vector3::Zero();
    vector3 angular_momentum = vector3::Zero();  ///< about the centre of mass
};

namespace detail {

/// World-frame kinematics of every body from the outward pass.
template <class S>
struct body_kinematics {
    using vector3 = Eigen::Matrix<S, 3, 1>;
    using matrix3 = Eigen::Matrix<S, 3, 3>;
    std::vector<matrix3> orientation;
    std::vector<vector3> position, velocity, acceleration;  // joint origins
    std::vector<vector3> omega, alpha;                      // angular velocity and acceleration
    std::vector<vector3> com, com_velocity, com_acceleration;
};

template <class S>
void outward_pass(const rigid_body_model<S>& model, const body_motion<S>& x, body_kinematics<S>& k) {
    using vector3 = Eigen::Matrix<S, 3, 1>;
    const std::size_t n = model.size();
    for (auto* v : {&k.position, &k.velocity, &k.acceleration, &k.omega, &k.alpha, &k.com, &k.com_velocity,
                    &k.com_acceleration})
        v->resize(n);
    k.orientation.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
        const int p = model.parents[j];
        if (p < 0) {
            k.orientation[j] = x.rotations[j];
            k.position[j] = x.root_position;
            k.velocity[j] = x.root_velocity;
            k.acceleration[j] = x.root_acceleration;
            k.omega[j] = x.angular_velocities[j];
            k.alpha[j] = x.angular_accelerations[j];
        } else {
            const auto q = static_cast<std::size_t>(p);
            const vector3 r = k.orientation[q] * model.offsets[j];
            const vector3 w_rel = k.orientation[q] * x.angular_velocities[j];
            k.orientation[j] = k.orientation[q] * x.rotations[j];
            k.position[j] = k.position[q] + r;
            k.velocity[j] = k.velocity[q] + k.omega[q].cross(r);
            k.acceleration[j] = k.acceleration[q] + k.alpha[q].cross(r) + k.omega[q].cross(k.omega[q].cross(r));
            k.omega[j] = k.omega[q] + w_rel;
            k.alpha[j] = k.alpha[q] + k.omega[q].cross(w_rel) + k.orientation[q] * x.angular_accelerations[j];
        }
        const vector3 rc = k.orientation[j] * model.coms[j];
        k.com[j] = k.position[j] + rc;
        k.com_velocity[j] = k.velocity[j] + k.omega[j].cross(rc);
        k.com_acceleration[j] = k.acceleration[j] + k.alpha[j].cross(rc) + k.omega[j].cross(k.omega[j].cross(rc));
    }
}

template <class S>
momentum_state<S> momentum_of(const rigid_body_model<S>& model, const body_kinematics<S>& k) {
    using vector3 = Eigen::Matrix<S, 3, 1>;
    momentum_state<S> out;
    vector3 first = vector3::Zero(), acc = vector3::Zero();
    for (std::size_t j = 0; j < model.size(); ++j) {
        out.mass += model.masses[j];
        first += model.masses[j] * k.com[j];
        out.linear_momentum += model.masses[j] * k.com_velocity[j];
        acc += model.masses[j] * k.com_acceleration[j];
    }
    out.centre_of_mass = first / out.mass;
    out.com_velocity = out.linear_momentum / out.mass;
    out.com_acceleration = acc / out.mass;
    for (std::size_t j = 0; j < model.size(); ++j) {
        const auto& R = k.orientation[j];
        out.angular_momentum += R * (model.inertias[j] * (R.transpose() * k.omega[j])) +
                                model.masses[j] * (k.com[j] - out.centre_of_mass).cross(k.com_velocity[j] - out.com_velocity);
    }
    return out;
}

template <class S>
void inward_pass(const rigid_body_model<S>& model, const body_kinematics<S>& k,
                 const Eigen::Matrix<S, 3, 1>& gravity, inverse_dynamics_result<S>& out) {
    using vector3 = Eigen::Matrix<S, 3, 1>;
    const std::size_t n = model.size();
    std::vector<vector3> force(n, vector3::Zero()), moment(n, vector3::Zero());  // about each joint
    out.joint_torques.resize(n);
    for (std::size_t j = n; j-- > 0;) {
        const auto& R = k.orientation[j];
        const vector3 w_body = R.transpose() * k.omega[j], a_body = R.transpose() * k.alpha[j];
        const vector3 f = model.masses[j] * (k.com_acceleration[j] - gravity);
        const vector3 n_com = R * (model.inertias[j] * a_body + w_body.cross(model.inertias[j] * w_body));
        force[j] += f;
        moment[j] += n_com + (k.com[j] - k.position[j]).cross(f);
        const int p = model.parents[j];
        if (p >= 0) {
            const auto q = static_cast<std::size_t>(p);
            force[q] += force[j];
            moment[q] += moment[j] + (k.position[j] - k.position[q]).cross(force[j]);
            out.joint_torques[j] = k.orientation[q].transpose() * moment[j];
        } else {
            out.joint_torques[j] = moment[j];
        }
    }
    out.root_force = vector3::Zero();
    out.root_moment = vector3::Zero();
    for (std::size_t j = 0; j < n; ++j)
        if (model.parents[j] < 0) {  // a forest: every root is floating; their sums are reported
            out.root_force += force[j];
            out.root_moment += moment[j] + (k.position[j] - k.position[0]).cross(force[j]);
        }
}

template <class S>
void check_motion(const rigid_body_model<S>& model, const body_motion<S>& x, const char* who) {
    const std::size_t n = model.size();
    if (n == 0) throw invalid_argument(std::string(who) + ": empty model");
    if (x.rotations.size() != n || x.angular_velocities.size() != n || x.angular_accelerations.size() != n)
        throw invalid_argument(std::string(who) + ": motion has " + std::to_string(x.rotations.size()) + "/" +
                               std::to_string(x.angular_velocities.size()) + "/" +
                               std::to_string(x.angular_accelerations.size()) +
                               " rotations/velocities/accelerations for " + std::to_string(n) + " bodies");
    bool finite = x.root_position.allFinite() && x.root_velocity.allFinite() && x.root_acceleration.allFinite();
    for (std::size_t j = 0; j < n; ++j)
        finite = finite && x.rotations[j].allFinite() && x.angular_velocities[j].allFinite() &&
                 x.angular_accelerations[j].allFinite();
    if (!finite) throw invalid_argument(std::string(who) + ": motion has non-finite values");
}

}  // namespace detail

/// F1..F6 and joint torques for one instant. gravity: world acceleration of
/// gravity (m/s^2), e.g. (0, -9.81, 0) for a Y-up world.
template <class S>
inverse_dynamics_result<S> inverse_dynamics(const rigid_body_model<S>& model, const body_motion<S>& motion,
                                            const Eigen::Matrix<S, 3, 1>& gravity) {
    detail::check_motion(model, motion, "anima::inverse_dynamics");
    if (!gravity.allFinite()) throw invalid_argument("anima::inverse_dynamics: gravity is not finite");
    detail::body_kinematics<S> k;
    detail::outward_pass(model, motion, k);
    inverse_dynamics_result<S> out;
    detail::inward_pass(model, k, gravity, out);
    return out;
}

/// Centre of mass, its velocity and acceleration, linear momentum and angular
/// momentum about the centre of mass. Throws for a model without mass.
template <class S>
momentum_state<S> momentum(const rigid_body_model<S>& model, const body_motion<S>& motion) {
    detail::check_motion(model, motion, "anima::momentum");
    if (!(model.total_mass() > S(0))) throw invalid_argument("anima::momentum: the model has no mass");
    detail::body_kinematics<S> k;
    detail::outward_pass(model, motion, k);
    return detail::momentum_of(model, k);
}

}  // namespace anima
