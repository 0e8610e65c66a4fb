// Optimisation-based IK: BFGS (anima::bfgs_minimize) on the weighted sum
// of squared goal errors, 0.5 sum |r_i|^2, with the analytic gradient
// -J^T r. Joint limits by the sine reparametrisation of
// detail/limited_solve.hpp.
#pragma once

#include <anima/core/error.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/detail/limited_solve.hpp>
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
    int polish_iterations = 10;       ///< pseudo-inverse steps after an attempt that misses (0: none)
};

template <class T>
ik_result<T> solve_ik_bfgs(const kinematic_tree<T>& tree, std::vector<ik_goal<T>> goals, const ik_vector_arg<T>& q0,
                           const bfgs_ik_params<T>& prm = {}) {
    const char* who = "anima::solve_ik_bfgs";
    tree.check_q(q0, who);
    check_goals(tree, goals, who);
    detail::check_ik_params(prm.ik, tree.dofs(), who);
    if (prm.memory < 0 || prm.polish_iterations < 0)
        throw invalid_argument(std::string(who) + ": memory is " + std::to_string(prm.memory) + ", polish_iterations " +
                               std::to_string(prm.polish_iterations) + " (both must be >= 0)");
    const int n = tree.dofs();
    const detail::sine_limits<T> limits(tree, prm.ik.limits);

    ik_state<T> s;
    ik_vector<T> r;
    ik_matrix<T> jac;
    const auto objective = [&](const ik_vector<T>& u, ik_vector<T>& grad) {
        const ik_vector<T> q = limits.to_q(u);
        tree.forward_unchecked(q, s);
        goal_residual(s, goals, r);
        goal_jacobian(tree, q, s, goals, jac);
        grad = -(jac.transpose() * r);
        for (int k = 0; k < n; ++k) grad[k] *= limits.derivative(u, k);
        return T(0.5) * r.squaredNorm();
    };

    bfgs_params<T> bp;
    bp.max_iterations = prm.ik.max_iterations;
    bp.memory = prm.memory;
    bp.gradient_tolerance = T(0);  // stop on the goal tolerances (or a stall), not on the gradient
    const T stop_value = detail::goal_stop_value(goals, prm.ik);
    bp.on_iteration = [&](int, T value) { return value > stop_value; };

    return detail::solve_with_restarts(tree, goals, ik_vector<T>(q0), prm.ik, limits,
                                       [&](const ik_vector<T>& u0) { return bfgs_minimize<T>(objective, u0, bp); },
                                       detail::pseudo_inverse_polish(tree, goals, prm.ik, prm.polish_iterations));
}

}  // namespace anima
