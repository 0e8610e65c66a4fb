// anima::flight_keys_from_clip: keys on the airborne phase of a recorded run,
// and the timing the objective prefers: from distorted key times,
// optimize_flight (model 2) returns to the recorded ones. Real motion is
// close to the minimum of T^-1 int sum F^2, which is the paper's premise.
#include "../test_support.hpp"

#include <anima/bvh/reader.hpp>
#include <anima/flight/clip_keys.hpp>
#include <anima/flight/optimize_flight.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace {

template <class T>
anima::clip<T> run_clip() {
    return anima::read_bvh<T>(anima_test::bundled("run_cmu_09_01.bvh"));
}

}  // namespace

TEST_CASE_TEMPLATE("flight_keys_from_clip places keys on the longest airborne phase of the run", T, float, double) {
    const auto c = run_clip<T>();
    const auto k = anima::flight_keys_from_clip(c);
    const auto contacts = anima::find_contacts(c);
    // The longest phase, and it is airborne in every frame.
    for (const auto& p : contacts.airborne_phases) CHECK(p.frames() <= k.phase.frames());
    for (std::size_t f = k.phase.first; f <= k.phase.last; ++f) CHECK(contacts.airborne[f]);
    REQUIRE(k.key_frames.size() == 8);
    CHECK(k.key_frames.front() == k.phase.first);
    CHECK(k.key_frames.back() == k.phase.last);
    const auto& keys = k.key_set.keys;
    for (std::size_t i = 0; i < keys.size(); ++i) {
        CAPTURE(i);
        if (i > 0) CHECK(k.key_frames[i] > k.key_frames[i - 1]);
        CHECK(keys.times[i] == doctest::Approx(static_cast<double>(k.key_frames[i] - k.phase.first) / 120.0).epsilon(1e-4));
        // Recorded poses: the root in metres (the Daz layout is in centimetres), local rotations as they are.
        CHECK((keys.root_positions[i] - c.root_position(k.key_frames[i]) * T(0.01)).norm() < T(1e-6));
        for (std::size_t j = 0; j < c.joints(); ++j)
            CHECK(keys.rotations[i][j].coeffs() == c.rotation(k.key_frames[i], j).coeffs());
    }
    CHECK(k.key_set.settings.gravity.isApprox(Eigen::Matrix<T, 3, 1>(T(0), T(-9.81), T(0))));
    CHECK(k.key_set.model.total_mass() == doctest::Approx(70.0));
    CHECK(k.key_set.metres_per_unit == doctest::Approx(0.01));
}

TEST_CASE("from distorted key times, model (2) returns to the recorded timing of the run") {
    const auto c = run_clip<double>();
    const auto k = anima::flight_keys_from_clip(c);
    auto distorted = k.key_set.keys;
    const double span = distorted.times.back();
    for (double& t : distorted.times) t = span * std::pow(t / span, 1.6);  // keys crowd towards the start
    const anima::flight_problem<double> problem(k.key_set.model, distorted, k.key_set.settings);
    anima::flight_optimization_params<double> params;
    // Under the sanitizers a few iterations show the path runs clean; the
    // return to the recording needs the full run.
    params.solver.max_iterations = anima_test::sanitized_build ? 3 : 100;
    const auto r = anima::optimize_flight(problem, params);
    double before = 0, after = 0;
    for (std::size_t i = 0; i < distorted.size(); ++i) {
        before = std::max(before, std::abs(r.initial.times[i] - k.key_set.keys.times[i]));
        after = std::max(after, std::abs(r.optimized.times[i] - k.key_set.keys.times[i]));
    }
    CHECK(r.objective_final < r.objective_initial);
    CHECK(before > 0.03);  // 38 ms: the distortion is real
    if (anima_test::sanitized_build) CHECK(after < before);
    else CHECK(after < 0.004);  // 1.9 ms: back at the recording
    CHECK(r.optimized.times.front() == 0.0);
    CHECK(r.optimized.times.back() == doctest::Approx(span));
}

TEST_CASE("flight_keys_from_clip refuses what it cannot use") {
    const auto walk = anima::read_bvh<double>(anima_test::bundled("walk_cmu31_02_01.bvh"));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { anima::flight_keys_from_clip(walk); }),
                               "has no airborne phase"));
    const auto run = run_clip<double>();
    anima::clip_flight_params<double> p;
    p.keys = 1;
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { anima::flight_keys_from_clip(run, p); }),
                               "keys must be at least 2, got 1"));
    p.keys = 40;
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { anima::flight_keys_from_clip(run, p); }),
                               "fewer than the 40 keys asked for"));
    p.keys = 4;
    p.phase = anima::frame_interval{140, 160};
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { anima::flight_keys_from_clip(run, p); }),
                               "is not within the clip's 149 frames"));
    // A phase given by the caller is used as it is, here a stance of the walk.
    p.phase = anima::frame_interval{100, 130};
    const auto k = anima::flight_keys_from_clip(walk, p);
    CHECK(k.key_frames == std::vector<std::size_t>{100, 110, 120, 130});
    CHECK(k.key_set.metres_per_unit == doctest::Approx(0.056444));
}
