// Joint velocities of a clip: linear (global positions) and angular (local
// rotation curves), both by finite differences over the clip's frame time.
#pragma once

#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/finite_difference.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/rotation/angular_velocity.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <vector>

namespace anima {

/// Global linear velocity of every joint: frames x (3 * joints), laid out as
/// global_positions(); units per second.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> joint_linear_velocities(const clip<T>& c) {
    auto v = time_derivative(global_positions(c), c.frame_time());
    if (!v.allFinite())
        throw invalid_argument("anima::joint_linear_velocities: a velocity overflows the scalar type; scale the clip "
                               "down (scale_clip)");
    return v;
}

/// Angular velocity (radians per second, axis * rate) of joint j's local
/// rotation at every frame, in the parent's frame or the joint's own.
template <class T>
std::vector<Eigen::Matrix<T, 3, 1>> joint_angular_velocities(const clip<T>& c, std::size_t j,
                                                             angular_frame frame = angular_frame::parent) {
    std::vector<Eigen::Quaternion<T>> curve;
    curve.reserve(c.frames());
    for (std::size_t f = 0; f < c.frames(); ++f) curve.push_back(c.rotation(f, j));
    return angular_velocities(curve, c.frame_time(), frame);
}

}  // namespace anima
