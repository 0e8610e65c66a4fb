// Time to build one transition on the real 31-joint skeleton (CMU 02_01 walk,
// from frame 120 to frame 250 of the same clip, a change of gait phase), and
// with classes given on the bundled 43-joint run (Daz layout, with fingers;
// from frame 70 to frame 30 of the same clip):
//
//   BM_transition<variable_timing>  anima::make_transition: classification of
//                                   both clips, timing, per-joint lerp/slerp/squad,
//                                   root path and placement of B
//   BM_transition<variable_timing, classified>
//                                   the same with both clips classified beforehand
//                                   (transition_params::class_a / class_b)
//   BM_transition<variable_timing, classified, into>
//                                   the same through make_transition_into, the
//                                   per-call form for a game loop: output and
//                                   workspace kept from call to call, nothing
//                                   allocated, B not copied (placement only)
//   BM_transition<..., 43 joints>   the two rows above on the run
//   BM_transition<..., key joints timed, 43 joints>
//                                   the per-call form with angular speeds measured
//                                   for the key joints only
//                                   (timing_params::every_joint = false): the same T
//   BM_transition<..., 43 joints, float>
//                                   the two per-call rows above in float, the
//                                   scalar of game engines (the run read as
//                                   clip<float>)
//   BM_transition<crossfade>        anima::crossfade over 0.3 s, the fixed-length
//                                   blend most engines use
//   BM_transition<inertialize>      anima::inertialize with a 0.1 s half-life
//   BM_transition<timing_only>      anima::variable_timing alone (the per-joint
//                                   angles and speeds that decide T)
//
// The baselines and make_transition each place B (a copy of the clip's frames
// from B's start onwards); make_transition also classifies both whole clips,
// which is most of its cost: a game would classify its clips once, offline.
#include <anima/bvh/reader.hpp>
#include <anima/transition.hpp>

#include <benchmark/benchmark.h>

#ifndef ANIMA_BENCH_DATA_DIR
#error "ANIMA_BENCH_DATA_DIR must name the examples/data directory"
#endif

namespace {

const anima::clip<double>& walk() {
    static const anima::clip<double> c = anima::read_bvh(ANIMA_BENCH_DATA_DIR "/walk_cmu31_02_01.bvh");
    return c;
}

template <class T = double>
const anima::clip<T>& run() {
    static const anima::clip<T> c = anima::read_bvh<T>(ANIMA_BENCH_DATA_DIR "/run_cmu_09_01.bvh");
    return c;
}

constexpr std::size_t trigger = 120, start = 250;

void variable_timing(benchmark::State& state) {
    const auto& c = walk();
    for (auto _ : state) {
        auto t = anima::make_transition(c, trigger, c, start);
        benchmark::DoNotOptimize(t.frames.rotations().data());
    }
}

template <class T>
anima::transition_params classified(const anima::clip<T>& c) {
    anima::transition_params params;
    params.class_a = params.class_b = anima::classify_motion(c, anima::joint_roles(c.skeleton()));
    return params;
}

void make_classified(benchmark::State& state, const anima::clip<double>& c, std::size_t at, std::size_t to) {
    const anima::transition_params params = classified(c);
    for (auto _ : state) {
        auto t = anima::make_transition(c, at, c, to, params);
        benchmark::DoNotOptimize(t.frames.rotations().data());
    }
}

template <class T>
void into_classified(benchmark::State& state, const anima::clip<T>& c, std::size_t at, std::size_t to,
                     bool every_joint = true) {
    anima::transition_params params = classified(c);
    params.timing.every_joint = every_joint;
    anima::transition_frames<T> out;
    anima::transition_workspace<T> workspace;
    for (auto _ : state) {
        anima::make_transition_into(c, at, c, to, params, out, workspace);
        benchmark::DoNotOptimize(out.frames.rotations().data());
    }
}

void variable_timing_preclassified(benchmark::State& state) { make_classified(state, walk(), trigger, start); }
void variable_timing_into(benchmark::State& state) { into_classified(state, walk(), trigger, start); }
void variable_timing_preclassified_43(benchmark::State& state) { make_classified(state, run(), 70, 30); }
void variable_timing_into_43(benchmark::State& state) { into_classified(state, run(), 70, 30); }
void variable_timing_into_43_key_joints(benchmark::State& state) { into_classified(state, run(), 70, 30, false); }
void variable_timing_into_43_float(benchmark::State& state) { into_classified(state, run<float>(), 70, 30); }
void variable_timing_into_43_key_joints_float(benchmark::State& state) {
    into_classified(state, run<float>(), 70, 30, false);
}

void crossfade(benchmark::State& state) {
    const auto& c = walk();
    for (auto _ : state) {
        auto j = anima::crossfade(c, trigger, c, start, 0.3);
        benchmark::DoNotOptimize(j.motion.rotations().data());
    }
}

void inertialize(benchmark::State& state) {
    const auto& c = walk();
    for (auto _ : state) {
        auto j = anima::inertialize(c, trigger, c, start, 0.1);
        benchmark::DoNotOptimize(j.motion.rotations().data());
    }
}

void timing_only(benchmark::State& state) {
    const auto& c = walk();
    const auto roles = anima::joint_roles(c.skeleton());
    const Eigen::Quaterniond turn = Eigen::Quaterniond::Identity();
    for (auto _ : state) {
        auto t = anima::variable_timing(c, trigger, c, start, roles, turn);
        benchmark::DoNotOptimize(t.duration);
    }
}

}  // namespace

BENCHMARK(variable_timing)->Name("BM_transition<variable_timing>")->Unit(benchmark::kMicrosecond);
BENCHMARK(variable_timing_preclassified)->Name("BM_transition<variable_timing, classified>")->Unit(benchmark::kMicrosecond);
BENCHMARK(variable_timing_into)
    ->Name("BM_transition<variable_timing, classified, into>")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(variable_timing_preclassified_43)
    ->Name("BM_transition<variable_timing, classified, 43 joints>")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(variable_timing_into_43)
    ->Name("BM_transition<variable_timing, classified, into, 43 joints>")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(variable_timing_into_43_key_joints)
    ->Name("BM_transition<variable_timing, classified, into, key joints timed, 43 joints>")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(variable_timing_into_43_float)
    ->Name("BM_transition<variable_timing, classified, into, 43 joints, float>")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(variable_timing_into_43_key_joints_float)
    ->Name("BM_transition<variable_timing, classified, into, key joints timed, 43 joints, float>")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(crossfade)->Name("BM_transition<crossfade>")->Unit(benchmark::kMicrosecond);
BENCHMARK(inertialize)->Name("BM_transition<inertialize>")->Unit(benchmark::kMicrosecond);
BENCHMARK(timing_only)->Name("BM_transition<timing_only>")->Unit(benchmark::kMicrosecond);
