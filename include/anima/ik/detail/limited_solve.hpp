// What the optimisation-based IK solvers (BFGS, Levenberg-Marquardt) share:
// joint limits by a smooth reparametrisation, the goal-tolerance stopping
// value, and their attempts (solve_with_attempts of solve.hpp, as every
// solver's) with a polish.
#pragma once

#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/solve.hpp>
#include <anima/optimize/result.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace anima::detail {

/// A DOF limited on both sides is q = mid + half sin(u), so every u is
/// feasible and the optimiser runs unconstrained; one-sided or unlimited
/// DOFs are optimised directly (and clamped at the end).
template <class T>
struct sine_limits {
    const ik_vector<T>& lo;
    const ik_vector<T>& hi;
    std::vector<bool> boxed;

    sine_limits(const kinematic_tree<T>& tree, bool limits)
        : lo(tree.lower()), hi(tree.upper()), boxed(static_cast<std::size_t>(tree.dofs()), false) {
        if (!limits) return;
        for (int k = 0; k < tree.dofs(); ++k)
            boxed[static_cast<std::size_t>(k)] = std::isfinite(lo[k]) && std::isfinite(hi[k]) && hi[k] > lo[k];
    }
    bool is_boxed(int k) const { return boxed[static_cast<std::size_t>(k)]; }
    ik_vector<T> to_q(const ik_vector<T>& u) const {
        ik_vector<T> q;
        to_q(u, q);
        return q;
    }
    /// to_q into q (no allocation once q has the size).
    void to_q(const ik_vector<T>& u, ik_vector<T>& q) const {
        q = u;
        for (int k = 0; k < q.size(); ++k)
            if (is_boxed(k)) q[k] = (lo[k] + hi[k]) / T(2) + (hi[k] - lo[k]) / T(2) * std::sin(u[k]);
    }
    ik_vector<T> to_u(const ik_vector<T>& q) const {
        ik_vector<T> u = q;
        for (int k = 0; k < q.size(); ++k)
            if (is_boxed(k)) {
                const T s = (q[k] - (lo[k] + hi[k]) / T(2)) / ((hi[k] - lo[k]) / T(2));
                u[k] = std::asin(std::clamp(s, T(-1), T(1)));
            }
        return u;
    }
    /// dq_k / du_k (1 for DOFs that are not reparametrised).
    T derivative(const ik_vector<T>& u, int k) const {
        return is_boxed(k) ? (hi[k] - lo[k]) / T(2) * std::cos(u[k]) : T(1);
    }
};

/// 0.5 |r|^2 below which every weighted goal residual is surely within its
/// tolerance: the optimisers stop there instead of polishing further.
template <class T>
T goal_stop_value(const std::vector<ik_goal<T>>& goals, const ik_params<T>& p) {
    T enough = std::numeric_limits<T>::infinity();
    for (const auto& g : goals) {
        if (g.has_position()) enough = std::min(enough, g.weight * p.tolerance);
        if (g.has_orientation()) enough = std::min(enough, g.weight * g.orientation_scale * p.angle_tolerance);
    }
    return T(0.5) * enough * enough;
}

/// The polish of solve_with_restarts by up to `iterations` pseudo-inverse
/// steps with the limits inside the step; an empty result (no errors) when
/// `iterations` is 0.
template <class T>
auto pseudo_inverse_polish(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals,
                           const ik_params<T>& params, int iterations) {
    ik_params<T> polish = params;
    polish.max_iterations = iterations;
    polish.restarts = 0;
    polish.null_space = {};
    return [&tree, &goals, polish](const ik_vector<T>& q) {
        return polish.max_iterations > 0 ? solve_ik(tree, goals, q, pseudo_inverse<T>{}, polish) : ik_result<T>{};
    };
}

/// solve_with_attempts with attempts `attempt(u0) -> optimize_result<T>`
/// in the sine parameters; a start that meets the goals already is kept as
/// it is. An attempt that ends outside the tolerances is polished by
/// `polish(q) -> ik_result<T>` (ignored when its errors are empty), e.g.
/// pseudo_inverse_polish: near a limit the sine reparametrisation flattens
/// the objective (dq/du -> 0) and the optimiser crawls, where the Newton
/// step with the DOF's column removed converges at once.
template <class T, class Attempt, class Polish>
ik_result<T> solve_with_restarts(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals,
                                 const ik_vector<T>& q0, const ik_params<T>& params, const sine_limits<T>& limits,
                                 Attempt&& attempt, Polish&& polish) {
    return solve_with_attempts(tree, goals, q0, params, [&](const ik_vector<T>& start, ik_result<T>& best, T& best_score) {
        attempt_end end;
        ik_result<T> trial;
        trial.q = start;
        evaluate_ik(tree, goals, trial);
        T score = summarise(trial.errors, params).score;
        const auto keep = [&] {
            if (score >= best_score) return;
            best_score = score;
            best.q = trial.q;
        };
        keep();
        if (score <= T(1)) return end;
        const optimize_result<T> res = attempt(limits.to_u(start));
        best.iterations += res.iterations;
        trial.q = limits.to_q(res.x);
        if (params.limits) trial.q = tree.clamp(trial.q);
        tree.wrap(trial.q);
        evaluate_ik(tree, goals, trial);
        score = summarise(trial.errors, params).score;
        if (score > T(1)) {
            ik_result<T> p = polish(trial.q);
            best.iterations += p.iterations;
            if (!p.errors.empty()) {
                const T polished = summarise(p.errors, params).score;
                if (polished < score) {
                    score = polished;
                    trial.q = std::move(p.q);
                }
            }
        }
        end.stalled = res.status != optimize_status::max_iterations && res.status != optimize_status::stopped;
        keep();
        return end;
    });
}

}  // namespace anima::detail
