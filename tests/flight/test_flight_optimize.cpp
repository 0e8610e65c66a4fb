// Optimising the flight: on the somersault (CMU skeleton, 12 keys, model 2)
// the objective falls monotonically, the tucked key intervals shorten and
// the stretched ones lengthen (the paper's Fig 7), and the angular momentum
// about the centre of mass varies less; model (1) on a small problem also
// descends monotonically and ends no worse than its start. The sampled clip
// follows the optimised keys.
#include "flight_test_support.hpp"

#include <anima/flight/flight_clip.hpp>
#include <anima/flight/optimize_flight.hpp>
#include <anima/flight/somersault.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

using namespace flight_test;

template <class T>
void check_monotone(const std::vector<T>& history, T start) {
    T previous = start * (T(1) + tolerance<T>(1e-12, 1e-5));
    for (const T& v : history) {
        CHECK(v <= previous);
        previous = v * (T(1) + tolerance<T>(1e-12, 1e-5));
    }
}

TEST_CASE_TEMPLATE("somersault, model (2): tuck shortens, stretched phases lengthen, momentum steadier", T, float,
                   double) {
    const auto sk = cmu31_skeleton<T>();
    const auto model = anima::make_body_model(sk, {});
    const anima::flight_problem<T> problem(model, anima::somersault_keys(sk), anima::somersault_settings<T>());
    anima::flight_optimization_params<T> params;
    params.solver.max_iterations = anima_test::sanitized_build ? 1 : 40;
    int calls = 0;
    params.solver.on_iteration = [&](int, T) { return ++calls > 0; };
    const auto r = anima::optimize_flight(problem, params);
    REQUIRE(r.optimized.times.size() == 12);
    CHECK(calls == static_cast<int>(r.history.size()));
    check_monotone(r.history, r.objective_initial);
    CHECK(std::abs(r.history.back() - r.objective_final) <= tolerance<T>(1e-8, 1e-3) * r.objective_final);
    REQUIRE(r.momentum_drift_initial);
    REQUIRE(r.momentum_drift_final);
    const auto& a = r.initial.times;
    const auto& b = r.optimized.times;
    CHECK(b.front() == a.front());
    CHECK(std::abs(b.back() - a.back()) < tolerance<T>(1e-12, 1e-5));
    if (!anima_test::sanitized_build) {  // the convergence trends need the 40 iterations
        CHECK(r.objective_final < T(0.5) * r.objective_initial);
        CHECK(*r.momentum_drift_final < *r.momentum_drift_initial);
        for (std::size_t k = 3; k <= 7; ++k) CHECK(b[k] - b[k - 1] < a[k] - a[k - 1]);  // tucked intervals
        CHECK(b[1] - b[0] > a[1] - a[0]);                                                // take-off, stretched
        for (std::size_t k = 9; k <= 11; ++k) CHECK(b[k] - b[k - 1] > a[k] - a[k - 1]);  // stretched, twisting
    }

    // The sampled clip passes through the optimised key poses.
    const auto c = anima::flight_clip(problem, r.optimized, sk, anima::default_metres_per_unit(sk), T(0.02));
    CHECK(c.frames() == 81);
    const T tol = tolerance<T>(1e-9, 1e-4);
    CHECK(c.rotation(0, 0).angularDistance(r.optimized.rotations[0][0]) < tol);
    CHECK(c.rotation(80, 0).angularDistance(r.optimized.rotations[11][0]) < tol);
}

TEST_CASE_TEMPLATE("model (1) descends monotonically and keeps its tolerances", T, float, double) {
    std::mt19937 rng(12);
    auto model = random_model<T>(rng, 3);
    auto keys = random_keys<T>(rng, model.size(), 5, T(1));
    anima::flight_settings<T> s;
    s.quadrature_points = 2;
    s.root_tolerance = T(0.02);
    s.joint_tolerance = T(0.05);
    const anima::flight_problem<T> problem(model, keys, s);
    anima::flight_optimization_params<T> params;
    params.model = anima::flight_model::timing_and_poses;
    params.solver.max_iterations = 15;
    const auto r = anima::optimize_flight(problem, params);
    CHECK(r.objective_final <= r.objective_initial);
    CHECK(r.objective_final < r.objective_initial);
    check_monotone(r.history, r.objective_initial);
    for (std::size_t k = 0; k < keys.size(); ++k)
        CHECK((r.optimized.root_positions[k] - keys.root_positions[k]).cwiseAbs().maxCoeff() <=
              T(0.02) * (T(1) + tolerance<T>(1e-9, 1e-4)));
}

TEST_CASE_TEMPLATE("somersault keys and optimiser arguments are checked", T, float, double) {
    const auto daz = anima::read_bvh<T>(bundled("run_cmu_09_01.bvh")).skeleton();
    CHECK(contains(invalid_argument_message([&] { anima::somersault_keys(daz); }), "LowerBack"));
    std::mt19937 rng(1);
    const auto model = random_model<T>(rng, 2);
    const anima::flight_problem<T> two(model, random_keys<T>(rng, 2, 2, T(1)), {});
    CHECK(contains(invalid_argument_message([&] { anima::optimize_flight(two); }), "at least 3 keys"));
    const auto sk = cmu31_skeleton<T>();
    CHECK(contains(invalid_argument_message([&] {
                       anima::flight_clip(two, two.keys(), sk, T(1), T(0.1));
                   }),
                   "joints"));

    // The solver's dense matrices grow with the square of the keys: refused
    // above max_memory, before any work.
    const anima::flight_problem<T> somersault(anima::make_body_model(sk, {}), anima::somersault_keys(sk),
                                              anima::somersault_settings<T>());
    anima::flight_optimization_params<T> small;
    small.max_memory = 1e4;
    const double bytes = anima::flight_solver_bytes(somersault, small.model);
    CHECK(bytes > small.max_memory);
    CHECK(bytes == doctest::Approx(sizeof(T) * (2.0 * 264 * 10 + 3.0 * 10 * 10 + 264.0 * 19)));
    // An iteration: one pass for 10 parameters, over 31 joints at 11 x 4 nodes.
    const anima::flight_iteration_work work = anima::flight_work_per_iteration(somersault, small.model);
    CHECK(work.passes == 1);
    CHECK(work.joint_evaluations == doctest::Approx(31.0 * 44));
    CHECK(work.flops == doctest::Approx(264.0 * 10 * 10 + 1000.0 / 3));
    const auto full = anima::flight_work_per_iteration(somersault, anima::flight_model::timing_and_poses);
    const double n = static_cast<double>(somersault.full_size());
    CHECK(full.passes == std::ceil(n / 16));
    CHECK(full.joint_evaluations == doctest::Approx(std::ceil(n / 16) * 31 * 44));
    const std::string message = invalid_argument_message([&] { anima::optimize_flight(somersault, small); });
    CHECK(contains(message, "12 keys with 4 quadrature points need a 264 x 10 Jacobian"));
    CHECK(contains(message, "more than max_memory"));
}

}  // namespace
