// The flight objective: its automatic-derivative Jacobians (models 1 and 2)
// agree with central differences; the Gauss-Legendre objective agrees with
// a dense Simpson integral of |F|^2 computed from inverse_dynamics directly;
// a ballistic root has no residual force; the timing parametrisation keeps
// the key order and end times for any parameters and round-trips; model (1)
// keys stay within e1 and e2; bad arguments are refused by name.
#include "flight_test_support.hpp"

#include <anima/flight/flight_objective.hpp>
#include <anima/flight/inverse_dynamics.hpp>
#include <anima/optimize/numeric_derivatives.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <type_traits>
#include <vector>

namespace {

using namespace flight_test;

template <class T>
anima::flight_problem<T> small_problem(std::uint32_t seed, bool ballistic, int quadrature = 3) {
    std::mt19937 rng(seed);
    auto model = random_model<T>(rng, 4);
    auto keys = random_keys<T>(rng, model.size(), 5, T(1.2));
    anima::flight_settings<T> s;
    s.quadrature_points = quadrature;
    if (ballistic) s.ballistic = anima::ballistic_path<T>{vec3<T>(T(0), T(1), T(0)), vec3<T>(T(0.5), T(4), T(0))};
    return anima::flight_problem<T>(std::move(model), std::move(keys), s);
}

template <class T>
void check_jacobian(const anima::matrix_x<T>& exact, const anima::matrix_x<T>& numeric, T tol) {
    REQUIRE(exact.rows() == numeric.rows());
    REQUIRE(exact.cols() == numeric.cols());
    CHECK((exact - numeric).norm() <= tol * (T(1) + exact.norm()));
}

TEST_CASE_TEMPLATE("model (2) Jacobian agrees with central differences", T, float, double) {
    const T tol = tolerance<T>(1e-6, 5e-2);
    for (bool ballistic : {false, true}) {
        const auto p = small_problem<T>(3, ballistic);
        anima::vector_x<T> x = p.timing_parameters(p.keys().times);
        x += anima::vector_x<T>::Constant(x.size(), T(0.1));
        anima::vector_x<T> r;
        anima::matrix_x<T> J;
        p.timing_residuals(x, r, &J);
        const auto numeric = anima::numeric_jacobian<T>(
            [&](const anima::vector_x<T>& y, anima::vector_x<T>& out) { p.timing_residuals(y, out, nullptr); }, x);
        check_jacobian<T>(J, numeric, tol);
        anima::vector_x<T> r2;
        p.timing_residuals(x, r2, nullptr);
        CHECK((r - r2).norm() <= tolerance<T>(1e-12, 1e-5) * (T(1) + r.norm()));
    }
}

TEST_CASE_TEMPLATE("model (1) Jacobian agrees with central differences", T, float, double) {
    const T tol = tolerance<T>(1e-6, 5e-2);
    for (bool ballistic : {false, true}) {
        const auto p = small_problem<T>(4, ballistic, 2);
        anima::vector_x<T> x = p.full_parameters(p.keys().times);
        std::mt19937 rng(1);
        std::uniform_real_distribution<double> u(-0.5, 0.5);
        for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += T(u(rng));
        anima::vector_x<T> r;
        anima::matrix_x<T> J;
        p.full_residuals(x, r, &J);
        REQUIRE(J.cols() == p.full_size());
        const auto numeric = anima::numeric_jacobian<T>(
            [&](const anima::vector_x<T>& y, anima::vector_x<T>& out) { p.full_residuals(y, out, nullptr); }, x);
        check_jacobian<T>(J, numeric, tol);
    }
}

TEST_CASE_TEMPLATE("the quadrature objective agrees with a dense Simpson integral of |F|^2", T, float, double) {
    for (bool ballistic : {false, true}) {
        const auto p = small_problem<T>(8, ballistic, 5);
        const auto& keys = p.keys();
        const T J = p.objective(keys);
        // Independent route: sample the motion, call inverse_dynamics, Simpson per interval.
        const auto traj = anima::key_trajectory<T>::from_keys(keys);
        const int m = 200;  // even
        T integral(0);
        for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
            const T a = keys.times[i], h = (keys.times[i + 1] - a) / T(m);
            for (int s = 0; s <= m; ++s) {
                const T t = a + h * T(s);
                const auto x = p.motion_at(traj, t);
                const T f2 = anima::inverse_dynamics(p.model(), x, p.settings().gravity).root_residual().squaredNorm();
                const T w = (s == 0 || s == m) ? T(1) : (s % 2 ? T(4) : T(2));
                integral += w * f2 * h / T(3);
            }
        }
        const T reference = integral / p.total_time();
        CHECK(std::abs(J - reference) <= tolerance<T>(1e-4, 1e-3) * reference);
        if (ballistic) {
            const auto x = p.motion_at(traj, T(0.5));
            const auto id = anima::inverse_dynamics(p.model(), x, p.settings().gravity);
            CHECK(id.root_force.norm() <= tolerance<T>(1e-9, 1e-3) * p.model().total_mass() * T(10));
            const auto mom = anima::momentum(p.model(), x);
            const vec3<T> expected = vec3<T>(T(0), T(1), T(0)) + vec3<T>(T(0.5), T(4), T(0)) * T(0.5) +
                                     p.settings().gravity * T(0.125);
            CHECK((mom.centre_of_mass - expected).norm() <= tolerance<T>(1e-10, 1e-4) * T(10));
        }
    }
}

TEST_CASE_TEMPLATE("timing parameters keep the key order and ends, and round-trip", T, float, double) {
    const auto p = small_problem<T>(5, false);
    const auto& times = p.keys().times;
    const auto back = p.key_times(p.timing_parameters(times));
    for (std::size_t k = 0; k < times.size(); ++k) CHECK(std::abs(back[k] - times[k]) < tolerance<T>(1e-12, 1e-5));
    std::mt19937 rng(2);
    std::normal_distribution<double> n(0.0, 3.0);
    for (int trial = 0; trial < 50; ++trial) {
        anima::vector_x<T> x(p.timing_size());
        for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = T(n(rng));
        const auto t = p.key_times(x);
        CHECK(t.front() == times.front());
        CHECK(t.back() == times.back());
        for (std::size_t k = 0; k + 1 < t.size(); ++k) CHECK(t[k + 1] > t[k]);
    }
}

TEST_CASE_TEMPLATE("model (1) keys stay within the tolerances e1 and e2", T, float, double) {
    std::mt19937 rng(6);
    auto model = random_model<T>(rng, 3);
    auto keys = random_keys<T>(rng, model.size(), 4, T(1));
    anima::flight_settings<T> s;
    s.root_tolerance = T(0.03);
    s.joint_tolerance = T(0.05);
    const anima::flight_problem<T> p(model, keys, s);
    std::normal_distribution<double> n(0.0, 10.0);
    anima::vector_x<T> x(p.full_size());
    for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = T(n(rng));
    const auto moved = p.keys_of(x);
    const T slack = tolerance<T>(1e-12, 1e-5);
    for (std::size_t k = 0; k < keys.size(); ++k) {
        CHECK((moved.root_positions[k] - keys.root_positions[k]).cwiseAbs().maxCoeff() <= T(0.03) + slack);
        for (std::size_t j = 0; j < model.size(); ++j) {
            const T angle = keys.rotations[k][j].normalized().angularDistance(moved.rotations[k][j]);
            CHECK(angle <= std::sqrt(T(3)) * T(0.05) + slack * T(10));
        }
    }
    // Zero parameters beyond the timing are the keys themselves.
    const auto same = p.keys_of(p.full_parameters(keys.times));
    CHECK(std::abs(p.objective(same) - p.objective(keys)) <= tolerance<T>(1e-10, 1e-4) * p.objective(keys));
}

TEST_CASE_TEMPLATE("flight problems refuse bad arguments by name", T, float, double) {
    std::mt19937 rng(7);
    const auto model = random_model<T>(rng, 3);
    const auto keys = random_keys<T>(rng, model.size(), 4, T(1));
    anima::flight_settings<T> s;
    s.quadrature_points = 9;
    CHECK(contains(invalid_argument_message([&] { anima::flight_problem<T>(model, keys, s); }), "quadrature_points"));
    s.quadrature_points = 3;
    s.joint_tolerance = T(-1);
    CHECK(contains(invalid_argument_message([&] { anima::flight_problem<T>(model, keys, s); }), "joint_tolerance"));
    auto bad = keys;
    bad.rotations[2].pop_back();
    CHECK(contains(invalid_argument_message([&] { anima::flight_problem<T>(model, bad, {}); }), "key 2"));
    const anima::flight_problem<T> p(model, keys, {});
    auto times = keys.times;
    times[1] = times[2];
    CHECK(contains(invalid_argument_message([&] { p.objective(times); }), "increase strictly"));
    times = keys.times;
    times.back() += T(1);
    CHECK(contains(invalid_argument_message([&] { p.objective(times); }), "first and last"));
    anima::vector_x<T> r;
    CHECK(contains(invalid_argument_message([&] { p.timing_residuals(anima::vector_x<T>(5), r, nullptr); }), "expected 2"));
}

TEST_CASE_TEMPLATE("key times and root positions beyond the documented bounds are refused by name", T, float, double) {
    std::mt19937 rng(11);
    const auto model = random_model<T>(rng, 3);
    auto keys = random_keys<T>(rng, model.size(), 4, T(1));
    keys.root_positions[2].x() = static_cast<T>(std::is_same_v<T, float> ? 1e30 : 1e300);
    CHECK(contains(invalid_argument_message([&] { anima::flight_problem<T>(model, keys, {}); }),
                   "key 2: root position has a coordinate outside +-1e6 m"));
    keys.root_positions[2].x() = T(9e5);  // far, but within the bound: a finite objective
    const anima::flight_problem<T> far(model, keys, {});
    CHECK(std::isfinite(far.objective(keys)));
    keys.times.back() = T(2e6);
    CHECK(contains(invalid_argument_message([&] { anima::flight_problem<T>(model, keys, {}); }), "outside +-1e6 s"));
}

TEST_CASE_TEMPLATE("keys whose objective overflows (times a hair apart, huge gravity) are refused, naming the interval",
                   T, float, double) {
    std::mt19937 rng(11);
    const auto model = random_model<T>(rng, 3);
    auto keys = random_keys<T>(rng, model.size(), 4, T(1));
    const anima::flight_problem<T> fine(model, keys, {});
    CHECK(std::isfinite(fine.objective(keys.times)));
    // Forces go as 1 / dt^2, squared in the objective: 1e-12 s overflows
    // float, 1e-100 s double.
    auto squeezed = keys;
    const T tiny = static_cast<T>(std::is_same_v<T, float> ? 1e-12 : 1e-100);
    for (std::size_t k = 0; k < squeezed.size(); ++k) squeezed.times[k] = tiny * static_cast<T>(k);
    CHECK(contains(invalid_argument_message([&] { anima::flight_problem<T>(model, squeezed, {}); }),
                   "the objective at the keys' own times is not finite in this precision (shortest key interval " +
                       anima::detail::argument_text(tiny)));
    // Closer still, the key spline's curvatures overflow too (cubic_spline
    // refuses them): still reported for the keys.
    const T closer = static_cast<T>(std::is_same_v<T, float> ? 1e-20 : 1e-300);
    for (std::size_t k = 0; k < squeezed.size(); ++k) squeezed.times[k] = closer * static_cast<T>(k);
    CHECK(contains(invalid_argument_message([&] { anima::flight_problem<T>(model, squeezed, {}); }),
                   "the objective at the keys' own times is not finite in this precision (shortest key interval " +
                       anima::detail::argument_text(closer)));
    anima::flight_settings<T> heavy;
    heavy.gravity = vec3<T>(T(0), -static_cast<T>(std::is_same_v<T, float> ? 1e30 : 1e300), T(0));
    CHECK(contains(invalid_argument_message([&] { anima::flight_problem<T>(model, keys, heavy); }),
                   "lessen gravity"));
}

TEST_CASE_TEMPLATE("momentum_drift is not defined (empty) without mean angular momentum, defined otherwise", T, float, double) {
    std::mt19937 rng(5);
    const auto model = random_model<T>(rng, 3);
    // Every key the same pose at the same root position: nothing rotates.
    anima::flight_keys<T> still;
    for (int k = 0; k < 4; ++k) {
        still.times.push_back(T(0.25) * T(k));
        still.root_positions.push_back(vec3<T>(T(1), T(2), T(3)));
        still.rotations.emplace_back(model.size(), Eigen::Quaternion<T>::Identity());
    }
    const anima::flight_problem<T> p(model, still, {});
    CHECK(!p.momentum_drift(still));
    CHECK(std::isfinite(p.objective(still)));
    // A moving key set has a finite, non-negative drift.
    const auto keys = random_keys<T>(rng, model.size(), 4, T(1));
    const anima::flight_problem<T> q(model, keys, {});
    const auto d = q.momentum_drift(keys);
    REQUIRE(d);
    CHECK(*d >= T(0));
    CHECK(std::isfinite(*d));
}

}  // namespace
