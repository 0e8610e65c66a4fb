// BFGS and L-BFGS against closed forms: the minimiser of a convex quadratic
// (Eigen's dense LDLT solve), Rosenbrock's valley, a domain boundary where
// the objective is NaN, and the finite differences they are checked with.
#include <anima/optimize.hpp>

#include <doctest/doctest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <random>

#include "../test_support.hpp"
#include "optimize_test_support.hpp"

using anima::vector_x;
using anima::matrix_x;
using anima_test::non_increasing;
using anima_test::tolerance;

namespace {

template <class T>
T rosenbrock(const vector_x<T>& x, vector_x<T>& g) {
    T f = 0;
    g.setZero(x.size());
    for (Eigen::Index i = 0; i + 1 < x.size(); ++i) {
        const T a = x[i + 1] - x[i] * x[i];
        const T b = T(1) - x[i];
        f += T(100) * a * a + b * b;
        g[i] += -T(400) * x[i] * a - T(2) * b;
        g[i + 1] += T(200) * a;
    }
    return f;
}

template <class T>
struct quadratic {
    matrix_x<T> a;
    vector_x<T> b;
    explicit quadratic(int n, unsigned seed) {
        std::mt19937 gen(seed);
        std::normal_distribution<double> normal;
        Eigen::MatrixXd m(n, n);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) m(i, j) = normal(gen);
        // Condition number about 100.
        Eigen::MatrixXd spd = m * m.transpose() / n + 0.05 * Eigen::MatrixXd::Identity(n, n);
        Eigen::VectorXd rhs(n);
        for (int i = 0; i < n; ++i) rhs[i] = normal(gen);
        a = spd.cast<T>();
        b = rhs.cast<T>();
    }
    T operator()(const vector_x<T>& x, vector_x<T>& g) const {
        g = a * x - b;
        return x.dot(a * x) / T(2) - b.dot(x);
    }
};

}  // namespace

TEST_CASE_TEMPLATE("bfgs_minimize finds the minimiser of a convex quadratic", T, float, double) {
    for (int memory : {0, 5}) {
        CAPTURE(memory);
        const quadratic<T> q(20, 7u);
        const vector_x<T> exact = q.a.ldlt().solve(q.b);
        anima::bfgs_params<T> params;
        params.memory = memory;
        params.gradient_tolerance = tolerance<T>(1e-10, 1e-4);
        const auto result = anima::bfgs_minimize<T>(q, vector_x<T>::Zero(20), params);
        if (std::is_same_v<T, double>) {
            CHECK(result.converged());
        } else {
            // In float f = -34 resolves changes of 4e-6 only, i.e. gradients
            // down to about 1e-3: the search stops there, and says so.
            CHECK(result.status != anima::optimize_status::max_iterations);
        }
        CHECK((result.x - exact).norm() <= tolerance<T>(1e-7, 1e-2) * exact.norm());
        CHECK(non_increasing(result.history, T(0)));
        // Dense BFGS with exact line searches ends in n steps; with Wolfe
        // steps it still needs far fewer than steepest descent's hundreds.
        CHECK(result.iterations <= (memory == 0 ? 60 : 150));
    }
}

TEST_CASE_TEMPLATE("bfgs_minimize follows Rosenbrock's valley to (1, 1)", T, float, double) {
    for (int memory : {0, 7}) {
        CAPTURE(memory);
        for (int n : {2, 10}) {
            CAPTURE(n);
            vector_x<T> x0(n);
            for (int i = 0; i < n; ++i) x0[i] = (i % 2 == 0) ? T(-1.2) : T(1);
            anima::bfgs_params<T> params;
            params.memory = memory;
            params.max_iterations = 1000;
            const auto result = anima::bfgs_minimize<T>(rosenbrock<T>, x0, params);
            vector_x<T> g(n);
            CHECK(result.value == doctest::Approx(double(rosenbrock<T>(result.x, g))));
            CHECK((result.x - vector_x<T>::Ones(n)).template lpNorm<Eigen::Infinity>() <= tolerance<T>(1e-6, 2e-2));
            CHECK(result.status != anima::optimize_status::max_iterations);
            vector_x<T> g0(n);
            CHECK(non_increasing(result.history, rosenbrock<T>(x0, g0)));
        }
    }
}

TEST_CASE_TEMPLATE("bfgs_minimize treats non-finite values as a step too far", T, float, double) {
    // f = x - log x is NaN for x < 0; a first step from x = 10 overshoots.
    auto f = [](const vector_x<T>& x, vector_x<T>& g) {
        g[0] = T(1) - T(1) / x[0];
        return x[0] - std::log(x[0]);
    };
    const auto result = anima::bfgs_minimize<T>(f, vector_x<T>::Constant(1, T(10)));
    CHECK(result.converged());
    CHECK(result.x[0] == doctest::Approx(1.0).epsilon(double(tolerance<T>(1e-6, 1e-2))));
    CHECK(std::isfinite(result.value));
}

TEST_CASE_TEMPLATE("bfgs_minimize reports how it stopped", T, float, double) {
    const quadratic<T> q(6, 3u);
    SUBCASE("at the minimum already") {
        const vector_x<T> exact = q.a.ldlt().solve(q.b);
        anima::bfgs_params<T> params;
        params.gradient_tolerance = T(1e-2);
        const auto result = anima::bfgs_minimize<T>(q, exact, params);
        CHECK(result.converged());
        CHECK(result.iterations == 0);
        CHECK(result.history.empty());
    }
    SUBCASE("no iterations allowed") {
        anima::bfgs_params<T> params;
        params.max_iterations = 0;
        const auto result = anima::bfgs_minimize<T>(q, vector_x<T>::Zero(6), params);
        CHECK(result.status == anima::optimize_status::max_iterations);
        CHECK(result.x == vector_x<T>::Zero(6));
    }
    SUBCASE("the callback stops it") {
        anima::bfgs_params<T> params;
        int calls = 0;
        params.on_iteration = [&](int iteration, T) {
            ++calls;
            return iteration < 2;
        };
        const auto result = anima::bfgs_minimize<T>(q, vector_x<T>::Zero(6), params);
        CHECK(result.status == anima::optimize_status::stopped);
        CHECK(calls == 2);
        CHECK(result.iterations == 2);
        CHECK(std::string(to_string(result.status)) == "stopped");
    }
    SUBCASE("a function with no minimum stalls or runs out, never NaN") {
        auto f = [](const vector_x<T>& x, vector_x<T>& g) {
            g[0] = T(1);
            return x[0];
        };
        anima::bfgs_params<T> params;
        params.max_iterations = 30;
        const auto result = anima::bfgs_minimize<T>(f, vector_x<T>::Zero(1), params);
        CHECK_FALSE(result.converged());
        CHECK(std::isfinite(result.value));
        CHECK(result.value < T(0));
    }
}

TEST_CASE_TEMPLATE("bfgs_minimize rejects bad input", T, float, double) {
    const quadratic<T> q(3, 1u);
    CHECK_THROWS_WITH_AS(anima::bfgs_minimize<T>(q, vector_x<T>()), "anima::bfgs_minimize: the start point is empty",
                         anima::invalid_argument);
    vector_x<T> x0 = vector_x<T>::Zero(3);
    x0[1] = std::numeric_limits<T>::quiet_NaN();
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { anima::bfgs_minimize<T>(q, x0); }),
                               "anima::bfgs_minimize: start point component 1"));
    auto nan_at_start = [](const vector_x<T>&, vector_x<T>& g) {
        g.setZero();
        return std::numeric_limits<T>::quiet_NaN();
    };
    CHECK_THROWS_AS(anima::bfgs_minimize<T>(nan_at_start, vector_x<T>::Zero(2)), anima::error);
    anima::bfgs_params<T> params;
    params.memory = -1;
    CHECK_THROWS_AS(anima::bfgs_minimize<T>(q, vector_x<T>::Zero(3), params), anima::invalid_argument);
}

TEST_CASE_TEMPLATE("numeric_gradient and numeric_jacobian match analytic derivatives", T, float, double) {
    vector_x<T> x(4);
    x << T(0.3), T(-1.1), T(2.0), T(0.7);
    vector_x<T> analytic(4);
    rosenbrock<T>(x, analytic);
    const vector_x<T> numeric = anima::numeric_gradient<T>(
        [](const vector_x<T>& p) {
            vector_x<T> g(p.size());
            return rosenbrock<T>(p, g);
        },
        x);
    CHECK((numeric - analytic).norm() <= tolerance<T>(1e-7, 2e-1) * analytic.norm());

    auto residuals = [](const vector_x<T>& p, vector_x<T>& r) {
        r.resize(3);
        r << std::sin(p[0]) * p[1], p[2] * p[2] - p[3], std::exp(p[0] * p[3]);
    };
    matrix_x<T> exact = matrix_x<T>::Zero(3, 4);
    exact(0, 0) = std::cos(x[0]) * x[1];
    exact(0, 1) = std::sin(x[0]);
    exact(1, 2) = T(2) * x[2];
    exact(1, 3) = T(-1);
    exact(2, 0) = x[3] * std::exp(x[0] * x[3]);
    exact(2, 3) = x[0] * std::exp(x[0] * x[3]);
    const matrix_x<T> jacobian = anima::numeric_jacobian<T>(residuals, x);
    CHECK(jacobian.rows() == 3);
    CHECK((jacobian - exact).norm() <= tolerance<T>(1e-8, 2e-3) * exact.norm());
    CHECK_THROWS_AS(anima::numeric_jacobian<T>(residuals, x, T(0)), anima::invalid_argument);
}

namespace {

/// 2^k * sum w_i (x_i - c_i)^2 / 2 with w_i = i + 1, c_i = 0.7 sin(i + 1) / w_i:
/// from x = 0 the largest gradient component (2^k times 0.69) has exponent
/// k, so bfgs_minimize divides by exactly 2^k.
template <class T>
struct scaled_quadratic {
    int k = 0;
    T operator()(const vector_x<T>& x, vector_x<T>& g) const {
        T f = T(0);
        for (Eigen::Index i = 0; i < x.size(); ++i) {
            const T w = T(i + 1), c = T(0.7 * std::sin(double(i + 1))) / w, d = x[i] - c;
            f += std::ldexp(w * d * d / T(2), k);
            g[i] = std::ldexp(w * d, k);
        }
        return f;
    }
};

}  // namespace

TEST_CASE_TEMPLATE("bfgs_minimize with a gradient whose squared norm overflows: the same steps as the scaled problem", T,
                   float, double) {
    // |g|^2 = inf for a finite gradient of 2^70 (float) or 2^530 (double):
    // every slope was infinite, and BFGS stalled at the start (1 iteration,
    // status stalled, x = 0). It now minimises f / 2^k.
    const int k = std::is_same_v<T, float> ? 70 : 530;
    for (const int memory : {0, 4}) {
        CAPTURE(memory);
        anima::bfgs_params<T> params;
        params.memory = memory;
        std::vector<T> seen;
        params.on_iteration = [&](int, T value) {
            seen.push_back(value);
            return true;
        };
        const vector_x<T> x0 = vector_x<T>::Zero(10);
        vector_x<T> g0(10);
        (void)scaled_quadratic<T>{k}(x0, g0);
        REQUIRE(g0.allFinite());
        REQUIRE_FALSE(std::isfinite(g0.squaredNorm()));
        const auto huge = anima::bfgs_minimize<T>(scaled_quadratic<T>{k}, x0, params);
        seen.clear();
        const auto plain = anima::bfgs_minimize<T>(scaled_quadratic<T>{0}, x0, params);
        const std::vector<T> seen_plain = seen;
        CHECK(plain.status == anima::optimize_status::converged);
        CHECK(huge.status == anima::optimize_status::converged);
        CHECK(huge.iterations == plain.iterations);
        CHECK(huge.evaluations == plain.evaluations);
        CHECK(huge.x == plain.x);  // exact: the division is by a power of two
        CHECK(huge.value == std::ldexp(plain.value, k));
        REQUIRE(huge.history.size() == plain.history.size());
        for (std::size_t i = 0; i < huge.history.size(); ++i) CHECK(huge.history[i] == std::ldexp(plain.history[i], k));
        for (Eigen::Index i = 0; i < 10; ++i)
            CHECK(std::abs(huge.x[i] - T(0.7 * std::sin(double(i + 1))) / T(i + 1)) < tolerance<T>(1e-6, 1e-3));
    }
}

TEST_CASE_TEMPLATE("bfgs_minimize names the iterate whose gradient's squared norm overflows", T, float, double) {
    // f = (x - 2)^2 + y C x^2: from (0, 0) the gradient is (-4, 0); the line
    // search along x stops near x = 2, where df/dy = 4 C has an infinite
    // square. The iteration used to stall there without a word.
    const T C = std::is_same_v<T, float> ? T(1e30) : T(1e200);
    const auto f = [C](const vector_x<T>& x, vector_x<T>& g) {
        g[0] = T(2) * (x[0] - T(2)) + T(2) * C * x[1] * x[0];
        g[1] = C * x[0] * x[0];
        return (x[0] - T(2)) * (x[0] - T(2)) + x[1] * C * x[0] * x[0];
    };
    CHECK_THROWS_WITH_AS(anima::bfgs_minimize<T>(f, vector_x<T>::Zero(2)),
                         doctest::Contains("anima::bfgs_minimize: at iterate 1 the gradient's squared norm overflows"),
                         anima::error);
}
