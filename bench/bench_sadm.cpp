// SADM timings on the bundled FGNet frames (144 x 160, the face about
// 120 x 120 pixels) and on random data of the real problem's shape.
//
//   BM_pca_fit<anima>/n/d        anima::pca::fit (Gram route), n samples of dimension d
//   BM_pca_fit<eigen_bdcsvd>/n/d Eigen's BDCSVD of the same centred data (thin V): the peer
//   BM_warp_sample               one frame warped onto the reference (g of Eq 2)
//   BM_synthesis                 steps 1-5 for one frame: landmarks -> b_s -> b_g -> g -> warped face
//   BM_synthesis_poisson         the same, pasted into the frame with Poisson blending
//   BM_train_regressor/<kind>    fitting each available regressor b_s -> b_g on the 36 frames
#include <anima/core/random.hpp>
#include <anima/image/pnm.hpp>
#include <anima/sadm.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/SVD>

#include <cstdio>
#include <string>
#include <vector>

namespace {

using matrix = Eigen::MatrixXd;

struct frames {
    std::vector<anima::grey_image<double>> images;
    std::vector<anima::landmark_set<double>> landmarks;
};

const frames& bundled() {
    static const frames f = [] {
        frames out;
        for (int k = 0; k < 36; ++k) {
            char name[32];
            std::snprintf(name, sizeof name, "franck_%05d", 11 * k);
            const std::string dir = ANIMA_BENCH_DATA_DIR "/face/";
            out.images.push_back(anima::read_grey_pnm<double>(dir + "images/" + name + ".pgm"));
            out.landmarks.push_back(anima::read_pts<double>(dir + "points/" + name + ".pts"));
        }
        return out;
    }();
    return f;
}

const anima::sadm_model<double>& model() {
    static const anima::sadm_model<double> m = anima::sadm_model<double>::train(bundled().images, bundled().landmarks);
    return m;
}

matrix random_data(Eigen::Index n, Eigen::Index d) {
    anima::random_source rng(1);
    matrix m(n, d);
    for (Eigen::Index j = 0; j < d; ++j)
        for (Eigen::Index i = 0; i < n; ++i) m(i, j) = 255 * rng.uniform();
    return m;
}

void BM_pca_fit_anima(benchmark::State& state) {
    const matrix x = random_data(state.range(0), state.range(1));
    for (auto _ : state) benchmark::DoNotOptimize(anima::pca<double>::fit(x, {1.0, 0}).size());
}

void BM_pca_fit_eigen_bdcsvd(benchmark::State& state) {
    const matrix x = random_data(state.range(0), state.range(1));
    for (auto _ : state) {
        const matrix centred = x.rowwise() - x.colwise().mean();
        Eigen::BDCSVD<matrix> svd(centred, Eigen::ComputeThinV);
        benchmark::DoNotOptimize(svd.singularValues().data());
    }
}

void BM_warp_sample(benchmark::State& state) {
    const auto& m = model();
    const auto& f = bundled();
    for (auto _ : state) benchmark::DoNotOptimize(m.grey().sample(f.images[5], f.landmarks[5]).data());
    state.counters["face_pixels"] = static_cast<double>(m.grey().raster().size());
}

void BM_synthesis(benchmark::State& state) {
    const auto& m = model();
    const auto& f = bundled();
    for (auto _ : state)
        benchmark::DoNotOptimize(m.render(f.landmarks[7], f.images[7].rows(), f.images[7].cols()).values.data());
}

void BM_synthesis_poisson(benchmark::State& state) {
    const auto& m = model();
    const auto& f = bundled();
    for (auto _ : state) benchmark::DoNotOptimize(m.synthesize(f.landmarks[7], f.images[7]).data());
}

void BM_train_regressor(benchmark::State& state, anima::regressor_kind kind) {
    const auto& m = model();
    const auto& f = bundled();
    matrix bs(36, m.shape().size()), bg(36, m.grey().size());
    for (int k = 0; k < 36; ++k) {
        bs.row(k) = m.shape().parameters(f.landmarks[static_cast<std::size_t>(k)]).transpose();
        bg.row(k) = m.grey().parameters(m.grey().sample(f.images[static_cast<std::size_t>(k)], f.landmarks[static_cast<std::size_t>(k)])).transpose();
    }
    std::unique_ptr<anima::regressor<double>> r;
    try {
        r = anima::make_regressor<double>(kind);
    } catch (const anima::invalid_argument& e) {
        state.SkipWithError(e.what());
        return;
    }
    for (auto _ : state) {
        r->fit(bs, bg);
        benchmark::DoNotOptimize(r.get());
    }
}

}  // namespace

BENCHMARK(BM_pca_fit_anima)->Args({36, 14000})->Args({300, 14000})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_pca_fit_eigen_bdcsvd)->Args({36, 14000})->Args({300, 14000})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_warp_sample)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_synthesis)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_synthesis_poisson)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_train_regressor, linear, anima::regressor_kind::linear)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_train_regressor, poly2, anima::regressor_kind::poly2)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_train_regressor, mlp, anima::regressor_kind::mlp)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_train_regressor, svr, anima::regressor_kind::svr)->Unit(benchmark::kMillisecond);
