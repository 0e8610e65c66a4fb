// Symmetry scores (Eq 3-5) of long clips: the banded route of
// anima::symmetry_scores, which evaluates only the pairs (i-r, i+r), next to
// the full-matrix route (anima::distance_matrix, then Eq 3-5 read from it).
//
//   BM_symmetry<banded, metric>/N       anima::symmetry_scores on N frames
//   BM_symmetry<full_matrix, metric>/N  make_frame_distance + distance_matrix
//                                       + Eq 3-5 from the matrix
//
// The N-frame clips are the DOF matrix (anima::frame_features) of the real
// CMU 02_01 walk (343 frames, 96 DOFs), resequenced by symmetric playback to
// N frames: real poses in a realistic order. Radius 10, smoothness 0.
// The full matrix takes O(N^2) memory and time: it runs at 1k and 2k frames
// only, to keep this file quick (4k frames already take over half a
// second per iteration, 10k frames would need 800 MB and several seconds).
// Before anything is timed both routes are compared at every size where
// both run: the program aborts if a score differs by more than 1e-9.
// items/s counts frames scored; the 100k-frame case is the time to score a
// long motion (the aim: well under a second).
#include <anima/bvh/reader.hpp>
#include <anima/symmetry.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <string>
#include <vector>

#ifndef ANIMA_BENCH_DATA_DIR
#error "ANIMA_BENCH_DATA_DIR must name the examples/data directory"
#endif

namespace {

using matrix = Eigen::MatrixXd;

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "bench_symmetry: %s\n", what.c_str());
    std::abort();
}

struct source {
    matrix dofs;  // frames x DOF of the walk
    double frame_time = 0;
    std::vector<anima::turning_candidate<double>> candidates;
};

const source& walk() {
    static const source s = [] {
        source out;
        try {
            const auto c = anima::read_bvh<double>(std::string(ANIMA_BENCH_DATA_DIR) + "/walk_cmu31_02_01.bvh");
            out.dofs = anima::frame_features(c);
            out.frame_time = c.frame_time();
            out.candidates = anima::symmetry_scores(out.dofs, out.frame_time).candidates;
        } catch (const std::exception& e) {
            fail(e.what());
        }
        if (out.candidates.size() < 2) fail("the walk has fewer than two turning candidates");
        return out;
    }();
    return s;
}

// The walk resequenced by symmetric playback to `frames` frames.
const matrix& clip_of(std::size_t frames) {
    static std::map<std::size_t, matrix> cache;
    if (const auto it = cache.find(frames); it != cache.end()) return it->second;
    const auto& w = walk();
    anima::symmetric_playback<double> playback(static_cast<std::size_t>(w.dofs.rows()), w.candidates);
    const auto stream = playback.take(frames);
    matrix m(static_cast<Eigen::Index>(frames), w.dofs.cols());
    for (std::size_t k = 0; k < frames; ++k)
        m.row(static_cast<Eigen::Index>(k)) = w.dofs.row(static_cast<Eigen::Index>(stream[k]));
    return cache.emplace(frames, std::move(m)).first->second;
}

anima::symmetry_params<double> params(anima::frame_metric metric) {
    anima::symmetry_params<double> p;
    p.distance.metric = metric;
    return p;
}

// Eq 3-5 read from the full distance matrix.
anima::symmetry_result<double> full_matrix_route(const matrix& dofs, double frame_time, const anima::symmetry_params<double>& p) {
    const matrix d = anima::distance_matrix(dofs, anima::make_frame_distance(dofs, frame_time, p.distance));
    const auto w = anima::binomial_weights<double>(p.radius, p.smoothness);
    const Eigen::Index n = d.rows();
    anima::symmetry_result<double> out;
    out.weighted_distance.setZero(n);
    out.score.setZero(n);
    out.pairs.assign(static_cast<std::size_t>(n), 0);
    double largest = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::Index reach = std::min<Eigen::Index>({p.radius, i, n - 1 - i});
        double sum = 0, used = 0;
        for (Eigen::Index r = 1; r <= reach; ++r) {
            sum += w[static_cast<std::size_t>(r - 1)] * d(i - r, i + r);
            used += w[static_cast<std::size_t>(r - 1)];
        }
        out.pairs[static_cast<std::size_t>(i)] = static_cast<int>(reach);
        if (reach > 0) largest = std::max(largest, out.weighted_distance[i] = sum / used);
    }
    for (Eigen::Index i = 0; i < n; ++i)
        if (out.pairs[static_cast<std::size_t>(i)] > 0) out.score[i] = largest > 0 ? 1 - out.weighted_distance[i] / largest : 1;
    // Candidates need a full window, as symmetry_scores' default min_pairs.
    const int full = static_cast<int>(std::min<Eigen::Index>(p.radius, std::max<Eigen::Index>(0, (n - 1) / 2)));
    out.candidates = anima::turning_candidates(out.score, out.pairs, p.radius, std::max(1, full));
    return out;
}

constexpr std::size_t full_matrix_sizes[] = {1000, 2000};
constexpr std::size_t banded_sizes[] = {1000, 2000, 10000, 100000};

void check_routes_agree() {
    for (auto metric : {anima::frame_metric::mahalanobis, anima::frame_metric::l2})
        for (std::size_t n : full_matrix_sizes) {
            const matrix& m = clip_of(n);
            const auto banded = anima::symmetry_scores(m, walk().frame_time, params(metric));
            const auto full = full_matrix_route(m, walk().frame_time, params(metric));
            const double gap = (banded.score - full.score).cwiseAbs().maxCoeff();
            if (!(gap <= 1e-9) || banded.candidates.size() != full.candidates.size())
                fail("banded and full-matrix scores differ by " + std::to_string(gap) + " at " + std::to_string(n) + " frames (" +
                     anima::to_string(metric) + ")");
        }
}

void banded(benchmark::State& state, anima::frame_metric metric) {
    const matrix& m = clip_of(static_cast<std::size_t>(state.range(0)));
    const auto p = params(metric);
    for (auto _ : state) {
        auto r = anima::symmetry_scores(m, walk().frame_time, p);
        benchmark::DoNotOptimize(r.score.data());
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
}

void full(benchmark::State& state, anima::frame_metric metric) {
    const matrix& m = clip_of(static_cast<std::size_t>(state.range(0)));
    const auto p = params(metric);
    for (auto _ : state) {
        auto r = full_matrix_route(m, walk().frame_time, p);
        benchmark::DoNotOptimize(r.score.data());
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
}

const bool registered = [] {
    for (auto metric : {anima::frame_metric::mahalanobis, anima::frame_metric::l2}) {
        const std::string name = anima::to_string(metric);
        auto* b = benchmark::RegisterBenchmark(("BM_symmetry<banded, " + name + ">").c_str(), banded, metric);
        for (std::size_t n : banded_sizes) b->Arg(static_cast<std::int64_t>(n));
        b->Unit(benchmark::kMillisecond);
        auto* f = benchmark::RegisterBenchmark(("BM_symmetry<full_matrix, " + name + ">").c_str(), full, metric);
        for (std::size_t n : full_matrix_sizes) f->Arg(static_cast<std::int64_t>(n));
        f->Unit(benchmark::kMillisecond);
    }
    check_routes_agree();
    return true;
}();

}  // namespace
