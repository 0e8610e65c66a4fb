// Rest poses at the start of a clip. Some exporters put the skeleton's rest
// pose (a T-pose, every rotation near the identity) before the motion, often
// followed by a few frames that swing out of it. Those frames are no motion
// to play, and their large steps would inflate velocity statistics.
#pragma once

#include <anima/core/constants.hpp>
#include <anima/core/nondeduced.hpp>
#include <anima/motion/clip.hpp>
#include <anima/rotation/quaternion.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace anima {

/// Whether frame 0 is the rest pose: every joint that moves during the clip
/// (by more than a degree from frame 0) is within `degrees` of the identity
/// there, and at least one joint moves. Joints that never move, such as
/// uncaptured fingers, may be held at any angle.
template <class T>
bool starts_at_rest_pose(const clip<T>& c, nondeduced_t<T> degrees = T(10)) {
    if (c.frames() < 2) return false;
    const T limit = degrees * pi<T> / T(180), still = pi<T> / T(180);
    const Eigen::Quaternion<T> identity = Eigen::Quaternion<T>::Identity();
    bool moves = false;
    for (std::size_t j = 0; j < c.joints(); ++j) {
        bool joint_moves = false;
        for (std::size_t f = 1; f < c.frames() && !joint_moves; ++f)
            joint_moves = angle_between(c.rotation(0, j), c.rotation(f, j)) > still;
        if (!joint_moves) continue;
        moves = true;
        if (angle_between(identity, c.rotation(0, j)) > limit) return false;
    }
    return moves;
}

/// The frames to skip when the clip starts at its rest pose: the first frame
/// f >= 1 whose step to f + 1 (the summed angle every joint turns) is
/// ordinary again, under twice the clip's median step; 1 when no later step
/// is. 0 when frame 0 is not the rest pose.
template <class T>
std::size_t rest_pose_lead_in(const clip<T>& c, nondeduced_t<T> degrees = T(10)) {
    if (!starts_at_rest_pose(c, degrees)) return 0;
    std::vector<T> step(c.frames() - 1, T(0));
    for (std::size_t f = 1; f < c.frames(); ++f)
        for (std::size_t j = 0; j < c.joints(); ++j) step[f - 1] += angle_between(c.rotation(f - 1, j), c.rotation(f, j));
    std::vector<T> sorted = step;
    const auto mid = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
    std::nth_element(sorted.begin(), mid, sorted.end());
    for (std::size_t f = 1; f < step.size(); ++f)
        if (step[f] < T(2) * *mid) return f;
    return 1;
}

}  // namespace anima
