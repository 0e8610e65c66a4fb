// Optimisation-based IK: BFGS (anima::bfgs_minimize) on the weighted sum
// of squared goal errors, 0.5 sum |r_i|^2, with the analytic gradient
// -J^T r. Joint limits by a smooth reparametrisation: a DOF limited on both
// sides is q = mid + half sin(u), so every u is feasible and the optimiser
// runs unconstrained; one-sided or unlimited DOFs are optimised directly
// (and clamped at the end).
#pragma once

#include <anima/core/error.hpp>
#include <anima/core/random.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/solve.hpp>
#include <anima/optimize/bfgs.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace anima {

template <class T>
struct bfgs_ik_params {
    ik_params<T> ik;            ///< tolerances, iterations (per attempt), restarts, limits
    int memory = 0;             ///< 0: dense BFGS; m > 0: L-BFGS
};

template <class T>
ik_result<T> solve_ik_bfgs(const kinematic_tree<T>& tree, std::vector<ik_goal<T>> goals, const ik_vector_arg<T>& q0,
                           const bfgs_ik_params<T>& prm = {}) {
    const char* who = "anima::solve_ik_bfgs";
    tree.check_q(q0, who);
    check_goals(tree, goals, who);
    detail::check_ik_params(prm.ik, tree.dofs(), who);
    if (prm.memory < 0) throw invalid_argument(std::string(who) + ": memory is " + std::to_string(prm.memory));
    const int n = tree.dofs();
    const auto& lo = tree.lower();
    const auto& hi = tree.upper();
    std::vector<bool> boxed(static_cast<std::size_t>(n), false);
    if (prm.ik.limits)
        for (int k = 0; k < n; ++k) boxed[static_cast<std::size_t>(k)] = std::isfinite(lo[k]) && std::isfinite(hi[k]) && hi[k] > lo[k];
    const auto to_q = [&](const ik_vector<T>& u) {
        ik_vector<T> q = u;
        for (int k = 0; k < n; ++k)
            if (boxed[static_cast<std::size_t>(k)]) q[k] = (lo[k] + hi[k]) / T(2) + (hi[k] - lo[k]) / T(2) * std::sin(u[k]);
        return q;
    };
    const auto to_u = [&](const ik_vector<T>& q) {
        ik_vector<T> u = q;
        for (int k = 0; k < n; ++k)
            if (boxed[static_cast<std::size_t>(k)]) {
                const T s = (q[k] - (lo[k] + hi[k]) / T(2)) / ((hi[k] - lo[k]) / T(2));
                u[k] = std::asin(std::clamp(s, T(-1), T(1)));
            }
        return u;
    };
    // Stop as soon as every weighted residual is surely within tolerance.
    T enough = std::numeric_limits<T>::infinity();
    for (const auto& g : goals) {
        if (g.has_position()) enough = std::min(enough, g.weight * prm.ik.tolerance);
        if (g.has_orientation()) enough = std::min(enough, g.weight * g.orientation_scale * prm.ik.angle_tolerance);
    }
    const T stop_value = T(0.5) * enough * enough;

    ik_state<T> s;
    ik_vector<T> r;
    ik_matrix<T> jac;
    const auto objective = [&](const ik_vector<T>& u, ik_vector<T>& grad) {
        const ik_vector<T> q = to_q(u);
        tree.forward_unchecked(q, s);
        goal_residual(s, goals, r);
        goal_jacobian(tree, q, s, goals, jac);
        grad = -(jac.transpose() * r);
        for (int k = 0; k < n; ++k)
            if (boxed[static_cast<std::size_t>(k)]) grad[k] *= (hi[k] - lo[k]) / T(2) * std::cos(u[k]);
        return T(0.5) * r.squaredNorm();
    };

    bfgs_params<T> bp;
    bp.max_iterations = prm.ik.max_iterations;
    bp.memory = prm.memory;
    bp.gradient_tolerance = T(0);  // stop on the goal tolerances (or a stall), not on the gradient
    bp.on_iteration = [&](int, T value) { return value > stop_value; };

    random_source rng(prm.ik.seed);
    ik_result<T> best;
    best.q = prm.ik.limits ? tree.clamp(q0) : ik_vector<T>(q0);
    evaluate_ik(tree, goals, best);
    T best_score = detail::summarise(best.errors, prm.ik).score;
    bool stalled = false;
    for (int attempt = 0; attempt <= prm.ik.restarts && best_score > T(1); ++attempt) {
        ++best.attempts;
        const ik_vector<T> start = attempt == 0 ? best.q : detail::random_pose(tree, ik_vector<T>(q0), rng);
        const auto res = bfgs_minimize<T>(objective, to_u(start), bp);
        best.iterations += res.iterations;
        ik_result<T> trial;
        trial.q = to_q(res.x);
        if (prm.ik.limits) trial.q = tree.clamp(trial.q);
        tree.wrap(trial.q);
        evaluate_ik(tree, goals, trial);
        const T score = detail::summarise(trial.errors, prm.ik).score;
        stalled = res.status != optimize_status::max_iterations && res.status != optimize_status::stopped;
        if (score < best_score) {
            best_score = score;
            best.q = trial.q;
            best.errors = trial.errors;
        }
    }
    evaluate_ik(tree, goals, best);
    best.status = best_score <= T(1) ? ik_status::converged
                  : stalled         ? ik_status::unreachable_closest
                                    : ik_status::max_iterations;
    return best;
}

}  // namespace anima
