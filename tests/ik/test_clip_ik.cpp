// Clip-level IK (solve_clip_ik) on the bundled CMU walk, checked with the
// motion module's own forward kinematics, and the run-time solver choice
// (solve_ik_with) against every solver it names.
#include "../test_support.hpp"
#include "ik_test_support.hpp"

#include <anima/bvh.hpp>
#include <anima/ik/clip_ik.hpp>
#include <anima/ik/position_targets.hpp>
#include <anima/ik/solve_with.hpp>
#include <anima/motion.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace {

using anima_test::bundled;
using anima_test::tolerance;

template <class T>
using point3 = Eigen::Matrix<T, 3, 1>;

/// Largest frame-to-frame joint rotation change over frames first..last, in
/// long double from the quaternions' dot products (not the library's code).
template <class T>
long double reference_max_step(const anima::clip<T>& c, std::size_t first, std::size_t last) {
    long double worst = 0;
    for (std::size_t f = std::max<std::size_t>(first, 1); f <= std::min(last, c.frames() - 1); ++f)
        for (std::size_t j = 0; j < c.joints(); ++j) {
            const auto& a = c.rotation(f - 1, j);
            const auto& b = c.rotation(f, j);
            const long double d =
                std::abs(static_cast<long double>(a.w()) * b.w() + static_cast<long double>(a.x()) * b.x() +
                         static_cast<long double>(a.y()) * b.y() + static_cast<long double>(a.z()) * b.z());
            worst = std::max(worst, 2 * std::acos(std::min<long double>(d, 1)));
        }
    return worst;
}

/// A whole-body tree of the clip; the root's position follows the recording.
template <class T>
anima::kinematic_tree<T> body_tree(const anima::clip<T>& c) {
    return anima::kinematic_tree<T>(c.skeleton());
}

/// The left hand moved by `by` over frames first..last of the walk.
template <class T>
std::vector<anima::frame_goals<T>> hand_offset(const anima::clip<T>& walk, std::size_t first, std::size_t last,
                                               const point3<T>& by) {
    return anima::offset_goals(walk, walk.skeleton().index_of("LeftHand"), by, first, last);
}

/// Joint j's global position at frame f, composed along its parents here in
/// long double (not the library's forward kinematics).
template <class T>
Eigen::Matrix<long double, 3, 1> reference_position(const anima::clip<T>& c, std::size_t f, std::size_t j) {
    using quat = Eigen::Quaternion<long double>;
    const auto& sk = c.skeleton();
    std::vector<std::size_t> chain;  // j up to the root
    for (long k = static_cast<long>(j); k >= 0; k = sk[static_cast<std::size_t>(k)].parent) chain.push_back(static_cast<std::size_t>(k));
    Eigen::Matrix<long double, 3, 1> p = Eigen::Matrix<long double, 3, 1>::Zero();
    quat q = quat::Identity();
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
        const Eigen::Matrix<long double, 3, 1> local = c.translation(f, *it).template cast<long double>();
        p += q * local;
        q = q * c.rotation(f, *it).template cast<long double>();
    }
    return p;
}

template <class T>
auto dls() {
    return [](const anima::kinematic_tree<T>& tree, const std::vector<anima::ik_goal<T>>& goals,
              const anima::ik_vector<T>& start, const anima::ik_params<T>& p) {
        return anima::solve_ik_with(anima::ik_solver::damped_least_squares, tree, goals, start, p);
    };
}

TEST_CASE_TEMPLATE("offset_goals: every frame's goal is the recorded position plus the offset", T, float, double) {
    const auto walk = anima::read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    const std::size_t hand = walk.skeleton().index_of("LeftHand");
    const point3<T> by(T(0.5), T(2), T(-1));
    const auto goals = anima::offset_goals(walk, hand, by, 10, 40);
    REQUIRE(goals.size() == 31);
    const long double tol = tolerance<T>(1e-12, 1e-4) * 100;  // positions of about 100 units
    for (std::size_t i = 0; i < goals.size(); ++i) {
        CHECK(goals[i].frame == 10 + i);
        REQUIRE(goals[i].goals.size() == 1);
        const auto& g = goals[i].goals[0];
        CHECK(g.kind == anima::ik_goal_kind::position);
        CHECK(g.joint == hand);
        CHECK(g.offset == point3<T>::Zero());
        const Eigen::Matrix<long double, 3, 1> want =
            reference_position(walk, goals[i].frame, hand) + by.template cast<long double>();
        CHECK((g.position.template cast<long double>() - want).norm() <= tol);
    }
    // One frame; the root itself; a GLM offset gives the same goals.
    CHECK(anima::offset_goals(walk, hand, by, 7, 7).size() == 1);
    const auto root = anima::offset_goals(walk, 0, by, 0, 0);
    CHECK((root[0].goals[0].position - (walk.root_position(0) + by)).norm() <= T(tol));
    const auto from_glm = anima::offset_goals(walk, hand, glm::vec<3, T>(T(0.5), T(2), T(-1)), 10, 40);
    for (std::size_t i = 0; i < goals.size(); ++i) CHECK(from_glm[i].goals[0].position == goals[i].goals[0].position);

    using anima_test::contains;
    using anima_test::invalid_argument_message;
    const auto refused = [&](std::size_t joint, const point3<T>& offset, std::size_t first, std::size_t last) {
        return invalid_argument_message([&] { (void)anima::offset_goals(walk, joint, offset, first, last); });
    };
    CHECK(contains(refused(walk.joints(), by, 0, 1), "anima::offset_goals: joint must be a joint of the clip's 31"));
    CHECK(contains(refused(hand, by, 5, 4), "anima::offset_goals: first must be at most last (4), got 5"));
    CHECK(contains(refused(hand, by, 0, walk.frames()), "anima::offset_goals: last must be a frame of the clip's"));
    CHECK(contains(refused(hand, point3<T>(0, std::numeric_limits<T>::quiet_NaN(), 0), 0, 1),
                   "anima::offset_goals: offset must be finite"));
}

TEST_CASE_TEMPLATE("solve_clip_ik moves a hand over a range: targets reached, others untouched, warm starts pay", T,
                   float, double) {
    const auto walk = anima::read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    const std::size_t hand = walk.skeleton().index_of("LeftHand");
    const point3<T> by(T(0), T(2), T(0));  // 2 units = 11 cm up
    const auto goals = hand_offset(walk, 10, 40, by);
    anima::clip_ik_params<T> p;
    p.ik.tolerance = tolerance<T>(1e-4, 1e-3);
    std::size_t reported = 0;
    p.progress = [&](std::size_t done, std::size_t total) {
        CHECK(done == reported + 1);
        CHECK(total == goals.size());
        reported = done;
    };
    const auto r = anima::solve_clip_ik(body_tree(walk), walk, goals, dls<T>(), p);
    CHECK(reported == goals.size());
    REQUIRE(r.frames.size() == 31);
    CHECK(r.results.size() == 31);
    CHECK(r.converged_frames == 31);
    CHECK(r.largest_error <= p.ik.tolerance);
    for (std::size_t i = 0; i < r.frames.size(); ++i) {
        const std::size_t f = r.frames[i];
        CHECK(f == 10 + i);
        const point3<T> want = anima::forward_kinematics(walk, f).positions[hand] + by;
        CHECK((anima::forward_kinematics(r.edited, f).positions[hand] - want).norm() <= 2 * p.ik.tolerance);
    }
    for (std::size_t f = 0; f < walk.frames(); ++f) {
        if (f >= 10 && f <= 40) continue;
        for (std::size_t j = 0; j < walk.joints(); ++j) {
            CHECK(r.edited.rotation(f, j).coeffs() == walk.rotation(f, j).coeffs());
            CHECK(r.edited.translation(f, j) == walk.translation(f, j));
        }
    }
    // The smoothness report, against a brute-force recount.
    const T eps = tolerance<T>(1e-12, 2e-3);
    CHECK(std::abs(r.max_joint_step_before - T(reference_max_step(walk, 10, 41))) <= eps);
    CHECK(std::abs(r.max_joint_step_after - T(reference_max_step(r.edited, 10, 41))) <= eps);
    CHECK(anima::max_joint_step(walk, 10, 41) == r.max_joint_step_before);
    // A warm start carries the previous frame's correction: the next frame
    // starts near its solution and needs fewer iterations than from its
    // recorded pose.
    anima::clip_ik_params<T> cold = p;
    cold.warm_start = false;
    cold.progress = nullptr;
    const auto from_recording = anima::solve_clip_ik(body_tree(walk), walk, goals, dls<T>(), cold);
    CHECK(from_recording.converged_frames == 31);
    CHECK(r.iterations < from_recording.iterations);
}

TEST_CASE_TEMPLATE("solve_clip_ik: one-frame clips, no goals, unreachable targets and bad input", T, float, double) {
    const auto walk = anima::read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    const std::size_t hand = walk.skeleton().index_of("LeftHand");
    anima::clip_ik_params<T> p;
    p.ik.tolerance = tolerance<T>(1e-4, 1e-3);

    // One frame.
    const auto one = walk.slice(0, 1);
    const auto r1 = anima::solve_clip_ik(body_tree(one), one, hand_offset(one, 0, 0, point3<T>(1, 0, 0)), dls<T>(), p);
    CHECK(r1.converged_frames == 1);
    CHECK(r1.max_joint_step_before == 0);
    CHECK(r1.max_joint_step_after == 0);

    // No goals: the clip back, unchanged.
    const auto r0 = anima::solve_clip_ik(body_tree(walk), walk, {}, dls<T>(), p);
    CHECK(r0.frames.empty());
    CHECK(r0.edited.frames() == walk.frames());
    CHECK(r0.edited.rotation(100, 5).coeffs() == walk.rotation(100, 5).coeffs());

    // Out of reach: every frame reported as missed, the clip still finite.
    anima::kinematic_tree<T> fixed_root(walk.skeleton());  // the root cannot walk over to the target
    p.ik.max_iterations = 30;
    const auto far = anima::solve_clip_ik(fixed_root, walk,
                                          {{5, {anima::position_goal<T>(hand, point3<T>(0, 1000, 0))}},
                                           {6, {anima::position_goal<T>(hand, point3<T>(0, 1000, 0))}}},
                                          dls<T>(), p);
    CHECK(far.converged_frames == 0);
    CHECK(far.largest_error > T(900));
    for (std::size_t f : {5, 6})
        for (std::size_t j = 0; j < walk.joints(); ++j) CHECK(far.edited.rotation(f, j).coeffs().allFinite());

    const auto goal = anima::position_goal<T>(hand, point3<T>(0, 0, 0));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] {
                                   anima::solve_clip_ik(body_tree(walk), walk, {{343, {goal}}}, dls<T>(), p);
                               }),
                               "outside the clip"));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] {
                                   anima::solve_clip_ik(body_tree(walk), walk, {{5, {goal}}, {5, {goal}}}, dls<T>(), p);
                               }),
                               "ascending and distinct"));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] {
                                   anima::solve_clip_ik(body_tree(walk), walk, {{7, {goal}}, {3, {goal}}}, dls<T>(), p);
                               }),
                               "frame 3 follows frame 7"));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] {
                                   anima::solve_clip_ik(body_tree(walk), walk, {{5, {}}}, dls<T>(), p);
                               }),
                               "frame 5 has no goals"));
    auto bad = p;
    bad.pose_pull = T(-1);
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] {
                                   anima::solve_clip_ik(body_tree(walk), walk, {{5, {goal}}}, dls<T>(), bad);
                               }),
                               "pose_pull"));
    const auto run = anima::read_bvh<T>(bundled("run_cmu_09_01.bvh"));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] {
                                   anima::solve_clip_ik(body_tree(run), walk, {{5, {goal}}}, dls<T>(), p);
                               }),
                               "skeleton differs"));
}

TEST_CASE_TEMPLATE("solve_ik_with: every named solver reaches reachable targets on the 7-DOF arm", T, float, double) {
    for (const anima::ik_solver s : anima::ik_solvers) CHECK(anima::parse_ik_solver(anima::to_string(s)) == s);
    CHECK(anima::enum_name_list<anima::ik_solver>() == std::vector<std::string>{"pinv", "dls", "ccd", "bfgs", "lm"});
    CHECK(anima_test::contains(anima_test::invalid_argument_message([] { anima::parse_ik_solver("newton"); }),
                               "'newton' is not an IK solver: use pinv, dls, ccd, bfgs or lm"));

    const auto tree = anima_ik_test::seven_dof_arm<T>();
    anima::random_source rng(31);
    anima::ik_params<T> p;
    p.tolerance = tolerance<T>(1e-6, 1e-4);
    p.max_iterations = 500;
    p.restarts = 3;
    for (const anima::ik_solver s : anima::ik_solvers) {
        int reached = 0;
        for (int trial = 0; trial < 10; ++trial) {
            const auto target_q = anima_ik_test::random_q(tree, rng);
            const point3<T> target = anima_ik_test::point_at(tree, target_q, 6, anima_ik_test::arm_tip<T>());
            const auto r =
                anima::solve_ik_with(s, tree, {anima::position_goal<T>(6, target, anima_ik_test::arm_tip<T>())},
                                     anima::ik_vector<T>::Zero(tree.dofs()), p);
            CHECK(r.q.allFinite());
            CHECK(tree.within_limits(r.q, T(1e-6)));
            reached +=
                r.converged() &&
                (anima_ik_test::point_at(tree, r.q, 6, anima_ik_test::arm_tip<T>()) - target).norm() <= 2 * p.tolerance;
        }
        INFO(anima::to_string(s));
        CHECK(reached >= 8);
    }
}

}  // namespace
