// Cyclic coordinate descent with quaternions (Johnson's formulation): joint
// by joint from the effector up, the shortest-arc rotation that swings the
// effector toward the target is applied to the joint (a ball joint takes it
// whole, a hinge its component about the axis), then clamped to the limits.
// Orientation and aim goals turn the joint by the rotation that takes the
// current orientation (or axis) to the target; a pose goal uses its
// position's swing on the ancestors and its orientation on its own joint.
// Line, plane and half-space goals swing toward the nearest point that
// meets them. A tree with root translation moves the root last, by the
// step that puts the effector on its aim point. Several goals are visited
// in turn each sweep.
#pragma once

#include <anima/core/constants.hpp>
#include <anima/core/error.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/solve.hpp>
#include <anima/rotation/exp_log.hpp>
#include <anima/rotation/shortest_arc.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace anima {

namespace detail {

/// The point a point goal swings its effector x toward: the target, or the
/// nearest point of the line, plane or (violated) half-space.
template <class T>
Eigen::Matrix<T, 3, 1> ccd_aim_point(const ik_goal<T>& g, const Eigen::Matrix<T, 3, 1>& x) {
    return x + position_projection(g, x) * (g.position - x);
}

/// World rotation CCD applies at joint ju for goal g (identity when the
/// joint cannot help), before it is reduced to the joint's DOFs.
template <class T>
Eigen::Quaternion<T> ccd_world_rotation(const ik_state<T>& s, const ik_goal<T>& g, std::size_t ju, T tiny) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    using quat = Eigen::Quaternion<T>;
    if (g.has_orientation() && (ju == g.joint || !g.has_position())) {
        if (g.kind == ik_goal_kind::aim) return shortest_arc<quat>(s.orientations[g.joint] * g.axis, g.direction);
        return (g.orientation * s.orientations[g.joint].conjugate()).normalized();
    }
    const vec3 x = effector_position(s, g);
    const vec3 a = x - s.positions[ju], b = ccd_aim_point(g, x) - s.positions[ju];
    if (a.norm() < tiny || b.norm() < tiny) return quat::Identity();
    return shortest_arc<quat>(a, b);
}

}  // namespace detail

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
    const auto& sk = tree.skeleton();
    const T tiny = std::sqrt(std::numeric_limits<T>::epsilon());
    ik_state<T> s;
    ik_vector<T> r;
    std::vector<goal_error<T>> errors;
    return detail::solve_with_attempts(tree, goals, ik_vector<T>(q0), params, [&](ik_vector<T> q, ik_result<T>& best,
                                                                                   T& best_score) {
        detail::attempt_progress<T> progress;
        for (int it = 0;; ++it) {
            tree.forward_unchecked(q, s);
            goal_residual(s, goals, r, &errors);
            if (progress.finished(detail::summarise(errors, params).score, it, params.max_iterations, q, best_score,
                                  best.q))
                break;
            ++best.iterations;
            for (const auto& g : goals) {
                for (int j = static_cast<int>(g.joint); j != -1; j = sk[static_cast<std::size_t>(j)].parent) {
                    const auto ju = static_cast<std::size_t>(j);
                    const int d0 = tree.first_dof(ju);
                    if (d0 < 0) continue;
                    tree.forward_unchecked(q, s);
                    const bool turning = g.has_orientation() && (ju == g.joint || !g.has_position());
                    if (tree.kind(ju) == ik_joint_kind::hinge) {
                        const vec3 axis = s.orientations[ju] * tree.hinge_axis(ju);
                        if (turning) {  // the twist of the wanted rotation about the hinge's axis
                            const quat turn = detail::ccd_world_rotation(s, g, ju, tiny);
                            T angle = T(2) * std::atan2(axis.dot(turn.vec()), turn.w());
                            if (angle > pi<T>) angle -= T(2) * pi<T>;
                            if (angle < -pi<T>) angle += T(2) * pi<T>;
                            q[d0] += angle;
                        } else {  // the best angle: both arms projected on the hinge's plane
                            const vec3 x = effector_position(s, g);
                            vec3 a = x - s.positions[ju], b = detail::ccd_aim_point(g, x) - s.positions[ju];
                            a -= axis * axis.dot(a);
                            b -= axis * axis.dot(b);
                            if (a.norm() < tiny || b.norm() < tiny) continue;
                            q[d0] += std::atan2(axis.dot(a.cross(b)), a.dot(b));
                        }
                    } else {
                        const quat turn = detail::ccd_world_rotation(s, g, ju, tiny);
                        const quat parent = sk[ju].parent < 0 ? quat::Identity()
                                                              : s.orientations[static_cast<std::size_t>(sk[ju].parent)];
                        const quat local = parent.conjugate() * turn * s.orientations[ju];
                        q.template segment<3>(d0) = to_rotation_vector(local.normalized());
                    }
                    if (params.limits) q = tree.clamp(q);
                }
                if (tree.root_translation() && g.has_position()) {
                    // The root's translation DOFs, last: the step that puts
                    // the effector on its aim point.
                    tree.forward_unchecked(q, s);
                    const vec3 x = effector_position(s, g);
                    q.template head<3>() += detail::ccd_aim_point(g, x) - x;
                    if (params.limits) q = tree.clamp(q);
                }
            }
        }
        return detail::attempt_end{progress.stalled, false};
    });
}

}  // namespace anima
