// Inverse kinematics over frames of a clip: per-frame goals, each frame
// warm-started from the solution of the frame before and pulled toward its
// own recorded pose in the null space, so that an edit (a hand moved over a
// range, a foot held in place) changes the motion smoothly and no more than
// the goals ask.
#pragma once

#include <anima/core/error.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/solve.hpp>
#include <anima/motion/clip.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace anima {

/// The goals of one frame.
template <class T>
struct frame_goals {
    std::size_t frame = 0;
    std::vector<ik_goal<T>> goals;
};

template <class T>
struct clip_ik_params {
    /// Per-frame solver settings. null_space is set per frame from pose_pull.
    ik_params<T> ik;
    /// Gain of the null-space pull toward each frame's recorded pose: the
    /// DOFs the goals do not need stay near the recording (0: no pull).
    T pose_pull = T(0.2);
    /// Start a frame from its recorded pose plus the previous frame's
    /// correction (solution minus recorded pose) when the two are
    /// consecutive, else from the recorded pose alone. Carrying the
    /// correction rather than the previous pose keeps the recorded motion of
    /// the DOFs the goals do not move.
    bool warm_start = true;
    /// Called after each solved frame with (frames done, frames in all).
    std::function<void(std::size_t, std::size_t)> progress;
};

template <class T>
struct clip_ik_result {
    clip<T> edited;  ///< the input with the solved frames replaced
    std::vector<std::size_t> frames;  ///< the solved frames, ascending
    std::vector<ik_result<T>> results;  ///< one per solved frame
    std::size_t converged_frames = 0;
    T largest_error = T(0);  ///< largest position error over all frames and goals
    int iterations = 0;  ///< over all frames
    /// Largest frame-to-frame change of a joint's rotation (radians) from the
    /// first solved frame to the frame after the last, before and after: how
    /// much the edit roughened the motion.
    T max_joint_step_before = T(0), max_joint_step_after = T(0);
};

/// Largest change of any joint's rotation (radians) between consecutive
/// frames of c from frame `first` to frame `last` (both clamped to the clip).
template <class T>
T max_joint_step(const clip<T>& c, std::size_t first, std::size_t last) {
    T step = T(0);
    if (c.frames() < 2) return step;
    last = std::min(last, c.frames() - 1);
    for (std::size_t f = std::max<std::size_t>(first, 1); f <= last; ++f)
        for (std::size_t j = 0; j < c.joints(); ++j)
            step = std::max(step, c.rotation(f, j).angularDistance(c.rotation(f - 1, j)));
    return step;
}

/// Solves the goals frame by frame on a copy of c and writes each solution
/// into it. `solve` is any IK solver in the form
///   ik_result<T> solve(const kinematic_tree<T>&, const
///   std::vector<ik_goal<T>>&,
///                      const ik_vector<T>& start, const ik_params<T>&)
/// (solve_ik_with adapts the library's solvers). The tree must be built on
/// c's skeleton; it is copied and based on each frame in turn (fixed joints
/// and a root that is not a DOF follow the recording). Frames must be
/// ascending, distinct and inside the clip, each with at least one goal.
template <class T, class Solve>
clip_ik_result<T> solve_clip_ik(kinematic_tree<T> tree, const clip<T>& c, const std::vector<frame_goals<T>>& goals,
                                Solve&& solve, const clip_ik_params<T>& params = {}) {
    const std::string who = "anima::solve_clip_ik";
    if (c.skeleton() != tree.skeleton()) throw invalid_argument(who + ": the clip's skeleton differs from the tree's");
    if (!(params.pose_pull >= T(0)) || !std::isfinite(params.pose_pull))
        throw invalid_argument(who + ": pose_pull must be finite and not negative, got " +
                               std::to_string(static_cast<double>(params.pose_pull)));
    for (std::size_t i = 0; i < goals.size(); ++i) {
        const std::size_t f = goals[i].frame;
        if (f >= c.frames())
            throw invalid_argument(who + ": goal set " + std::to_string(i) + " is for frame " + std::to_string(f) +
                                   ", outside the clip (" + std::to_string(c.frames()) + " frames)");
        if (i > 0 && f <= goals[i - 1].frame)
            throw invalid_argument(who + ": frames must be ascending and distinct, but frame " + std::to_string(f) +
                                   " follows frame " + std::to_string(goals[i - 1].frame));
        if (goals[i].goals.empty()) throw invalid_argument(who + ": frame " + std::to_string(f) + " has no goals");
    }
    clip_ik_result<T> out{c, {}, {}, 0, T(0), 0, T(0), T(0)};
    if (goals.empty()) return out;

    ik_vector<T> correction;  // the previous frame's solution minus its recorded pose
    for (std::size_t i = 0; i < goals.size(); ++i) {
        const std::size_t f = goals[i].frame;
        tree.set_base(c, f);
        const ik_vector<T> own = tree.pose_of(c, f);
        ik_params<T> p = params.ik;
        if (params.pose_pull > T(0)) {
            p.null_space.gain = params.pose_pull;
            p.null_space.reference = own;
        }
        const bool follows = params.warm_start && i > 0 && f == goals[i - 1].frame + 1;
        const kinematic_tree<T>& based = tree;
        const ik_vector<T> start = follows ? ik_vector<T>(own + correction) : own;
        ik_result<T> r = solve(based, goals[i].goals, start, static_cast<const ik_params<T>&>(p));
        tree.write_pose(r.q, out.edited, f);
        correction = r.q - own;
        out.converged_frames += r.converged();
        out.largest_error = std::max(out.largest_error, r.max_position_error);
        out.iterations += r.iterations;
        out.frames.push_back(f);
        out.results.push_back(std::move(r));
        if (params.progress) params.progress(i + 1, goals.size());
    }
    const std::size_t first = goals.front().frame, last = goals.back().frame + 1;
    out.max_joint_step_before = max_joint_step(c, first, last);
    out.max_joint_step_after = max_joint_step(out.edited, first, last);
    return out;
}

}  // namespace anima
