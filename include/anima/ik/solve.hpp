// The Jacobian IK iteration of Table 1 with the step rule as a policy:
//   e = g - f(q); J = Jacobian(q); dq = alpha * rule(J, e); q += dq
// plus what a usable solver needs around it: a null-space secondary task
// (pull toward a reference pose without disturbing the goals), joint limits
// inside the solve (a DOF that would leave its range is clamped and its
// column removed before the step is recomputed, so the other DOFs take
// over instead of the solve sticking at the limit), a cap on the step,
// random restarts, and a result that is the best pose seen, never NaN.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/core/random.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/step_rules.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace anima {

enum class ik_status : unsigned char {
    converged,            ///< every goal within tolerance
    unreachable_closest,  ///< stopped at a pose no step improves: the closest found
    max_iterations,       ///< still improving when the iteration cap was reached
    singular              ///< the rule could not invert J (jacobian_inverse only)
};

template <>
struct enum_names<ik_status> {
    static constexpr const char* what = "IK status";
    static constexpr enum_entry<ik_status> entries[] = {{ik_status::converged, "converged"},
                                                        {ik_status::unreachable_closest, "unreachable_closest"},
                                                        {ik_status::max_iterations, "max_iterations"},
                                                        {ik_status::singular, "singular"}};
};

/// Options shared by every IK solver.
template <class T>
struct ik_params {
    int max_iterations = 100;            ///< per attempt
    T tolerance = T(1e-5);               ///< position error, in skeleton units
    T angle_tolerance = T(1e-5);         ///< orientation error, radians
    T step_scale = T(1);                 ///< alpha of Table 1
    T max_step = T(0.5);                 ///< largest DOF change per iteration (0: none)
    /// Each goal's position residual is shortened to this length before
    /// the step (Buss's error clamping: a far target's huge residual is not
    /// a good linearisation). Negative: a quarter of the goal's lever (the
    /// bone lengths from the root to the effector point); 0: no clamping.
    T residual_clamp = T(-1);
    bool limits = true;                  ///< keep DOFs within the tree's limits
    int restarts = 0;                    ///< random restarts after a failed attempt
    std::uint64_t seed = 1;              ///< of the restarts' random poses
    /// Null-space task: dq += (I - J+ J) gain (reference - q). Off when the
    /// gain is 0 or reference is empty.
    struct null_space_params {
        T gain = T(0);
        ik_vector<T> reference;
    } null_space;
};

template <class T>
struct ik_result {
    ik_vector<T> q;                      ///< best pose found (always finite)
    ik_status status = ik_status::max_iterations;
    int iterations = 0;                  ///< over all attempts
    int attempts = 0;
    std::vector<goal_error<T>> errors;   ///< per goal, at q
    T max_position_error = T(0);
    T max_angle_error = T(0);
    ik_vector<T> singular_values;        ///< of the last Jacobian, when the rule computed them
    T damping = T(0);                    ///< last damping used
    bool converged() const { return status == ik_status::converged; }
};

namespace detail {

template <class T>
void check_ik_params(const ik_params<T>& p, int dofs, const char* who) {
    check_at_least(who, "ik_params::max_iterations", p.max_iterations, 0);
    check_at_least(who, "ik_params::restarts", p.restarts, 0);
    check_positive(who, "ik_params::tolerance", p.tolerance);
    check_positive(who, "ik_params::angle_tolerance", p.angle_tolerance);
    check_positive(who, "ik_params::step_scale", p.step_scale);
    check_non_negative(who, "ik_params::max_step", p.max_step);
    check_finite(who, "ik_params::residual_clamp", p.residual_clamp);
    check_non_negative(who, "ik_params::null_space.gain", p.null_space.gain);
    if (p.null_space.reference.size() != 0 &&
        (p.null_space.reference.size() != dofs || !p.null_space.reference.allFinite()))
        throw invalid_argument(std::string(who) + ": null_space.reference has " +
                               std::to_string(p.null_space.reference.size()) + " entries (or non-finite ones), the tree " +
                               std::to_string(dofs) + " DOFs");
}

template <class T>
struct error_summary {
    T position = T(0), angle = T(0), score = T(0);
};

template <class T>
error_summary<T> summarise(const std::vector<goal_error<T>>& errors, const ik_params<T>& p) {
    error_summary<T> s;
    for (const auto& e : errors) {
        s.position = std::max(s.position, e.position);
        s.angle = std::max(s.angle, e.angle);
    }
    s.score = std::max(s.position / p.tolerance, s.angle / p.angle_tolerance);
    return s;
}

/// One attempt's bookkeeping, shared by the iterative solvers: keeps the
/// best pose seen and ends the attempt on success, at the iteration cap, or
/// after 8 iterations without 0.1% progress (a local minimum, or an
/// unreachable target's closest pose: a restart has better odds).
template <class T>
struct attempt_progress {
    T last = std::numeric_limits<T>::infinity();
    int slow = 0;
    bool stalled = false;

    bool finished(T score, int iteration, int max_iterations, const ik_vector<T>& q, T& best_score,
                  ik_vector<T>& best_q) {
        if (score < best_score) {
            best_score = score;
            best_q = q;
        }
        if (score <= T(1) || iteration == max_iterations) return true;
        slow = score > last * T(0.999) ? slow + 1 : 0;
        last = std::min(last, score);
        stalled = slow >= 8;
        return stalled;
    }
};

/// A random pose: limited DOFs uniform within their limits, ball DOFs
/// without limits within +-1 rad of `around`, translations at `around`.
template <class T>
void random_pose(const kinematic_tree<T>& tree, const ik_vector<T>& around, random_source& rng, ik_vector<T>& q) {
    q = around;
    for (int k = 0; k < tree.dofs(); ++k) {
        const T lo = tree.lower()[k], hi = tree.upper()[k];
        const T u = static_cast<T>(rng.uniform());
        if (std::isfinite(lo) && std::isfinite(hi)) q[k] = lo + u * (hi - lo);
        else if (!(tree.root_translation() && k < 3)) q[k] = around[k] + (T(2) * u - T(1));
    }
    tree.clamp_in_place(q);
}

/// Per goal, the length its position residual is clamped to (0: none).
template <class T>
void residual_clamps(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals, const ik_params<T>& p,
                     std::vector<T>& out) {
    out.assign(goals.size(), p.residual_clamp > T(0) ? p.residual_clamp : T(0));
    if (p.residual_clamp >= T(0)) return;
    const auto& sk = tree.skeleton();
    for (std::size_t i = 0; i < goals.size(); ++i) {
        T lever = goals[i].offset.norm();
        for (int j = static_cast<int>(goals[i].joint); sk[static_cast<std::size_t>(j)].parent != -1;
             j = sk[static_cast<std::size_t>(j)].parent)
            lever += tree.base_translation(static_cast<std::size_t>(j)).norm();
        out[i] = goals[i].weight * lever / T(4);
    }
}

template <class T>
void clamp_residual(const std::vector<ik_goal<T>>& goals, const std::vector<T>& clamps, ik_vector<T>& r) {
    int row = 0;
    for (std::size_t i = 0; i < goals.size(); ++i) {
        if (goals[i].has_position() && clamps[i] > T(0)) {
            const T n = r.template segment<3>(row).norm();
            if (n > clamps[i]) r.template segment<3>(row) *= clamps[i] / n;
        }
        row += goals[i].rows();
    }
}

}  // namespace detail

/// Fills result.errors and the maxima at result.q, with s and r as scratch.
template <class T>
void evaluate_ik(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals, ik_result<T>& result,
                 ik_state<T>& s, ik_vector<T>& r) {
    tree.forward_unchecked(result.q, s);
    goal_residual(s, goals, r, &result.errors);
    result.max_position_error = result.max_angle_error = T(0);
    for (const auto& e : result.errors) {
        result.max_position_error = std::max(result.max_position_error, e.position);
        result.max_angle_error = std::max(result.max_angle_error, e.angle);
    }
}

/// Fills result.errors and the maxima at result.q.
template <class T>
void evaluate_ik(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals, ik_result<T>& result) {
    ik_state<T> s;
    ik_vector<T> r;
    evaluate_ik(tree, goals, result, s, r);
}

/// What solve_ik_into keeps from call to call so that, once it has seen a
/// tree and a goal set of the same shapes, a solve allocates nothing: keep
/// one per thread (or per character) and pass it to every call. The
/// members are scratch space, not results.
template <class T>
struct ik_workspace {
    std::vector<ik_goal<T>> goals;  ///< the call's goals, checked and normalised
    std::vector<T> clamps;          ///< per goal, its residual's length cap
    std::vector<goal_error<T>> errors;
    std::vector<unsigned char> locked;  ///< per DOF: held at a limit in this step
    ik_state<T> state;
    ik_vector<T> start, r, dq, z, jz, zstep, parked;
    ik_matrix<T> jacobian, limited;  ///< J; J with the locked DOFs' columns zeroed
    ik_step_info<T> info, null_info;
    ik_step_scratch<T> step;
};

namespace detail {

/// How an attempt ended, beyond the best pose it left.
struct attempt_end {
    bool stalled = false;   ///< stopped without progress: a local minimum, or an unreachable target's closest pose
    bool singular = false;  ///< the step rule met a singular Jacobian: no other start does better
};

/// The attempts every solver makes: the first from q0 (clamped when
/// params.limits), then, while the goals are not met, up to params.restarts
/// more from random poses (random_pose about q0, seeded by params.seed).
/// attempt(start, best, best_score) runs one attempt from `start` (which it
/// may use as its own): it keeps the best pose it sees in best.q and its
/// score (summarise's, at most 1 when every goal is met) in best_score, adds
/// its iterations to best.iterations, and says how it ended. The errors and
/// status are set at the end; s and r are scratch for that. best's storage
/// is reused.
template <class T, class Attempt>
void solve_with_attempts_into(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals,
                              const ik_vector<T>& q0, const ik_params<T>& params, ik_result<T>& best,
                              ik_vector<T>& start, ik_state<T>& s, ik_vector<T>& r, Attempt&& attempt) {
    random_source rng(params.seed);
    best.q = q0;
    if (params.limits) tree.clamp_in_place(best.q);
    best.iterations = best.attempts = 0;
    best.damping = T(0);
    T best_score = std::numeric_limits<T>::infinity();
    attempt_end ended;
    for (int a = 0; a <= params.restarts; ++a) {
        if (a == 0) start = best.q;
        else random_pose(tree, q0, rng, start);
        ++best.attempts;
        const attempt_end end = attempt(start, best, best_score);
        ended.stalled = ended.stalled || end.stalled;
        ended.singular = ended.singular || end.singular;
        if (best_score <= T(1) || ended.singular) break;
    }
    evaluate_ik(tree, goals, best, s, r);
    best.status = best_score <= T(1) ? ik_status::converged
                  : ended.singular   ? ik_status::singular
                  : ended.stalled    ? ik_status::unreachable_closest
                                     : ik_status::max_iterations;
}

/// solve_with_attempts_into with a result and scratch of its own.
template <class T, class Attempt>
ik_result<T> solve_with_attempts(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals,
                                 const ik_vector<T>& q0, const ik_params<T>& params, Attempt&& attempt) {
    ik_result<T> best;
    ik_vector<T> start, r;
    ik_state<T> s;
    solve_with_attempts_into(tree, goals, q0, params, best, start, s, r, attempt);
    return best;
}

}  // namespace detail

namespace detail {

/// One step of the Jacobian iteration at q into ws.dq: the rule's step (plus
/// the null-space task), with DOFs that would leave their limits moved onto
/// them, their columns removed and the step recomputed (up to 4 passes), so
/// the other DOFs take over instead of the solve sticking at the limit.
/// Returns whether the rule met a singular Jacobian it could not invert.
template <class T, class Rule>
bool limited_step(const kinematic_tree<T>& tree, const Rule& rule, const ik_params<T>& params, bool use_null,
                  ik_vector<T>& q, ik_workspace<T>& ws) {
    const int n = tree.dofs();
    bool singular = false;
    ws.locked.assign(static_cast<std::size_t>(n), 0);
    ws.limited = ws.jacobian;
    for (int pass = 0; pass < 4; ++pass) {
        apply_rule(rule, ws.limited, ws.r, ws.dq, ws.info, ws.step);
        if (ws.info.singular && !ws.info.decomposed && ws.dq.isZero()) singular = true;
        ws.dq *= params.step_scale;
        if (use_null) {
            ws.z = params.null_space.gain * (params.null_space.reference - q);
            for (int k = 0; k < n; ++k)
                if (ws.locked[static_cast<std::size_t>(k)]) ws.z[k] = T(0);
            ws.jz.noalias() = ws.limited * ws.z;
            apply_rule(rule, ws.limited, ws.jz, ws.zstep, ws.null_info, ws.step);
            ws.dq += ws.z - ws.zstep;
        }
        for (int k = 0; k < n; ++k)
            if (ws.locked[static_cast<std::size_t>(k)]) ws.dq[k] = T(0);
        if (params.max_step > T(0)) {
            const T big = ws.dq.cwiseAbs().maxCoeff();
            if (big > params.max_step) ws.dq *= params.max_step / big;
        }
        if (!params.limits) break;
        bool more = false;
        for (int k = 0; k < n; ++k) {
            const auto ku = static_cast<std::size_t>(k);
            if (ws.locked[ku]) continue;
            const T next = q[k] + ws.dq[k];
            if (next < tree.lower()[k] || next > tree.upper()[k]) {
                const T at = next < tree.lower()[k] ? tree.lower()[k] : tree.upper()[k];
                // Move the DOF onto its limit, then keep it there.
                ws.r -= ws.limited.col(k) * (at - q[k]);
                q[k] = at;
                ws.locked[ku] = 1;
                ws.limited.col(k).setZero();
                more = true;
            }
        }
        if (!more) break;
    }
    return singular;
}

/// result.singular_values from a step's info (empty when the rule computed
/// none, or when no step was taken), keeping the storage of an emptied
/// vector in `parked` for the next call that has some.
template <class T>
void report_singular_values(const ik_step_info<T>& info, bool stepped, ik_vector<T>& out, ik_vector<T>& parked) {
    if (stepped && info.decomposed) {
        if (out.size() != info.singular_values.size() && parked.size() == info.singular_values.size()) out.swap(parked);
        out = info.singular_values;
    } else if (out.size() != 0) {
        if (parked.size() == 0) out.swap(parked);
        else out.resize(0);
    }
}

}  // namespace detail

/// solve_ik into caller-owned storage, for a game loop: the result goes to
/// `out` and `ws` is scratch. The results are solve_ik's, bit for bit. Once
/// `out` and `ws` have seen a tree and a goal set of the same sizes, a call
/// allocates nothing when the rule is one of the library's (they keep their
/// decompositions in ws) and params.restarts is 0 or the first attempt
/// meets the goals. Throws as solve_ik does; `out` is then unspecified.
template <class T, class Rule>
void solve_ik_into(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals, const ik_vector_arg<T>& q0,
                   const Rule& rule, const ik_params<T>& params, ik_result<T>& out, ik_workspace<T>& ws) {
    const char* who = "anima::solve_ik";
    tree.check_q(q0, who);
    ws.goals = goals;
    check_goals(tree, ws.goals, who);
    detail::check_ik_params(params, tree.dofs(), who);
    const bool use_null = params.null_space.gain > T(0) && params.null_space.reference.size() == tree.dofs();
    detail::residual_clamps(tree, ws.goals, params, ws.clamps);
    bool stepped = false;
    detail::solve_with_attempts_into(
        tree, ws.goals, q0, params, out, ws.start, ws.state, ws.r,
        [&](ik_vector<T>& start, ik_result<T>& best, T& best_score) {
            ik_vector<T>& q = start;  // the attempt's own
            detail::attempt_end end;
            detail::attempt_progress<T> progress;
            for (int it = 0;; ++it) {
                tree.forward_unchecked(q, ws.state);
                goal_residual(ws.state, ws.goals, ws.r, &ws.errors);
                if (progress.finished(detail::summarise(ws.errors, params).score, it, params.max_iterations, q,
                                      best_score, best.q)) {
                    end.stalled = progress.stalled;
                    break;
                }
                ++best.iterations;
                goal_jacobian(tree, q, ws.state, ws.goals, ws.jacobian);
                detail::clamp_residual(ws.goals, ws.clamps, ws.r);
                end.singular = detail::limited_step(tree, rule, params, use_null, q, ws) || end.singular;
                if (!ws.dq.allFinite()) break;  // defensive: a rule that failed keeps the best pose
                q += ws.dq;
                if (params.limits) tree.clamp_in_place(q);
                tree.wrap(q);
                stepped = true;
                detail::report_singular_values(ws.info, true, best.singular_values, ws.parked);
                best.damping = ws.info.damping;
                if (end.singular) break;
            }
            return end;
        });
    if (!stepped) detail::report_singular_values(ws.info, false, out.singular_values, ws.parked);
}

/// Solves for q moving every goal to its target, from q0, with the step
/// rule `rule` (jacobian_inverse, pseudo_inverse, damped_least_squares,
/// weighted_rule<...> or any callable of that shape, with or without a
/// trailing ik_step_scratch<T>&). Throws anima::invalid_argument for bad
/// goals, q0 or params.
template <class T, class Rule>
ik_result<T> solve_ik(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals, const ik_vector_arg<T>& q0,
                      const Rule& rule, const ik_params<T>& params = {}) {
    ik_result<T> out;
    ik_workspace<T> ws;
    solve_ik_into(tree, goals, q0, rule, params, out, ws);
    return out;
}

}  // namespace anima
