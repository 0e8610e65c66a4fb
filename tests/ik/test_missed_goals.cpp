// missed_goals: the per-joint summary of goals a clip solve did not reach,
// on a solve result written by hand (frames, goals and errors chosen so that
// every count, worst error and worst frame is known), and the mismatches it
// refuses.
#include "../test_support.hpp"

#include <anima/core/error.hpp>
#include <anima/ik/clip_ik.hpp>
#include <anima/ik/goal.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <cstddef>
#include <limits>
#include <vector>

namespace {

using anima_test::contains;
using anima_test::invalid_argument_message;

/// One solved frame: a position goal on each of `joints`, ended at the
/// given position errors.
template <class T>
void add_frame(anima::clip_ik_result<T>& solved, std::vector<anima::frame_goals<T>>& goals, std::size_t frame,
               const std::vector<std::size_t>& joints, const std::vector<T>& errors) {
    anima::frame_goals<T> g{frame, {}};
    anima::ik_result<T> r;
    for (std::size_t k = 0; k < joints.size(); ++k) {
        g.goals.push_back(anima::position_goal<T>(joints[k], Eigen::Matrix<T, 3, 1>::Zero()));
        r.errors.push_back({errors[k], T(0)});
    }
    goals.push_back(g);
    solved.frames.push_back(frame);
    solved.results.push_back(r);
}

TEST_CASE_TEMPLATE("missed_goals counts each joint's missed frames and its worst miss", T, float, double) {
    anima::clip_ik_result<T> solved;
    std::vector<anima::frame_goals<T>> goals;
    add_frame<T>(solved, goals, 3, {7, 2}, {T(0.5), T(0.01)});
    add_frame<T>(solved, goals, 5, {7, 2, 4, 2}, {T(0.9), T(0.2), T(0.1), T(0.3)});
    add_frame<T>(solved, goals, 9, {7, 2}, {T(0.9), T(0.05)});
    const auto missed = anima::missed_goals(solved, goals, T(0.1));
    // Joint 4's 0.1 is not over the tolerance; joint 2 misses in frame 5
    // only (twice: one frame); joint 7 in every frame, worst first at 5.
    REQUIRE(missed.size() == 2);
    CHECK(missed[0].joint == 2);
    CHECK(missed[0].frames == 1);
    CHECK(missed[0].worst == T(0.3));
    CHECK(missed[0].worst_frame == 5);
    CHECK(missed[1].joint == 7);
    CHECK(missed[1].frames == 3);
    CHECK(missed[1].worst == T(0.9));
    CHECK(missed[1].worst_frame == 5);
    // A tolerance over every error: nothing missed; 0: every non-zero error.
    CHECK(anima::missed_goals(solved, goals, T(1)).empty());
    const auto strict = anima::missed_goals(solved, goals, T(0));
    REQUIRE(strict.size() == 3);
    CHECK(strict[0].frames == 3);  // joint 2
    CHECK(strict[1].joint == 4);
    CHECK(strict[1].worst == T(0.1));

    CHECK(contains(invalid_argument_message([&] { (void)anima::missed_goals(solved, goals, T(-1)); }),
                   "anima::missed_goals: tolerance must be >= 0, got -1"));
    CHECK_THROWS_AS((void)anima::missed_goals(solved, goals, std::numeric_limits<T>::quiet_NaN()), anima::invalid_argument);
    auto fewer = goals;
    fewer.pop_back();
    CHECK(contains(invalid_argument_message([&] { (void)anima::missed_goals(solved, fewer, T(0.1)); }),
                   "anima::missed_goals: 2 goal sets for 3 solved frames"));
    auto moved = goals;
    moved[1].frame = 6;
    CHECK(contains(invalid_argument_message([&] { (void)anima::missed_goals(solved, moved, T(0.1)); }),
                   "goal set 1 (frame 6, 4 goals) does not match solved frame 5 (4 errors)"));
}

}  // namespace
