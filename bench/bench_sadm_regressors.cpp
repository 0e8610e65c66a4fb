// Training and prediction time of the four SADM regressors on data shaped
// like a face sequence's parameters: n frames of d shape parameters (PCA
// coordinates, standard deviations falling as 1 / (1 + i)) mapped to m
// grey-level parameters that depend smoothly and non-linearly on them,
// plus noise. Eq 5's ridge solve is timed next to Eigen's column-pivoting
// QR least squares on the same data (with an intercept column).
//
//   BM_fit<kind>/<n>/<d>/<m>       fit on n samples
//   BM_predict<kind>/<n>/<d>/<m>   predict one frame with the fitted model
//   BM_fit_eigen_qr/<n>/<d>/<m>    [1 S] \ G by colPivHouseholderQr (no ridge)
//
// Double precision, default options (mlp: one hidden layer of 16, 500
// L-BFGS iterations at most; svr: C = 10, epsilon = 0.05, gamma = 1/d).

#include <anima/core/random.hpp>
#include <anima/sadm/regressor.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/Dense>

#include <cmath>
#include <memory>

namespace {

using matrix = anima::matrix_x<double>;

struct sadm_like_data {
    matrix inputs, outputs;
};

sadm_like_data make_data(int n, int d, int m, std::uint64_t seed = 5) {
    anima::random_source rng(seed);
    sadm_like_data data{matrix(n, d), matrix(n, m)};
    for (int c = 0; c < d; ++c)
        for (int r = 0; r < n; ++r) data.inputs(r, c) = 30.0 / (1 + c) * (2 * rng.uniform() - 1);
    matrix mix(d, m);
    for (int c = 0; c < m; ++c)
        for (int r = 0; r < d; ++r) mix(r, c) = (2 * rng.uniform() - 1) / (1 + r);
    const matrix z = data.inputs * mix / 10.0;
    for (int c = 0; c < m; ++c)
        for (int r = 0; r < n; ++r)
            data.outputs(r, c) = 500.0 / (1 + c) * (std::tanh(z(r, c)) + 0.2 * z(r, c) * z(r, (c + 1) % m)) +
                                 2 * (2 * rng.uniform() - 1);
    return data;
}

void fit(benchmark::State& state, anima::regressor_kind kind) {
    const sadm_like_data data = make_data(int(state.range(0)), int(state.range(1)), int(state.range(2)));
    for (auto _ : state) {
        auto r = anima::make_regressor<double>(kind);
        r->fit(data.inputs, data.outputs);
        benchmark::DoNotOptimize(r);
    }
}

void predict(benchmark::State& state, anima::regressor_kind kind) {
    const sadm_like_data data = make_data(int(state.range(0)), int(state.range(1)), int(state.range(2)));
    auto r = anima::make_regressor<double>(kind);
    r->fit(data.inputs, data.outputs);
    const matrix frame = data.inputs.row(7);
    for (auto _ : state) {
        matrix out = r->predict(frame);
        benchmark::DoNotOptimize(out.data());
    }
}

void BM_fit_eigen_qr(benchmark::State& state) {
    const sadm_like_data data = make_data(int(state.range(0)), int(state.range(1)), int(state.range(2)));
    for (auto _ : state) {
        matrix design(data.inputs.rows(), data.inputs.cols() + 1);
        design << matrix::Ones(data.inputs.rows(), 1), data.inputs;
        matrix w = design.colPivHouseholderQr().solve(data.outputs);
        benchmark::DoNotOptimize(w.data());
    }
}

void sizes(benchmark::internal::Benchmark* b) {
    b->Args({300, 15, 45})->Args({300, 10, 30})->Args({300, 20, 60})->Unit(benchmark::kMicrosecond);
}

}  // namespace

BENCHMARK_CAPTURE(fit, linear, anima::regressor_kind::linear)->Apply(sizes);
BENCHMARK(BM_fit_eigen_qr)->Apply(sizes);
BENCHMARK_CAPTURE(fit, poly2, anima::regressor_kind::poly2)->Apply(sizes);
BENCHMARK_CAPTURE(fit, mlp, anima::regressor_kind::mlp)->Apply(sizes);
BENCHMARK_CAPTURE(fit, svr, anima::regressor_kind::svr)->Apply(sizes);
BENCHMARK_CAPTURE(predict, linear, anima::regressor_kind::linear)->Apply(sizes);
BENCHMARK_CAPTURE(predict, poly2, anima::regressor_kind::poly2)->Apply(sizes);
BENCHMARK_CAPTURE(predict, mlp, anima::regressor_kind::mlp)->Apply(sizes);
BENCHMARK_CAPTURE(predict, svr, anima::regressor_kind::svr)->Apply(sizes);
