// The Jacobian solvers (inverse, pseudo-inverse, DLS fixed and adaptive,
// weighted, null-space task) and quaternion CCD: reachable random targets
// on a 7-DOF arm and on CMU limbs converge to 1e-5 of the reach, limits
// hold, singular and unreachable cases end as documented, bad input throws.
#include "ik_test_support.hpp"
#include "../test_support.hpp"

#include <anima/bvh.hpp>
#include <anima/ik.hpp>
#include <anima/motion.hpp>

#include <doctest/doctest.h>

#include <glm/ext/quaternion_double.hpp>
#include <glm/ext/quaternion_float.hpp>
#include <glm/ext/vector_double3.hpp>
#include <glm/ext/vector_float3.hpp>

using namespace anima;
using anima_test::bundled;
using anima_test::tolerance;
using anima_ik_test::random_q;

namespace {

template <class T>
using vec3 = Eigen::Matrix<T, 3, 1>;

/// Solves `trials` reachable random targets of the arm's tip with `solve`
/// (a callable (tree, goals, q0) -> result) and returns the success count;
/// every result must be finite and within limits.
template <class T, class Solve>
int arm_successes(const kinematic_tree<T>& arm, int trials, T tol, Solve&& solve) {
    random_source rng(42);
    int ok = 0;
    for (int t = 0; t < trials; ++t) {
        const auto goal_q = random_q(arm, rng);
        const auto q0 = random_q(arm, rng);
        std::vector<ik_goal<T>> goals{
            position_goal<T>(6, anima_ik_test::point_at(arm, goal_q, 6, anima_ik_test::arm_tip<T>()),
                             anima_ik_test::arm_tip<T>())};
        const auto r = solve(arm, goals, q0);
        CHECK(r.q.allFinite());
        CHECK(arm.within_limits(r.q));
        CHECK(std::isfinite(r.max_position_error));
        // The reported error is the real one.
        CHECK(std::abs(r.max_position_error -
                       (anima_ik_test::point_at(arm, r.q, 6, anima_ik_test::arm_tip<T>()) - goals[0].position).norm()) <
              tolerance<T>(1e-12, 1e-5));
        if (r.converged()) {
            ++ok;
            CHECK(r.max_position_error <= tol);
        }
    }
    return ok;
}

template <class T>
ik_params<T> arm_params() {
    ik_params<T> p;
    p.tolerance = T(1e-5) * T(1.2);  // 1e-5 of the reach
    p.max_iterations = 100;
    p.restarts = 5;
    return p;
}

}  // namespace

TEST_CASE_TEMPLATE("7-DOF arm: every Jacobian rule and CCD reach random reachable targets within limits", T, double,
                   float) {
    const auto arm = anima_ik_test::seven_dof_arm<T>();
    auto p = arm_params<T>();
    if (std::is_same_v<T, float>) p.tolerance = T(2e-5);  // float FK carries ~1e-6 rounding
    // The first 16 of the same targets under the sanitizers.
    const int trials = anima_test::sanitized_build ? 16 : 40;
    const auto run = [&](auto rule) {
        return arm_successes(arm, trials, p.tolerance, [&](const auto& a, const auto& g, const auto& q0) {
            return solve_ik(a, g, q0, rule, p);
        });
    };
    CHECK(run(pseudo_inverse<T>{}) >= trials - 1);
    typename damped_least_squares<T>::params adaptive;
    adaptive.adaptive = true;
    CHECK(run(damped_least_squares<T>(adaptive)) >= trials - 1);
    typename damped_least_squares<T>::params fixed;
    fixed.damping = T(0.01);
    CHECK(run(damped_least_squares<T>(fixed)) >= trials - 2);
    ik_vector<T> w(7);
    w << T(4), T(1), T(1), T(1), T(1), T(1), T(0.5);
    CHECK(run(weighted_rule<T, damped_least_squares<T>>(w, damped_least_squares<T>(adaptive))) >= trials - 2);
    auto pc = p;
    pc.max_iterations = 300;
    const int ccd = arm_successes(arm, trials, p.tolerance, [&](const auto& a, const auto& g, const auto& q0) {
        return solve_ik_ccd(a, g, q0, pc);
    });
    CHECK(ccd >= trials * 3 / 4);
    bfgs_ik_params<T> pb;
    pb.ik = p;
    pb.ik.max_iterations = 200;
    const int bfgs = arm_successes(arm, trials, p.tolerance, [&](const auto& a, const auto& g, const auto& q0) {
        return solve_ik_bfgs(a, g, q0, pb);
    });
    CHECK(bfgs >= trials - 2);
    levenberg_marquardt_ik_params<T> pl;
    pl.ik = p;
    const int lm = arm_successes(arm, trials, p.tolerance, [&](const auto& a, const auto& g, const auto& q0) {
        return solve_ik_levenberg_marquardt(a, g, q0, pl);
    });
    CHECK(lm >= trials - 1);
}

TEST_CASE_TEMPLATE("Levenberg-Marquardt: pose goals on the 7-DOF arm, sine attempts and limits inside the step", T, double,
                   float) {
    // Position and orientation of the tip, as in bench_ik: both ways of
    // keeping the limits solve nearly all, never leave the limits, and
    // report converged exactly when the errors are within tolerance.
    const auto arm = anima_ik_test::seven_dof_arm<T>();
    const auto tip = anima_ik_test::arm_tip<T>();
    auto p = arm_params<T>();
    p.tolerance = tolerance<T>(1.2e-5, 2e-5);
    p.angle_tolerance = tolerance<T>(1e-5, 1e-4);
    const int trials = 40;
    const auto successes = [&](const levenberg_marquardt_ik_params<T>& pl) {
        random_source rng(7);
        int ok = 0;
        for (int t = 0; t < trials; ++t) {
            const auto goal_q = random_q(arm, rng);
            const auto q0 = random_q(arm, rng);
            ik_state<T> s;
            arm.forward(goal_q, s);
            auto g = pose_goal(std::size_t{6}, anima_ik_test::point_at(arm, goal_q, 6, tip), s.orientations[6], T(1.2));
            g.offset = tip;
            const auto r = solve_ik_levenberg_marquardt(arm, {g}, q0, pl);
            CHECK(r.q.allFinite());
            CHECK(arm.within_limits(r.q));
            const bool within = r.max_position_error <= p.tolerance && r.max_angle_error <= p.angle_tolerance;
            CHECK(r.converged() == within);
            CHECK(r.attempts <= p.restarts + 1);
            ok += r.converged();
        }
        return ok;
    };
    levenberg_marquardt_ik_params<T> pl;
    pl.ik = p;
    CHECK(successes(pl) >= trials - 1);
    pl.limits_in_step = true;
    CHECK(successes(pl) >= trials - 2);
    pl.limits_in_step = false;
    pl.polish_iterations = 0;
    CHECK(successes(pl) >= trials * 3 / 4);
    pl.stall_window = 0;
    CHECK_THROWS_AS(successes(pl), anima::invalid_argument);
    pl.stall_window = 6;
    pl.stall_decrease = T(1);
    CHECK_THROWS_AS(successes(pl), anima::invalid_argument);
}

TEST_CASE_TEMPLATE("Levenberg-Marquardt with the limits inside the step: closed form, limits, unreachable", T, double,
                   float) {
    // One hinge with the tip at (0, 0, 1) turning about y: a target at
    // angle 0.5 is reached exactly; one at angle 1.2 past the limit 1 ends
    // on the limit as the closest pose, not converged and never past it.
    skeleton<T> sk;
    sk.add_joint("a", -1, vec3<T>::Zero(), {channel::y_rotation});
    kinematic_tree<T> tree(sk);
    tree.set_hinge(0, vec3<T>::UnitY(), T(-1), T(1));
    const vec3<T> tip(0, 0, 1);
    levenberg_marquardt_ik_params<T> pl;
    pl.ik.tolerance = tolerance<T>(1e-9, 1e-5);
    pl.limits_in_step = true;
    const ik_vector<T> q0 = ik_vector<T>::Zero(1);
    const auto at = [&](T angle) { return vec3<T>(std::sin(angle), 0, std::cos(angle)); };
    const auto inside = solve_ik_levenberg_marquardt(tree, {position_goal<T>(0, at(T(0.5)), tip)}, q0, pl);
    CHECK(inside.converged());
    CHECK(inside.q[0] == doctest::Approx(0.5).epsilon(tolerance<T>(1e-8, 1e-4)));
    for (const bool in_step : {true, false}) {
        pl.limits_in_step = in_step;
        const auto past = solve_ik_levenberg_marquardt(tree, {position_goal<T>(0, at(T(1.2)), tip)}, q0, pl);
        CHECK(!past.converged());
        CHECK(past.q.allFinite());
        CHECK(past.q[0] <= T(1));
        CHECK(past.q[0] == doctest::Approx(1.0).epsilon(tolerance<T>(1e-6, 1e-4)));
        CHECK(past.max_position_error == doctest::Approx(2 * std::sin(0.1)).epsilon(1e-3));
    }
}

TEST_CASE_TEMPLATE("jacobian_inverse: square regular chain converges; a singular one says so", T, double, float) {
    // Base yaw, shoulder and elbow pitch: 3 DOFs for a 3D position.
    skeleton<T> sk;
    sk.add_joint("base", -1, vec3<T>::Zero(), {channel::z_rotation});
    sk.add_joint("shoulder", 0, vec3<T>(0, 0, T(0.2)), {channel::y_rotation});
    sk.add_joint("elbow", 1, vec3<T>(0, 0, T(0.5)), {channel::y_rotation});
    kinematic_tree<T> tree(sk);
    tree.set_hinge(0, vec3<T>::UnitZ());
    tree.set_hinge(1, vec3<T>::UnitY());
    tree.set_hinge(2, vec3<T>::UnitY());
    const vec3<T> tip(0, 0, T(0.4));
    ik_vector<T> q0(3), qg(3);
    q0 << T(0.1), T(0.4), T(0.8);
    qg << T(0.5), T(0.2), T(1.1);
    std::vector<ik_goal<T>> goals{position_goal<T>(2, anima_ik_test::point_at(tree, qg, 2, tip), tip)};
    ik_params<T> p;
    p.tolerance = tolerance<T>(1e-9, 2e-6);
    const auto r = solve_ik(tree, goals, q0, jacobian_inverse<T>{}, p);
    CHECK(r.converged());
    CHECK(r.iterations <= 10);  // Newton: quadratic convergence
    // Straight up, the base yaw moves nothing: J has a zero column.
    const auto s = solve_ik(tree, goals, ik_vector<T>::Zero(3), jacobian_inverse<T>{}, p);
    CHECK(s.status == ik_status::singular);
    CHECK(s.q.allFinite());
    // A non-square J is refused with a message saying what to use instead.
    goals.push_back(goals[0]);
    CHECK(anima_test::contains(
        anima_test::invalid_argument_message([&] { (void)solve_ik(tree, goals, q0, jacobian_inverse<T>{}, p); }),
        "not square"));
}

TEST_CASE_TEMPLATE("singular and unreachable: stretched arm, target out of reach", T, double, float) {
    const auto arm = anima_ik_test::seven_dof_arm<T>();
    const ik_vector<T> straight = ik_vector<T>::Zero(7);  // fully stretched along +z: J loses rank
    const T reach = T(1.2);
    // Target further along the stretched direction: unreachable.
    std::vector<ik_goal<T>> far{position_goal<T>(6, vec3<T>(0, 0, T(1.5)), anima_ik_test::arm_tip<T>())};
    typename damped_least_squares<T>::params adaptive;
    adaptive.adaptive = true;
    const auto r = solve_ik(arm, far, straight, damped_least_squares<T>(adaptive), arm_params<T>());
    CHECK(r.status == ik_status::unreachable_closest);
    CHECK(r.q.allFinite());
    CHECK(r.max_position_error == doctest::Approx(1.5 - 1.2).epsilon(1e-4));
    // The stretched arm's Jacobian has rank 2: its third singular value is 0.
    auto once = arm_params<T>();
    once.max_iterations = 1;
    once.restarts = 0;
    const auto first = solve_ik(arm, far, straight, pseudo_inverse<T>{}, once);
    REQUIRE(first.singular_values.size() == 3);
    // Straight up, only the three y hinges move the tip, all along x: rank 1.
    CHECK(first.singular_values[0] > T(0.1));
    CHECK(first.singular_values[1] < tolerance<T>(1e-12, 1e-5));
    // Target sideways from a stretched start: pinv and DLS both leave the
    // singular pose and converge, without NaN.
    std::vector<ik_goal<T>> side{position_goal<T>(6, vec3<T>(T(0.5), T(0.2), T(0.6)), anima_ik_test::arm_tip<T>())};
    for (const auto& rr : {solve_ik(arm, side, straight, pseudo_inverse<T>{}, arm_params<T>()),
                           solve_ik(arm, side, straight, damped_least_squares<T>(adaptive), arm_params<T>())}) {
        CHECK(rr.q.allFinite());
        CHECK(rr.converged());
    }
    // Levenberg-Marquardt from the singular pose: the closest pose for the
    // unreachable target, convergence for the sideways one.
    levenberg_marquardt_ik_params<T> pl;
    pl.ik = arm_params<T>();
    const auto lf = solve_ik_levenberg_marquardt(arm, far, straight, pl);
    CHECK(lf.status != ik_status::converged);
    CHECK(lf.q.allFinite());
    CHECK(lf.max_position_error == doctest::Approx(1.5 - 1.2).epsilon(1e-3));
    const auto ls = solve_ik_levenberg_marquardt(arm, side, straight, pl);
    CHECK(ls.q.allFinite());
    CHECK(ls.converged());
    pl.initial_damping = T(0);
    CHECK_THROWS_AS(solve_ik_levenberg_marquardt(arm, side, straight, pl), anima::invalid_argument);
    // A target far away elsewhere: Gauss-Newton approaches the closest pose
    // (arm pointing at it) slowly and says it stopped short.
    std::vector<ik_goal<T>> away{position_goal<T>(6, vec3<T>(T(3), T(1), T(2)), anima_ik_test::arm_tip<T>())};
    auto p = arm_params<T>();
    p.restarts = 0;
    const auto u = solve_ik(arm, away, straight, damped_least_squares<T>(adaptive), p);
    CHECK(u.status == ik_status::unreachable_closest);
    CHECK(u.max_position_error >= away[0].position.norm() - reach - T(1e-5));
    CHECK(u.max_position_error < T(1.1) * (away[0].position.norm() - reach));
}

TEST_CASE_TEMPLATE("every solver's attempts: a solved start is kept, restarts only while the goals are missed", T, double,
                   float) {
    // The attempts loop all five solvers share (detail::solve_with_attempts).
    const auto arm = anima_ik_test::seven_dof_arm<T>();
    random_source rng(7);
    const ik_vector<T> start = random_q(arm, rng);
    const vec3<T> there = anima_ik_test::point_at(arm, start, 6, anima_ik_test::arm_tip<T>());
    std::vector<ik_goal<T>> met{position_goal<T>(6, there, anima_ik_test::arm_tip<T>())};
    std::vector<ik_goal<T>> far{position_goal<T>(6, vec3<T>(T(3), T(1), T(2)), anima_ik_test::arm_tip<T>())};
    auto p = arm_params<T>();
    p.restarts = 3;
    p.max_iterations = 30;
    for (const ik_solver solver : ik_solvers) {
        CAPTURE(to_string(solver));
        // The start meets the goal: one attempt, no iteration, the start itself.
        const auto kept = solve_ik_with(solver, arm, met, start, p);
        CHECK(kept.converged());
        CHECK(kept.attempts == 1);
        CHECK(kept.iterations == 0);
        CHECK(kept.q == arm.clamp(start));
        // Out of reach: every restart is taken, and the best pose is no
        // worse than the start.
        const auto missed = solve_ik_with(solver, arm, far, start, p);
        CHECK(!missed.converged());
        CHECK(missed.attempts == p.restarts + 1);
        CHECK(missed.iterations > 0);
        CHECK(missed.q.allFinite());
        CHECK(missed.max_position_error <=
              (anima_ik_test::point_at(arm, start, 6, anima_ik_test::arm_tip<T>()) - far[0].position).norm());
        CHECK(missed.max_position_error >= far[0].position.norm() - T(1.2) - T(1e-4));
        // The same seed, the same restarts.
        CHECK(solve_ik_with(solver, arm, far, start, p).q == missed.q);
    }
}

TEST_CASE_TEMPLATE("joint limits are held inside the solve and never violated", T, double, float) {
    auto arm = anima_ik_test::seven_dof_arm<T>();
    for (int i = 0; i < 7; ++i) arm.set_hinge(static_cast<std::size_t>(i), vec3<T>::Unit(anima_ik_test::arm_axis(i)), T(-0.4), T(0.4));
    random_source rng(9);
    int converged = 0, converged_bfgs = 0, converged_lm = 0;
    // 20 targets; 6 under the sanitizers, where only the limits are checked.
    const int targets = anima_test::sanitized_build ? 6 : 20;
    for (int t = 0; t < targets; ++t) {
        const auto qg = random_q(arm, rng);
        std::vector<ik_goal<T>> goals{
            position_goal<T>(6, anima_ik_test::point_at(arm, qg, 6, anima_ik_test::arm_tip<T>()), anima_ik_test::arm_tip<T>())};
        const auto r = solve_ik(arm, goals, ik_vector<T>::Zero(7), pseudo_inverse<T>{}, arm_params<T>());
        CHECK(arm.within_limits(r.q));
        converged += r.converged();
        const auto c = solve_ik_ccd(arm, goals, ik_vector<T>::Zero(7), arm_params<T>());
        CHECK(arm.within_limits(c.q));
        bfgs_ik_params<T> pb;
        pb.ik = arm_params<T>();
        pb.ik.tolerance = tolerance<T>(1.2e-5, 5e-5);  // float: f = |r|^2 / 2 runs out of digits first
        const auto b = solve_ik_bfgs(arm, goals, ik_vector<T>::Zero(7), pb);
        CHECK(arm.within_limits(b.q));
        converged_bfgs += b.converged();
        levenberg_marquardt_ik_params<T> pl;
        pl.ik = arm_params<T>();
        const auto l = solve_ik_levenberg_marquardt(arm, goals, ik_vector<T>::Zero(7), pl);
        CHECK(arm.within_limits(l.q));
        CHECK(l.q.allFinite());
        converged_lm += l.converged();
    }
    if (anima_test::sanitized_build) return;
    CHECK(converged_lm >= 18);
    CHECK(converged >= 18);
    // In float, BFGS on |r|^2 / 2 stalls near 1e-4 of the reach: only double is held to the tolerance.
    if (std::is_same_v<T, double>) CHECK(converged_bfgs >= 18);
    // Target needing joints beyond their limits: the closest pose within them.
    std::vector<ik_goal<T>> behind{position_goal<T>(6, vec3<T>(0, 0, T(-1)), anima_ik_test::arm_tip<T>())};
    const auto r = solve_ik(arm, behind, ik_vector<T>::Zero(7), pseudo_inverse<T>{}, arm_params<T>());
    CHECK_FALSE(r.converged());
    CHECK(arm.within_limits(r.q));
}

TEST_CASE_TEMPLATE("null-space task keeps the solution nearer the reference pose", T, double, float) {
    const auto arm = anima_ik_test::seven_dof_arm<T>();
    random_source rng(21);
    T with = 0, without = 0;
    for (int t = 0; t < 10; ++t) {
        const ik_vector<T> ref = T(0.5) * random_q(arm, rng);
        ik_vector<T> qg = ref;
        qg[1] += T(0.3);
        qg[3] -= T(0.3);
        std::vector<ik_goal<T>> goals{
            position_goal<T>(6, anima_ik_test::point_at(arm, qg, 6, anima_ik_test::arm_tip<T>()), anima_ik_test::arm_tip<T>())};
        auto p = arm_params<T>();
        p.restarts = 0;
        const ik_vector<T> start = ref + T(0.6) * random_q(arm, rng) / T(2.9);  // elsewhere
        const auto plain = solve_ik(arm, goals, start, pseudo_inverse<T>{}, p);
        p.null_space.gain = T(0.2);
        p.null_space.reference = ref;
        const auto pulled = solve_ik(arm, goals, start, pseudo_inverse<T>{}, p);
        REQUIRE(plain.converged());
        REQUIRE(pulled.converged());
        without += (plain.q - ref).norm();
        with += (pulled.q - ref).norm();
    }
    CHECK(with < T(0.7) * without);
}

TEST_CASE_TEMPLATE("orientation and pose goals; glm and Eigen quaternions give the same goal", T, double, float) {
    const auto arm = anima_ik_test::seven_dof_arm<T>();
    random_source rng(8);
    const auto qg = random_q(arm, rng);
    ik_state<T> s;
    arm.forward(qg, s);
    const Eigen::Quaternion<T> target = s.orientations[6];
    glm::qua<T> gq;
    gq.w = target.w();
    gq.x = target.x();
    gq.y = target.y();
    gq.z = target.z();
    CHECK(orientation_goal(6, gq).orientation.coeffs() == orientation_goal(6, target).orientation.coeffs());
    std::vector<ik_goal<T>> goals{pose_goal(6, anima_ik_test::point_at(arm, qg, 6, anima_ik_test::arm_tip<T>()), gq, T(0.5))};
    goals[0].offset = anima_ik_test::arm_tip<T>();
    auto p = arm_params<T>();
    p.angle_tolerance = tolerance<T>(1e-7, 1e-4);
    p.tolerance = tolerance<T>(1e-6, 3e-5);
    typename damped_least_squares<T>::params adaptive;
    adaptive.adaptive = true;
    const auto r = solve_ik(arm, goals, ik_vector<T>::Zero(7), damped_least_squares<T>(adaptive), p);
    CHECK(r.converged());
    CHECK(r.max_angle_error <= p.angle_tolerance);
}

/// Two goals are the same field for field.
template <class T>
void check_same_goal(const ik_goal<T>& a, const ik_goal<T>& b) {
    CHECK(a.kind == b.kind);
    CHECK(a.joint == b.joint);
    CHECK(a.offset == b.offset);
    CHECK(a.position == b.position);
    CHECK(a.direction == b.direction);
    CHECK(a.axis == b.axis);
    CHECK(a.orientation.coeffs() == b.orientation.coeffs());
    CHECK(a.orientation_scale == b.orientation_scale);
    CHECK(a.weight == b.weight);
}

TEST_CASE_TEMPLATE("goals from GLM vectors are the goals from Eigen vectors, and solve alike", T, double, float) {
    using gvec = glm::vec<3, T>;
    const auto glm_of = [](const vec3<T>& v) { return gvec(v.x(), v.y(), v.z()); };
    const vec3<T> point(T(0.3), T(-1.25), T(2)), direction(T(0), T(0.6), T(0.8)), offset(T(0.1), T(0), T(-0.2));
    const gvec gp = glm_of(point), gd = glm_of(direction), go = glm_of(offset);
    check_same_goal(position_goal(4, gp), position_goal(4, point));
    check_same_goal(position_goal(4, gp, go), position_goal(4, point, offset));
    check_same_goal(line_goal(2, gp, gd), line_goal(2, point, direction));
    check_same_goal(line_goal(2, gp, gd, go), line_goal(2, point, direction, offset));
    check_same_goal(plane_goal(3, gp, gd, go), plane_goal(3, point, direction, offset));
    check_same_goal(half_space_goal(5, gp, gd), half_space_goal(5, point, direction));
    check_same_goal(aim_goal(6, gd, gp), aim_goal(6, direction, point));
    const Eigen::Quaternion<T> turn(Eigen::AngleAxis<T>(T(0.7), direction));
    glm::qua<T> gturn;
    gturn.w = turn.w();
    gturn.x = turn.x();
    gturn.y = turn.y();
    gturn.z = turn.z();
    check_same_goal(pose_goal(6, gp, gturn, T(0.5)), pose_goal(6, point, turn, T(0.5)));
    check_same_goal(pose_goal(6, gp, turn), pose_goal(6, point, turn));
    // Solved from the same start, the GLM goal reaches the same pose.
    const auto arm = anima_ik_test::seven_dof_arm<T>();
    random_source rng(11);
    const vec3<T> target = anima_ik_test::point_at(arm, random_q(arm, rng), 6, anima_ik_test::arm_tip<T>());
    const auto p = arm_params<T>();
    const auto from_eigen = solve_ik(arm, {position_goal(6, target, anima_ik_test::arm_tip<T>())},
                                     ik_vector<T>::Zero(7), damped_least_squares<T>{}, p);
    const auto from_glm = solve_ik(arm, {position_goal(6, glm_of(target), glm_of(anima_ik_test::arm_tip<T>()))},
                                   ik_vector<T>::Zero(7), damped_least_squares<T>{}, p);
    CHECK(from_eigen.converged());
    CHECK(from_glm.q == from_eigen.q);
}

TEST_CASE_TEMPLATE("Levenberg-Marquardt IK meets a reachable target whatever the bones' length", T, double, float) {
    // Its damping is relative to J'J's diagonal, which grows as the bones
    // squared: scaled by it twice, a chain of 1e5-unit bones never left its
    // start ("unreachable" at 2.5 bone lengths) while the others met it.
    const std::vector<channel> rot{channel::z_rotation, channel::x_rotation, channel::y_rotation};
    for (const double length : {1.0, 1e3, 1e5}) {
        CAPTURE(length);
        const T bone = static_cast<T>(length);
        skeleton<T> sk;
        sk.add_joint("root", -1, vec3<T>::Zero(), rot);
        sk.add_joint("a", 0, vec3<T>(T(0), bone, T(0)), rot);
        sk.add_joint("b", 1, vec3<T>(T(0), bone, T(0)), rot);
        sk.add_joint("c", 2, vec3<T>(T(0), bone, T(0)));
        const kinematic_tree<T> tree(sk);
        ik_vector<T> aim(tree.dofs());
        for (int i = 0; i < tree.dofs(); ++i) aim[i] = T(0.3) * static_cast<T>(i % 3 - 1) + T(0.1);
        ik_state<T> s;
        tree.forward(aim, s);
        ik_params<T> p;
        p.tolerance = T(1e-4) * bone;
        const auto r = solve_ik_with<T>(ik_solver::levenberg_marquardt, tree, {position_goal<T>(3, s.positions[3])},
                                        ik_vector<T>::Zero(tree.dofs()), p);
        CHECK(r.converged());
        CHECK(r.max_position_error <= p.tolerance);
    }
}

TEST_CASE_TEMPLATE("CCD with orientation, pose and aim goals on the CMU arm", T, double, float) {
    const auto walk = read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    const auto arm = anima_ik_test::cmu_left_arm(walk);
    const std::size_t hand = walk.skeleton().index_of("LeftHand");
    ik_params<T> p;
    p.tolerance = tolerance<T>(1e-6, 1e-4);
    p.angle_tolerance = tolerance<T>(1e-6, 1e-4);
    p.max_iterations = 500;
    random_source rng(3);
    int converged = 0;
    for (int trial = 0; trial < 10; ++trial) {
        const auto qg = random_q(arm, rng, T(0.8));
        ik_state<T> s;
        arm.forward(qg, s);
        // The hand's own ball joint takes the orientation, the shoulder and
        // elbow the position (the hand's point is its joint).
        const std::vector<ik_goal<T>> pose{pose_goal(hand, s.positions[hand], s.orientations[hand])};
        const auto r = solve_ik_ccd(arm, pose, ik_vector<T>::Zero(arm.dofs()), p);
        converged += r.converged();
        CHECK(arm.within_limits(r.q, T(1e-6)));
        // An orientation goal alone: one sweep.
        const auto o = solve_ik_ccd(arm, {orientation_goal(hand, s.orientations[hand])}, ik_vector<T>::Zero(arm.dofs()), p);
        CHECK(o.converged());
        CHECK(o.iterations <= 2);
        // Aim: the hand's x axis along world -y.
        const auto a = solve_ik_ccd(arm, {aim_goal<T>(hand, Eigen::Matrix<T, 3, 1>::UnitX(), -Eigen::Matrix<T, 3, 1>::UnitY())},
                                    qg, p);
        CHECK(a.converged());
        ik_state<T> sa;
        arm.forward(a.q, sa);
        CHECK((sa.orientations[hand] * Eigen::Matrix<T, 3, 1>::UnitX()).y() < T(-1) + tolerance<T>(1e-9, 1e-5));
    }
    CHECK(converged >= 8);  // 8 of 10 in double: CCD stalls short of the others
}

TEST_CASE_TEMPLATE("CCD moves a translating root: out-of-reach targets are met, the limbs share a reachable one", T,
                   double, float) {
    const auto walk = read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    const auto& sk = walk.skeleton();
    const std::size_t hand = sk.index_of("LeftHand");
    kinematic_tree<T> body(sk);
    body.set_root_translation(true);
    body.set_base(walk, 40);
    const ik_vector<T> q0 = body.pose_of(walk, 40);
    ik_state<T> s0;
    body.forward(q0, s0);
    ik_params<T> p;
    p.tolerance = tolerance<T>(1e-6, 1e-3);
    p.max_iterations = 200;
    // 30 units ahead of the hand, beyond the arm's reach (the figure is about
    // 30 units tall): CCD used to leave the root where it was ("unreachable").
    const vec3<T> far = s0.positions[hand] + vec3<T>(0, 0, 30);
    const auto r = solve_ik_ccd(body, {position_goal<T>(hand, far)}, q0, p);
    CHECK(r.converged());
    ik_state<T> s;
    body.forward(r.q, s);
    CHECK((s.positions[hand] - far).norm() <= p.tolerance * T(1.01));
    CHECK((r.q.template head<3>() - q0.template head<3>()).norm() > T(1));
    // Without root translation the same target is out of reach.
    kinematic_tree<T> fixed_root(sk);
    fixed_root.set_base(walk, 40);
    CHECK_FALSE(solve_ik_ccd(fixed_root, {position_goal<T>(hand, far)}, fixed_root.pose_of(walk, 40), p).converged());
    // A target 2 units away, within the arm's reach: the root takes what the
    // limbs' swings leave of each sweep (about 1 unit here), not all of it.
    const vec3<T> near = s0.positions[hand] + vec3<T>(0, 0, 2);
    const auto rn = solve_ik_ccd(body, {position_goal<T>(hand, near)}, q0, p);
    CHECK(rn.converged());
    CHECK((rn.q.template head<3>() - q0.template head<3>()).norm() < T(1.5));
}

namespace {

/// One hinge about z at the origin carrying a point at (L, 0, 0): the point
/// is on the circle (L cos t, L sin t, 0), so every goal type below has a
/// closed-form answer.
template <class T>
kinematic_tree<T> one_hinge(T length) {
    skeleton<T> sk;
    sk.add_joint("j", -1, Eigen::Matrix<T, 3, 1>::Zero(), {channel::z_rotation, channel::y_rotation, channel::x_rotation});
    sk.set_end_site(0, Eigen::Matrix<T, 3, 1>(length, 0, 0));
    kinematic_tree<T> tree(sk);
    tree.set_hinge(0, Eigen::Matrix<T, 3, 1>::UnitZ());
    return tree;
}

}  // namespace

TEST_CASE_TEMPLATE("line, plane, half-space and aim goals reach their closed-form solutions", T, double, float) {
    using v3 = Eigen::Matrix<T, 3, 1>;
    const T length = T(2), a = T(1.2), b = T(0.8);
    const auto tree = one_hinge<T>(length);
    const v3 tip(length, 0, 0);
    ik_params<T> p;
    p.tolerance = tolerance<T>(1e-9, 1e-5);
    p.angle_tolerance = tolerance<T>(1e-9, 1e-5);
    p.max_step = T(0.2);
    ik_vector<T> q0(1);
    q0 << T(0.3);
    const auto angle_of = [&](const std::vector<ik_goal<T>>& goals, const ik_vector<T>& start) {
        const auto r = solve_ik(tree, goals, start, pseudo_inverse<T>{}, p);
        CHECK(r.converged());
        return r.q[0];
    };
    const T tol = tolerance<T>(1e-7, 1e-3);
    // On the plane x = a (and on the line x = a, z = 0 along y): cos t = a / L.
    CHECK(angle_of({plane_goal<T>(0, v3(a, 5, 7), v3(-3, 0, 0), tip)}, q0) == doctest::Approx(std::acos(a / length)).epsilon(tol));
    CHECK(angle_of({line_goal<T>(0, v3(a, -4, 0), v3(0, 2, 0), tip)}, q0) == doctest::Approx(std::acos(a / length)).epsilon(tol));
    // Above y = b from below: the point stops on the boundary, sin t = b / L;
    // from inside, nothing moves.
    CHECK(angle_of({half_space_goal<T>(0, v3(0, b, 0), v3(0, 1, 0), tip)}, q0) == doctest::Approx(std::asin(b / length)).epsilon(tol));
    ik_vector<T> inside(1);
    inside << T(1.2);
    const auto still = solve_ik(tree, {half_space_goal<T>(0, v3(0, b, 0), v3(0, 1, 0), tip)}, inside, pseudo_inverse<T>{}, p);
    CHECK(still.converged());
    CHECK(still.iterations == 0);
    CHECK(still.q[0] == inside[0]);
    // Aim the local x axis along (cos 1, sin 1, 0): t = 1, for BFGS and LM too.
    const std::vector<ik_goal<T>> aim{aim_goal<T>(0, v3(1, 0, 0), v3(std::cos(T(1)), std::sin(T(1)), 0))};
    CHECK(angle_of(aim, q0) == doctest::Approx(1.0).epsilon(tol));
    // CCD meets the plane, the half-space and the aim in closed form too.
    const auto ccd_angle = [&](const std::vector<ik_goal<T>>& goals) {
        const auto r = solve_ik_ccd(tree, goals, q0, p);
        CHECK(r.converged());
        return r.q[0];
    };
    CHECK(ccd_angle({plane_goal<T>(0, v3(a, 5, 7), v3(-3, 0, 0), tip)}) == doctest::Approx(std::acos(a / length)).epsilon(tol));
    CHECK(ccd_angle({half_space_goal<T>(0, v3(0, b, 0), v3(0, 1, 0), tip)}) == doctest::Approx(std::asin(b / length)).epsilon(tol));
    CHECK(ccd_angle(aim) == doctest::Approx(1.0).epsilon(tol));
    bfgs_ik_params<T> bp;
    bp.ik = p;
    levenberg_marquardt_ik_params<T> lp;
    lp.ik = p;
    CHECK(solve_ik_bfgs(tree, aim, q0, bp).q[0] == doctest::Approx(1.0).epsilon(tolerance<T>(1e-5, 1e-3)));
    CHECK(solve_ik_levenberg_marquardt(tree, aim, q0, lp).q[0] == doctest::Approx(1.0).epsilon(tolerance<T>(1e-5, 1e-3)));
    // A goal the hinge cannot meet (plane x = 3 > L): the closest pose, t = 0.
    const auto far = solve_ik_bfgs(tree, {plane_goal<T>(0, v3(3, 0, 0), v3(1, 0, 0), tip)}, q0, bp);
    CHECK(!far.converged());
    CHECK(std::abs(far.q[0]) < tolerance<T>(1e-3, 1e-2));
    CHECK(far.max_position_error == doctest::Approx(1.0).epsilon(tolerance<T>(1e-5, 1e-3)));
}

TEST_CASE_TEMPLATE("CMU whole body: feet above the floor, head aimed, hands on a line and a plane", T, double, float) {
    using v3 = Eigen::Matrix<T, 3, 1>;
    const auto walk = read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    const auto& sk = walk.skeleton();
    kinematic_tree<T> tree(sk);
    tree.set_fixed(0);
    tree.set_base(walk, 100);
    const auto truth = forward_kinematics(walk, 100);
    const T floor = truth.positions[sk.index_of("LeftFoot")].y() + T(1);  // one unit above the left foot
    const v3 hand = truth.positions[sk.index_of("LeftHand")];
    std::vector<ik_goal<T>> goals{half_space_goal<T>(sk.index_of("LeftFoot"), v3(0, floor, 0), v3(0, 1, 0)),
                                  half_space_goal<T>(sk.index_of("RightFoot"), v3(0, floor, 0), v3(0, 1, 0)),
                                  aim_goal<T>(sk.index_of("Head"), v3(0, 0, 1), v3(1, 0, 1)),
                                  line_goal<T>(sk.index_of("LeftHand"), hand + v3(2, 0, 0), v3(0, 0, 1)),
                                  plane_goal<T>(sk.index_of("RightHand"), v3(0, hand.y() + 3, 0), v3(0, 1, 0))};
    ik_params<T> p;
    p.tolerance = tolerance<T>(1e-5, 1e-3);
    p.angle_tolerance = tolerance<T>(1e-5, 1e-3);
    p.max_iterations = 300;
    const auto r = solve_ik(tree, goals, tree.pose_of(walk, 100), damped_least_squares<T>{}, p);
    CHECK(r.converged());
    ik_state<T> s;
    tree.forward(r.q, s);
    const T tol = T(2) * p.tolerance;
    CHECK(s.positions[sk.index_of("LeftFoot")].y() >= floor - tol);
    CHECK(s.positions[sk.index_of("RightFoot")].y() >= floor - tol);
    const v3 look = s.orientations[sk.index_of("Head")] * v3(0, 0, 1);
    CHECK(look.dot(v3(1, 0, 1).normalized()) > T(1) - T(4) * p.angle_tolerance);
    const v3 lh = s.positions[sk.index_of("LeftHand")] - (hand + v3(2, 0, 0));
    CHECK(std::hypot(lh.x(), lh.y()) < tol);
    CHECK(std::abs(s.positions[sk.index_of("RightHand")].y() - (hand.y() + T(3))) < tol);
}

TEST_CASE_TEMPLATE("CMU limbs and the whole body reach real poses' effector positions", T, double, float) {
    const auto walk = read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    const auto& sk = walk.skeleton();
    const vec3<T> hand_tip = sk[sk.index_of("LeftFingerBase")].offset;
    const auto arm = anima_ik_test::cmu_left_arm(walk);
    const T reach = anima_ik_test::chain_length(sk, sk.index_of("LeftArm"), sk.index_of("LeftHand"), hand_tip);
    auto p = arm_params<T>();
    p.tolerance = (std::is_same_v<T, float> ? T(1e-4) : T(1e-5)) * reach;
    typename damped_least_squares<T>::params adaptive;
    adaptive.adaptive = true;
    adaptive.threshold = T(0.1) * reach;
    adaptive.damping = T(0.05) * reach;
    random_source rng(4);
    int ok = 0;
    for (int t = 0; t < 30; ++t) {
        const auto qg = random_q(arm, rng);
        std::vector<ik_goal<T>> goals{position_goal<T>(sk.index_of("LeftHand"),
                                                       anima_ik_test::point_at(arm, qg, sk.index_of("LeftHand"), hand_tip), hand_tip)};
        const auto r = solve_ik(arm, goals, arm.pose_of(walk, 0), damped_least_squares<T>(adaptive), p);
        CHECK(arm.within_limits(r.q));
        ok += r.converged();
    }
    CHECK(ok >= 29);

    // Whole body, root free: both hands and feet to frame 250's positions from frame 30's pose.
    kinematic_tree<T> body(sk);
    body.set_root_translation(true);
    body.set_base(walk, 30);
    const auto truth = forward_kinematics(walk, 250);
    std::vector<ik_goal<T>> goals;
    for (const char* name : {"LeftHand", "RightHand", "LeftFoot", "RightFoot"})
        goals.push_back(position_goal<T>(sk.index_of(name), truth.positions[sk.index_of(name)]));
    auto pb = p;
    pb.tolerance = (std::is_same_v<T, float> ? T(1e-4) : T(1e-5)) * T(30);  // body height ~30 units
    const auto r = solve_ik(body, goals, body.pose_of(walk, 30), pseudo_inverse<T>{}, pb);
    CHECK(r.converged());
    auto out = walk;
    body.write_pose(r.q, out, 30);
    const auto solved = forward_kinematics(out, 30);
    for (const auto& g : goals) CHECK((solved.positions[g.joint] - g.position).norm() <= pb.tolerance * T(1.01));
}

TEST_CASE_TEMPLATE("solvers refuse bad goals, poses and parameters naming them", T, double, float) {
    const auto arm = anima_ik_test::seven_dof_arm<T>();
    const ik_vector<T> q0 = ik_vector<T>::Zero(7);
    std::vector<ik_goal<T>> goals{position_goal<T>(6, vec3<T>(T(0.3), 0, T(0.5)))};
    const auto msg = [&](auto&& f) { return anima_test::invalid_argument_message(f); };
    CHECK(anima_test::contains(msg([&] { (void)solve_ik(arm, {}, q0, pseudo_inverse<T>{}); }), "no goals"));
    auto nan_goal = goals;
    nan_goal[0].position.x() = std::numeric_limits<T>::quiet_NaN();
    CHECK(anima_test::contains(msg([&] { (void)solve_ik(arm, nan_goal, q0, pseudo_inverse<T>{}); }), "non-finite"));
    // Finite, but its squared distance overflows (1e300 in double, 1e30 in float).
    auto far_goal = goals;
    far_goal[0].position.y() = std::numeric_limits<T>::max() / T(1e8);
    CHECK(anima_test::contains(msg([&] { (void)solve_ik(arm, far_goal, q0, pseudo_inverse<T>{}); }), "too far out"));
    far_goal[0].position.y() = std::sqrt(std::numeric_limits<T>::max()) / T(4);  // its square is still finite
    CHECK_NOTHROW((void)solve_ik(arm, far_goal, q0, pseudo_inverse<T>{}));
    // A tree whose every joint is fixed has nothing to move: refused by every
    // solver (the SVD of its 3 x 0 Jacobian asserted in Eigen before).
    auto fixed = arm;
    for (std::size_t j = 0; j < fixed.skeleton().size(); ++j) fixed.set_fixed(j);
    REQUIRE(fixed.dofs() == 0);
    for (const anima::ik_solver solver : anima::ik_solvers)
        CHECK(anima_test::contains(msg([&] { (void)anima::solve_ik_with(solver, fixed, goals, ik_vector<T>()); }),
                                   "no free DOF"));
    auto bad_joint = goals;
    bad_joint[0].joint = 99;
    CHECK(anima_test::contains(msg([&] { (void)solve_ik(arm, bad_joint, q0, pseudo_inverse<T>{}); }), "99"));
    CHECK(anima_test::contains(msg([&] { (void)solve_ik(arm, goals, ik_vector<T>::Zero(4), pseudo_inverse<T>{}); }),
                               "4 DOFs"));
    ik_params<T> p;
    p.tolerance = T(-1e-7);  // printed exactly (std::to_string gave -0.000000)
    CHECK(msg([&] { (void)solve_ik(arm, goals, q0, pseudo_inverse<T>{}, p); }) ==
          "anima::solve_ik: ik_params::tolerance must be positive and finite, got -1e-07");
    p = ik_params<T>{};
    p.restarts = -2;
    CHECK(msg([&] { (void)solve_ik(arm, goals, q0, pseudo_inverse<T>{}, p); }) ==
          "anima::solve_ik: ik_params::restarts must be at least 0, got -2");
    p = ik_params<T>{};
    p.null_space.gain = T(1);
    p.null_space.reference = ik_vector<T>::Zero(3);
    CHECK(anima_test::contains(msg([&] { (void)solve_ik(arm, goals, q0, pseudo_inverse<T>{}, p); }), "null_space"));
    ik_vector<T> w = ik_vector<T>::Ones(7);
    w[2] = T(0);
    CHECK(anima_test::contains(msg([&] { (void)weighted_rule<T, pseudo_inverse<T>>(w); }), "weight 2"));
    CHECK(std::string(to_string(ik_status::unreachable_closest)) == "unreachable_closest");
}
