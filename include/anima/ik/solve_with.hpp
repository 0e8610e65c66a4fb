// One entry point for the library's iterative IK solvers, chosen at run
// time: solve_ik_with(solver, tree, goals, start, params). Every solver runs
// the same goals from the same start with the same iteration cap, tolerance,
// limits, restarts and null-space task, so they can be swapped or compared.
#pragma once

#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/ik/bfgs_ik.hpp>
#include <anima/ik/ccd.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/levenberg_marquardt_ik.hpp>
#include <anima/ik/solve.hpp>
#include <anima/ik/step_rules.hpp>

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace anima {

enum class ik_solver : unsigned char {
    pseudo_inverse,  ///< Table 1 with J+ (SVD)
    damped_least_squares,  ///< Table 1 with adaptive damping
    ccd,  ///< cyclic coordinate descent
    bfgs,  ///< L-BFGS on the squared goal errors
    levenberg_marquardt,  ///< Levenberg-Marquardt with limits in the step
};

/// Every solver, in the order of enum_name_list<ik_solver>().
inline constexpr std::array<ik_solver, 5> ik_solvers = {ik_solver::pseudo_inverse, ik_solver::damped_least_squares,
                                                        ik_solver::ccd, ik_solver::bfgs,
                                                        ik_solver::levenberg_marquardt};

/// Short names: "pinv", "dls", "ccd", "bfgs", "lm".
template <>
struct enum_names<ik_solver> {
    static constexpr const char* what = "IK solver";
    static constexpr enum_entry<ik_solver> entries[] = {{ik_solver::pseudo_inverse, "pinv"},
                                                        {ik_solver::damped_least_squares, "dls"},
                                                        {ik_solver::ccd, "ccd"},
                                                        {ik_solver::bfgs, "bfgs"},
                                                        {ik_solver::levenberg_marquardt, "lm"}};
};

/// The solver of a short name (any case); anima::invalid_argument naming
/// the choices for any other.
inline ik_solver parse_ik_solver(std::string_view name) {
    return parse_enum<ik_solver>(name, "anima::parse_ik_solver");
}

/// Solves the goals with the chosen solver from `start`. The solver-specific
/// settings keep their defaults (the damped least squares rule adapts its
/// damping); params carries what they share.
template <class T>
ik_result<T> solve_ik_with(ik_solver solver, const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals,
                           const ik_vector_arg<T>& start, const ik_params<T>& params = {}) {
    switch (solver) {
        case ik_solver::pseudo_inverse: return solve_ik(tree, goals, start, pseudo_inverse<T>{}, params);
        case ik_solver::damped_least_squares: {
            typename damped_least_squares<T>::params d;
            d.adaptive = true;
            return solve_ik(tree, goals, start, damped_least_squares<T>(d), params);
        }
        case ik_solver::ccd: return solve_ik_ccd(tree, goals, start, params);
        case ik_solver::bfgs: {
            bfgs_ik_params<T> b;
            b.ik = params;
            return solve_ik_bfgs(tree, goals, start, b);
        }
        case ik_solver::levenberg_marquardt: {
            levenberg_marquardt_ik_params<T> l;
            l.ik = params;
            return solve_ik_levenberg_marquardt(tree, goals, start, l);
        }
    }
    throw invalid_argument("anima::solve_ik_with: unknown solver");
}

/// One of the library's solvers, chosen at run time, as a solver of the
/// shape solve_clip_ik takes: solve(tree, goals, start, params) is
/// solve_ik_with(solver, tree, goals, start, params).
template <class T>
struct ik_solver_call {
    ik_solver solver = ik_solver::damped_least_squares;
    ik_result<T> operator()(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals,
                            const ik_vector<T>& start, const ik_params<T>& params) const {
        return solve_ik_with(solver, tree, goals, start, params);
    }
};

}  // namespace anima
