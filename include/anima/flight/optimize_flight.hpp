// Models (1) and (2) solved by Levenberg-Marquardt on the residuals of
// flight_objective.hpp, with exact Jacobians from forward-mode automatic
// differentiation. Reports the objective and the angular-momentum drift
// before and after, the key times, and the solver's monotone history.
#pragma once

#include <anima/core/error.hpp>
#include <anima/flight/flight_objective.hpp>
#include <anima/optimize/levenberg_marquardt.hpp>

#include <chrono>
#include <cmath>
#include <string>
#include <optional>
#include <vector>

namespace anima {

enum class flight_model {
    timing = 2,           ///< model (2): key poses fixed, key times optimised
    timing_and_poses = 1  ///< model (1): key times and poses within e1 / e2
};

template <class T>
struct flight_optimization_params {
    flight_model model = flight_model::timing;
    int momentum_samples = 201;           ///< instants used for the drift figures
    levenberg_marquardt_params<T> solver;  ///< max_iterations, tolerances, on_iteration
    /// Refuse a problem whose solver would need more memory than this, in
    /// bytes (anima::flight_solver_bytes); 0: no limit.
    double max_memory = 1024.0 * 1024.0 * 1024.0;
};

template <class T>
struct flight_optimization_result {
    flight_keys<T> initial, optimized;
    T objective_initial{}, objective_final{};  ///< T^-1 integral of sum F_i^2, (N^2 + (N m)^2)
    /// flight_problem::momentum_drift of the initial and optimised keys;
    /// empty where it is not defined (no mean angular momentum).
    std::optional<T> momentum_drift_initial, momentum_drift_final;
    std::vector<T> history;  ///< objective after each accepted step (non-increasing)
    int iterations = 0, evaluations = 0;
    optimize_status status = optimize_status::max_iterations;
    double seconds = 0;
};

/// Number of parameters the solver moves for the problem under `model`.
template <class T>
Eigen::Index flight_parameter_count(const flight_problem<T>& problem, flight_model model) {
    return model == flight_model::timing ? problem.timing_size() : problem.full_size();
}

/// Bytes optimize_flight needs for the problem under `model`: two dense
/// residuals x parameters Jacobians (current and trial), three parameters x
/// parameters matrices (J'J, its damped copy and the factorisation), and
/// the residuals with their derivative vectors while a Jacobian is taken.
/// Grows with the square of the key count: 2000 keys of model (2) with 4
/// quadrature points need about 1.5 GiB.
template <class T>
double flight_solver_bytes(const flight_problem<T>& problem, flight_model model) {
    const double m = static_cast<double>(problem.residual_count());
    const double n = static_cast<double>(flight_parameter_count(problem, model));
    const double width = flight_problem<T>::jacobian_width;
    return static_cast<double>(sizeof(T)) * (2 * m * n + 3 * n * n + m * (width + 3));
}

/// The work of one iteration of optimize_flight: the passes its Jacobian
/// makes over the quadrature nodes (ceil(parameters / jacobian_width)),
/// the evaluations of one joint's dynamics at one node they make (passes x
/// joints x nodes, a node being 6 residuals), and the floating-point
/// operations of its normal equations (residuals x parameters^2 to form
/// J'J, parameters^3 / 3 to factor it). What a caller multiplies by the
/// iterations and its machine's speed to refuse a run that would take too
/// long.
struct flight_iteration_work {
    double passes = 0, joint_evaluations = 0, flops = 0;
};

template <class T>
flight_iteration_work flight_work_per_iteration(const flight_problem<T>& problem, flight_model model) {
    const double m = static_cast<double>(problem.residual_count());
    const double n = static_cast<double>(flight_parameter_count(problem, model));
    flight_iteration_work out;
    out.passes = std::ceil(n / flight_problem<T>::jacobian_width);
    out.joint_evaluations = out.passes * static_cast<double>(problem.model().size()) * m / 6;
    out.flops = m * n * n + n * n * n / 3;
    return out;
}

/// Optimises the problem's keys from their own times and poses. Throws
/// anima::invalid_argument for fewer than 3 keys, a bad model, or a problem
/// whose solver would need more than params.max_memory bytes.
template <class T>
flight_optimization_result<T> optimize_flight(const flight_problem<T>& problem,
                                              const flight_optimization_params<T>& params = {}) {
    if (problem.key_count() < 3)
        throw invalid_argument("anima::optimize_flight: needs at least 3 keys to move a key time, got " +
                               std::to_string(problem.key_count()));
    if (params.model != flight_model::timing && params.model != flight_model::timing_and_poses)
        throw invalid_argument("anima::optimize_flight: model must be 1 or 2, got " +
                               std::to_string(static_cast<int>(params.model)));
    const double bytes = flight_solver_bytes(problem, params.model);
    if (params.max_memory > 0 && !(bytes <= params.max_memory)) {
        const auto mib = [](double b) { return std::to_string(static_cast<long long>(std::ceil(b / (1024.0 * 1024.0)))); };
        throw invalid_argument("anima::optimize_flight: " + std::to_string(problem.key_count()) + " keys with " +
                               std::to_string(problem.settings().quadrature_points) +
                               " quadrature points need a " + std::to_string(problem.residual_count()) + " x " +
                               std::to_string(flight_parameter_count(problem, params.model)) +
                               " Jacobian, about " + mib(bytes) + " MiB in all, more than max_memory (" +
                               mib(params.max_memory) + " MiB): use fewer keys or quadrature points");
    }
    const auto start = std::chrono::steady_clock::now();
    flight_optimization_result<T> out;
    out.initial = problem.keys();
    out.objective_initial = problem.objective(out.initial);
    out.momentum_drift_initial = problem.momentum_drift(out.initial, params.momentum_samples);
    using vector = vector_x<T>;
    using matrix = matrix_x<T>;
    optimize_result<T> solved;
    if (params.model == flight_model::timing) {
        solved = levenberg_marquardt<T>(
            [&](const vector& x, vector& r, matrix* j) { problem.timing_residuals(x, r, j); },
            problem.timing_parameters(out.initial.times), params.solver);
        out.optimized = out.initial;
        out.optimized.times = problem.key_times(solved.x);
    } else {
        solved = levenberg_marquardt<T>(
            [&](const vector& x, vector& r, matrix* j) { problem.full_residuals(x, r, j); },
            problem.full_parameters(out.initial.times), params.solver);
        out.optimized = problem.keys_of(solved.x);
    }
    out.objective_final = problem.objective(out.optimized);
    out.momentum_drift_final = problem.momentum_drift(out.optimized, params.momentum_samples);
    for (const T& v : solved.history) out.history.push_back(T(2) * v);
    out.iterations = solved.iterations;
    out.evaluations = solved.evaluations;
    out.status = solved.status;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

}  // namespace anima
