// End-effector goals (position, orientation or both for a point fixed to a
// joint), their residuals, and the analytic geometric Jacobian of any set of
// goals with respect to a kinematic tree's DOFs.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/rotation/detail/so3.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/rotation/exp_log.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <glm/ext/vector_double3.hpp>
#include <glm/ext/vector_float3.hpp>

#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace anima {

/// position / orientation / pose: the point reaches a position, the joint
/// an orientation, or both. Zhao and Badler's constraints on the point:
/// `line` (on the line through `position` along `direction`), `plane` (on
/// the plane through `position` with normal `direction`), `half_space` (on
/// the side of that plane the normal points to, e.g. a foot above the
/// floor). `aim`: the joint-local `axis` points along the world `direction`.
enum class ik_goal_kind : unsigned char { position, orientation, pose, line, plane, half_space, aim };

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
    Eigen::Matrix<T, 3, 1> direction = Eigen::Matrix<T, 3, 1>::UnitZ();  ///< line, normal or aim direction (world)
    Eigen::Matrix<T, 3, 1> axis = Eigen::Matrix<T, 3, 1>::UnitZ();       ///< aim: the axis in the joint's frame
    T weight = T(1);
    T orientation_scale = T(1);

    int rows() const { return kind == ik_goal_kind::pose ? 6 : 3; }
    /// Three rows on the point's position (projected for line, plane, half-space).
    bool has_position() const { return kind != ik_goal_kind::orientation && kind != ik_goal_kind::aim; }
    /// Three rows on the joint's orientation (for aim: the axis's direction).
    bool has_orientation() const {
        return kind == ik_goal_kind::orientation || kind == ik_goal_kind::pose || kind == ik_goal_kind::aim;
    }
    bool constrains_direction() const {
        return kind == ik_goal_kind::line || kind == ik_goal_kind::plane || kind == ik_goal_kind::half_space ||
               kind == ik_goal_kind::aim;
    }
};

namespace detail {

template <class T>
ik_goal<T> point_constraint(ik_goal_kind kind, std::size_t joint, const Eigen::Matrix<T, 3, 1>& point,
                            const Eigen::Matrix<T, 3, 1>& direction, const Eigen::Matrix<T, 3, 1>& offset) {
    ik_goal<T> g;
    g.kind = kind;
    g.joint = joint;
    g.offset = offset;
    g.position = point;
    g.direction = direction;
    return g;
}

}  // namespace detail

/// The point (joint plus local offset) on the line through `point` along `direction`.
template <class T>
ik_goal<T> line_goal(std::size_t joint, const Eigen::Matrix<T, 3, 1>& point, const Eigen::Matrix<T, 3, 1>& direction,
                     const Eigen::Matrix<T, 3, 1>& offset = Eigen::Matrix<T, 3, 1>::Zero()) {
    return detail::point_constraint(ik_goal_kind::line, joint, point, direction, offset);
}

/// The point on the plane through `point` with normal `normal`.
template <class T>
ik_goal<T> plane_goal(std::size_t joint, const Eigen::Matrix<T, 3, 1>& point, const Eigen::Matrix<T, 3, 1>& normal,
                      const Eigen::Matrix<T, 3, 1>& offset = Eigen::Matrix<T, 3, 1>::Zero()) {
    return detail::point_constraint(ik_goal_kind::plane, joint, point, normal, offset);
}

/// The point on the side of the plane through `point` that `normal` points
/// to (normal . (x - point) >= 0); no pull while it is there.
template <class T>
ik_goal<T> half_space_goal(std::size_t joint, const Eigen::Matrix<T, 3, 1>& point, const Eigen::Matrix<T, 3, 1>& normal,
                           const Eigen::Matrix<T, 3, 1>& offset = Eigen::Matrix<T, 3, 1>::Zero()) {
    return detail::point_constraint(ik_goal_kind::half_space, joint, point, normal, offset);
}

/// The joint-local `axis` of joint j points along the world `direction`
/// (a head looking at something, a hand's palm turned down); rotation about
/// the axis is free.
template <class T>
ik_goal<T> aim_goal(std::size_t joint, const Eigen::Matrix<T, 3, 1>& axis, const Eigen::Matrix<T, 3, 1>& direction) {
    ik_goal<T> g;
    g.kind = ik_goal_kind::aim;
    g.joint = joint;
    g.axis = axis;
    g.direction = direction;
    return g;
}

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

// The same goals from GLM vectors (glm::vec3, glm::dvec3): a GLM program
// builds its goals from the vectors it already has. The scalar type is the
// vectors'; the goal holds Eigen vectors, as the solvers do.
namespace detail {

template <class T, glm::qualifier P>
Eigen::Matrix<T, 3, 1> eigen_vector(const glm::vec<3, T, P>& v) {
    return {v.x, v.y, v.z};
}

}  // namespace detail

template <class T, glm::qualifier P>
ik_goal<T> position_goal(std::size_t joint, const glm::vec<3, T, P>& target,
                         const glm::vec<3, T, P>& offset = glm::vec<3, T, P>(T(0))) {
    return position_goal(joint, detail::eigen_vector(target), detail::eigen_vector(offset));
}

template <class T, glm::qualifier P>
ik_goal<T> line_goal(std::size_t joint, const glm::vec<3, T, P>& point, const glm::vec<3, T, P>& direction,
                     const glm::vec<3, T, P>& offset = glm::vec<3, T, P>(T(0))) {
    return line_goal(joint, detail::eigen_vector(point), detail::eigen_vector(direction), detail::eigen_vector(offset));
}

template <class T, glm::qualifier P>
ik_goal<T> plane_goal(std::size_t joint, const glm::vec<3, T, P>& point, const glm::vec<3, T, P>& normal,
                      const glm::vec<3, T, P>& offset = glm::vec<3, T, P>(T(0))) {
    return plane_goal(joint, detail::eigen_vector(point), detail::eigen_vector(normal), detail::eigen_vector(offset));
}

template <class T, glm::qualifier P>
ik_goal<T> half_space_goal(std::size_t joint, const glm::vec<3, T, P>& point, const glm::vec<3, T, P>& normal,
                           const glm::vec<3, T, P>& offset = glm::vec<3, T, P>(T(0))) {
    return half_space_goal(joint, detail::eigen_vector(point), detail::eigen_vector(normal),
                           detail::eigen_vector(offset));
}

template <class T, glm::qualifier P>
ik_goal<T> aim_goal(std::size_t joint, const glm::vec<3, T, P>& axis, const glm::vec<3, T, P>& direction) {
    return aim_goal(joint, detail::eigen_vector(axis), detail::eigen_vector(direction));
}

/// A pose goal with a GLM target and any quaternion type of its scalar.
template <class Q, glm::qualifier P, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
ik_goal<quat_scalar_t<Q>> pose_goal(std::size_t joint, const glm::vec<3, quat_scalar_t<Q>, P>& target,
                                    const Q& orientation, quat_scalar_t<Q> orientation_scale = 1) {
    return pose_goal(joint, detail::eigen_vector(target), orientation, orientation_scale);
}

/// Checks goals against a tree: the tree has a free DOF, joints exist, values finite (and small
/// enough that their weighted squared lengths are), weights and scales
/// positive, orientations non-zero (they are normalised).
template <class T>
void check_goals(const kinematic_tree<T>& tree, std::vector<ik_goal<T>>& goals, std::string_view who) {
    if (goals.empty()) throw invalid_argument(std::string(who) + ": no goals");
    if (tree.dofs() == 0)
        throw invalid_argument(std::string(who) + ": the tree has no free DOF (every joint is fixed): nothing can move");
    // The messages are built only on failure: a check that passes allocates nothing.
    const auto at = [&](std::size_t i) { return std::string(who) + ": goal " + std::to_string(i); };
    for (std::size_t i = 0; i < goals.size(); ++i) {
        auto& g = goals[i];
        if (g.joint >= tree.skeleton().size())
            throw invalid_argument(at(i) + ": joint index " + std::to_string(g.joint) + " out of range");
        if (!g.offset.allFinite() || !g.position.allFinite() || !g.orientation.coeffs().allFinite())
            throw invalid_argument(at(i) + " (joint '" + tree.skeleton()[g.joint].name +
                                   "'): non-finite target or offset");
        if (!(g.weight > T(0)) || !std::isfinite(g.weight) || !(g.orientation_scale > T(0)) ||
            !std::isfinite(g.orientation_scale))
            throw invalid_argument(at(i) + ": weight and orientation_scale must be positive and finite, got " +
                                   detail::argument_text(g.weight) + " and " +
                                   detail::argument_text(g.orientation_scale));
        // Squared distances and weighted residuals must stay finite: a target
        // at 1e300 would give an infinite error rather than a solve.
        if (!std::isfinite((g.position.squaredNorm() + g.offset.squaredNorm()) * g.weight * g.weight))
            throw invalid_argument(at(i) + " (joint '" + tree.skeleton()[g.joint].name +
                                   "'): target or offset too far out: its weighted squared length overflows");
        const T n = g.orientation.norm();
        if (!(n > T(0))) throw invalid_argument(at(i) + ": zero orientation quaternion");
        g.orientation.coeffs() /= n;
        if (g.constrains_direction()) {
            const T dn = g.direction.norm(), an = g.axis.norm();
            if (!(dn > T(0)) || !std::isfinite(dn) || !(an > T(0)) || !std::isfinite(an))
                throw invalid_argument(at(i) + " (joint '" + tree.skeleton()[g.joint].name +
                                       "'): the direction (line, normal or aim) and the aim axis must be finite and "
                                       "non-zero");
            g.direction /= dn;
            g.axis /= an;
        }
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

namespace detail {

/// The projection applied to a point goal's residual (target - x): identity
/// for a position, onto the plane normal to the line for a line, onto the
/// normal for a plane, and for a half-space onto the normal while the point
/// is on the wrong side, zero otherwise.
template <class T>
Eigen::Matrix<T, 3, 3> position_projection(const ik_goal<T>& g, const Eigen::Matrix<T, 3, 1>& x) {
    using mat3 = Eigen::Matrix<T, 3, 3>;
    const Eigen::Matrix<T, 3, 1>& d = g.direction;
    switch (g.kind) {
        case ik_goal_kind::line: return mat3::Identity() - d * d.transpose();
        case ik_goal_kind::plane: return d * d.transpose();
        case ik_goal_kind::half_space: return d.dot(x - g.position) < T(0) ? mat3(d * d.transpose()) : mat3(mat3::Zero());
        default: return mat3::Identity();
    }
}

}  // namespace detail

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
            const Eigen::Matrix<T, 3, 1> d = detail::position_projection(g, effector_position(s, g)) *
                                             (g.position - effector_position(s, g));
            e.position = d.norm();
            r.template segment<3>(row) = g.weight * d;
            row += 3;
        }
        if (g.kind == ik_goal_kind::aim) {
            const Eigen::Matrix<T, 3, 1> u = s.orientations[g.joint] * g.axis;
            e.angle = std::atan2(u.cross(g.direction).norm(), u.dot(g.direction));
            r.template segment<3>(row) = g.weight * g.orientation_scale * (g.direction - u);
            row += 3;
        } else if (g.has_orientation()) {
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
        const Eigen::Matrix<T, 3, 3> proj = detail::position_projection(g, x);
        const vec3 u = s.orientations[g.joint] * g.axis;  // aim: the axis in world
        const bool aim = g.kind == ik_goal_kind::aim;
        const int prow = g.has_position() ? row : -1;
        const int orow = g.has_orientation() ? row + (g.has_position() ? 3 : 0) : -1;
        const T ow = g.weight * g.orientation_scale;
        for (int j = static_cast<int>(g.joint); j != -1; j = sk[static_cast<std::size_t>(j)].parent) {
            const auto ju = static_cast<std::size_t>(j);
            const int d0 = tree.first_dof(ju);
            if (d0 < 0) continue;
            const auto column = [&](int k, const vec3& w) {
                if (prow >= 0) jac.template block<3, 1>(prow, k) = g.weight * (proj * w.cross(x - s.positions[ju]));
                if (orow >= 0) jac.template block<3, 1>(orow, k) = aim ? vec3(ow * w.cross(u)) : vec3(ow * w);
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
            jac.template block<3, 3>(prow, 0) = g.weight * proj;
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
