// Cyclic coordinate descent with quaternions (Johnson's formulation): joint
// by joint from the effector up, the shortest-arc rotation that swings the
// effector toward the target is applied to the joint (a ball joint takes it
// whole, a hinge its component about the axis), then clamped to the limits.
// Position goals only; several goals are visited in turn each sweep.
#pragma once

#include <anima/core/error.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/solve.hpp>
#include <anima/rotation/exp_log.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace anima {

/// One sweep is one iteration. params.null_space, step_scale and restarts
/// are not used (restarts: yes, from random poses, as in solve_ik).
template <class T>
ik_result<T> solve_ik_ccd(const kinematic_tree<T>& tree, std::vector<ik_goal<T>> goals, const ik_vector_arg<T>& q0,
                          const ik_params<T>& params = {}) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    using quat = Eigen::Quaternion<T>;
    const char* who = "anima::solve_ik_ccd";
    tree.check_q(q0, who);
    check_goals(tree, goals, who);
    detail::check_ik_params(params, tree.dofs(), who);
    for (std::size_t i = 0; i < goals.size(); ++i)
        if (goals[i].kind != ik_goal_kind::position)
            throw invalid_argument(std::string(who) + ": goal " + std::to_string(i) +
                                   " is not a position goal; CCD handles position goals only");
    const auto& sk = tree.skeleton();
    const T tiny = std::sqrt(std::numeric_limits<T>::epsilon());
    ik_state<T> s;
    ik_vector<T> r;
    std::vector<goal_error<T>> errors;
    random_source rng(params.seed);
    ik_result<T> best;
    best.q = params.limits ? tree.clamp(q0) : q0;
    T best_score = std::numeric_limits<T>::infinity();
    bool stationary = false;

    for (int attempt = 0; attempt <= params.restarts; ++attempt) {
        ik_vector<T> q = attempt == 0 ? best.q : detail::random_pose(tree, q0, rng);
        ++best.attempts;
        detail::attempt_progress<T> progress;
        for (int it = 0;; ++it) {
            tree.forward_unchecked(q, s);
            goal_residual(s, goals, r, &errors);
            if (progress.finished(detail::summarise(errors, params).score, it, params.max_iterations, q, best_score,
                                  best.q)) {
                stationary = stationary || progress.stalled;
                break;
            }
            ++best.iterations;
            for (const auto& g : goals) {
                for (int j = static_cast<int>(g.joint); j != -1; j = sk[static_cast<std::size_t>(j)].parent) {
                    const auto ju = static_cast<std::size_t>(j);
                    const int d0 = tree.first_dof(ju);
                    if (d0 < 0) continue;
                    tree.forward_unchecked(q, s);
                    vec3 a = effector_position(s, g) - s.positions[ju];
                    vec3 b = g.position - s.positions[ju];
                    if (tree.kind(ju) == ik_joint_kind::hinge) {
                        const vec3 axis = s.orientations[ju] * tree.hinge_axis(ju);
                        a -= axis * axis.dot(a);
                        b -= axis * axis.dot(b);
                        if (a.norm() < tiny || b.norm() < tiny) continue;
                        q[d0] += std::atan2(axis.dot(a.cross(b)), a.dot(b));
                    } else {
                        if (a.norm() < tiny || b.norm() < tiny) continue;
                        const quat swing = quat::FromTwoVectors(a, b);  // world frame
                        const quat parent = sk[ju].parent < 0 ? quat::Identity()
                                                              : s.orientations[static_cast<std::size_t>(sk[ju].parent)];
                        const quat local = parent.conjugate() * swing * s.orientations[ju];
                        q.template segment<3>(d0) = to_rotation_vector(local.normalized());
                    }
                    if (params.limits) q = tree.clamp(q);
                }
            }
        }
        if (best_score <= T(1)) break;
    }
    evaluate_ik(tree, goals, best);
    best.status = best_score <= T(1) ? ik_status::converged
                  : stationary       ? ik_status::unreachable_closest
                                     : ik_status::max_iterations;
    return best;
}

}  // namespace anima
