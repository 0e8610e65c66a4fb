// Samples the motion of a key set (as the flight objective sees it: spline
// poses, the root under the ballistic centre of mass when one is set) into
// a clip for writing as BVH.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/nondeduced.hpp>
#include <anima/flight/flight_objective.hpp>
#include <anima/flight/key_trajectory.hpp>
#include <anima/motion/clip.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <string>

namespace anima {

/// One frame every frame_time seconds from the first key to the last (the
/// last frame lands on it when the flight is a whole number of frames).
/// Root positions go back to skeleton units (divided by metres_per_unit).
template <class T>
clip<T> flight_clip(const flight_problem<T>& problem, const flight_keys<T>& keys, const skeleton<T>& sk,
                    nondeduced_t<T> metres_per_unit, nondeduced_t<T> frame_time) {
    const char* who = "anima::flight_clip";
    if (sk.size() != problem.model().size())
        throw invalid_argument(std::string(who) + ": skeleton has " + std::to_string(sk.size()) +
                               " joints, the body model " + std::to_string(problem.model().size()));
    if (sk.translation_slot(0) < 0)
        throw invalid_argument(std::string(who) + ": the root joint '" + sk[0].name + "' has no position channels");
    check_positive(who, "metres_per_unit", metres_per_unit);
    check_positive(who, "frame_time", frame_time);
    const auto traj = key_trajectory<T>::from_keys(keys);
    const T span = traj.end_time() - traj.start_time();
    const auto frames = static_cast<std::size_t>(std::floor(span / frame_time + T(1e-3))) + 1;
    clip<T> out(sk, frames, frame_time);
    for (std::size_t f = 0; f < frames; ++f) {
        const T t = std::min(traj.end_time(), traj.start_time() + frame_time * T(f));
        const auto m = problem.motion_at(traj, t);
        out.set_root_position(f, m.root_position / metres_per_unit);
        for (std::size_t j = 0; j < sk.size(); ++j) out.set_rotation(f, j, Eigen::Quaternion<T>(m.rotations[j]));
    }
    return out;
}

}  // namespace anima
