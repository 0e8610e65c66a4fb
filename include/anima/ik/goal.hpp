// End-effector goals (position, orientation or both for a point fixed to a
// joint), their residuals, and the analytic geometric Jacobian of any set of
// goals with respect to a kinematic tree's DOFs.
#pragma once

#include <anima/core/error.hpp>
#include <anima/rotation/detail/so3.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/rotation/exp_log.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace anima {

enum class ik_goal_kind : unsigned char { position, orientation, pose };

/// A point fixed to a joint (`offset` in the joint's frame, e.g. its End
/// Site) asked to reach a world position, the joint to reach a world
/// orientation, or both. Orientation residuals (radians) are multiplied by
/// `orientation_scale` (a length) so they weigh like positions.
template <class T>
struct ik_goal {
    std::size_t joint = 0;
    Eigen::Matrix<T, 3, 1> offset = Eigen::Matrix<T, 3, 1>::Zero();
    ik_goal_kind kind = ik_goal_kind::position;
    Eigen::Matrix<T, 3, 1> position = Eigen::Matrix<T, 3, 1>::Zero();
    Eigen::Quaternion<T> orientation = Eigen::Quaternion<T>::Identity();
    T weight = T(1);
    T orientation_scale = T(1);

    int rows() const { return kind == ik_goal_kind::pose ? 6 : 3; }
    bool has_position() const { return kind != ik_goal_kind::orientation; }
    bool has_orientation() const { return kind != ik_goal_kind::position; }
};

/// A position goal for joint j (plus a local offset).
template <class T>
ik_goal<T> position_goal(std::size_t joint, const Eigen::Matrix<T, 3, 1>& target,
                         const Eigen::Matrix<T, 3, 1>& offset = Eigen::Matrix<T, 3, 1>::Zero()) {
    ik_goal<T> g;
    g.joint = joint;
    g.offset = offset;
    g.position = target;
    return g;
}

/// An orientation goal for joint j, from any quaternion type the rotation
/// toolkit knows (Eigen::Quaternion, glm::qua...).
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
ik_goal<quat_scalar_t<Q>> orientation_goal(std::size_t joint, const Q& target) {
    using T = quat_scalar_t<Q>;
    using tr = quat_traits<Q>;
    ik_goal<T> g;
    g.joint = joint;
    g.kind = ik_goal_kind::orientation;
    g.orientation = Eigen::Quaternion<T>(tr::w(target), tr::x(target), tr::y(target), tr::z(target));
    return g;
}

/// Both: the point reaches `target` and the joint turns to `orientation`.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
ik_goal<quat_scalar_t<Q>> pose_goal(std::size_t joint, const Eigen::Matrix<quat_scalar_t<Q>, 3, 1>& target,
                                    const Q& orientation, quat_scalar_t<Q> orientation_scale = 1) {
    auto g = orientation_goal(joint, orientation);
    g.kind = ik_goal_kind::pose;
    g.position = target;
    g.orientation_scale = orientation_scale;
    return g;
}

/// Checks goals against a tree: joints exist, values finite, weights and
/// scales positive, orientations non-zero (they are normalised).
template <class T>
void check_goals(const kinematic_tree<T>& tree, std::vector<ik_goal<T>>& goals, const std::string& who) {
    if (goals.empty()) throw invalid_argument(who + ": no goals");
    for (std::size_t i = 0; i < goals.size(); ++i) {
        auto& g = goals[i];
        const std::string at = who + ": goal " + std::to_string(i);
        if (g.joint >= tree.skeleton().size())
            throw invalid_argument(at + ": joint index " + std::to_string(g.joint) + " out of range");
        if (!g.offset.allFinite() || !g.position.allFinite() || !g.orientation.coeffs().allFinite())
            throw invalid_argument(at + " (joint '" + tree.skeleton()[g.joint].name + "'): non-finite target or offset");
        if (!(g.weight > T(0)) || !std::isfinite(g.weight) || !(g.orientation_scale > T(0)) ||
            !std::isfinite(g.orientation_scale))
            throw invalid_argument(at + ": weight and orientation_scale must be positive and finite, got " +
                                   std::to_string(static_cast<double>(g.weight)) + " and " +
                                   std::to_string(static_cast<double>(g.orientation_scale)));
        const T n = g.orientation.norm();
        if (!(n > T(0))) throw invalid_argument(at + ": zero orientation quaternion");
        g.orientation.coeffs() /= n;
    }
}

/// Number of residual rows of a goal set.
template <class T>
int goal_rows(const std::vector<ik_goal<T>>& goals) {
    int m = 0;
    for (const auto& g : goals) m += g.rows();
    return m;
}

/// World position of a goal's point in state s.
template <class T>
Eigen::Matrix<T, 3, 1> effector_position(const ik_state<T>& s, const ik_goal<T>& g) {
    return s.positions[g.joint] + s.orientations[g.joint] * g.offset;
}

/// Unweighted errors of one goal: position distance and orientation angle.
template <class T>
struct goal_error {
    T position = T(0);
    T angle = T(0);
};

/// Weighted residual (target - current) of every goal stacked: 3 rows of
/// position, then 3 of orientation (the rotation vector taking the current
/// orientation to the target, in world axes, times orientation_scale).
/// Fills the unweighted per-goal errors when `errors` is non-null.
template <class T>
void goal_residual(const ik_state<T>& s, const std::vector<ik_goal<T>>& goals, ik_vector<T>& r,
                   std::vector<goal_error<T>>* errors = nullptr) {
    r.resize(goal_rows(goals));
    if (errors) errors->resize(goals.size());
    int row = 0;
    for (std::size_t i = 0; i < goals.size(); ++i) {
        const auto& g = goals[i];
        goal_error<T> e;
        if (g.has_position()) {
            const Eigen::Matrix<T, 3, 1> d = g.position - effector_position(s, g);
            e.position = d.norm();
            r.template segment<3>(row) = g.weight * d;
            row += 3;
        }
        if (g.has_orientation()) {
            const Eigen::Matrix<T, 3, 1> w = to_rotation_vector(Eigen::Quaternion<T>(g.orientation * s.orientations[g.joint].conjugate()));
            e.angle = w.norm();
            r.template segment<3>(row) = g.weight * g.orientation_scale * w;
            row += 3;
        }
        if (errors) (*errors)[i] = e;
    }
}

/// The analytic geometric Jacobian d(effector)/d(q) of the goal set at q,
/// rows as in goal_residual (weights included, sign: d(current)/dq, so the
/// residual changes by -J dq). A rotation DOF with world axis w at joint
/// position p moves a point x by w x (x - p) and turns it by w; the root
/// translation moves it along the axis.
template <class T>
void goal_jacobian(const kinematic_tree<T>& tree, const ik_vector<T>& q, const ik_state<T>& s,
                   const std::vector<ik_goal<T>>& goals, ik_matrix<T>& jac) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    const int m = goal_rows(goals);
    jac.setZero(m, tree.dofs());
    const auto& sk = tree.skeleton();
    int row = 0;
    for (const auto& g : goals) {
        const vec3 x = effector_position(s, g);
        const int prow = g.has_position() ? row : -1;
        const int orow = g.has_orientation() ? row + (g.has_position() ? 3 : 0) : -1;
        const T ow = g.weight * g.orientation_scale;
        for (int j = static_cast<int>(g.joint); j != -1; j = sk[static_cast<std::size_t>(j)].parent) {
            const auto ju = static_cast<std::size_t>(j);
            const int d0 = tree.first_dof(ju);
            if (d0 < 0) continue;
            const auto column = [&](int k, const vec3& w) {
                if (prow >= 0) jac.template block<3, 1>(prow, k) = g.weight * w.cross(x - s.positions[ju]);
                if (orow >= 0) jac.template block<3, 1>(orow, k) = ow * w;
            };
            if (tree.kind(ju) == ik_joint_kind::hinge) {
                column(d0, s.orientations[ju] * tree.hinge_axis(ju));
            } else {
                const Eigen::Matrix<T, 3, 3> axes =
                    s.orientations[ju].toRotationMatrix() * detail::right_jacobian_so3<T>(q.template segment<3>(d0));
                for (int k = 0; k < 3; ++k) column(d0 + k, axes.col(k));
            }
        }
        if (tree.root_translation() && prow >= 0 && tree.is_ancestor(0, g.joint))
            jac.template block<3, 3>(prow, 0) = g.weight * Eigen::Matrix<T, 3, 3>::Identity();
        row += g.rows();
    }
}

/// Convenience: FK plus Jacobian at q.
template <class T>
ik_matrix<T> goal_jacobian(const kinematic_tree<T>& tree, const ik_vector<T>& q, std::vector<ik_goal<T>> goals) {
    check_goals(tree, goals, "anima::goal_jacobian");
    ik_state<T> s;
    tree.forward(q, s);
    ik_matrix<T> jac;
    goal_jacobian(tree, q, s, goals, jac);
    return jac;
}

}  // namespace anima
