// A smooth motion through keyframes: the root position on a natural cubic
// spline (C2), and every joint's rotation on a natural cubic spline of its
// quaternion's four components, renormalised: q(t) = s(t) / |s(t)|.
//
// Why this quaternion spline: it passes through the keys exactly, is C2 in
// the rotation (so angular velocity and acceleration are continuous, which
// the dynamics need), its derivatives are closed-form (only a square root:
// it runs on AutoDiff scalars), and it has no singularity as long as s(t)
// stays away from 0, which holding consecutive keys in one hemisphere
// (q_k . q_k+1 >= 0, done by the caller-facing constructor) ensures for key
// steps below ~150 degrees. It is not constant-speed between keys, which
// the dynamics do not ask for.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/flight/cubic_spline.hpp>
#include <anima/core/scalar_value.hpp>
#include <anima/flight/inverse_dynamics.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace anima {

/// Keyframes of a motion in flight: key times (seconds), root positions
/// (metres, world) and every joint's local rotation (rotations[k][j]; the
/// root's is its world orientation), joints indexed as in the body model.
template <class T>
struct flight_keys {
    std::vector<T> times;
    std::vector<Eigen::Matrix<T, 3, 1>> root_positions;
    std::vector<std::vector<Eigen::Quaternion<T>>> rotations;

    std::size_t size() const noexcept { return times.size(); }

    /// Sets a rotation from any quaternion type with quat_traits (glm::qua,
    /// Eigen::Quaternion).
    template <class Q>
    void set_rotation(std::size_t key, std::size_t joint, const Q& q) {
        using tr = quat_traits<Q>;
        if (key >= rotations.size() || joint >= rotations[key].size())
            throw invalid_argument("anima::flight_keys::set_rotation: key " + std::to_string(key) + ", joint " +
                                   std::to_string(joint) + " out of range");
        rotations[key][joint] = Eigen::Quaternion<T>(T(tr::w(q)), T(tr::x(q)), T(tr::y(q)), T(tr::z(q)));
    }
};

/// The largest key time (seconds) and root coordinate (metres) a flight may
/// have, in magnitude: beyond them the dynamics' squares overflow.
constexpr double flight_max_time = 1e6, flight_max_position = 1e6;

/// Checks a key set against a number of joints: >= 2 keys, strictly
/// increasing finite times within +-flight_max_time, root positions within
/// +-flight_max_position, non-zero finite quaternions.
template <class T>
void check_keys(const flight_keys<T>& keys, std::size_t joints, const char* who) {
    const std::string w(who);
    const std::size_t n = keys.times.size();
    if (n < 2) throw invalid_argument(w + ": needs at least 2 keys, got " + std::to_string(n));
    if (keys.root_positions.size() != n || keys.rotations.size() != n)
        throw invalid_argument(w + ": " + std::to_string(n) + " key times but " +
                               std::to_string(keys.root_positions.size()) + " root positions and " +
                               std::to_string(keys.rotations.size()) + " rotation sets");
    for (std::size_t k = 0; k < n; ++k) {
        if (!std::isfinite(keys.times[k]) || (k > 0 && !(keys.times[k] > keys.times[k - 1])))
            throw invalid_argument(w + ": key times must be finite and increase strictly; key " + std::to_string(k) +
                                   " has " + detail::argument_text(keys.times[k]));
        if (!(std::abs(static_cast<double>(keys.times[k])) <= flight_max_time))
            throw invalid_argument(w + ": key " + std::to_string(k) + ": time " +
                                   detail::argument_text(keys.times[k]) + " s is outside +-1e6 s");
        if (!keys.root_positions[k].allFinite())
            throw invalid_argument(w + ": key " + std::to_string(k) + ": root position is not finite");
        if (!(static_cast<double>(keys.root_positions[k].cwiseAbs().maxCoeff()) <= flight_max_position))
            throw invalid_argument(w + ": key " + std::to_string(k) + ": root position has a coordinate outside +-1e6 m");
        if (keys.rotations[k].size() != joints)
            throw invalid_argument(w + ": key " + std::to_string(k) + " has " +
                                   std::to_string(keys.rotations[k].size()) + " rotations for " +
                                   std::to_string(joints) + " joints");
        for (std::size_t j = 0; j < joints; ++j) {
            const T nq = keys.rotations[k][j].norm();
            if (!(nq > T(0)) || !std::isfinite(nq))
                throw invalid_argument(w + ": key " + std::to_string(k) + ", joint " + std::to_string(j) +
                                       ": zero or non-finite quaternion");
        }
    }
}

namespace detail {

/// Rotation matrix of a unit quaternion stored as (w, x, y, z): the rotation
/// toolkit's to_matrix, which runs on AutoDiff scalars.
template <class S>
Eigen::Matrix<S, 3, 3> rotation_matrix(const Eigen::Matrix<S, 4, 1>& q) {
    const auto m = to_matrix(quat4<S>{q[0], q[1], q[2], q[3]});
    Eigen::Matrix<S, 3, 3> r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = m[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
    return r;
}

/// Vector part of 2 a (x) conj(q): the angular velocity when a = dq/dt, the
/// angular acceleration when a = d2q/dt2 (q unit, (w, x, y, z)).
template <class S>
Eigen::Matrix<S, 3, 1> twice_vector_times_conjugate(const Eigen::Matrix<S, 4, 1>& a, const Eigen::Matrix<S, 4, 1>& q) {
    const Eigen::Matrix<S, 3, 1> av = a.template tail<3>(), qv = q.template tail<3>();
    return S(2) * (q[0] * av - a[0] * qv + qv.cross(av));
}

/// Unit quaternions of the keys as (w, x, y, z) columns, each joint's keys
/// flipped into the hemisphere of the previous key.
template <class T>
std::vector<std::vector<Eigen::Matrix<T, 4, 1>>> aligned_key_quaternions(const flight_keys<T>& keys) {
    std::vector<std::vector<Eigen::Matrix<T, 4, 1>>> out(keys.size());
    for (std::size_t k = 0; k < keys.size(); ++k) {
        out[k].resize(keys.rotations[k].size());
        for (std::size_t j = 0; j < keys.rotations[k].size(); ++j) {
            const auto& q = keys.rotations[k][j];
            Eigen::Matrix<T, 4, 1> v(q.w(), q.x(), q.y(), q.z());
            v /= v.norm();
            if (k > 0 && v.dot(out[k - 1][j]) < T(0)) v = -v;
            out[k][j] = v;
        }
    }
    return out;
}

}  // namespace detail

/// The spline motion through a key set, for one scalar type S.
template <class S>
class key_trajectory {
public:
    using vector3 = Eigen::Matrix<S, 3, 1>;
    using vector4 = Eigen::Matrix<S, 4, 1>;

    key_trajectory() = default;

    /// From raw key values: times, root positions and per key the joints'
    /// quaternions as (w, x, y, z), already hemisphere-aligned.
    key_trajectory(std::vector<S> times, const std::vector<vector3>& root_positions,
                   const std::vector<std::vector<vector4>>& quaternions) {
        const std::size_t n = times.size();
        if (n < 2 || root_positions.size() != n || quaternions.size() != n)
            throw invalid_argument("anima::key_trajectory: needs >= 2 keys with one root position and one rotation "
                                   "set each");
        joints_ = quaternions[0].size();
        typename cubic_spline<S>::matrix values(static_cast<Eigen::Index>(n),
                                                static_cast<Eigen::Index>(3 + 4 * joints_));
        for (std::size_t k = 0; k < n; ++k) {
            if (quaternions[k].size() != joints_)
                throw invalid_argument("anima::key_trajectory: key " + std::to_string(k) + " has " +
                                       std::to_string(quaternions[k].size()) + " rotations, key 0 has " +
                                       std::to_string(joints_));
            const auto K = static_cast<Eigen::Index>(k);
            values.row(K).template head<3>() = root_positions[k].transpose();
            for (std::size_t j = 0; j < joints_; ++j)
                values.row(K).template segment<4>(static_cast<Eigen::Index>(3 + 4 * j)) = quaternions[k][j].transpose();
        }
        spline_ = cubic_spline<S>(std::move(times), std::move(values));
    }

    /// From a key set (checked; quaternions normalised and hemisphere-aligned).
    template <class T>
    static key_trajectory from_keys(const flight_keys<T>& keys) {
        check_keys(keys, keys.rotations.empty() ? 0 : keys.rotations[0].size(), "anima::key_trajectory::from_keys");
        const auto q = detail::aligned_key_quaternions(keys);
        std::vector<S> times(keys.times.begin(), keys.times.end());
        std::vector<vector3> roots;
        std::vector<std::vector<vector4>> quats(q.size());
        for (std::size_t k = 0; k < q.size(); ++k) {
            roots.push_back(keys.root_positions[k].template cast<S>());
            for (const auto& v : q[k]) quats[k].push_back(v.template cast<S>());
        }
        return key_trajectory(std::move(times), roots, quats);
    }

    std::size_t joints() const noexcept { return joints_; }
    S start_time() const { return spline_.times().front(); }
    S end_time() const { return spline_.times().back(); }
    const std::vector<S>& key_times() const noexcept { return spline_.times(); }

    /// Pose, velocities and accelerations at time t in [start, end];
    /// throws anima::invalid_argument outside.
    body_motion<S> at(const S& t) const {
        if (!(t >= start_time() && t <= end_time()))
            throw invalid_argument("anima::key_trajectory::at: t = " + detail::argument_text(detail::scalar_value(t)) +
                                   " is outside [" + detail::argument_text(detail::scalar_value(start_time())) + ", " +
                                   detail::argument_text(detail::scalar_value(end_time())) + "]");
        body_motion<S> m;
        evaluate(t, m);
        return m;
    }

    /// Unchecked: t within the key range.
    void evaluate(const S& t, body_motion<S>& m) const {
        using std::sqrt;
        typename cubic_spline<S>::row y, dy, ddy;
        spline_.evaluate(t, y, dy, ddy);
        m.root_position = y.template head<3>().transpose();
        m.root_velocity = dy.template head<3>().transpose();
        m.root_acceleration = ddy.template head<3>().transpose();
        m.rotations.resize(joints_);
        m.angular_velocities.resize(joints_);
        m.angular_accelerations.resize(joints_);
        for (std::size_t j = 0; j < joints_; ++j) {
            const auto J = static_cast<Eigen::Index>(3 + 4 * j);
            const vector4 s = y.template segment<4>(J).transpose(), ds = dy.template segment<4>(J).transpose(),
                          dds = ddy.template segment<4>(J).transpose();
            // q = s / n; derivatives of the normalisation.
            const S n = sqrt(s.squaredNorm());
            const vector4 q = s / n;
            const S dn = q.dot(ds);
            const vector4 dq = (ds - q * dn) / n;
            const S ddn = (ds.squaredNorm() + s.dot(dds) - dn * dn) / n;
            const vector4 ddq = (dds - S(2) * dn * dq - ddn * q) / n;
            m.rotations[j] = detail::rotation_matrix(q);
            m.angular_velocities[j] = detail::twice_vector_times_conjugate(dq, q);
            m.angular_accelerations[j] = detail::twice_vector_times_conjugate(ddq, q);
        }
    }

private:
    cubic_spline<S> spline_;
    std::size_t joints_ = 0;
};

}  // namespace anima
