// Inverse kinematics over frames of a clip: per-frame goals, each frame
// warm-started from the solution of the frame before and pulled toward its
// own recorded pose in the null space, so that an edit (a hand moved over a
// range, a foot held in place) changes the motion smoothly and no more than
// the goals ask. solve_clip_ik edits a copy of the clip; solve_clip_frame_into
// solves one frame at a time into caller-owned storage, for a game loop.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/solve.hpp>
#include <anima/ik/step_rules.hpp>
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

/// How the goals on one joint missed over a solved clip: the solved frames
/// where one ended farther from its target than the tolerance, and the
/// largest such error.
template <class T>
struct goal_misses {
    std::size_t joint = 0;
    std::size_t frames = 0;       ///< solved frames where a goal on the joint missed
    std::size_t worst_frame = 0;  ///< the frame of the largest miss (the first of equal ones)
    T worst = T(0);               ///< that position error
};

/// Per joint with a goal that missed in any solved frame, by joint index:
/// what a tool warns about when solve_clip_ik did not reach every target.
/// `goals` are those solve_clip_ik was given (their joints name the
/// errors). Throws anima::invalid_argument for a negative or NaN tolerance,
/// or goals that do not match `solved` (frames or goal counts).
template <class T>
std::vector<goal_misses<T>> missed_goals(const clip_ik_result<T>& solved, const std::vector<frame_goals<T>>& goals,
                                         T tolerance) {
    const std::string who = "anima::missed_goals";
    if (!(tolerance >= T(0)))
        throw invalid_argument(who + ": tolerance must be >= 0, got " + detail::argument_text(tolerance));
    if (goals.size() != solved.frames.size() || solved.results.size() != solved.frames.size())
        throw invalid_argument(who + ": " + std::to_string(goals.size()) + " goal sets for " +
                               std::to_string(solved.frames.size()) + " solved frames");
    std::vector<goal_misses<T>> out;
    for (std::size_t i = 0; i < goals.size(); ++i) {
        const auto& errors = solved.results[i].errors;
        if (goals[i].frame != solved.frames[i] || errors.size() != goals[i].goals.size())
            throw invalid_argument(who + ": goal set " + std::to_string(i) + " (frame " +
                                   std::to_string(goals[i].frame) + ", " + std::to_string(goals[i].goals.size()) +
                                   " goals) does not match solved frame " + std::to_string(solved.frames[i]) + " (" +
                                   std::to_string(errors.size()) + " errors)");
        std::vector<std::size_t> counted;  // the joints this frame has counted already
        for (std::size_t k = 0; k < errors.size(); ++k) {
            if (!(errors[k].position > tolerance)) continue;
            const std::size_t joint = goals[i].goals[k].joint;
            auto it = std::find_if(out.begin(), out.end(), [&](const goal_misses<T>& m) { return m.joint == joint; });
            if (it == out.end()) it = out.insert(out.end(), goal_misses<T>{joint, 0, 0, T(0)});
            if (std::find(counted.begin(), counted.end(), joint) == counted.end()) {
                ++it->frames;
                counted.push_back(joint);
            }
            if (errors[k].position > it->worst) {
                it->worst = errors[k].position;
                it->worst_frame = solved.frames[i];
            }
        }
    }
    // (a.joint) in parentheses: `a.joint <` would start anima::joint's template arguments.
    std::sort(out.begin(), out.end(), [](const goal_misses<T>& a, const goal_misses<T>& b) { return (a.joint) < b.joint; });
    return out;
}

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

/// What solve_clip_frame_into keeps from frame to frame: the previous
/// frame's correction for the warm start, and the scratch of the solve.
/// Keep one per character; reset() before a new, unrelated run of frames.
template <class T>
struct clip_ik_workspace {
    ik_workspace<T> ik;
    ik_params<T> params;          ///< the frame's: params.ik with the pull toward the recorded pose
    ik_vector<T> own, start;      ///< the frame's recorded pose; where its solve starts
    ik_vector<T> correction;      ///< the last solved frame's solution minus its recorded pose
    ik_vector<T> spare_reference; ///< storage of params.null_space.reference while the pull is off
    std::size_t last_frame = 0;
    bool solved_any = false;      ///< last_frame and correction hold a solved frame
    void reset() { solved_any = false; }
};

namespace detail {

/// Checks clip_ik_params, naming `who`.
template <class T>
void check_clip_ik_params(const clip_ik_params<T>& params, const char* who) {
    if (!(params.pose_pull >= T(0)) || !std::isfinite(params.pose_pull))
        throw invalid_argument(std::string(who) + ": pose_pull must be finite and not negative, got " +
                               detail::argument_text(params.pose_pull));
}

/// Bases the tree on frame f of c and sets the frame's solver parameters
/// and start in ws: the recorded pose, plus the previous frame's correction
/// when f follows the last solved frame and warm starts are on.
template <class T>
void begin_clip_frame(kinematic_tree<T>& tree, const clip<T>& c, std::size_t f, const clip_ik_params<T>& params,
                      clip_ik_workspace<T>& ws) {
    tree.set_base(c, f);
    tree.pose_of(c, f, ws.own);
    // params.ik copied without giving up the reference's storage.
    ws.params.null_space.reference.swap(ws.spare_reference);
    ws.params = params.ik;
    if (params.pose_pull > T(0)) {
        ws.params.null_space.gain = params.pose_pull;
        ws.params.null_space.reference.swap(ws.spare_reference);
        ws.params.null_space.reference = ws.own;
    }
    const bool follows = params.warm_start && ws.solved_any && f == ws.last_frame + 1;
    if (follows) ws.start = ws.own + ws.correction;
    else ws.start = ws.own;
}

/// Records frame f's solution q for the next frame's warm start.
template <class T>
void end_clip_frame(std::size_t f, const ik_vector<T>& q, clip_ik_workspace<T>& ws) {
    ws.correction = q - ws.own;
    ws.last_frame = f;
    ws.solved_any = true;
}

}  // namespace detail

/// One frame of clip IK into caller-owned storage, for a game loop: the
/// goals of frame f of c solved with the step rule `rule` (solve_ik_into),
/// started and pulled toward the recording as solve_clip_ik does (warm from
/// the last frame solved with this workspace when f follows it). The
/// frame's solution is out.q: write it where it goes with
/// tree.write_pose(out.q, clip, frame). `tree` must be built on c's
/// skeleton; it is based on frame f. Frame by frame over a range, the
/// solutions are solve_clip_ik's with the same rule, bit for bit. Once the
/// workspace has seen the tree and a goal set of the same sizes, a call
/// allocates nothing (as solve_ik_into, without restarts).
template <class T, class Rule>
void solve_clip_frame_into(kinematic_tree<T>& tree, const clip<T>& c, std::size_t f,
                           const std::vector<ik_goal<T>>& goals, const Rule& rule, const clip_ik_params<T>& params,
                           ik_result<T>& out, clip_ik_workspace<T>& ws) {
    const char* who = "anima::solve_clip_frame_into";
    detail::check_clip_ik_params(params, who);
    if (goals.empty()) throw invalid_argument(std::string(who) + ": frame " + std::to_string(f) + " has no goals");
    detail::begin_clip_frame(tree, c, f, params, ws);
    solve_ik_into(tree, goals, ws.start, rule, ws.params, out, ws.ik);
    detail::end_clip_frame(f, out.q, ws);
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
    detail::check_clip_ik_params(params, who.c_str());
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

    clip_ik_workspace<T> ws;
    for (std::size_t i = 0; i < goals.size(); ++i) {
        const std::size_t f = goals[i].frame;
        detail::begin_clip_frame(tree, c, f, params, ws);
        const kinematic_tree<T>& based = tree;
        ik_result<T> r = solve(based, goals[i].goals, static_cast<const ik_vector<T>&>(ws.start),
                               static_cast<const ik_params<T>&>(ws.params));
        tree.write_pose(r.q, out.edited, f);
        detail::end_clip_frame(f, r.q, ws);
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
