// The rotation toolkit on GLM quaternions: blend two orientations, build a
// smooth squad curve through keys, measure angles between them, and hand a
// rotation to Eigen (the clip model's type) and back.
#include <anima/rotation.hpp>

#include <glm/ext/quaternion_trigonometric.hpp>
#include <glm/ext/vector_float3.hpp>

#include <Eigen/Geometry>

#include <cstdio>

int main() {
    const glm::quat a = glm::angleAxis(0.0f, glm::vec3(0, 1, 0));
    const glm::quat b = glm::angleAxis(2.0f, glm::vec3(0, 1, 0));

    // Halfway in angle: a 1 rad turn about +Y.
    const glm::quat mid = anima::slerp(a, b, 0.5f);
    std::printf("slerp halfway: %.4f rad\n", anima::angle_between(a, mid));

    // A whole pose at once: each joint a quarter of the way from pose_a to pose_b.
    const glm::quat pose_a[3] = {a, b, glm::angleAxis(1.0f, glm::vec3(1, 0, 0))};
    const glm::quat pose_b[3] = {b, a, glm::angleAxis(-1.0f, glm::vec3(1, 0, 0))};
    glm::quat blended[3];
    anima::slerp_batch(pose_a, pose_b, 0.25f, 3, blended);
    std::printf("slerp_batch t=0.25: %.4f %.4f %.4f rad from pose_a\n", anima::angle_between(pose_a[0], blended[0]),
                anima::angle_between(pose_a[1], blended[1]), anima::angle_between(pose_a[2], blended[2]));

    // Squad through four keys: control points from each key's neighbours.
    const glm::quat keys[4] = {a, b, anima::from_euler<glm::quat>(0.3f, 1.2f, -0.4f, anima::euler_order::zxy),
                               glm::angleAxis(0.5f, glm::vec3(1, 0, 0))};
    const glm::quat s1 = anima::squad_control_point(keys[0], keys[1], keys[2]);
    const glm::quat s2 = anima::squad_control_point(keys[1], keys[2], keys[3]);
    for (float t : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f}) {
        const glm::quat q = anima::squad(keys[1], keys[2], s1, s2, t);
        const auto e = anima::to_euler(q, anima::euler_order::zxy);
        std::printf("squad t=%.2f  zxy Euler (rad) = %+.4f %+.4f %+.4f\n", t, e[0], e[1], e[2]);
    }

    // Rotation vectors (exponential map) and back.
    const glm::vec3 v = anima::to_rotation_vector(keys[2]);
    std::printf("rotation vector: %+.4f %+.4f %+.4f, round trip error %.2e rad\n", v.x, v.y, v.z,
                anima::angle_between(keys[2], anima::from_rotation_vector<glm::quat>(v)));

    // Into Eigen, as anima::clip stores rotations, and back: the same four numbers.
    const Eigen::Quaternionf e = anima::quaternion_cast<Eigen::Quaternionf>(keys[2]);
    const glm::quat back = anima::quaternion_cast<glm::quat>(e);
    std::printf("as Eigen: w %+.4f x %+.4f y %+.4f z %+.4f; back to GLM: %s\n", e.w(), e.x(), e.y(), e.z(),
                back == keys[2] ? "identical" : "changed");
    return 0;
}
