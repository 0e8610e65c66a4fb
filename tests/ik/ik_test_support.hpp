// Shared by the IK tests and benchmark: a 7-DOF arm (hinges about z, y, z,
// y, z, y, z, as on common redundant manipulators), reachable random
// targets from random joint vectors within limits, and the CMU arm chain.
#pragma once

#include <anima/bvh.hpp>
#include <anima/core/random.hpp>
#include <anima/ik.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace anima_ik_test {

/// Link offsets of the arm (metres); total reach 1.2.
template <class T>
std::vector<Eigen::Matrix<T, 3, 1>> arm_offsets() {
    using v = Eigen::Matrix<T, 3, 1>;
    return {v(0, 0, 0), v(0, 0, T(0.3)), v(0, 0, T(0.1)), v(0, 0, T(0.3)), v(0, 0, T(0.1)), v(0, 0, T(0.25)),
            v(0, 0, T(0.05))};
}
/// Tool tip below the last joint.
template <class T>
Eigen::Matrix<T, 3, 1> arm_tip() {
    return {T(0), T(0), T(0.1)};
}
/// Axis index of joint i: z, y, z, y, z, y, z.
inline int arm_axis(int i) { return i % 2 == 0 ? 2 : 1; }
/// Limit of every joint (radians), symmetric.
template <class T>
T arm_limit(int i) {
    return i % 2 == 0 ? T(2.9) : T(2.0);
}

/// The arm as a skeleton and a hinge tree with limits.
template <class T>
anima::kinematic_tree<T> seven_dof_arm() {
    anima::skeleton<T> sk;
    const auto offsets = arm_offsets<T>();
    for (int i = 0; i < 7; ++i)
        sk.add_joint("j" + std::to_string(i), i - 1, offsets[static_cast<std::size_t>(i)],
                     {anima::channel::z_rotation, anima::channel::y_rotation, anima::channel::x_rotation});
    sk.set_end_site(6, arm_tip<T>());
    anima::kinematic_tree<T> tree(sk);
    for (int i = 0; i < 7; ++i)
        tree.set_hinge(static_cast<std::size_t>(i), Eigen::Matrix<T, 3, 1>::Unit(arm_axis(i)), -arm_limit<T>(i),
                       arm_limit<T>(i));
    return tree;
}

/// Uniform random DOF vector within the tree's limits (unlimited DOFs in +-limit).
template <class T>
anima::ik_vector<T> random_q(const anima::kinematic_tree<T>& tree, anima::random_source& rng, T unlimited = T(1.2)) {
    anima::ik_vector<T> q(tree.dofs());
    for (int k = 0; k < tree.dofs(); ++k) {
        const T lo = std::isfinite(tree.lower()[k]) ? tree.lower()[k] : -unlimited;
        const T hi = std::isfinite(tree.upper()[k]) ? tree.upper()[k] : unlimited;
        q[k] = lo + static_cast<T>(rng.uniform()) * (hi - lo);
    }
    return q;
}

/// Position of joint j's point `offset` under q.
template <class T>
Eigen::Matrix<T, 3, 1> point_at(const anima::kinematic_tree<T>& tree, const anima::ik_vector<T>& q, std::size_t j,
                                const Eigen::Matrix<T, 3, 1>& offset) {
    anima::ik_state<T> s;
    tree.forward(q, s);
    return s.positions[j] + s.orientations[j] * offset;
}

/// The bundled CMU walk's left arm, LeftArm..LeftHand, with elbow and wrist
/// limits loose enough for mocap; the effector is the hand's position.
template <class T>
anima::kinematic_tree<T> cmu_left_arm(const anima::clip<T>& walk) {
    auto tree = anima::kinematic_tree<T>::chain(walk.skeleton(), "LeftArm", "LeftHand");
    tree.set_base(walk, 0);
    const T lim = T(2.5);
    for (const char* name : {"LeftArm", "LeftForeArm", "LeftHand"})
        tree.set_ball_limits(walk.skeleton().index_of(name), Eigen::Matrix<T, 3, 1>::Constant(-lim),
                             Eigen::Matrix<T, 3, 1>::Constant(lim));
    return tree;
}

/// Sum of the chain's bone lengths from `first` to joint `last` plus an offset.
template <class T>
T chain_length(const anima::skeleton<T>& sk, std::size_t first, std::size_t last, const Eigen::Matrix<T, 3, 1>& tip) {
    T len = tip.norm();
    for (int j = static_cast<int>(last); j != static_cast<int>(first) && j >= 0; j = sk[static_cast<std::size_t>(j)].parent)
        len += sk[static_cast<std::size_t>(j)].offset.norm();
    return len;
}

}  // namespace anima_ik_test
