// The paper's experiment as a key set: a 1 3/4 front somersault with a 1/2
// twist in 12 keys on the CMU 31-joint skeleton, stretched at take-off,
// tucked through keys 2-7 (the paper's frames 3-8), opening at key 8 and
// twisting while stretched through keys 9-11. The somersault angle grows by
// the same step from key to key and the keys start evenly spaced in time, as
// an animator would first lay them out; the timing comes from the dynamics.
// The centre of mass flies ballistically: take-off velocity (0, 7.8, 0.015)
// m/s (7.8 up, 0.015 forward in this Y-up frame) and 1.6 s of hang time.
#pragma once

#include <anima/core/constants.hpp>
#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/flight/flight_objective.hpp>
#include <anima/flight/key_trajectory.hpp>
#include <anima/motion/skeleton.hpp>
#include <anima/rotation/shortest_arc.hpp>

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace anima {

template <class T>
struct somersault_params {
    T hang_time = T(1.6);                                            ///< s
    Eigen::Matrix<T, 3, 1> take_off_velocity{T(0), T(7.8), T(0.015)};  ///< of the centre of mass, m/s
    T somersault_degrees = T(630);                                   ///< 1 3/4 turns forward
    T twist_degrees = T(180);                                        ///< 1/2 twist
};

/// The 12 keys on a skeleton with the CMU 31-joint names (Hips, LowerBack,
/// Spine, Spine1, LeftUpLeg, LeftLeg, LeftArm, LeftForeArm and the right
/// side), evenly spaced over the hang time; other joints keep their rest
/// rotation. Throws anima::invalid_argument naming a missing joint.
template <class T>
flight_keys<T> somersault_keys(const skeleton<T>& sk, const somersault_params<T>& p = {}) {
    using vector3 = Eigen::Matrix<T, 3, 1>;
    using quat = Eigen::Quaternion<T>;
    if (!(p.hang_time > T(0)) || !std::isfinite(p.hang_time))
        throw invalid_argument("anima::somersault_keys: hang_time must be positive, got " +
                               detail::argument_text(p.hang_time));
    const auto need = [&](const char* name) {
        if (auto j = sk.find(name)) return *j;
        throw invalid_argument(std::string("anima::somersault_keys: the skeleton has no joint '") + name +
                               "' (CMU 31-joint names are expected)");
    };
    const std::size_t hips = 0, lower_back = need("LowerBack"), spine = need("Spine"), spine1 = need("Spine1"),
                      l_up = need("LeftUpLeg"), l_leg = need("LeftLeg"), r_up = need("RightUpLeg"),
                      r_leg = need("RightLeg"), l_arm = need("LeftArm"), l_fore = need("LeftForeArm"),
                      r_arm = need("RightArm"), r_fore = need("RightForeArm");
    const auto rx = [](T a) { return quat(Eigen::AngleAxis<T>(radians(a), vector3::UnitX())); };
    const auto ry = [](T a) { return quat(Eigen::AngleAxis<T>(radians(a), vector3::UnitY())); };

    // Per key: twist (fraction of the full twist), hip flexion, knee flexion,
    // trunk flexion, arm direction in the trunk frame, elbow flexion.
    struct pose {
        T twist, hip, knee, trunk;
        vector3 arm;
        T elbow;
    };
    const vector3 up(T(0), T(1), T(0)), up_fwd(T(0), T(0.7), T(0.7)), fwd(T(0), T(0), T(1)),
        shins(T(0), T(-0.5), T(0.85)), down(T(0), T(-1), T(0));
    const std::array<pose, 12> poses{{
        {T(0), T(0), T(0), T(0), up, T(0)},                 // take-off, stretched
        {T(0), T(15), T(5), T(5), up_fwd, T(0)},            // stretched, arms coming forward
        {T(0), T(100), T(110), T(25), fwd, T(60)},          // closing into the tuck
        {T(0), T(125), T(135), T(30), shins, T(80)},        // tuck
        {T(0), T(125), T(135), T(30), shins, T(80)},
        {T(0), T(125), T(135), T(30), shins, T(80)},
        {T(0), T(125), T(135), T(30), shins, T(80)},
        {T(0), T(120), T(130), T(30), shins, T(80)},        // last tucked key
        {T(0), T(60), T(50), T(10), fwd, T(30)},            // opening
        {T(0.25), T(10), T(5), T(0), down, T(0)},           // stretched, twisting
        {T(0.75), T(5), T(5), T(0), down, T(0)},
        {T(1), T(10), T(10), T(0), up_fwd, T(10)},          // landing
    }};
    flight_keys<T> keys;
    const std::size_t n = poses.size();
    for (std::size_t k = 0; k < n; ++k) {
        const auto& q = poses[k];
        keys.times.push_back(p.hang_time * T(k) / T(n - 1));
        keys.root_positions.push_back(vector3::Zero());  // the root follows the ballistic centre of mass
        std::vector<quat> rot(sk.size(), quat::Identity());
        const T pitch = p.somersault_degrees * T(k) / T(n - 1);
        rot[hips] = rx(pitch) * ry(q.twist * p.twist_degrees);
        for (std::size_t j : {lower_back, spine, spine1}) rot[j] = rx(q.trunk / T(3));
        rot[l_up] = rot[r_up] = rx(-q.hip);
        rot[l_leg] = rot[r_leg] = rx(q.knee);
        rot[l_arm] = shortest_arc<quat>(vector3::UnitX(), q.arm);
        rot[r_arm] = shortest_arc<quat>(-vector3::UnitX(), q.arm);
        rot[l_fore] = ry(-q.elbow);
        rot[r_fore] = ry(q.elbow);
        keys.rotations.push_back(std::move(rot));
    }
    return keys;
}

/// Settings for the somersault: ballistic centre of mass from the origin
/// with the take-off velocity, Y-up gravity.
template <class T>
flight_settings<T> somersault_settings(const somersault_params<T>& p = {}) {
    flight_settings<T> s;
    ballistic_path<T> b;
    b.velocity = p.take_off_velocity;
    s.ballistic = b;
    return s;
}

}  // namespace anima
