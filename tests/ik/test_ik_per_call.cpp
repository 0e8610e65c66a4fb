// The per-call forms of the IK solvers, for a game loop: solve_ik_into and
// solve_clip_frame_into give what solve_ik and solve_clip_ik give, bit for
// bit, whatever the workspace saw before, and allocate nothing once the
// workspace has seen the shapes. The step rules' in-place solves are checked
// against Eigen's own.

// Heap allocations are counted: this comes before any header that includes Eigen.
#include "../heap_count.hpp"

#include "../test_support.hpp"
#include "ik_test_support.hpp"

#include <anima/bvh.hpp>
#include <anima/ik/clip_ik.hpp>
#include <anima/ik/solve.hpp>
#include <anima/ik/step_rules.hpp>
#include <anima/motion.hpp>

#include <doctest/doctest.h>

#include <Eigen/LU>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace {

using anima_test::bundled;
using anima_test::tolerance;
using heap_count::allocations_in;

template <class T>
using point3 = Eigen::Matrix<T, 3, 1>;

/// Every field of two IK results, bit for bit.
template <class T>
void check_same_result(const anima::ik_result<T>& a, const anima::ik_result<T>& b) {
    REQUIRE(a.q.size() == b.q.size());
    CHECK(a.q == b.q);
    CHECK(a.status == b.status);
    CHECK(a.iterations == b.iterations);
    CHECK(a.attempts == b.attempts);
    CHECK(a.max_position_error == b.max_position_error);
    CHECK(a.max_angle_error == b.max_angle_error);
    CHECK(a.damping == b.damping);
    REQUIRE(a.singular_values.size() == b.singular_values.size());
    CHECK(a.singular_values == b.singular_values);
    REQUIRE(a.errors.size() == b.errors.size());
    for (std::size_t i = 0; i < a.errors.size(); ++i) {
        CHECK(a.errors[i].position == b.errors[i].position);
        CHECK(a.errors[i].angle == b.errors[i].angle);
    }
}

/// The arm every problem is posed on (built once per precision).
template <class T>
const anima::kinematic_tree<T>& arm_of() {
    static const anima::kinematic_tree<T> arm = anima_ik_test::seven_dof_arm<T>();
    return arm;
}

/// One IK problem on the 7-DOF arm: a reachable target from a random pose
/// (or the start's own tip: already solved), solved from another.
template <class T>
struct arm_problem {
    std::vector<anima::ik_goal<T>> goals;
    anima::ik_vector<T> start;
};

template <class T>
std::vector<arm_problem<T>> arm_problems(const anima::kinematic_tree<T>& arm, int count, std::uint64_t seed) {
    anima::random_source rng(seed);
    std::vector<arm_problem<T>> out;
    for (int i = 0; i < count; ++i) {
        const anima::ik_vector<T> goal_q = anima_ik_test::random_q(arm, rng), start = anima_ik_test::random_q(arm, rng);
        const auto tip = anima_ik_test::arm_tip<T>();
        // Every third problem starts where its goal is already met: no step is taken.
        const auto& at = i % 3 == 2 ? start : goal_q;
        out.push_back({{anima::position_goal<T>(6, anima_ik_test::point_at(arm, at, 6, tip), tip)}, start});
    }
    return out;
}

/// The rules a solve can take, each run through one function.
template <class T>
using rule_run = std::function<void(const arm_problem<T>&, const anima::ik_params<T>&, anima::ik_result<T>*,
                                    anima::ik_workspace<T>*, anima::ik_result<T>*)>;

template <class T, class Rule>
rule_run<T> run_with(Rule rule) {
    // into != nullptr: solve_ik_into into *into with *ws; fresh != nullptr: solve_ik into *fresh.
    return [rule](const arm_problem<T>& p, const anima::ik_params<T>& params, anima::ik_result<T>* into,
                  anima::ik_workspace<T>* ws, anima::ik_result<T>* fresh) {
        if (into) anima::solve_ik_into(arm_of<T>(), p.goals, p.start, rule, params, *into, *ws);
        if (fresh) *fresh = anima::solve_ik(arm_of<T>(), p.goals, p.start, rule, params);
    };
}

template <class T>
std::vector<rule_run<T>> library_rules() {
    typename anima::damped_least_squares<T>::params adaptive;
    adaptive.adaptive = true;
    anima::ik_vector<T> weights = anima::ik_vector<T>::Ones(7);
    weights[1] = T(50);
    return {run_with<T>(anima::pseudo_inverse<T>{}), run_with<T>(anima::damped_least_squares<T>{}),
            run_with<T>(anima::damped_least_squares<T>(adaptive)),
            run_with<T>(anima::weighted_rule<T, anima::pseudo_inverse<T>>(weights)),
            run_with<T>(anima::weighted_rule<T, anima::damped_least_squares<T>>(weights))};
}

template <class T>
anima::ik_params<T> arm_params(bool null_space) {
    anima::ik_params<T> p;
    p.tolerance = tolerance<T>(1e-8, 1e-4);
    p.max_iterations = 60;
    if (null_space) {
        p.null_space.gain = T(0.1);
        p.null_space.reference = anima::ik_vector<T>::Zero(7);
    }
    return p;
}

}  // namespace

TEST_CASE_TEMPLATE("solve_ik_into: one workspace through many solves gives each fresh solve's result bit for bit", T,
                   double, float) {
    const auto problems = arm_problems(arm_of<T>(), 12, 7);
    const auto rules = library_rules<T>();
    anima::ik_result<T> out;
    anima::ik_workspace<T> ws;
    // Rules, null-space task and problems interleaved, so each call meets
    // what another left in the workspace and in `out` (singular values of a
    // decomposing rule before a call that takes no step, another damping...).
    int solved_at_start = 0, decomposed = 0;
    for (std::size_t i = 0; i < problems.size() * rules.size(); ++i) {
        const auto& problem = problems[i % problems.size()];
        const auto params = arm_params<T>(i % 2 == 1);
        anima::ik_result<T> fresh;
        rules[(i * 3) % rules.size()](problem, params, &out, &ws, &fresh);
        CAPTURE(i);
        check_same_result(out, fresh);
        solved_at_start += out.iterations == 0;
        decomposed += out.singular_values.size() > 0;
    }
    CHECK(solved_at_start >= 10);  // the cases that clear the singular values happened
    CHECK(decomposed >= 10);

    // A square chain with jacobian_inverse, then the arm again: the workspace follows the shapes.
    anima::skeleton<T> sk;
    sk.add_joint("base", -1, point3<T>::Zero(), {anima::channel::z_rotation});
    sk.add_joint("shoulder", 0, point3<T>(0, 0, T(0.2)), {anima::channel::y_rotation});
    sk.add_joint("elbow", 1, point3<T>(0, 0, T(0.5)), {anima::channel::y_rotation});
    anima::kinematic_tree<T> chain(sk);
    chain.set_hinge(0, point3<T>::UnitZ());
    chain.set_hinge(1, point3<T>::UnitY());
    chain.set_hinge(2, point3<T>::UnitY());
    anima::ik_vector<T> q0(3), qg(3);
    q0 << T(0.1), T(0.4), T(0.8);
    qg << T(0.5), T(0.2), T(1.1);
    const point3<T> tip(0, 0, T(0.4));
    const std::vector<anima::ik_goal<T>> goals{
        anima::position_goal<T>(2, anima_ik_test::point_at(chain, qg, 2, tip), tip)};
    for (const auto& start : {q0, anima::ik_vector<T>(anima::ik_vector<T>::Zero(3))}) {  // regular, then singular
        anima::solve_ik_into(chain, goals, start, anima::jacobian_inverse<T>{}, arm_params<T>(false), out, ws);
        check_same_result(out, anima::solve_ik(chain, goals, start, anima::jacobian_inverse<T>{}, arm_params<T>(false)));
    }
    CHECK(out.status == anima::ik_status::singular);
    anima::ik_result<T> fresh;
    rules[0](problems[0], arm_params<T>(false), &out, &ws, &fresh);
    check_same_result(out, fresh);
}

TEST_CASE_TEMPLATE("solve_ik_into allocates nothing once it has seen the tree and the goal shapes", T, double, float) {
    const auto problems = arm_problems(arm_of<T>(), 9, 11);
    anima::ik_result<T> out;
    for (const auto& rule : library_rules<T>())
        for (bool null_space : {false, true}) {
            CAPTURE(null_space);
            anima::ik_workspace<T> ws;
            const auto params = arm_params<T>(null_space);
            // The first calls size the result and the workspace (a decomposing
            // call after one that took no step included)...
            for (const auto& p : problems) rule(p, params, &out, &ws, nullptr);
            // ... after which no call allocates, solved at the start or not.
            for (const auto& p : problems) {
                CHECK(allocations_in([&] { rule(p, params, &out, &ws, nullptr); }) == 0);
                CHECK(out.q.allFinite());
            }
        }
    // The counter does count: solve_ik allocates its result and scratch.
    anima::ik_result<T> fresh;
    CHECK(allocations_in([&] { library_rules<T>()[0](problems[0], arm_params<T>(false), nullptr, nullptr, &fresh); }) >
          0);
}

TEST_CASE_TEMPLATE("jacobian_inverse's in-place solve is FullPivLU::solve's; a singular J is reported", T, double,
                   float) {
    anima::random_source rng(5);
    anima::ik_step_scratch<T> scratch;
    for (int n : {3, 6, 6, 4}) {
        anima::ik_matrix<T> j(n, n);
        anima::ik_vector<T> e(n);
        for (int r = 0; r < n; ++r) {
            e[r] = static_cast<T>(rng.uniform() - 0.5);
            for (int c = 0; c < n; ++c) j(r, c) = static_cast<T>(rng.uniform() - 0.5) + (r == c ? T(1) : T(0));
        }
        anima::ik_vector<T> dq;
        anima::ik_step_info<T> info;
        anima::jacobian_inverse<T>{}(j, e, dq, info, scratch);
        const anima::ik_vector<T> reference = Eigen::FullPivLU<anima::ik_matrix<T>>(j).solve(e);
        CHECK_FALSE(info.singular);
        CHECK((dq - reference).norm() <= tolerance<T>(1e-13, 1e-5) * reference.norm());
        CHECK((j * dq - e).norm() <= tolerance<T>(1e-12, 1e-4));
        j.col(1) = j.col(0) * T(2);  // rank n - 1
        anima::jacobian_inverse<T>{}(j, e, dq, info, scratch);
        CHECK(info.singular);
        CHECK(dq.isZero());
    }
}

namespace {

/// The left hand moved by `by` at each of `frames` of the walk.
template <class T>
std::vector<anima::frame_goals<T>> hand_goals(const anima::clip<T>& walk, const std::vector<std::size_t>& frames,
                                              const point3<T>& by) {
    const std::size_t hand = walk.skeleton().index_of("LeftHand");
    std::vector<anima::frame_goals<T>> goals;
    for (std::size_t f : frames)
        goals.push_back({f, {anima::position_goal<T>(hand, anima::forward_kinematics(walk, f).positions[hand] + by)}});
    return goals;
}

template <class T>
anima::damped_least_squares<T> adaptive_dls() {
    typename anima::damped_least_squares<T>::params d;
    d.adaptive = true;
    return anima::damped_least_squares<T>(d);
}

}  // namespace

TEST_CASE_TEMPLATE("solve_clip_frame_into: solve_clip_ik's edit frame by frame, bit for bit, allocating nothing", T,
                   double, float) {
    const auto walk = anima::read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    // Two runs of consecutive frames with a gap: the warm start carries
    // within a run and not across the gap.
    std::vector<std::size_t> frames;
    for (std::size_t f = 10; f <= 24; ++f) frames.push_back(f);
    for (std::size_t f = 30; f <= 38; ++f) frames.push_back(f);
    const auto goals = hand_goals(walk, frames, point3<T>(T(0), T(2), T(1)));
    anima::clip_ik_params<T> params;
    params.ik.tolerance = tolerance<T>(1e-4, 1e-3);
    const auto rule = adaptive_dls<T>();
    const auto solve = [&](const anima::kinematic_tree<T>& tree, const std::vector<anima::ik_goal<T>>& g,
                           const anima::ik_vector<T>& start, const anima::ik_params<T>& p) {
        return anima::solve_ik(tree, g, start, rule, p);
    };
    for (bool warm : {true, false}) {
        CAPTURE(warm);
        params.warm_start = warm;
        const auto whole = anima::solve_clip_ik(anima::kinematic_tree<T>(walk.skeleton()), walk, goals, solve, params);
        REQUIRE(whole.converged_frames == goals.size());

        anima::kinematic_tree<T> tree(walk.skeleton());
        anima::clip<T> edited = walk;
        anima::ik_result<T> out;
        anima::clip_ik_workspace<T> ws;
        long allocated_after_first = 0;
        for (std::size_t i = 0; i < goals.size(); ++i) {
            const auto frame = [&] {
                anima::solve_clip_frame_into(tree, walk, goals[i].frame, goals[i].goals, rule, params, out, ws);
                tree.write_pose(out.q, edited, goals[i].frame);
            };
            if (i == 0) frame();
            else allocated_after_first += allocations_in(frame);
            CHECK(out.iterations == whole.results[i].iterations);
            CHECK(out.q == whole.results[i].q);
        }
        CHECK(allocated_after_first == 0);
        for (std::size_t f = 0; f < walk.frames(); ++f)
            for (std::size_t j = 0; j < walk.joints(); ++j)
                REQUIRE(edited.rotation(f, j).coeffs() == whole.edited.rotation(f, j).coeffs());
    }

    // reset() forgets the last frame: the next one starts from its recording,
    // as the first frame of a solve_clip_ik run does.
    params.warm_start = true;
    anima::kinematic_tree<T> tree(walk.skeleton());
    anima::ik_result<T> out;
    anima::clip_ik_workspace<T> ws;
    anima::solve_clip_frame_into(tree, walk, goals[0].frame, goals[0].goals, rule, params, out, ws);
    ws.reset();
    anima::solve_clip_frame_into(tree, walk, goals[1].frame, goals[1].goals, rule, params, out, ws);
    const auto alone =
        anima::solve_clip_ik(anima::kinematic_tree<T>(walk.skeleton()), walk, {goals[1]}, solve, params);
    CHECK(out.q == alone.results[0].q);
    CHECK(out.iterations == alone.results[0].iterations);

    // Bad input, named.
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] {
                                   anima::solve_clip_frame_into(tree, walk, 5, {}, rule, params, out, ws);
                               }),
                               "frame 5 has no goals"));
    auto bad = params;
    bad.pose_pull = T(-1);
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] {
                                   anima::solve_clip_frame_into(tree, walk, 5, goals[0].goals, rule, bad, out, ws);
                               }),
                               "anima::solve_clip_frame_into: pose_pull"));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] {
                                   anima::solve_clip_frame_into(tree, walk, walk.frames(), goals[0].goals, rule,
                                                                params, out, ws);
                               }),
                               "out of range"));
}
