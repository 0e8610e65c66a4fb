// The motion-texture pipeline stage by stage, on the paper's figure: a
// 209-frame clip (the bundled CMU walk, frames 0..208) made into 1,700
// frames with m = 100 and an overlap of 50.
//
//   features         DOF view, frame features, Eq 2 weights
//   search           the (i, j) loop by diagonal prefix sums: 51 x 51 windows of 50 frames
//   search_brute     the same windows summed one by one (the cubic loop), for comparison
//   cut              Eq 8-9 capacities and the (row x overlap frame) min-cut
//   texton           all of the above plus the fades (anima::make_texton)
//   patch            textons end to end and resequenced, no smoothing
//   patch_poisson_1d patching and Poisson smoothing per row (the default)
//   patch_poisson_2d patching and the paper's 2D Poisson form
//   pipeline         anima::make_motion_texture (feet planted, the default); counters: each stage's own time (ms)
//   texton<3 clips>  make_texton of the whole walk as three clips (m = 70, overlap 35): three seams
//   least_cost_clip_order<3 clips>
//                    the search for their cheapest order: six junctions' overlap searches
#include <anima/bvh/reader.hpp>
#include <anima/motion/dof_view.hpp>
#include <anima/motion/frame_distance.hpp>
#include <anima/motion/frame_features.hpp>
#include <anima/texture.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace {

constexpr std::size_t clip_frames = 209, texture_frames = 1700, m = 100, overlap = 50;

const anima::clip<double>& input() {
    static const anima::clip<double> c =
        anima::read_bvh<double>(std::string(ANIMA_BENCH_DATA_DIR) + "/walk_cmu31_02_01.bvh").slice(0, clip_frames);
    return c;
}

anima::motion_texture_params<double> params() {
    anima::motion_texture_params<double> p;
    p.texton.m = m;
    p.texton.overlap = overlap;
    return p;
}

const Eigen::MatrixXd& features() {
    static const Eigen::MatrixXd x = anima::frame_features(input());
    return x;
}

const anima::frame_distance<double>& distance() {
    static const auto d = anima::make_frame_distance(features(), input().frame_time());
    return d;
}

void features_stage(benchmark::State& state) {
    for (auto _ : state) {
        const auto layout = anima::make_dof_layout(input());
        const Eigen::MatrixXd x = anima::frame_features(input());
        benchmark::DoNotOptimize(anima::make_frame_distance(x, input().frame_time()));
        benchmark::DoNotOptimize(layout);
    }
}
BENCHMARK(features_stage)->Name("features")->Unit(benchmark::kMicrosecond);

void search_stage(benchmark::State& state) {
    const auto F = static_cast<Eigen::Index>(clip_frames), M = static_cast<Eigen::Index>(m);
    for (auto _ : state)
        benchmark::DoNotOptimize(
            anima::search_overlap(anima::frame_pair_costs(features().middleRows(F - M, M), features().topRows(M), distance()), overlap));
}
BENCHMARK(search_stage)->Name("search")->Unit(benchmark::kMicrosecond);

void search_brute(benchmark::State& state) {
    const auto F = static_cast<Eigen::Index>(clip_frames), M = static_cast<Eigen::Index>(m), N = static_cast<Eigen::Index>(overlap);
    const Eigen::MatrixXd a = features().middleRows(F - M, M).transpose(), b = features().topRows(M).transpose();
    for (auto _ : state) {
        double best = 1e300;
        for (Eigen::Index i = 0; i + N <= M; ++i)
            for (Eigen::Index j = 0; j + N <= M; ++j) {
                double sum = 0;
                for (Eigen::Index t = 0; t < N; ++t) sum += distance()(a.col(i + t), b.col(j + t));
                best = std::min(best, sum);
            }
        benchmark::DoNotOptimize(best);
    }
}
BENCHMARK(search_brute)->Unit(benchmark::kMicrosecond);

void cut_stage(benchmark::State& state) {
    const auto texton = anima::make_texton(input(), params().texton);
    const Eigen::Index a = static_cast<Eigen::Index>(clip_frames - m + texton.offset_m2);
    const Eigen::Index b = static_cast<Eigen::Index>(texton.offset_m1);
    const auto n = static_cast<Eigen::Index>(overlap);
    // The same neighbours make_texton ties: each joint to its parent.
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t r = 1; r < texton.rows(); ++r) {
        const int parent = input().skeleton()[texton.row_joint[r]].parent;
        for (std::size_t q = 0; q < texton.rows(); ++q)
            if (parent >= 0 && texton.row_rotation[q] && texton.row_joint[q] == static_cast<std::size_t>(parent))
                pairs.emplace_back(q, r);
    }
    for (auto _ : state) {
        const anima::seam_cost<double> cost(features().middleRows(a, n), features().middleRows(b, n), 3, distance().precision);
        benchmark::DoNotOptimize(anima::cut_seams(cost, pairs, 0.5));
    }
    state.counters["rows"] = static_cast<double>(texton.rows());
}
BENCHMARK(cut_stage)->Name("cut")->Unit(benchmark::kMicrosecond);

void texton_stage(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(anima::make_texton(input(), params().texton));
}
BENCHMARK(texton_stage)->Name("texton")->Unit(benchmark::kMicrosecond);

// The whole bundled walk (343 frames) as three clips of 140-143 frames:
// one loop through the three (three seams instead of one), and the search
// for the order whose seams cost least (all six junctions).
const std::vector<anima::clip<double>>& three_clips() {
    static const std::vector<anima::clip<double>> clips = [] {
        const auto walk = anima::read_bvh<double>(std::string(ANIMA_BENCH_DATA_DIR) + "/walk_cmu31_02_01.bvh");
        return std::vector<anima::clip<double>>{walk.slice(0, 140), walk.slice(100, 240), walk.slice(200, walk.frames())};
    }();
    return clips;
}

anima::texton_params<double> three_clip_params() {
    anima::texton_params<double> p;
    p.m = 70;
    p.overlap = 35;
    return p;
}

void texton_three_clips(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(anima::make_texton(three_clips(), three_clip_params()));
}
BENCHMARK(texton_three_clips)->Name("texton<3 clips>")->Unit(benchmark::kMicrosecond);

void clip_order_three(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(anima::least_cost_clip_order(three_clips(), three_clip_params()));
}
BENCHMARK(clip_order_three)->Name("least_cost_clip_order<3 clips>")->Unit(benchmark::kMicrosecond);

void patch_with(benchmark::State& state, bool smoothing, anima::seam_smoothing_form form) {
    const auto texton = anima::make_texton(input(), params().texton);
    auto p = params();
    p.smoothing.enabled = smoothing;
    p.smoothing.poisson.form = form;
    p.planting.enabled = false;  // patching and smoothing alone
    for (auto _ : state) benchmark::DoNotOptimize(anima::patch_texton(texton, texture_frames, p));
}
void patch(benchmark::State& state) { patch_with(state, false, anima::seam_smoothing_form::temporal); }
void patch_poisson_1d(benchmark::State& state) { patch_with(state, true, anima::seam_smoothing_form::temporal); }
void patch_poisson_2d(benchmark::State& state) { patch_with(state, true, anima::seam_smoothing_form::image); }
BENCHMARK(patch)->Unit(benchmark::kMicrosecond);
BENCHMARK(patch_poisson_1d)->Unit(benchmark::kMicrosecond);
BENCHMARK(patch_poisson_2d)->Unit(benchmark::kMicrosecond);

void pipeline(benchmark::State& state) {
    anima::texture_timings sum;
    double runs = 0;
    for (auto _ : state) {
        const auto t = anima::make_motion_texture(input(), texture_frames, params());
        sum.features += t.timings.features;
        sum.search += t.timings.search;
        sum.cut += t.timings.cut;
        sum.blend += t.timings.blend;
        sum.patch += t.timings.patch;
        sum.smoothing += t.timings.smoothing;
        sum.planting += t.timings.planting;
        runs += 1;
        benchmark::DoNotOptimize(t);
    }
    const double ms = 1e3 / runs;
    state.counters["features_ms"] = sum.features * ms;
    state.counters["search_ms"] = sum.search * ms;
    state.counters["cut_ms"] = sum.cut * ms;
    state.counters["fades_ms"] = sum.blend * ms;
    state.counters["patch_ms"] = sum.patch * ms;
    state.counters["poisson_ms"] = sum.smoothing * ms;
    state.counters["planting_ms"] = sum.planting * ms;
}
BENCHMARK(pipeline)->Unit(benchmark::kMillisecond);

}  // namespace
