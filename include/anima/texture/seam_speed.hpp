// Whether a stitched motion is seamless: around each seam, every joint's
// frame-to-frame angular speed and the root's speed should stay within the
// range the input clip itself shows. A cut-and-paste loop fails this at
// once (the pose jumps in one frame); a good seam passes it.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/speed_limits.hpp>
#include <anima/rotation/quaternion.hpp>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace anima {

/// The speeds around one seam relative to the limits.
template <class T>
struct seam_speed {
    std::size_t first = 0, last = 0;  ///< the frames checked: steps first-1 -> first ... last -> last+1
    T joint_ratio = T(0);             ///< the largest joint speed / that joint's limit
    std::size_t worst_joint = 0;
    T root_ratio = T(0);              ///< the largest root speed / the root's limit
    bool within(T tolerance = T(0)) const { return joint_ratio <= T(1) + tolerance && root_ratio <= T(1) + tolerance; }
};

/// Speeds of `c` over each span [first, last] of frames (and the steps
/// into and out of it) relative to `limits`. A joint's limit is raised to
/// at least `floor` times the fastest joint's, so a joint that never moves
/// in the input (uncaptured fingers) is not judged on rounding noise.
/// Throws anima::invalid_argument for limits of another skeleton, a span
/// outside the clip or a negative floor.
template <class T>
std::vector<seam_speed<T>> seam_speeds(const clip<T>& c, const std::vector<std::pair<std::size_t, std::size_t>>& spans,
                                       const speed_limits<T>& limits, T floor = T(0.01)) {
    if (limits.joint.size() != c.joints())
        throw invalid_argument("anima::seam_speeds: limits for " + std::to_string(limits.joint.size()) +
                               " joints, the clip has " + std::to_string(c.joints()));
    check_argument(floor >= T(0), "anima::seam_speeds", "floor", "non-negative", floor);
    const T fastest = limits.joint.empty() ? T(0) : *std::max_element(limits.joint.begin(), limits.joint.end());
    const T rate = c.frame_rate();
    const bool root_moves = c.joints() > 0 && c.skeleton().translation_slot(0) >= 0;
    // A limit of 0 with a speed of 0 is within; any motion over it is not.
    const auto ratio = [](T speed, T limit) {
        return limit > T(0) ? speed / limit : (speed > T(0) ? std::numeric_limits<T>::infinity() : T(0));
    };
    std::vector<seam_speed<T>> out;
    for (const auto& [first, last] : spans) {
        if (first > last || last >= c.frames())
            throw invalid_argument("anima::seam_speeds: span [" + std::to_string(first) + ", " + std::to_string(last) +
                                   "] is not within the clip's " + std::to_string(c.frames()) + " frames");
        seam_speed<T> s;
        s.first = first;
        s.last = last;
        for (std::size_t f = std::max<std::size_t>(first, 1); f <= std::min(last + 1, c.frames() - 1); ++f) {
            for (std::size_t j = 0; j < c.joints(); ++j) {
                const T r = ratio(angle_between(c.rotation(f - 1, j), c.rotation(f, j)) * rate,
                                  std::max(limits.joint[j], floor * fastest));
                if (r > s.joint_ratio) {
                    s.joint_ratio = r;
                    s.worst_joint = j;
                }
            }
            if (root_moves)
                s.root_ratio = std::max(s.root_ratio, ratio((c.root_position(f) - c.root_position(f - 1)).norm() * rate, limits.root));
        }
        out.push_back(s);
    }
    return out;
}

/// The worst of several seams: the largest joint_ratio (with its joint and
/// its span) and the largest root_ratio, which may be another seam's. All
/// zero for no seam.
template <class T>
seam_speed<T> worst_seam_speed(const std::vector<seam_speed<T>>& speeds) {
    seam_speed<T> out;
    for (const auto& s : speeds) {
        if (s.joint_ratio > out.joint_ratio) {
            out.joint_ratio = s.joint_ratio;
            out.worst_joint = s.worst_joint;
            out.first = s.first;
            out.last = s.last;
        }
        out.root_ratio = std::max(out.root_ratio, s.root_ratio);
    }
    return out;
}

}  // namespace anima
