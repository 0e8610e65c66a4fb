// Kinematic trees and the analytic Jacobian: FK against the clip's forward
// kinematics, DOF round trips through clip frames, Jacobian against central
// differences (ball, hinge, root translation, orientation rows) and against
// KDL on the equivalent 7-DOF chain.
#include "ik_test_support.hpp"
#include "../test_support.hpp"

#include <anima/bvh.hpp>
#include <anima/ik.hpp>
#include <anima/motion.hpp>
#include <anima/optimize/numeric_derivatives.hpp>

#include <doctest/doctest.h>

#ifdef ANIMA_HAVE_KDL
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#endif

using namespace anima;
using anima_test::bundled;
using anima_test::tolerance;

namespace {

/// Central differences of the stacked weighted goal values (position, then
/// orientation as a rotation vector relative to the value at q).
template <class T>
ik_matrix<T> difference_jacobian(const kinematic_tree<T>& tree, const ik_vector<T>& q,
                                 const std::vector<ik_goal<T>>& goals, T h) {
    ik_state<T> s0;
    tree.forward(q, s0);
    const int m = goal_rows(goals);
    ik_matrix<T> jac(m, tree.dofs());
    const auto values = [&](const ik_vector<T>& x) {
        ik_state<T> s;
        tree.forward(x, s);
        ik_vector<T> v(m);
        int row = 0;
        for (const auto& g : goals) {
            if (g.has_position()) {
                v.template segment<3>(row) = g.weight * effector_position(s, g);
                row += 3;
            }
            if (g.has_orientation()) {
                const Eigen::Quaternion<T> d = s.orientations[g.joint] * s0.orientations[g.joint].conjugate();
                v.template segment<3>(row) = g.weight * g.orientation_scale * to_rotation_vector(d);
                row += 3;
            }
        }
        return v;
    };
    for (int k = 0; k < tree.dofs(); ++k) {
        ik_vector<T> a = q, b = q;
        a[k] += h;
        b[k] -= h;
        jac.col(k) = (values(a) - values(b)) / (T(2) * h);
    }
    return jac;
}

}  // namespace

TEST_CASE_TEMPLATE("kinematic_tree: FK of a clip frame's pose equals the clip's forward kinematics", T, float, double) {
    const auto walk = read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    kinematic_tree<T> tree(walk.skeleton());
    tree.set_root_translation(true);
    const T tol = tolerance<T>(1e-9, 2e-3);
    for (std::size_t f : {0u, 100u, 342u}) {
        const auto q = tree.pose_of(walk, f);
        ik_state<T> s;
        tree.forward(q, s);
        const auto ref = forward_kinematics(walk, f);
        for (std::size_t j = 0; j < walk.joints(); ++j) {
            CHECK((s.positions[j] - ref.positions[j]).norm() < tol * T(100));
            CHECK(std::abs(std::abs(s.orientations[j].dot(ref.orientations[j])) - T(1)) < tol);
        }
        // Writing the pose into another frame reproduces the frame.
        auto copy = walk;
        tree.write_pose(q, copy, 1);
        const auto again = forward_kinematics(copy, 1);
        for (std::size_t j = 0; j < walk.joints(); ++j)
            CHECK((again.positions[j] - ref.positions[j]).norm() < tol * T(100));
    }
}

TEST_CASE_TEMPLATE("kinematic_tree: DOF layout, chains, limits and bad arguments", T, float, double) {
    const auto walk = read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    auto arm = kinematic_tree<T>::chain(walk.skeleton(), "LeftArm", "LeftHand");
    CHECK(arm.dofs() == 9);
    CHECK(arm.dof_name(0) == "LeftArm.x");
    CHECK(arm.joint_of_dof(8) == walk.skeleton().index_of("LeftHand"));
    const auto elbow = walk.skeleton().index_of("LeftForeArm");
    arm.set_hinge(elbow, {T(1), T(0), T(0)}, T(0), T(2.5));
    CHECK(arm.dofs() == 7);
    CHECK(arm.dof_name(3) == "LeftForeArm.hinge");
    CHECK(arm.lower()[3] == T(0));
    CHECK(arm.upper()[3] == T(2.5));
    ik_vector<T> q = ik_vector<T>::Constant(7, T(3));
    CHECK_FALSE(arm.within_limits(q));
    CHECK(arm.within_limits(arm.clamp(q)));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { arm.set_hinge(elbow, {0, 0, 0}); }),
                               "LeftForeArm"));
    CHECK(anima_test::contains(
        anima_test::invalid_argument_message([&] { arm.set_hinge(elbow, {1, 0, 0}, T(1), T(0)); }), "not a range"));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] {
                                   (void)kinematic_tree<T>::chain(walk.skeleton(), "LeftHand", "RightHand");
                               }),
                               "not an ancestor"));
    ik_vector<T> bad = ik_vector<T>::Zero(7);
    bad[2] = std::numeric_limits<T>::quiet_NaN();
    ik_state<T> s;
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { arm.forward(bad, s); }), "LeftArm.z"));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { arm.forward(ik_vector<T>::Zero(3), s); }),
                               "3 DOFs"));
    // A hinge keeps only the twist about its axis.
    auto one = walk.slice(0, 1);
    one.set_rotation(0, elbow, Eigen::Quaternion<T>(Eigen::AngleAxis<T>(T(0.7), Eigen::Matrix<T, 3, 1>::UnitX())));
    CHECK(arm.pose_of(one, 0)[3] == doctest::Approx(0.7).epsilon(1e-5));
}

TEST_CASE_TEMPLATE("goal_jacobian matches central differences (ball, hinge, root translation, pose goals)", T, float,
                   double) {
    const auto walk = read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    const auto& sk = walk.skeleton();
    kinematic_tree<T> tree(sk);
    tree.set_root_translation(true);
    tree.set_hinge(sk.index_of("LeftLeg"), {T(1), T(0), T(0)});
    tree.set_base(walk, 50);
    std::vector<ik_goal<T>> goals;
    goals.push_back(position_goal<T>(sk.index_of("LeftFoot"), Eigen::Matrix<T, 3, 1>::Zero(), {T(0), T(-1), T(2)}));
    goals.push_back(pose_goal(sk.index_of("RightHand"), Eigen::Matrix<T, 3, 1>::Zero(),
                              Eigen::Quaternion<T>::Identity(), T(7)));
    goals.push_back(orientation_goal(sk.index_of("Head"), Eigen::Quaternion<T>::Identity()));
    goals[1].weight = T(2);
    random_source rng(5);
    for (int trial = 0; trial < 4; ++trial) {
        ik_vector<T> q = tree.pose_of(walk, 50) + T(0.3) * anima_ik_test::random_q(tree, rng);
        if (trial == 3) q.setZero();  // the identity: the chart's Taylor branch
        const auto jac = goal_jacobian(tree, q, goals);
        const auto num = difference_jacobian(tree, q, goals, tolerance<T>(1e-6, 3e-3));
        const T scale = T(1) + num.cwiseAbs().maxCoeff();
        CHECK((jac - num).cwiseAbs().maxCoeff() < tolerance<T>(1e-6, 5e-2) * scale);
    }
}

TEST_CASE_TEMPLATE("goal_jacobian of line, plane, half-space and aim goals matches central differences", T, float,
                   double) {
    using v3 = Eigen::Matrix<T, 3, 1>;
    const auto walk = read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    const auto& sk = walk.skeleton();
    kinematic_tree<T> tree(sk);
    tree.set_root_translation(true);
    tree.set_base(walk, 50);
    std::vector<ik_goal<T>> goals{line_goal<T>(sk.index_of("LeftHand"), v3(1, 2, 3), v3(1, 1, 0)),
                                  plane_goal<T>(sk.index_of("RightHand"), v3(0, 5, 0), v3(0, 1, 1), v3(0, T(0.5), 0)),
                                  // the floor far above the foot: the half-space is violated, its row active
                                  half_space_goal<T>(sk.index_of("LeftFoot"), v3(0, 100, 0), v3(0, 1, 0)),
                                  aim_goal<T>(sk.index_of("Head"), v3(0, 0, 1), v3(1, 0, 1))};
    goals[3].weight = T(3);
    check_goals(tree, goals, "test");  // normalises the directions, as every solver does
    random_source rng(7);
    for (int trial = 0; trial < 3; ++trial) {
        const ik_vector<T> q = tree.pose_of(walk, 50) + T(0.3) * anima_ik_test::random_q(tree, rng);
        // These residuals are not raw positions and rotations: differentiate
        // goal_residual itself (its derivative is -J).
        const auto residual = [&](const ik_vector<T>& x, ik_vector<T>& r) {
            ik_state<T> s;
            tree.forward(x, s);
            goal_residual(s, goals, r);
        };
        const auto jac = goal_jacobian(tree, q, goals);
        const auto num = numeric_jacobian<T>(residual, q, tolerance<T>(1e-6, 3e-3));
        const T scale = T(1) + num.cwiseAbs().maxCoeff();
        CHECK((jac + num).cwiseAbs().maxCoeff() < tolerance<T>(1e-6, 5e-2) * scale);
    }
    // Satisfied half-space: no residual, no Jacobian rows.
    std::vector<ik_goal<T>> below{half_space_goal<T>(sk.index_of("LeftFoot"), v3(0, -100, 0), v3(0, 1, 0))};
    CHECK(goal_jacobian(tree, tree.pose_of(walk, 50), below).isZero());
    // A zero direction is refused by name.
    below[0].direction.setZero();
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)goal_jacobian(tree, tree.pose_of(walk, 50), below); }),
                               "non-zero"));
}

TEST_CASE_TEMPLATE("7-DOF arm: Jacobian of a hinge chain matches central differences", T, float, double) {
    const auto arm = anima_ik_test::seven_dof_arm<T>();
    std::vector<ik_goal<T>> goals{pose_goal(6, Eigen::Matrix<T, 3, 1>::Zero(), Eigen::Quaternion<T>::Identity())};
    goals[0].offset = anima_ik_test::arm_tip<T>();
    random_source rng(11);
    for (int trial = 0; trial < 5; ++trial) {
        const auto q = anima_ik_test::random_q(arm, rng);
        const auto jac = goal_jacobian(arm, q, goals);
        const auto num = difference_jacobian(arm, q, goals, tolerance<T>(1e-6, 3e-3));
        CHECK((jac - num).cwiseAbs().maxCoeff() < tolerance<T>(1e-7, 1e-2));
    }
}

TEST_CASE_TEMPLATE("goal_jacobian is minus numeric_jacobian of the residual (optimize module)", T, double, float) {
    const auto walk = read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    const auto& sk = walk.skeleton();
    auto tree = kinematic_tree<T>::chain(sk, "Hips", "RightHand");
    tree.set_root_translation(true);
    std::vector<ik_goal<T>> goals{position_goal<T>(sk.index_of("RightHand"), Eigen::Matrix<T, 3, 1>(T(1), T(2), T(3)))};
    const ik_vector<T> q = tree.pose_of(walk, 120);
    const auto residual = [&](const ik_vector<T>& x, ik_vector<T>& r) {
        ik_state<T> s;
        tree.forward(x, s);
        goal_residual(s, goals, r);
    };
    const auto num = numeric_jacobian<T>(residual, q, tolerance<T>(1e-6, 3e-3));
    const auto jac = goal_jacobian(tree, q, goals);
    CHECK((jac + num).cwiseAbs().maxCoeff() < tolerance<T>(1e-5, 5e-2) * (T(1) + num.cwiseAbs().maxCoeff()));
}

#ifdef ANIMA_HAVE_KDL
namespace {

KDL::Chain kdl_arm() {
    KDL::Chain chain;
    const auto offsets = anima_ik_test::arm_offsets<double>();
    const auto tip = anima_ik_test::arm_tip<double>();
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None),
                                  KDL::Frame(KDL::Vector(offsets[0].x(), offsets[0].y(), offsets[0].z()))));
    for (int i = 0; i < 7; ++i) {
        const auto next = i < 6 ? offsets[static_cast<std::size_t>(i + 1)] : tip;
        const auto type = anima_ik_test::arm_axis(i) == 2 ? KDL::Joint::RotZ : KDL::Joint::RotY;
        chain.addSegment(KDL::Segment(KDL::Joint(type), KDL::Frame(KDL::Vector(next.x(), next.y(), next.z()))));
    }
    return chain;
}

}  // namespace

TEST_CASE_TEMPLATE("7-DOF arm: FK and Jacobian agree with KDL on the equivalent chain", T, float, double) {
    const auto arm = anima_ik_test::seven_dof_arm<T>();
    const KDL::Chain chain = kdl_arm();
    KDL::ChainFkSolverPos_recursive fk(chain);
    KDL::ChainJntToJacSolver jac_solver(chain);
    std::vector<ik_goal<T>> goals{pose_goal(6, Eigen::Matrix<T, 3, 1>::Zero(), Eigen::Quaternion<T>::Identity())};
    goals[0].offset = anima_ik_test::arm_tip<T>();
    random_source rng(3);
    for (int trial = 0; trial < 20; ++trial) {
        const auto q = anima_ik_test::random_q(arm, rng);
        KDL::JntArray kq(7);
        for (int k = 0; k < 7; ++k) kq(static_cast<unsigned>(k)) = static_cast<double>(q[k]);
        KDL::Frame frame;
        REQUIRE(fk.JntToCart(kq, frame) >= 0);
        const auto tip = anima_ik_test::point_at(arm, q, 6, anima_ik_test::arm_tip<T>());
        for (int a = 0; a < 3; ++a) CHECK(static_cast<double>(tip[a]) == doctest::Approx(frame.p(static_cast<unsigned>(a))).epsilon(tolerance<T>(1e-12, 1e-5)));
        KDL::Jacobian kj(7);
        REQUIRE(jac_solver.JntToJac(kq, kj) >= 0);
        const auto jac = goal_jacobian(arm, q, goals);
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c < 7; ++c)
                CHECK(std::abs(static_cast<double>(jac(r, c)) - kj(static_cast<unsigned>(r), static_cast<unsigned>(c))) <
                      tolerance<T>(1e-12, 1e-5));
    }
}
#else
TEST_CASE("KDL comparison skipped") { MESSAGE("KDL (liborocos-kdl-dev) not found: FK/Jacobian comparison skipped"); }
#endif
