// Levenberg-Marquardt for nonlinear least squares, min 0.5 |r(x)|^2: a
// Gauss-Newton step damped towards gradient descent, the damping adapted by
// how well the linear model predicted the decrease (Nielsen's rule, as in
// Madsen, Nielsen & Tingleff, "Methods for non-linear least squares
// problems", 2004). Only steps that lower the objective are accepted.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include <Eigen/Cholesky>

#include <anima/core/check_argument.hpp>
#include <anima/optimize/result.hpp>

namespace anima {

template <class T>
struct levenberg_marquardt_params {
    int max_iterations = 100;
    /// Stop when |J' r|_inf <= gradient_tolerance * max(1, 0.5 |r|^2).
    T gradient_tolerance = detail::default_gradient_tolerance<T>();
    /// Stop when |step| <= step_tolerance * (|x| + step_tolerance).
    T step_tolerance = detail::default_step_tolerance<T>();
    /// Stop when a step lowers the objective by less than value_tolerance
    /// times the objective.
    T value_tolerance = detail::default_value_tolerance<T>();
    /// Starting damping mu of the step (J'J + mu D) h = -J'r: with D the
    /// diagonal of J'J, mu itself (no units); with D = I, relative to the
    /// largest diagonal entry of J'J. Either way the first step is the same
    /// whatever the residuals' scale.
    T initial_damping = T(1e-3);
    /// Marquardt's scaling: damp each variable by its own diagonal entry of
    /// J'J (invariant to the variables' units) instead of the identity.
    bool scale_by_diagonal = true;
    /// Called after each accepted step with the iteration number and the
    /// objective; return false to stop.
    std::function<bool(int iteration, T value)> on_iteration;
};

namespace detail {

template <class T>
void check_lm_params(const levenberg_marquardt_params<T>& params) {
    if (params.max_iterations < 0 || !(params.gradient_tolerance >= T(0)) || !(params.step_tolerance >= T(0)) ||
        !(params.value_tolerance >= T(0)) || !(params.initial_damping > T(0))) {
        throw invalid_argument(
            "levenberg_marquardt: max_iterations and tolerances must not be negative, initial_damping must be positive");
    }
}

/// The first evaluation: an m x n Jacobian (m > 0), every value finite.
template <class T>
void check_lm_start(const vector_x<T>& residuals, const matrix_x<T>& jacobian, Eigen::Index n) {
    const Eigen::Index m = residuals.size();
    if (m == 0 || jacobian.rows() != m || jacobian.cols() != n) {
        throw error("levenberg_marquardt: the Jacobian must be " + std::to_string(m) + " x " + std::to_string(n) +
                    ", got " + std::to_string(jacobian.rows()) + " x " + std::to_string(jacobian.cols()) +
                    (m == 0 ? " (and there are no residuals)" : ""));
    }
    if (!residuals.allFinite() || !jacobian.allFinite()) {
        throw error("levenberg_marquardt: the residuals or the Jacobian are not finite at the start point");
    }
}

}  // namespace detail

/// Minimises 0.5 |r(x)|^2 from x0. R: void(const vector_x<T>& x,
/// vector_x<T>& residuals, matrix_x<T>* jacobian) writes the residuals
/// (resizing them) and, when `jacobian` is not null, the m x n Jacobian.
/// Throws invalid_argument for an empty or non-finite x0, anima::error if
/// the residuals or Jacobian are not finite at x0 or change size, or if
/// |r|^2, J'J or J'r overflow there (scale the residuals down).
template <class T, class R>
optimize_result<T> levenberg_marquardt(R&& r, vector_x<T> x0, const levenberg_marquardt_params<T>& params = {}) {
    detail::check_start(x0, "anima::levenberg_marquardt");
    detail::check_lm_params(params);
    const Eigen::Index n = x0.size();
    optimize_result<T> result;
    result.x = std::move(x0);

    vector_x<T> residuals;
    matrix_x<T> jacobian;
    r(static_cast<const vector_x<T>&>(result.x), residuals, &jacobian);
    result.evaluations = 1;
    const Eigen::Index m = residuals.size();
    detail::check_lm_start(residuals, jacobian, n);
    result.value = residuals.squaredNorm() / T(2);

    matrix_x<T> normal = jacobian.transpose() * jacobian;
    vector_x<T> gradient = jacobian.transpose() * residuals;
    // Finite residuals whose square overflows would make every test below
    // compare infinities: "converged" at the start, the value inf.
    if (!std::isfinite(result.value) || !normal.allFinite() || !gradient.allFinite())
        throw error("levenberg_marquardt: |r|^2, J'J or J'r overflow at the start point (|r|^2 / 2 = " +
                    detail::argument_text(result.value) + "): scale the residuals down");
    const T tiny = std::numeric_limits<T>::min() / std::numeric_limits<T>::epsilon();
    // Scaled by the diagonal, mu D already carries J'J's units: mu starts
    // as given. (Scaled twice, it grew as |J|^4 and the first steps of a
    // problem in large units were too short to leave the start.)
    T damping = params.scale_by_diagonal ? params.initial_damping
                                         : params.initial_damping * std::max(normal.diagonal().maxCoeff(), tiny);
    T growth = T(2);

    vector_x<T> trial_x(n), trial_residuals;
    matrix_x<T> trial_jacobian;
    matrix_x<T> damped;
    Eigen::LDLT<matrix_x<T>> solver;
    result.status = optimize_status::max_iterations;
    while (true) {
        if (gradient.template lpNorm<Eigen::Infinity>() <=
            params.gradient_tolerance * std::max(T(1), result.value)) {
            result.status = optimize_status::converged;
            break;
        }
        if (result.iterations >= params.max_iterations) break;
        ++result.iterations;

        // Scaled damping: a variable the residuals barely see still gets a
        // floor, so a rank-deficient J'J stays solvable.
        damped = normal;
        const T floor = std::numeric_limits<T>::epsilon() * std::max(normal.diagonal().maxCoeff(), tiny);
        for (Eigen::Index i = 0; i < n; ++i) {
            const T d = params.scale_by_diagonal ? std::max(normal(i, i), floor) : T(1);
            damped(i, i) += damping * d;
        }
        solver.compute(damped);
        const vector_x<T> step = solver.solve(-gradient);
        if (solver.info() != Eigen::Success || !step.allFinite()) {
            damping *= growth;
            growth *= T(2);
            if (!std::isfinite(damping)) {
                result.status = optimize_status::stalled;
                break;
            }
            continue;
        }
        if (step.norm() <= params.step_tolerance * (result.x.norm() + params.step_tolerance)) {
            result.status = optimize_status::converged;
            break;
        }

        trial_x = result.x + step;
        r(static_cast<const vector_x<T>&>(trial_x), trial_residuals, &trial_jacobian);
        ++result.evaluations;
        if (trial_residuals.size() != m || trial_jacobian.rows() != m || trial_jacobian.cols() != n) {
            throw error("levenberg_marquardt: the residual function changed the size of its output");
        }
        const T trial_value = trial_residuals.squaredNorm() / T(2);
        // Decrease predicted by the damped linear model: 0.5 h'(mu D h - g).
        const T predicted = (step.dot((damped - normal) * step) - step.dot(gradient)) / T(2);
        const bool finite = std::isfinite(trial_value) && trial_jacobian.allFinite();
        if (finite && trial_value < result.value && predicted > T(0)) {
            const T rho = (result.value - trial_value) / predicted;
            const T previous = result.value;
            result.x = trial_x;
            residuals.swap(trial_residuals);
            jacobian.swap(trial_jacobian);
            result.value = trial_value;
            result.history.push_back(result.value);
            normal.noalias() = jacobian.transpose() * jacobian;
            gradient.noalias() = jacobian.transpose() * residuals;
            const T shrink = T(1) - std::pow(T(2) * rho - T(1), 3);
            damping *= std::max(T(1) / T(3), shrink);
            damping = std::max(damping, tiny);
            growth = T(2);
            if (params.on_iteration && !params.on_iteration(result.iterations, result.value)) {
                result.status = optimize_status::stopped;
                break;
            }
            if (previous - result.value <= params.value_tolerance * previous) {
                result.status = optimize_status::converged;
                break;
            }
        } else {
            damping *= growth;
            growth *= T(2);
            if (!std::isfinite(damping) || damping > T(1) / tiny) {
                result.status = optimize_status::stalled;
                break;
            }
        }
    }
    return result;
}

}  // namespace anima
