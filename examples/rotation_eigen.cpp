// The same toolkit on Eigen quaternions, plus the angular velocity of a
// sampled rotation curve.
#include <anima/rotation.hpp>

#include <Eigen/Geometry>

#include <cstdio>
#include <vector>

int main() {
    using quat = Eigen::Quaterniond;
    const quat a(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()));
    const quat b(Eigen::AngleAxisd(1.4, Eigen::Vector3d(1, 1, 0).normalized()));

    // anima::slerp takes the shorter arc even when b's sign is flipped.
    const quat flipped(-b.coeffs());
    std::printf("slerp(a, b, .3) vs slerp(a, -b, .3): %.2e rad apart\n",
                anima::angle_between(anima::slerp(a, b, 0.3), anima::slerp(a, flipped, 0.3)));

    // Sample a turn at 2 rad/s about +X at 120 Hz and measure it back.
    const double dt = 1.0 / 120.0;
    std::vector<quat> curve;
    for (int i = 0; i < 10; ++i)
        curve.push_back(a * quat(Eigen::AngleAxisd(2.0 * dt * i, Eigen::Vector3d::UnitX())));
    const auto w = anima::angular_velocities(curve, dt, anima::angular_frame::local);
    std::printf("angular velocity (local frame) at sample 5: %.6f %.6f %.6f rad/s\n", w[5].x(), w[5].y(), w[5].z());

    // Axis-angle and Euler conversions in every order.
    const auto aa = anima::to_axis_angle(b);
    std::printf("b = %.4f rad about (%.4f, %.4f, %.4f)\n", aa.angle, aa.axis.x(), aa.axis.y(), aa.axis.z());
    for (auto order : {anima::euler_order::xyz, anima::euler_order::zxy, anima::euler_order::zyx}) {
        const auto e = anima::to_euler(b, order);
        std::printf("%s: %+.4f %+.4f %+.4f\n", anima::to_string(order).c_str(), e[0], e[1], e[2]);
    }
    return 0;
}
