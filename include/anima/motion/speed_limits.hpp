// How fast a clip moves at most: per joint, the largest angle between the
// local rotations of consecutive frames, and the root's largest step. Seams
// are judged against it (texture/seam_speed.hpp), and foot planting keeps
// the legs it solves within it (ik/plant_feet.hpp).
#pragma once

#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/rotation/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace anima {

/// The fastest a clip moves: per joint the largest angle between the
/// local rotations of consecutive frames, and the root's largest
/// displacement, both per second.
template <class T>
struct speed_limits {
    std::vector<T> joint;  ///< rad/s, per joint
    T root = T(0);         ///< length units/s
};

template <class T>
speed_limits<T> clip_speed_limits(const clip<T>& c) {
    speed_limits<T> out;
    out.joint.assign(c.joints(), T(0));
    const T rate = c.frame_rate();
    const bool root_moves = c.joints() > 0 && c.skeleton().translation_slot(0) >= 0;
    for (std::size_t f = 1; f < c.frames(); ++f) {
        for (std::size_t j = 0; j < c.joints(); ++j)
            out.joint[j] = std::max(out.joint[j], angle_between(c.rotation(f - 1, j), c.rotation(f, j)) * rate);
        if (root_moves) out.root = std::max(out.root, (c.root_position(f) - c.root_position(f - 1)).norm() * rate);
    }
    if (!std::isfinite(out.root))
        throw invalid_argument("anima::clip_speed_limits: the root's speed overflows the scalar type; scale the clip "
                               "down (scale_clip)");
    return out;
}

}  // namespace anima
