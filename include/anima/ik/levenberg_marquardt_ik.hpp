// Optimisation-based IK by Levenberg-Marquardt on the weighted goal
// residuals: a damped Gauss-Newton step whose damping adapts to how well the
// linear model predicted the decrease (Nielsen's rule, as in
// anima::levenberg_marquardt), so it moves like the pseudo-inverse far from
// singularities and like damped least squares near them, and never accepts
// a step that makes the pose worse. The iteration is specialised for IK: its
// buffers are allocated once per solve, it stops as soon as every goal is
// within tolerance, and an attempt that stalls ends early for the next
// restart. Joint limits by the sine reparametrisation of
// detail/limited_solve.hpp, with a polish that keeps the limits inside the
// step, or by the limits inside the step alone.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/ik/detail/limited_solve.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/solve.hpp>
#include <anima/optimize/result.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace anima {

template <class T>
struct levenberg_marquardt_ik_params {
    ik_params<T> ik;                  ///< tolerances, iterations (per attempt), restarts, limits
    /// mu of (J'J + mu diag(J'J)) h = J'r at the start: no units, so a
    /// figure in millimetres starts as damped as one in metres. 0.1 keeps
    /// bench_ik's solves as fast as the unit-dependent start it replaced.
    T initial_damping = T(0.1);
    /// false (default): attempts run on the sine reparametrisation, and one
    /// that misses is polished by up to `polish_iterations` steps with the
    /// limits inside the step. true: the attempts themselves keep the limits
    /// inside the step (a DOF the step would push past a limit is moved onto
    /// it and its column removed, as in solve_ik); fewer iterations, but
    /// more attempts end in a local minimum at a limit.
    bool limits_in_step = false;
    int polish_iterations = 20;       ///< limits-inside-the-step steps after a missed attempt (0: none)
    /// An attempt (or polish) ends, and the next restart begins, when
    /// `stall_window` steps tried in a row lowered the objective by less
    /// than `stall_decrease` of its value at the start of the window.
    int stall_window = 6;
    T stall_decrease = T(0.1);
};

namespace detail {

/// Buffers of lm_attempt, allocated on the first attempt of a solve.
template <class T>
struct lm_ik_workspace {
    ik_state<T> s;
    ik_vector<T> r, trial_r, jh, g, h, fixed, rhs, trial_x, q;
    ik_matrix<T> jac, normal, damped;
    Eigen::LLT<ik_matrix<T>> llt;
    std::vector<goal_error<T>> errors, trial_errors;
    std::vector<unsigned char> locked;
};

/// The damped step w.h from w.normal and w.g at x, with damping mu scaled by
/// the normal matrix's diagonal. With `limits`, DOFs the step pushes past a
/// limit are fixed on it and the rest solved again (up to four passes).
/// False when the damped matrix cannot be factored.
template <class T>
bool limited_damped_step(lm_ik_workspace<T>& w, const ik_vector<T>& x, const ik_vector<T>& lo,
                         const ik_vector<T>& hi, T mu, bool limits) {
    const int n = static_cast<int>(x.size());
    const T tiny = std::numeric_limits<T>::min() / std::numeric_limits<T>::epsilon();
    const T floor = std::numeric_limits<T>::epsilon() * std::max(w.normal.diagonal().maxCoeff(), tiny);
    std::fill(w.locked.begin(), w.locked.end(), static_cast<unsigned char>(0));
    w.fixed.setZero(n);
    for (int pass = 0; pass < 4; ++pass) {
        w.damped = w.normal;
        w.rhs.noalias() = w.g - w.normal * w.fixed;
        for (int i = 0; i < n; ++i) {
            if (w.locked[static_cast<std::size_t>(i)]) {
                w.damped.row(i).setZero();
                w.damped.col(i).setZero();
                w.damped(i, i) = T(1);
                w.rhs[i] = T(0);
            } else {
                w.damped(i, i) += mu * std::max(w.normal(i, i), floor);
            }
        }
        w.llt.compute(w.damped);
        if (w.llt.info() != Eigen::Success) return false;
        w.h = w.llt.solve(w.rhs);
        w.h += w.fixed;
        if (!limits) return true;
        bool more = false;
        for (int k = 0; k < n; ++k) {
            if (w.locked[static_cast<std::size_t>(k)]) continue;
            const T next = x[k] + w.h[k];
            if (next < lo[k] || next > hi[k]) {
                w.fixed[k] = (next < lo[k] ? lo[k] : hi[k]) - x[k];
                w.locked[static_cast<std::size_t>(k)] = 1;
                more = true;
            }
        }
        if (!more) return true;
    }
    return true;
}

/// One Levenberg-Marquardt attempt from x0, on preallocated buffers. With
/// `chart` null the variables are the DOFs and the limits are inside the
/// step: the damped Gauss-Newton step (J'J + mu D) h = J'r is solved for
/// the free DOFs; a DOF it would push past a limit is moved onto the limit,
/// fixed, and the step solved again for the others (up to four passes, then
/// the step is clamped). With a chart the variables are its u
/// (q = chart.to_q(u), the sine reparametrisation) and the step is free.
/// Nielsen's damping update on the actual against the predicted decrease;
/// only steps that lower 0.5 |r|^2 are taken. Ends when every goal is
/// within tolerance (stopped), at the iteration cap (max_iterations) or on
/// a stall (stalled): `stall_window` steps tried in a row that lowered the
/// objective by less than `stall_decrease` of its value, or damping past
/// any use. The result's x is in the attempt's variables.
template <class T>
optimize_result<T> lm_attempt(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals,
                              const levenberg_marquardt_ik_params<T>& prm, const ik_vector<T>& x0,
                              const sine_limits<T>* chart, lm_ik_workspace<T>& w) {
    const ik_params<T>& p = prm.ik;
    const int n = tree.dofs();
    const auto& lo = tree.lower();
    const auto& hi = tree.upper();
    const bool limits = p.limits && !chart;
    const T tiny = std::numeric_limits<T>::min() / std::numeric_limits<T>::epsilon();
    optimize_result<T> res;
    res.x = x0;
    ik_vector<T>& x = res.x;
    w.trial_x.resize(n);
    w.locked.resize(static_cast<std::size_t>(n));
    const auto pose = [&](const ik_vector<T>& v) -> const ik_vector<T>& {
        if (!chart) return v;
        chart->to_q(v, w.q);
        return w.q;
    };

    tree.forward_unchecked(pose(x), w.s);
    goal_residual(w.s, goals, w.r, &w.errors);
    res.evaluations = 1;
    res.value = w.r.squaredNorm() / T(2);
    if (summarise(w.errors, p).score <= T(1)) {
        res.status = optimize_status::stopped;
        return res;
    }
    // goal_residual is target - reached: the residual moves by -J h.
    const auto linearise = [&] {
        goal_jacobian(tree, pose(x), w.s, goals, w.jac);
        if (chart)
            for (int k = 0; k < n; ++k) w.jac.col(k) *= chart->derivative(x, k);
        w.normal.noalias() = w.jac.transpose().lazyProduct(w.jac);
        w.g.noalias() = w.jac.transpose() * w.r;
    };
    linearise();
    // The step scales mu by J'J's diagonal already: mu itself has no units,
    // so a figure in millimetres starts as damped as one in metres.
    T mu = prm.initial_damping;
    T growth = T(2);
    T window_start = res.value;
    int window = 0;
    res.status = optimize_status::max_iterations;
    while (res.iterations < p.max_iterations) {
        ++res.iterations;
        const bool solved = limited_damped_step(w, x, lo, hi, mu, limits);
        bool accepted = false;
        if (solved && w.h.allFinite()) {
            w.trial_x = x + w.h;
            if (limits) {
                w.trial_x = w.trial_x.cwiseMax(lo).cwiseMin(hi);
                w.h = w.trial_x - x;
            }
            tree.forward_unchecked(pose(w.trial_x), w.s);
            goal_residual(w.s, goals, w.trial_r, &w.trial_errors);
            ++res.evaluations;
            const T trial_value = w.trial_r.squaredNorm() / T(2);
            // Decrease the linear model predicts: 0.5 (|r|^2 - |r - J h|^2).
            w.jh.noalias() = w.jac * w.h;
            const T predicted = (w.r.squaredNorm() - (w.r - w.jh).squaredNorm()) / T(2);
            if (std::isfinite(trial_value) && trial_value < res.value && predicted > T(0)) {
                accepted = true;
                const T rho = (res.value - trial_value) / predicted;
                x.swap(w.trial_x);
                w.r.swap(w.trial_r);
                res.value = trial_value;
                w.errors.swap(w.trial_errors);
                if (summarise(w.errors, p).score <= T(1)) {
                    res.status = optimize_status::stopped;
                    break;
                }
                if (!chart) tree.wrap(x);
                linearise();
                const T c = T(2) * rho - T(1);
                mu *= std::max(T(1) / T(3), T(1) - c * c * c);
                mu = std::max(mu, tiny);
                growth = T(2);
            }
        }
        if (!accepted) {
            mu *= growth;
            growth *= T(2);
            if (!std::isfinite(mu) || mu > T(1) / tiny) {
                res.status = optimize_status::stalled;
                break;
            }
        }
        if (++window >= prm.stall_window) {
            if (res.value > (T(1) - prm.stall_decrease) * window_start) {
                res.status = optimize_status::stalled;
                break;
            }
            window = 0;
            window_start = res.value;
        }
    }
    return res;
}

}  // namespace detail

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
                               detail::argument_text(prm.initial_damping));
    if (prm.polish_iterations < 0)
        throw invalid_argument(std::string(who) + ": polish_iterations is " + std::to_string(prm.polish_iterations));
    if (prm.stall_window < 1 || !(prm.stall_decrease >= T(0) && prm.stall_decrease < T(1)))
        throw invalid_argument(std::string(who) + ": stall_window is " + std::to_string(prm.stall_window) +
                               " (must be >= 1), stall_decrease " + std::to_string(prm.stall_decrease) +
                               " (must be in [0, 1))");
    detail::lm_ik_workspace<T> w;
    const detail::sine_limits<T> limits(tree, prm.ik.limits && !prm.limits_in_step);
    // Polish: the limits-inside-the-step iteration from the attempt's pose.
    levenberg_marquardt_ik_params<T> polish_prm = prm;
    polish_prm.ik.max_iterations = prm.polish_iterations;
    const auto polish = [&](const ik_vector<T>& q) {
        ik_result<T> out;
        if (prm.polish_iterations == 0 || prm.limits_in_step) return out;
        const optimize_result<T> res = detail::lm_attempt<T>(tree, goals, polish_prm, q, nullptr, w);
        out.q = res.x;
        out.iterations = res.iterations;
        evaluate_ik(tree, goals, out);
        return out;
    };
    const auto attempt = [&](const ik_vector<T>& x0) {
        return detail::lm_attempt<T>(tree, goals, prm, x0, prm.limits_in_step ? nullptr : &limits, w);
    };
    return detail::solve_with_restarts(tree, goals, ik_vector<T>(q0), prm.ik, limits, attempt, polish);
}

}  // namespace anima
