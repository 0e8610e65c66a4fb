// Held-out evaluation of IK solvers on real motion: for each frame of a
// held-out block, the effectors' true positions become position goals, the
// root is placed as in that frame, and a solver runs from a start every
// solver shares (one fixed pose, or its own solution of the previous
// frame). Measured: success (every goal within tolerance), the pose
// distance of the solution to the real pose of the frame, its distance to
// the nearest training pose, and time. Also the practitioner's baseline
// start: the training pose whose effectors are nearest the targets.
#pragma once

#include <anima/core/error.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/learned_inverse.hpp>
#include <anima/ik/pose_statistics.hpp>
#include <anima/ik/solve.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/forward_kinematics.hpp>

#include <Eigen/Core>

#include <chrono>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace anima {

/// Where every solver starts on a frame of the block.
enum class ik_start : unsigned char {
    fixed,     ///< the same given pose on every frame
    previous   ///< the solver's own solution of the previous frame (the fixed pose on the first)
};

/// Sums over the solves of one solver; the means are what is reported.
template <class T>
struct ik_evaluation {
    int solves = 0, successes = 0;
    double to_real = 0, to_training = 0, seconds = 0, iterations = 0;
    double success_rate() const { return solves ? double(successes) / solves : 0.0; }
    double mean_to_real() const { return solves ? to_real / solves : 0.0; }
    double mean_to_training() const { return solves ? to_training / solves : 0.0; }
    double ms_per_solve() const { return solves ? 1e3 * seconds / solves : 0.0; }
    double mean_iterations() const { return solves ? iterations / solves : 0.0; }
};

/// Position goals putting each effector where it is in frame f of c.
template <class T>
std::vector<ik_goal<T>> goals_from_frame(const clip<T>& c, std::size_t f, const std::vector<ik_effector<T>>& effectors) {
    const auto truth = forward_kinematics(c, f);
    std::vector<ik_goal<T>> goals;
    for (const auto& e : effectors) {
        const auto j = c.skeleton().index_of(e.joint);
        goals.push_back(position_goal<T>(j, truth.positions[j] + truth.orientations[j] * e.offset, e.offset));
    }
    return goals;
}

/// Runs `solve(tree, goals, q0)` (returning an ik_result or a type derived
/// from it) on frames of c. The tree (fixed root) is copied and based on
/// each frame; success is convergence with every goal within `tolerance`.
template <class T, class Solve>
ik_evaluation<T> evaluate_ik_on_frames(kinematic_tree<T> tree, const clip<T>& c, const std::vector<std::size_t>& frames,
                                       const std::vector<ik_effector<T>>& effectors, const ik_matrix<T>& training,
                                       const ik_vector<T>& start, ik_start mode, T tolerance, Solve&& solve) {
    const std::string who = "anima::evaluate_ik_on_frames";
    tree.check_q(start, who);
    if (frames.empty() || effectors.empty() || !(tolerance > T(0)))
        throw invalid_argument(who + ": needs frames, effectors and a positive tolerance");
    ik_evaluation<T> out;
    ik_vector<T> q0 = start;
    for (const std::size_t f : frames) {
        if (f >= c.frames()) throw invalid_argument(who + ": frame " + std::to_string(f) + " out of range");
        tree.set_base(c, f);
        const auto goals = goals_from_frame(c, f, effectors);
        const auto t0 = std::chrono::steady_clock::now();
        const auto r = solve(static_cast<const kinematic_tree<T>&>(tree), goals, static_cast<const ik_vector<T>&>(q0));
        out.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        ++out.solves;
        out.successes += r.converged() && r.max_position_error <= tolerance;
        out.iterations += r.iterations;
        out.to_real += static_cast<double>(pose_distance<T>(tree, r.q, tree.pose_of(c, f)));
        out.to_training += static_cast<double>(distance_to_nearest_pose<T>(tree, r.q, training));
        if (mode == ik_start::previous) q0 = r.q;
    }
    return out;
}

/// The training pose whose effectors (in the root's frame) are nearest the
/// targets: the start of the nearest-pose baseline.
template <class T>
class nearest_pose_by_effectors {
public:
    nearest_pose_by_effectors(const kinematic_tree<T>& tree, std::vector<ik_effector<T>> effectors, ik_matrix<T> poses)
        : effectors_(std::move(effectors)), poses_(std::move(poses)) {
        const std::string who = "anima::nearest_pose_by_effectors";
        learned_ik_model<T>::check_tree(tree, who);
        if (poses_.rows() != tree.dofs() || poses_.cols() < 1 || !poses_.allFinite())
            throw invalid_argument(who + ": need finite poses of " + std::to_string(tree.dofs()) + " DOFs");
        for (const auto& e : effectors_) joints_.push_back(tree.skeleton().index_of(e.joint));
        reach_.resize(3 * static_cast<Eigen::Index>(joints_.size()), poses_.cols());
        for (Eigen::Index k = 0; k < poses_.cols(); ++k)
            reach_.col(k) = root_frame_effectors<T>(tree, joints_, effectors_, poses_.col(k));
    }
    /// The nearest pose for goals on the effectors (in order) under tree's base.
    ik_vector<T> operator()(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals) const {
        if (goals.size() != joints_.size())
            throw invalid_argument("anima::nearest_pose_by_effectors: " + std::to_string(goals.size()) + " goals for " +
                                   std::to_string(joints_.size()) + " effectors");
        ik_state<T> s;
        tree.forward_unchecked(poses_.col(0), s);
        const auto root_inv = s.orientations[0].conjugate();
        ik_vector<T> target(reach_.rows());
        for (std::size_t i = 0; i < goals.size(); ++i)
            target.template segment<3>(3 * static_cast<Eigen::Index>(i)) = root_inv * (goals[i].position - s.positions[0]);
        Eigen::Index best = 0;
        (reach_.colwise() - target).colwise().squaredNorm().minCoeff(&best);
        return poses_.col(best);
    }

private:
    std::vector<ik_effector<T>> effectors_;
    ik_matrix<T> poses_, reach_;
    std::vector<std::size_t> joints_;
};

}  // namespace anima
