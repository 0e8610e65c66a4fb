// What every optimiser returns.
#pragma once

#include <cmath>
#include <limits>
#include <string_view>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include <anima/core/eigen_types.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>

namespace anima {

/// Why an optimiser stopped.
enum class optimize_status {
    converged,       ///< a gradient, step or value tolerance was met
    max_iterations,  ///< the iteration cap was reached first
    stalled,         ///< no step lowers the objective any more (rounding floor)
    stopped,         ///< the on_iteration callback asked to stop
};

template <>
struct enum_names<optimize_status> {
    static constexpr const char* what = "optimiser status";
    static constexpr enum_entry<optimize_status> entries[] = {{optimize_status::converged, "converged"},
                                                              {optimize_status::max_iterations, "max_iterations"},
                                                              {optimize_status::stalled, "stalled"},
                                                              {optimize_status::stopped, "stopped"}};
};

template <class T>
struct optimize_result {
    vector_x<T> x;            ///< the best point found: never worse than the start
    T value{};                ///< objective at x (least squares: 0.5 * |r(x)|^2)
    int iterations = 0;       ///< iterations run (least squares: steps tried)
    int evaluations = 0;      ///< calls of the objective
    optimize_status status = optimize_status::max_iterations;
    std::vector<T> history;   ///< objective after each accepted step: non-increasing

    bool converged() const noexcept { return status == optimize_status::converged; }
};

namespace detail {

// Tolerances that mean "as far as the scalar's precision sensibly goes".
template <class T>
constexpr T default_gradient_tolerance() {
    return std::is_same<T, float>::value ? T(1e-4) : T(1e-8);
}
template <class T>
constexpr T default_value_tolerance() {
    return std::is_same<T, float>::value ? T(1e-7) : T(1e-15);
}
template <class T>
constexpr T default_step_tolerance() {
    return std::is_same<T, float>::value ? T(1e-6) : T(1e-12);
}

template <class T>
void check_start(const vector_x<T>& x0, const char* function) {
    if (x0.size() == 0) {
        throw invalid_argument(std::string(function) + ": the start point is empty");
    }
    for (Eigen::Index i = 0; i < x0.size(); ++i) {
        if (!std::isfinite(x0[i])) {
            throw invalid_argument(std::string(function) + ": start point component " +
                                   std::to_string(i) + " is not finite");
        }
    }
}

}  // namespace detail
}  // namespace anima
