// A kinematic tree over a skeleton: which joints move and how (ball, hinge
// or fixed), an optional root translation, joint limits, and the vector of
// degrees of freedom (DOFs) the IK solvers work on. Poses convert to and
// from a clip frame, so a solved pose can be written back to BVH.
//
// DOF parameterisation (absolute, so limits, mocap statistics and learned
// inverses all see the same numbers for the same pose):
//   ball joint   3 DOFs v, local rotation = exp(v) (rotation vector, radians)
//   hinge joint  1 DOF t, local rotation = rotation by t about the joint's axis
//   fixed joint  0 DOFs, local rotation taken from the base pose
//   root translation (optional) 3 DOFs, the root's position
// Joints that do not move, and the root when its translation is not a DOF,
// take their values from the base pose (set_base).
#pragma once

#include <anima/core/constants.hpp>
#include <anima/core/eigen_types.hpp>
#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/rotation/exp_log.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace anima {

/// The IK names of the shared dynamic-size aliases (core/eigen_types.hpp).
template <class T>
using ik_vector = vector_x<T>;
template <class T>
using ik_matrix = matrix_x<T>;

namespace detail {
template <class T>
struct non_deduced {
    using type = T;
};
}  // namespace detail
/// A DOF vector parameter that accepts Eigen expressions (the scalar is
/// deduced from the tree, not from the expression).
template <class T>
using ik_vector_arg = typename detail::non_deduced<ik_vector<T>>::type;

enum class ik_joint_kind : unsigned char { fixed, hinge, ball };

/// Global positions and orientations of every skeleton joint for one DOF
/// vector (reused between calls: no allocation once sized).
template <class T>
struct ik_state {
    std::vector<Eigen::Matrix<T, 3, 1>> positions;
    std::vector<Eigen::Quaternion<T>> orientations;
};

template <class T>
class kinematic_tree {
public:
    using vector3 = Eigen::Matrix<T, 3, 1>;
    using quaternion = Eigen::Quaternion<T>;

    /// Every joint with rotation channels becomes a ball joint, the others
    /// are fixed; no root translation; no limits; base pose = rest pose.
    explicit kinematic_tree(anima::skeleton<T> sk) : skeleton_(std::move(sk)) {
        if (skeleton_.empty()) throw invalid_argument("anima::kinematic_tree: empty skeleton");
        const std::size_t n = skeleton_.size();
        kind_.assign(n, ik_joint_kind::fixed);
        axis_.assign(n, vector3::UnitX());
        lower_.assign(n, vector3::Constant(-std::numeric_limits<T>::infinity()));
        upper_.assign(n, vector3::Constant(std::numeric_limits<T>::infinity()));
        base_rotation_.assign(n, quaternion::Identity());
        base_translation_.resize(n);
        for (std::size_t j = 0; j < n; ++j) {
            base_translation_[j] = skeleton_[j].offset;
            if (skeleton_.has_rotation_channels(j)) kind_[j] = ik_joint_kind::ball;
        }
        renumber();
    }

    /// Only the joints on the path from `first` down to `last` (both
    /// included) move, as ball joints; everything else is fixed.
    static kinematic_tree chain(const anima::skeleton<T>& sk, std::string_view first, std::string_view last) {
        kinematic_tree t(sk);
        const std::size_t a = sk.index_of(first), b = sk.index_of(last);
        std::vector<bool> on_path(sk.size(), false);
        int j = static_cast<int>(b);
        for (; j != -1 && j != static_cast<int>(a); j = sk[static_cast<std::size_t>(j)].parent)
            on_path[static_cast<std::size_t>(j)] = true;
        if (j == -1)
            throw invalid_argument("anima::kinematic_tree::chain: joint '" + std::string(first) +
                                   "' is not an ancestor of '" + std::string(last) + "'");
        on_path[a] = true;
        for (std::size_t k = 0; k < sk.size(); ++k) t.kind_[k] = on_path[k] ? ik_joint_kind::ball : ik_joint_kind::fixed;
        t.renumber();
        return t;
    }

    const anima::skeleton<T>& skeleton() const noexcept { return skeleton_; }
    int dofs() const noexcept { return dofs_; }
    ik_joint_kind kind(std::size_t j) const { return kind_.at(j); }
    /// First DOF of joint j (-1 for a fixed joint); the root translation,
    /// when it is a DOF, takes DOFs 0..2.
    int first_dof(std::size_t j) const { return first_dof_.at(j); }
    bool root_translation() const noexcept { return root_translation_; }
    /// The skeleton joint DOF k belongs to.
    std::size_t joint_of_dof(int k) const { return dof_joint_.at(static_cast<std::size_t>(k)); }
    /// "LeftArm.x" (ball), "LeftForeArm.hinge", "Hips.tx" (root translation).
    std::string dof_name(int k) const {
        const std::size_t j = joint_of_dof(k);
        const int local = k - (root_translation_ && k < 3 ? 0 : first_dof_[j]);
        if (root_translation_ && k < 3) return skeleton_[0].name + (k == 0 ? ".tx" : k == 1 ? ".ty" : ".tz");
        if (kind_[j] == ik_joint_kind::hinge) return skeleton_[j].name + ".hinge";
        return skeleton_[j].name + (local == 0 ? ".x" : local == 1 ? ".y" : ".z");
    }

    void set_ball(std::size_t j) { set_kind(j, ik_joint_kind::ball, "set_ball"); }
    void set_fixed(std::size_t j) { set_kind(j, ik_joint_kind::fixed, "set_fixed"); }
    /// A one-DOF joint turning about `axis` (in the joint's own frame,
    /// normalised here) between lower and upper radians.
    void set_hinge(std::size_t j, const vector3& axis, T lower = -std::numeric_limits<T>::infinity(),
                   T upper = std::numeric_limits<T>::infinity()) {
        const T n = axis.norm();
        if (!(n > T(0)) || !std::isfinite(n))
            throw invalid_argument("anima::kinematic_tree::set_hinge: joint '" + name(j) +
                                   "': axis must be non-zero and finite");
        check_range(lower, upper, "set_hinge", j);
        set_kind(j, ik_joint_kind::hinge, "set_hinge");
        axis_[j] = axis / n;
        lower_[j] = vector3::Constant(lower);
        upper_[j] = vector3::Constant(upper);
        renumber();
    }
    /// Box limits on a ball joint's rotation vector components (radians).
    void set_ball_limits(std::size_t j, const vector3& lower, const vector3& upper) {
        if (kind_.at(j) != ik_joint_kind::ball)
            throw invalid_argument("anima::kinematic_tree::set_ball_limits: joint '" + name(j) + "' is not a ball joint");
        for (int k = 0; k < 3; ++k) check_range(lower[k], upper[k], "set_ball_limits", j);
        lower_[j] = lower;
        upper_[j] = upper;
        renumber();
    }
    void set_root_translation(bool on) {
        root_translation_ = on;
        renumber();
    }

    /// Takes fixed joints' rotations, joint translations and (when it is not
    /// a DOF) the root position from frame f of a clip with this skeleton.
    void set_base(const clip<T>& c, std::size_t f) {
        if (c.skeleton() != skeleton_)
            throw invalid_argument("anima::kinematic_tree::set_base: the clip's skeleton differs from the tree's");
        if (f >= c.frames())
            throw invalid_argument("anima::kinematic_tree::set_base: frame " + std::to_string(f) + " out of range (" +
                                   std::to_string(c.frames()) + " frames)");
        for (std::size_t j = 0; j < skeleton_.size(); ++j) {
            base_rotation_[j] = c.rotation(f, j);
            base_translation_[j] = c.translation(f, j);
        }
    }
    const quaternion& base_rotation(std::size_t j) const { return base_rotation_.at(j); }
    const vector3& base_translation(std::size_t j) const { return base_translation_.at(j); }

    /// Per-DOF limits (-inf / +inf where unlimited).
    const ik_vector<T>& lower() const noexcept { return lower_dof_; }
    const ik_vector<T>& upper() const noexcept { return upper_dof_; }
    bool within_limits(const ik_vector<T>& q, T slack = T(0)) const {
        return (q.array() >= lower_dof_.array() - slack).all() && (q.array() <= upper_dof_.array() + slack).all();
    }
    ik_vector<T> clamp(const ik_vector<T>& q) const { return q.cwiseMax(lower_dof_).cwiseMin(upper_dof_); }
    /// clamp(q) in place, allocating nothing.
    void clamp_in_place(ik_vector<T>& q) const { q = q.cwiseMax(lower_dof_).cwiseMin(upper_dof_); }

    /// Ball joints without limits whose rotation vector has grown past pi
    /// are mapped to the equal rotation of angle below pi (the chart's
    /// derivative degenerates at 2 pi); limited ones are left alone.
    void wrap(ik_vector<T>& q) const {
        for (std::size_t j = 0; j < skeleton_.size(); ++j) {
            if (kind_[j] != ik_joint_kind::ball || std::isfinite(lower_[j][0]) || std::isfinite(upper_[j][0]))
                continue;
            auto v = q.template segment<3>(first_dof_[j]);
            const T angle = v.norm();
            if (angle > pi<T>) v *= (angle - T(2) * pi<T>) / angle;
        }
    }

    /// Local rotation of joint j under the DOF vector q.
    quaternion local_rotation(const ik_vector<T>& q, std::size_t j) const {
        switch (kind_[j]) {
            case ik_joint_kind::ball:
                return from_rotation_vector<quaternion>(q.template segment<3>(first_dof_[j]));
            case ik_joint_kind::hinge:
                return quaternion(Eigen::AngleAxis<T>(q[first_dof_[j]], axis_[j]));
            default:
                return base_rotation_[j];
        }
    }
    const vector3& hinge_axis(std::size_t j) const { return axis_.at(j); }

    /// Forward kinematics of q into s. q must have dofs() finite entries.
    void forward(const ik_vector<T>& q, ik_state<T>& s) const {
        check_q(q, "anima::kinematic_tree::forward");
        forward_unchecked(q, s);
    }
    /// forward() without the argument check, for the solvers' inner loops.
    void forward_unchecked(const ik_vector<T>& q, ik_state<T>& s) const {
        const std::size_t n = skeleton_.size();
        s.positions.resize(n);
        s.orientations.resize(n);
        for (std::size_t j = 0; j < n; ++j) {
            const quaternion local = local_rotation(q, j);
            const int p = skeleton_[j].parent;
            if (p < 0) {
                s.positions[j] = (j == 0 && root_translation_) ? vector3(q.template head<3>()) : base_translation_[j];
                s.orientations[j] = local;
            } else {
                const auto pp = static_cast<std::size_t>(p);
                s.positions[j] = s.positions[pp] + s.orientations[pp] * base_translation_[j];
                s.orientations[j] = s.orientations[pp] * local;
            }
        }
    }

    /// The DOF vector of frame f of a clip with this skeleton: ball joints
    /// take the rotation vector of their local rotation (angle <= pi), hinge
    /// joints the twist angle of their rotation about the axis (a rotation
    /// off the axis cannot be represented and is dropped). Not clamped.
    ik_vector<T> pose_of(const clip<T>& c, std::size_t f) const {
        ik_vector<T> q;
        pose_of(c, f, q);
        return q;
    }
    /// pose_of into q, which is resized only when its size differs.
    void pose_of(const clip<T>& c, std::size_t f, ik_vector<T>& q) const {
        if (c.skeleton() != skeleton_)
            throw invalid_argument("anima::kinematic_tree::pose_of: the clip's skeleton differs from the tree's");
        if (f >= c.frames())
            throw invalid_argument("anima::kinematic_tree::pose_of: frame " + std::to_string(f) + " out of range (" +
                                   std::to_string(c.frames()) + " frames)");
        q.setZero(dofs_);  // keeps q's storage when it has the size
        if (root_translation_) q.template head<3>() = c.translation(f, 0);
        for (std::size_t j = 0; j < skeleton_.size(); ++j) {
            const quaternion& r = c.rotation(f, j);
            if (kind_[j] == ik_joint_kind::ball) {
                q.template segment<3>(first_dof_[j]) = to_rotation_vector(r);
            } else if (kind_[j] == ik_joint_kind::hinge) {
                const T along = r.vec().dot(axis_[j]);
                T angle = T(2) * std::atan2(along, r.w());
                if (angle > pi<T>) angle -= T(2) * pi<T>;
                if (angle < -pi<T>) angle += T(2) * pi<T>;
                q[first_dof_[j]] = angle;
            }
        }
    }

    /// Writes q into frame f of c: moving joints' rotations, the root
    /// position when it is a DOF. Other values of the frame are kept.
    void write_pose(const ik_vector<T>& q, clip<T>& c, std::size_t f) const {
        check_q(q, "anima::kinematic_tree::write_pose");
        if (c.skeleton() != skeleton_)
            throw invalid_argument("anima::kinematic_tree::write_pose: the clip's skeleton differs from the tree's");
        for (std::size_t j = 0; j < skeleton_.size(); ++j)
            if (kind_[j] != ik_joint_kind::fixed) c.set_rotation(f, j, local_rotation(q, j));
        if (root_translation_) {
            if (skeleton_.translation_slot(0) < 0)
                throw invalid_argument("anima::kinematic_tree::write_pose: root '" + skeleton_[0].name +
                                       "' has no position channels to take the translation");
            c.set_translation(f, 0, q.template head<3>());
        }
    }

    /// Throws anima::invalid_argument unless q has dofs() finite entries.
    void check_q(const ik_vector<T>& q, std::string_view who) const {
        if (q.size() != dofs_)
            throw invalid_argument(std::string(who) + ": pose has " + std::to_string(q.size()) + " DOFs, the tree has " +
                                   std::to_string(dofs_));
        for (int k = 0; k < dofs_; ++k)
            if (!std::isfinite(q[k]))
                throw invalid_argument(std::string(who) + ": DOF " + std::to_string(k) + " (" + dof_name(k) + ") is not finite");
    }

    /// True when joint a is b or an ancestor of b.
    bool is_ancestor(std::size_t a, std::size_t b) const {
        for (int j = static_cast<int>(b); j != -1; j = skeleton_[static_cast<std::size_t>(j)].parent)
            if (static_cast<std::size_t>(j) == a) return true;
        return false;
    }

private:
    std::string name(std::size_t j) const { return skeleton_.at(j).name; }
    void set_kind(std::size_t j, ik_joint_kind k, const char* who) {
        (void)skeleton_.at(j);
        (void)who;
        kind_[j] = k;
        lower_[j] = vector3::Constant(-std::numeric_limits<T>::infinity());
        upper_[j] = vector3::Constant(std::numeric_limits<T>::infinity());
        renumber();
    }
    void check_range(T lo, T hi, const char* who, std::size_t j) const {
        if (std::isnan(lo) || std::isnan(hi) || lo > hi || lo == std::numeric_limits<T>::infinity() ||
            hi == -std::numeric_limits<T>::infinity())
            throw invalid_argument(std::string("anima::kinematic_tree::") + who + ": joint '" + name(j) +
                                   "': limits [" + detail::argument_text(lo) + ", " +
                                   detail::argument_text(hi) + "] are not a range");
    }
    void renumber() {
        const std::size_t n = skeleton_.size();
        first_dof_.assign(n, -1);
        dof_joint_.clear();
        int k = 0;
        if (root_translation_) {
            k = 3;
            dof_joint_.assign(3, 0);
        }
        for (std::size_t j = 0; j < n; ++j) {
            const int d = kind_[j] == ik_joint_kind::ball ? 3 : kind_[j] == ik_joint_kind::hinge ? 1 : 0;
            if (d == 0) continue;
            first_dof_[j] = k;
            k += d;
            for (int i = 0; i < d; ++i) dof_joint_.push_back(j);
        }
        dofs_ = k;
        lower_dof_ = ik_vector<T>::Constant(k, -std::numeric_limits<T>::infinity());
        upper_dof_ = ik_vector<T>::Constant(k, std::numeric_limits<T>::infinity());
        for (std::size_t j = 0; j < n; ++j) {
            if (first_dof_[j] < 0) continue;
            const int d = kind_[j] == ik_joint_kind::ball ? 3 : 1;
            for (int i = 0; i < d; ++i) {
                lower_dof_[first_dof_[j] + i] = lower_[j][i];
                upper_dof_[first_dof_[j] + i] = upper_[j][i];
            }
        }
    }

    anima::skeleton<T> skeleton_;
    std::vector<ik_joint_kind> kind_;
    std::vector<vector3> axis_, lower_, upper_;
    std::vector<quaternion> base_rotation_;
    std::vector<vector3> base_translation_;
    std::vector<int> first_dof_;
    std::vector<std::size_t> dof_joint_;
    ik_vector<T> lower_dof_, upper_dof_;
    bool root_translation_ = false;
    int dofs_ = 0;
};

}  // namespace anima
