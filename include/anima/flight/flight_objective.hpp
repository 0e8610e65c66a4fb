// The spacetime objective of section 3.2: J = T^-1 * integral over the
// flight of sum_i F_i(t)^2, F1..F6 the root's generalised forces of the
// spline motion through the keys. Integrated by Gauss-Legendre quadrature on
// every key interval (the motion is a cubic piece there), and written as a
// sum of squared residuals r = sqrt(w_q / T) F_i(t_q), so that ||r||^2 = J
// and a least-squares solver fits it.
//
// Parameters (x):
//  - model (2), key times only: t_0 and t_n-1 stay where they are; the n-1
//    interval lengths are d_0 : d_i = 1 : exp(x_i), i = 1..n-2, scaled to the
//    hang time. Any x gives ordered times: the order constraint holds by
//    construction.
//  - model (1), key times and poses: x = (timing, root, joints). Every root
//    key position moves by e1 * tanh(u) per axis, every joint rotation (the
//    root's orientation too) by the rotation vector e2 * tanh(v) per
//    component, applied in the joint's own frame: the tolerances hold by
//    construction, per component (a box, not a ball).
//
// Ballistic root (optional): the centre of mass follows c0 + v0 t + g t^2/2
// and the root is placed under it at every instant (the keys' root
// positions are then not used). F1..F3 vanish identically and J measures
// only the rate of change of angular momentum about the centre of mass.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/flight/body_model.hpp>
#include <anima/flight/inverse_dynamics.hpp>
#include <anima/flight/key_trajectory.hpp>
#include <anima/rotation/detail/quat4.hpp>

#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace anima {

template <class T>
struct ballistic_path {
    Eigen::Matrix<T, 3, 1> start = Eigen::Matrix<T, 3, 1>::Zero();     ///< centre of mass at the first key, m
    Eigen::Matrix<T, 3, 1> velocity = Eigen::Matrix<T, 3, 1>::Zero();  ///< its take-off velocity, m/s
};

template <class T>
struct flight_settings {
    Eigen::Matrix<T, 3, 1> gravity{T(0), T(-9.81), T(0)};  ///< m/s^2, Y up
    int quadrature_points = 4;                              ///< Gauss-Legendre nodes per key interval, 1..5
    std::optional<ballistic_path<T>> ballistic;             ///< place the root under a ballistic centre of mass
    T root_tolerance = T(0.05);                             ///< e1, metres (model 1)
    T joint_tolerance = T(0.1);                             ///< e2, radians per rotation-vector component (model 1)
};

namespace detail {

/// Gauss-Legendre nodes on [-1, 1] and weights, for 1..5 points.
inline void gauss_legendre(int points, std::vector<double>& nodes, std::vector<double>& weights) {
    switch (points) {
    case 1: nodes = {0.0}; weights = {2.0}; break;
    case 2: nodes = {-0.5773502691896257, 0.5773502691896257}; weights = {1.0, 1.0}; break;
    case 3:
        nodes = {-0.7745966692414834, 0.0, 0.7745966692414834};
        weights = {0.5555555555555556, 0.8888888888888888, 0.5555555555555556};
        break;
    case 4:
        nodes = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
        weights = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
        break;
    case 5:
        nodes = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
        weights = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                   0.2369268850561891};
        break;
    default:
        throw invalid_argument("anima::flight: quadrature_points must be 1..5, got " + std::to_string(points));
    }
}

/// Kinematics of the trajectory's motion at t, with the root moved under
/// the ballistic centre of mass when one is set.
template <class S, class T>
void flight_kinematics(const rigid_body_model<S>& model, const key_trajectory<S>& traj, const flight_settings<T>& set,
                       const S& t, body_motion<S>& motion, body_kinematics<S>& k) {
    using vector3 = Eigen::Matrix<S, 3, 1>;
    traj.evaluate(t, motion);
    if (!set.ballistic) {
        outward_pass(model, motion, k);
        return;
    }
    // Translating the root adds the same position, velocity and acceleration
    // to every point: compute with the root's linear motion at zero, then
    // shift everything so that the centre of mass lands on the parabola.
    motion.root_position.setZero();
    motion.root_velocity.setZero();
    motion.root_acceleration.setZero();
    outward_pass(model, motion, k);
    const auto m = momentum_of(model, k);
    const S tau = t - traj.start_time();
    const vector3 g = set.gravity.template cast<S>(), c0 = set.ballistic->start.template cast<S>(),
                  v0 = set.ballistic->velocity.template cast<S>();
    const vector3 dp = c0 + v0 * tau + g * (tau * tau / S(2)) - m.centre_of_mass;
    const vector3 dv = v0 + g * tau - m.com_velocity;
    const vector3 da = g - m.com_acceleration;
    motion.root_position = dp;
    motion.root_velocity = dv;
    motion.root_acceleration = da;
    for (std::size_t j = 0; j < model.size(); ++j) {
        k.position[j] += dp;
        k.com[j] += dp;
        k.velocity[j] += dv;
        k.com_velocity[j] += dv;
        k.acceleration[j] += da;
        k.com_acceleration[j] += da;
    }
}

/// The residuals sqrt(w_q / T) F_i(t_q), six per quadrature node.
template <class S, class T>
void flight_residuals(const rigid_body_model<S>& model, const key_trajectory<S>& traj, const flight_settings<T>& set,
                      Eigen::Matrix<S, Eigen::Dynamic, 1>& r) {
    using std::sqrt;
    std::vector<double> nodes, weights;
    gauss_legendre(set.quadrature_points, nodes, weights);
    const auto& times = traj.key_times();
    const std::size_t intervals = times.size() - 1, q = nodes.size();
    const S total = times.back() - times.front();
    const Eigen::Matrix<S, 3, 1> g = set.gravity.template cast<S>();
    r.resize(static_cast<Eigen::Index>(6 * intervals * q));
    body_motion<S> motion;
    body_kinematics<S> k;
    inverse_dynamics_result<S> id;
    Eigen::Index row = 0;
    for (std::size_t i = 0; i < intervals; ++i) {
        const S h = times[i + 1] - times[i];
        for (std::size_t g_i = 0; g_i < q; ++g_i) {
            const S t = times[i] + (S(nodes[g_i]) + S(1)) * (h / S(2));
            flight_kinematics(model, traj, set, t, motion, k);
            inward_pass(model, k, g, id);
            const S scale = sqrt(S(weights[g_i]) * h / (S(2) * total));
            r.template segment<6>(row) = scale * id.root_residual();
            row += 6;
        }
    }
}

}  // namespace detail

/// The objective of models (1) and (2) for one body model and key set.
template <class T>
class flight_problem {
public:
    using vector = Eigen::Matrix<T, Eigen::Dynamic, 1>;
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

    flight_problem(rigid_body_model<T> model, flight_keys<T> keys, flight_settings<T> settings = {})
        : model_(std::move(model)), keys_(std::move(keys)), settings_(std::move(settings)) {
        const char* who = "anima::flight_problem";
        if (model_.size() == 0) throw invalid_argument(std::string(who) + ": empty body model");
        if (!(model_.total_mass() > T(0))) throw invalid_argument(std::string(who) + ": the body model has no mass");
        check_keys(keys_, model_.size(), who);
        std::vector<double> n, w;
        detail::gauss_legendre(settings_.quadrature_points, n, w);
        if (!settings_.gravity.allFinite()) throw invalid_argument(std::string(who) + ": gravity is not finite");
        if (settings_.ballistic && !(settings_.ballistic->start.allFinite() && settings_.ballistic->velocity.allFinite()))
            throw invalid_argument(std::string(who) + ": ballistic start or velocity is not finite");
        if (!(settings_.root_tolerance >= T(0)) || !std::isfinite(settings_.root_tolerance))
            throw invalid_argument(std::string(who) + ": root_tolerance (e1) must be finite and >= 0, got " +
                                   detail::argument_text(settings_.root_tolerance));
        if (!(settings_.joint_tolerance >= T(0)) || !std::isfinite(settings_.joint_tolerance))
            throw invalid_argument(std::string(who) + ": joint_tolerance (e2) must be finite and >= 0, got " +
                                   detail::argument_text(settings_.joint_tolerance));
        quats_ = detail::aligned_key_quaternions(keys_);
        // Forces grow as 1 / dt^2 and the objective squares them: key times a
        // hair apart (or a huge gravity) overflow it, in float long before
        // double. Refused here, where the keys are named, rather than as a
        // non-finite start in the optimiser.
        bool finite = false;
        try {
            finite = std::isfinite(objective(keys_.times));
        } catch (const invalid_argument&) {
            // cubic_spline refuses curvatures that overflow (keys closer
            // still): the same cause, reported below for the keys.
        }
        if (!finite) {
            T shortest = keys_.times[1] - keys_.times[0];
            for (std::size_t k = 2; k < keys_.size(); ++k) shortest = std::min(shortest, keys_.times[k] - keys_.times[k - 1]);
            throw invalid_argument(std::string(who) + ": the objective at the keys' own times is not finite in this "
                                   "precision (shortest key interval " + detail::argument_text(shortest) +
                                   " s): lengthen the shortest interval, or lessen gravity or the root's moves");
        }
    }

    const rigid_body_model<T>& model() const noexcept { return model_; }
    const flight_keys<T>& keys() const noexcept { return keys_; }
    const flight_settings<T>& settings() const noexcept { return settings_; }
    std::size_t key_count() const noexcept { return keys_.size(); }
    /// Number of residuals: six per quadrature node, quadrature_points nodes
    /// per key interval.
    Eigen::Index residual_count() const noexcept {
        return 6 * (static_cast<Eigen::Index>(keys_.size()) - 1) * settings_.quadrature_points;
    }
    /// The Jacobian is taken by forward-mode automatic differentiation,
    /// seeding `jacobian_width` parameters per pass: a model of n parameters
    /// costs ceil(n / jacobian_width) passes over every quadrature node. The
    /// derivative vectors have a compile-time size so that every scalar,
    /// constants included, carries one of the same length (Eigen's
    /// AutoDiffScalar cannot reconcile an empty derivative inside an
    /// expression with a full one).
    static constexpr int jacobian_width = 16;
    T total_time() const { return keys_.times.back() - keys_.times.front(); }

    // ----- key times (model 2) --------------------------------------------------
    /// Number of timing parameters: n - 2.
    Eigen::Index timing_size() const noexcept { return static_cast<Eigen::Index>(keys_.size()) - 2; }

    /// Timing parameters that reproduce the given times (same first and last
    /// key time as the problem's keys).
    vector timing_parameters(const std::vector<T>& times) const {
        check_times(times, "anima::flight_problem::timing_parameters");
        vector x(timing_size());
        const T d0 = times[1] - times[0];
        for (Eigen::Index i = 0; i < x.size(); ++i) {
            const auto k = static_cast<std::size_t>(i + 1);
            x[i] = std::log((times[k + 1] - times[k]) / d0);
        }
        return x;
    }

    /// Key times of timing parameters x (also the head of a model (1) vector).
    std::vector<T> key_times(const vector& x) const { return times_of<T>(x); }

    /// The objective for the problem's key poses at the given key times.
    T objective(const std::vector<T>& times) const {
        check_times(times, "anima::flight_problem::objective");
        vector r;
        residuals_at(times, quats_, r);
        return r.squaredNorm();
    }

    /// Model (2) residuals of timing parameters x, and their Jacobian when
    /// jacobian is non-null (exact, by forward-mode automatic differentiation).
    void timing_residuals(const vector& x, vector& r, matrix* jacobian) const {
        check_size(x, timing_size(), "anima::flight_problem::timing_residuals");
        evaluate(x, r, jacobian, false);
    }

    // ----- key times and poses (model 1) ----------------------------------------
    /// Size of a model (1) parameter vector: timing, then 3 per key root
    /// position (none with a ballistic root), then 3 per key and joint.
    Eigen::Index full_size() const noexcept {
        const auto n = static_cast<Eigen::Index>(keys_.size()), j = static_cast<Eigen::Index>(model_.size());
        return timing_size() + (settings_.ballistic ? 0 : 3 * n) + 3 * n * j;
    }

    /// A model (1) vector holding the given times and the keys' poses.
    vector full_parameters(const std::vector<T>& times) const {
        vector x = vector::Zero(full_size());
        x.head(timing_size()) = timing_parameters(times);
        return x;
    }

    void full_residuals(const vector& x, vector& r, matrix* jacobian) const {
        check_size(x, full_size(), "anima::flight_problem::full_residuals");
        evaluate(x, r, jacobian, true);
    }

    /// The keys a model (1) vector stands for (times and moved poses).
    flight_keys<T> keys_of(const vector& x) const {
        check_size(x, full_size(), "anima::flight_problem::keys_of");
        flight_keys<T> out = keys_;
        out.times = times_of<T>(x);
        std::vector<Eigen::Matrix<T, 3, 1>> roots;
        std::vector<std::vector<Eigen::Matrix<T, 4, 1>>> quats;
        moved_poses<T>(x, roots, quats);
        for (std::size_t k = 0; k < keys_.size(); ++k) {
            out.root_positions[k] = roots[k];
            for (std::size_t j = 0; j < model_.size(); ++j) {
                const auto& q = quats[k][j];
                out.rotations[k][j] = Eigen::Quaternion<T>(q[0], q[1], q[2], q[3]);
            }
        }
        return out;
    }

    // ----- evaluation of a key set ----------------------------------------------
    /// The objective of any key set for this model and settings.
    T objective(const flight_keys<T>& keys) const {
        check_keys(keys, model_.size(), "anima::flight_problem::objective");
        vector r;
        residuals_at(keys.times, detail::aligned_key_quaternions(keys), r, &keys.root_positions);
        return r.squaredNorm();
    }

    /// The motion of a key set at time t (root under the ballistic path when set).
    body_motion<T> motion_at(const key_trajectory<T>& traj, T t) const {
        if (!(t >= traj.start_time() && t <= traj.end_time()))
            throw invalid_argument("anima::flight_problem::motion_at: t = " + detail::argument_text(t) +
                                   " is outside the keys");
        body_motion<T> m;
        detail::body_kinematics<T> k;
        detail::flight_kinematics(model_, traj, settings_, t, m, k);
        return m;
    }

    /// Angular momentum about the centre of mass at `samples` evenly spaced
    /// instants of the key set's flight.
    std::vector<Eigen::Matrix<T, 3, 1>> angular_momentum(const flight_keys<T>& keys, int samples = 201) const {
        if (samples < 2)
            throw invalid_argument("anima::flight_problem::angular_momentum: samples must be >= 2, got " +
                                   std::to_string(samples));
        const auto traj = key_trajectory<T>::from_keys(keys);
        std::vector<Eigen::Matrix<T, 3, 1>> out;
        body_motion<T> m;
        detail::body_kinematics<T> k;
        for (int s = 0; s < samples; ++s) {
            const T t = traj.start_time() + (traj.end_time() - traj.start_time()) * T(s) / T(samples - 1);
            detail::flight_kinematics(model_, traj, settings_, t, m, k);
            out.push_back(detail::momentum_of(model_, k).angular_momentum);
        }
        return out;
    }

    /// Relative variation of the angular momentum about the centre of mass
    /// over the flight: max_t |L(t) - mean L| / |mean L| (0 when conserved).
    /// Not defined (empty) when the mean angular momentum is zero, e.g. for a
    /// body that does not rotate, or when it is not finite.
    std::optional<T> momentum_drift(const flight_keys<T>& keys, int samples = 201) const {
        const auto L = angular_momentum(keys, samples);
        Eigen::Matrix<T, 3, 1> mean = Eigen::Matrix<T, 3, 1>::Zero();
        for (const auto& l : L) mean += l;
        mean /= T(L.size());
        T worst(0);
        for (const auto& l : L) worst = std::max(worst, (l - mean).norm());
        const T drift = worst / mean.norm();
        if (!(mean.norm() > T(0)) || !std::isfinite(drift)) return std::nullopt;
        return drift;
    }

private:
    void check_times(const std::vector<T>& times, const char* who) const {
        const std::size_t n = keys_.size();
        if (times.size() != n)
            throw invalid_argument(std::string(who) + ": " + std::to_string(times.size()) + " times for " +
                                   std::to_string(n) + " keys");
        for (std::size_t k = 0; k < n; ++k)
            if (!std::isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1])))
                throw invalid_argument(std::string(who) + ": times must be finite and increase strictly; time " +
                                       std::to_string(k) + " is " + detail::argument_text(times[k]));
        if (std::abs(times.front() - keys_.times.front()) > T(1e-6) * (T(1) + total_time()) ||
            std::abs(times.back() - keys_.times.back()) > T(1e-6) * (T(1) + total_time()))
            throw invalid_argument(std::string(who) + ": the first and last times must stay " +
                                   detail::argument_text(keys_.times.front()) + " and " +
                                   detail::argument_text(keys_.times.back()));
    }
    static void check_size(const vector& x, Eigen::Index n, const char* who) {
        if (x.size() != n)
            throw invalid_argument(std::string(who) + ": x has " + std::to_string(x.size()) + " entries, expected " +
                                   std::to_string(n));
        if (!x.allFinite()) throw invalid_argument(std::string(who) + ": x is not finite");
    }

    template <class S, class V>
    std::vector<S> times_of(const V& x) const {
        using std::exp;
        const std::size_t n = keys_.size();
        std::vector<S> d(n - 1);
        d[0] = S(1);
        S sum = d[0];
        for (std::size_t i = 1; i + 1 < n; ++i) {
            d[i] = exp(x[static_cast<Eigen::Index>(i - 1)]);
            sum += d[i];
        }
        std::vector<S> t(n);
        t[0] = S(keys_.times.front());
        S acc(0);
        const S total(total_time());
        for (std::size_t i = 1; i < n; ++i) {
            acc += d[i - 1];
            t[i] = t[0] + total * acc / sum;
        }
        t[n - 1] = S(keys_.times.back());
        return t;
    }

    template <class S, class V>
    void moved_poses(const V& x, std::vector<Eigen::Matrix<S, 3, 1>>& roots,
                     std::vector<std::vector<Eigen::Matrix<S, 4, 1>>>& quats) const {
        using std::tanh;
        const std::size_t n = keys_.size(), nj = model_.size();
        Eigen::Index at = timing_size();
        const S e1(settings_.root_tolerance), e2(settings_.joint_tolerance);
        roots.resize(n);
        quats.assign(n, std::vector<Eigen::Matrix<S, 4, 1>>(nj));
        for (std::size_t k = 0; k < n; ++k) {
            roots[k] = keys_.root_positions[k].template cast<S>();
            if (!settings_.ballistic) {
                for (int c = 0; c < 3; ++c) roots[k][c] += e1 * tanh(S(x[at + c]));
                at += 3;
            }
        }
        for (std::size_t k = 0; k < n; ++k)
            for (std::size_t j = 0; j < nj; ++j) {
                // The key's rotation times exp of the rotation vector v = e2 tanh(x):
                // the rotation toolkit's core, on the automatic-derivative scalar.
                S h[3];
                for (int c = 0; c < 3; ++c) h[c] = e2 * tanh(S(x[at + c])) / S(2);
                at += 3;
                const auto& key = quats_[k][j];
                const detail::quat4<S> moved =
                    detail::quat4<S>{S(key[0]), S(key[1]), S(key[2]), S(key[3])} * detail::exp_pure(h[0], h[1], h[2]);
                quats[k][j] << moved.w, moved.x, moved.y, moved.z;
            }
    }

    /// Residuals of keys with the problem's root positions (or the given
    /// ones) and the given aligned quaternions, at the given times.
    void residuals_at(const std::vector<T>& times, const std::vector<std::vector<Eigen::Matrix<T, 4, 1>>>& quats,
                      vector& r, const std::vector<Eigen::Matrix<T, 3, 1>>* roots = nullptr) const {
        const key_trajectory<T> traj(times, roots ? *roots : keys_.root_positions, quats);
        detail::flight_residuals(model_, traj, settings_, r);
    }

    template <class S>
    void residuals_of(const Eigen::Matrix<S, Eigen::Dynamic, 1>& x, bool full, const rigid_body_model<S>& model,
                      Eigen::Matrix<S, Eigen::Dynamic, 1>& r) const {
        auto times = times_of<S>(x);
        std::vector<Eigen::Matrix<S, 3, 1>> roots;
        std::vector<std::vector<Eigen::Matrix<S, 4, 1>>> quats;
        if (full) {
            moved_poses<S>(x, roots, quats);
        } else {
            for (std::size_t k = 0; k < keys_.size(); ++k) {
                roots.push_back(keys_.root_positions[k].template cast<S>());
                quats.emplace_back();
                for (const auto& q : quats_[k]) quats.back().push_back(q.template cast<S>());
            }
        }
        const key_trajectory<S> traj(std::move(times), roots, quats);
        detail::flight_residuals(model, traj, settings_, r);
    }

    void jacobian(const vector& x, bool full, vector& r, matrix& jac) const {
        using ad = Eigen::AutoDiffScalar<Eigen::Matrix<T, jacobian_width, 1>>;
        const Eigen::Index n = x.size();
        const auto model = model_.template cast<ad>();
        Eigen::Matrix<ad, Eigen::Dynamic, 1> xa(n), ra;
        for (Eigen::Index first = 0; first < n || first == 0; first += jacobian_width) {
            for (Eigen::Index i = 0; i < n; ++i) {
                xa[i] = ad(x[i]);
                if (i >= first && i < first + jacobian_width) xa[i].derivatives()[i - first] = T(1);
            }
            residuals_of(xa, full, model, ra);
            if (first == 0) {
                r.resize(ra.size());
                jac.resize(ra.size(), n);
                for (Eigen::Index k = 0; k < ra.size(); ++k) r[k] = ra[k].value();
            }
            const Eigen::Index cols = std::min<Eigen::Index>(jacobian_width, n - first);
            for (Eigen::Index k = 0; k < ra.size(); ++k)
                for (Eigen::Index c = 0; c < cols; ++c) jac(k, first + c) = ra[k].derivatives()[c];
            if (n == 0) break;
        }
    }

    void evaluate(const vector& x, vector& r, matrix* jacobian_out, bool full) const {
        if (!jacobian_out) {
            residuals_of(x, full, model_, r);
            return;
        }
        jacobian(x, full, r, *jacobian_out);
    }

    rigid_body_model<T> model_;
    flight_keys<T> keys_;
    flight_settings<T> settings_;
    std::vector<std::vector<Eigen::Matrix<T, 4, 1>>> quats_;
};

}  // namespace anima
