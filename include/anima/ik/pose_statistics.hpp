// Poses of real clips in a tree's DOF space, and what they say: Komura's
// per-DOF weights from mocap variance (DOFs that move a lot in real motion
// are cheap for the weighted inverse) and the naturalness measure (distance
// of a pose to the nearest training pose).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/nondeduced.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/motion/clip.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace anima {

/// DOF vectors of frames [first, last) of a clip, one column per frame.
template <class T>
ik_matrix<T> clip_poses(const kinematic_tree<T>& tree, const clip<T>& c, std::size_t first = 0,
                        std::size_t last = static_cast<std::size_t>(-1)) {
    last = std::min(last, c.frames());
    if (first >= last)
        throw invalid_argument("anima::clip_poses: frame range [" + std::to_string(first) + ", " +
                               std::to_string(last) + ") is empty");
    ik_matrix<T> out(tree.dofs(), static_cast<Eigen::Index>(last - first));
    for (std::size_t f = first; f < last; ++f) out.col(static_cast<Eigen::Index>(f - first)) = tree.pose_of(c, f);
    return out;
}

/// Komura's weighting matrix, diagonal, from poses (columns): weight_k =
/// mean variance / variance_k, with variances floored at `floor` times the
/// mean so a DOF that never moved in the data is expensive, not frozen.
template <class T>
ik_vector<T> dof_weights_from_poses(const ik_matrix<T>& poses, nondeduced_t<T> floor = T(0.01)) {
    if (poses.cols() < 2 || poses.rows() == 0)
        throw invalid_argument("anima::dof_weights_from_poses: need at least 2 poses of at least 1 DOF, got " +
                               std::to_string(poses.cols()) + " of " + std::to_string(poses.rows()));
    if (!poses.allFinite()) throw invalid_argument("anima::dof_weights_from_poses: non-finite pose");
    if (!(floor > T(0)) || !std::isfinite(floor))
        throw invalid_argument("anima::dof_weights_from_poses: floor is " + detail::argument_text(floor));
    const ik_vector<T> mean = poses.rowwise().mean();
    const ik_vector<T> var = (poses.colwise() - mean).array().square().rowwise().sum() / T(poses.cols() - 1);
    T avg = var.mean();
    if (!(avg > T(0))) return ik_vector<T>::Ones(poses.rows());  // nothing moved: no preference
    return var.cwiseMax(floor * avg).cwiseInverse() * avg;
}

/// Distance between two poses of a tree: the root-mean-square over moving
/// joints of the angle between their local rotations (radians), combined
/// with the root translation difference divided by `length` when the root
/// translation is a DOF (pass the body scale).
template <class T>
T pose_distance(const kinematic_tree<T>& tree, const ik_vector<T>& a, const ik_vector<T>& b,
                nondeduced_t<T> length = T(1)) {
    T sum = T(0);
    int count = 0;
    for (std::size_t j = 0; j < tree.skeleton().size(); ++j) {
        if (tree.kind(j) == ik_joint_kind::fixed) continue;
        const T d = tree.local_rotation(a, j).angularDistance(tree.local_rotation(b, j));
        sum += d * d;
        ++count;
    }
    if (tree.root_translation()) {
        sum += (a.template head<3>() - b.template head<3>()).squaredNorm() / (length * length);
        ++count;
    }
    return count ? std::sqrt(sum / T(count)) : T(0);
}

/// Naturalness of a pose: its pose_distance to the nearest of the training
/// poses (columns). Smaller is more natural.
template <class T>
T distance_to_nearest_pose(const kinematic_tree<T>& tree, const ik_vector<T>& q, const ik_matrix<T>& poses,
                           nondeduced_t<T> length = T(1)) {
    if (poses.cols() == 0 || poses.rows() != tree.dofs())
        throw invalid_argument("anima::distance_to_nearest_pose: " + std::to_string(poses.cols()) + " poses of " +
                               std::to_string(poses.rows()) + " DOFs for a tree of " + std::to_string(tree.dofs()));
    T best = std::numeric_limits<T>::infinity();
    for (Eigen::Index c = 0; c < poses.cols(); ++c)
        best = std::min(best, pose_distance<T>(tree, q, poses.col(c), length));
    return best;
}

}  // namespace anima
