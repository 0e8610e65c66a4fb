// The shared optimisers next to Eigen's MINPACK port on the same problems.
//
//   BM_rosenbrock<bfgs|lbfgs>/<n>      extended Rosenbrock from (-1.2, 1, ...)
//   BM_curve_fit<anima_lm|eigen_lm>    y = a exp(-b t) + c + noise, 200 samples
//
// Counters: iterations, evaluations and the final objective, so a faster
// run that stops short is visible. Before timing, both least-squares
// solvers' answers are compared; the program aborts if they differ.

#include <anima/optimize.hpp>

#include <benchmark/benchmark.h>

#include "../tests/optimize/optimize_test_support.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

namespace {

using vec = Eigen::VectorXd;
using mat = Eigen::MatrixXd;

double rosenbrock(const vec& x, vec& g) {
    double f = 0;
    g.setZero(x.size());
    for (Eigen::Index i = 0; i + 1 < x.size(); ++i) {
        const double a = x[i + 1] - x[i] * x[i];
        const double b = 1 - x[i];
        f += 100 * a * a + b * b;
        g[i] += -400 * x[i] * a - 2 * b;
        g[i + 1] += 200 * a;
    }
    return f;
}

void BM_rosenbrock(benchmark::State& state, int memory) {
    const int n = static_cast<int>(state.range(0));
    vec x0(n);
    for (int i = 0; i < n; ++i) x0[i] = (i % 2 == 0) ? -1.2 : 1.0;
    anima::bfgs_params<double> params;
    params.memory = memory;
    params.max_iterations = 5000;
    anima::optimize_result<double> result;
    for (auto _ : state) {
        result = anima::bfgs_minimize<double>(rosenbrock, x0, params);
        benchmark::DoNotOptimize(result.x.data());
    }
    state.counters["iterations"] = result.iterations;
    state.counters["evaluations"] = result.evaluations;
    state.counters["final_value"] = result.value;
}

struct curve {
    vec t, y;
    curve() : t(200), y(200) {
        std::mt19937 gen(5);
        std::normal_distribution<double> noise(0.0, 0.05);
        for (int i = 0; i < 200; ++i) {
            t[i] = 0.02 * i;
            y[i] = 1.7 * std::exp(-0.8 * t[i]) + 0.3 + noise(gen);
        }
    }
    void residuals(const vec& p, vec& r, mat* j) const {
        r.resize(t.size());
        if (j) j->resize(t.size(), 3);
        for (Eigen::Index i = 0; i < t.size(); ++i) {
            const double e = std::exp(-p[1] * t[i]);
            r[i] = p[0] * e + p[2] - y[i];
            if (j) {
                (*j)(i, 0) = e;
                (*j)(i, 1) = -p[0] * t[i] * e;
                (*j)(i, 2) = 1;
            }
        }
    }
};

const curve& data() {
    static const curve c;
    return c;
}

vec start() {
    vec x0(3);
    x0 << 1.0, 0.3, 0.0;
    return x0;
}

struct eigen_functor {
    using Scalar = double;
    using InputType = vec;
    using ValueType = vec;
    using JacobianType = mat;
    enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
    int inputs() const { return 3; }
    int values() const { return int(data().t.size()); }
    int operator()(const vec& p, vec& r) const {
        data().residuals(p, r, nullptr);
        return 0;
    }
    int df(const vec& p, mat& j) const {
        vec r;
        data().residuals(p, r, &j);
        return 0;
    }
};

anima::optimize_result<double> anima_fit() {
    return anima::levenberg_marquardt<double>(
        [](const vec& p, vec& r, mat* j) { data().residuals(p, r, j); }, start());
}

vec eigen_fit(int* iterations) {
    vec x = start();
    eigen_functor functor;
    Eigen::LevenbergMarquardt<eigen_functor> lm(functor);
    lm.minimize(x);
    *iterations = int(lm.iter);
    return x;
}

void BM_curve_fit_anima(benchmark::State& state) {
    anima::optimize_result<double> result;
    for (auto _ : state) {
        result = anima_fit();
        benchmark::DoNotOptimize(result.x.data());
    }
    state.counters["iterations"] = result.iterations;
    state.counters["final_value"] = result.value;
}

void BM_curve_fit_eigen(benchmark::State& state) {
    int iterations = 0;
    vec x;
    for (auto _ : state) {
        x = eigen_fit(&iterations);
        benchmark::DoNotOptimize(x.data());
    }
    vec r;
    data().residuals(x, r, nullptr);
    state.counters["iterations"] = iterations;
    state.counters["final_value"] = r.squaredNorm() / 2;
}

const bool checked = [] {
    int iterations = 0;
    const vec reference = eigen_fit(&iterations);
    const auto ours = anima_fit();
    if ((ours.x - reference).norm() > 1e-6 * reference.norm()) {
        std::fprintf(stderr, "bench_optimize: anima and Eigen disagree on the curve fit\n");
        std::abort();
    }
    return true;
}();

}  // namespace

BENCHMARK_CAPTURE(BM_rosenbrock, bfgs, 0)->Arg(2)->Arg(10)->Arg(100)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_rosenbrock, lbfgs, 7)->Arg(2)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_curve_fit_anima)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_curve_fit_eigen)->Unit(benchmark::kMicrosecond);
