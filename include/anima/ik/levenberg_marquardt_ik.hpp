// Optimisation-based IK by Levenberg-Marquardt (anima::levenberg_marquardt)
// on the weighted goal residuals: a damped Gauss-Newton step whose damping
// adapts to how well the linear model predicted the decrease, so it moves
// like the pseudo-inverse far from singularities and like damped least
// squares near them, and never accepts a step that makes the pose worse.
// Joint limits by the sine reparametrisation of detail/limited_solve.hpp.
#pragma once

#include <anima/core/error.hpp>
#include <anima/ik/detail/limited_solve.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/solve.hpp>
#include <anima/optimize/levenberg_marquardt.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace anima {

template <class T>
struct levenberg_marquardt_ik_params {
    ik_params<T> ik;                  ///< tolerances, iterations (per attempt), restarts, limits
    T initial_damping = T(1e-3);      ///< relative to the largest diagonal entry of J'J
    int polish_iterations = 10;       ///< pseudo-inverse steps after an attempt that misses (0: none)
};

template <class T>
ik_result<T> solve_ik_levenberg_marquardt(const kinematic_tree<T>& tree, std::vector<ik_goal<T>> goals,
                                          const ik_vector_arg<T>& q0,
                                          const levenberg_marquardt_ik_params<T>& prm = {}) {
    const char* who = "anima::solve_ik_levenberg_marquardt";
    tree.check_q(q0, who);
    check_goals(tree, goals, who);
    detail::check_ik_params(prm.ik, tree.dofs(), who);
    if (!(prm.initial_damping > T(0)))
        throw invalid_argument(std::string(who) + ": initial_damping must be positive, got " +
                               std::to_string(prm.initial_damping));
    if (prm.polish_iterations < 0)
        throw invalid_argument(std::string(who) + ": polish_iterations is " + std::to_string(prm.polish_iterations));
    const int n = tree.dofs();
    const detail::sine_limits<T> limits(tree, prm.ik.limits);

    ik_state<T> s;
    ik_matrix<T> jac;
    // goal_residual is target - reached, so its derivative is -J.
    const auto residuals = [&](const ik_vector<T>& u, ik_vector<T>& r, ik_matrix<T>* jacobian) {
        const ik_vector<T> q = limits.to_q(u);
        tree.forward_unchecked(q, s);
        goal_residual(s, goals, r);
        if (!jacobian) return;
        goal_jacobian(tree, q, s, goals, jac);
        *jacobian = -jac;
        for (int k = 0; k < n; ++k) jacobian->col(k) *= limits.derivative(u, k);
    };

    levenberg_marquardt_params<T> lp;
    lp.max_iterations = prm.ik.max_iterations;
    lp.initial_damping = prm.initial_damping;
    lp.gradient_tolerance = T(0);  // stop on the goal tolerances (or a stall), not on the gradient
    const T stop_value = detail::goal_stop_value(goals, prm.ik);
    lp.on_iteration = [&](int, T value) { return value > stop_value; };

    return detail::solve_with_restarts(tree, goals, ik_vector<T>(q0), prm.ik, limits, prm.polish_iterations,
                                       [&](const ik_vector<T>& u0) { return levenberg_marquardt<T>(residuals, u0, lp); });
}

}  // namespace anima
