// Whole-clip functions on the bundled 43-joint run, read as clip<float> and
// as clip<double>: the same calls in both scalars on the same file.
//
//   BM_float_mocap<function, scalar>
//
// The run's BVH holds channel values such as 3.9e-19 degrees: in float its
// quaternion components and the products made from them are subnormal
// numbers, which x86 handles in microcode. Each function timed here holds
// an anima::flush_denormals scope (see docs/rotation.md); without it the
// float rows were 1.2 to 2.2 times slower (docs/benchmarks.md).
//
//   resample             to 30 frames per second
//   global_positions     every joint's world position in every frame
//   frame_features       the DOF matrix symmetry and textures compare
//   classify_motion      the motion class and contact phases of the clip
//   find_contacts        the feet's contact runs
//   symmetry_scores      Eq 3-5 on the clip's frame features
//   crossfade            0.3 s from frame 70 to frame 30
//   inertialize          half-life 0.1 s, the same frames
//   plant_feet           contacts found, planted legs solved by IK
//   make_motion_texture  300 frames, m = 60, overlap 30
#include <anima/bvh/reader.hpp>
#include <anima/ik/plant_feet.hpp>
#include <anima/motion/contacts.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/frame_features.hpp>
#include <anima/motion/resample.hpp>
#include <anima/symmetry/symmetry_scores.hpp>
#include <anima/texture/motion_texture.hpp>
#include <anima/transition/baselines.hpp>
#include <anima/transition/classify.hpp>

#include <benchmark/benchmark.h>

#include <string>

#ifndef ANIMA_BENCH_DATA_DIR
#error "ANIMA_BENCH_DATA_DIR must name the examples/data directory"
#endif

namespace {

template <class T>
const anima::clip<T>& run() {
    static const anima::clip<T> c = anima::read_bvh<T>(std::string(ANIMA_BENCH_DATA_DIR) + "/run_cmu_09_01.bvh");
    return c;
}

template <class T>
void resample(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(anima::resample(run<T>(), T(1) / T(30)).rotations().data());
}

template <class T>
void positions(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(anima::global_positions(run<T>()).data());
}

template <class T>
void features(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(anima::frame_features(run<T>()).data());
}

template <class T>
void classify(benchmark::State& state) {
    const auto& c = run<T>();
    const auto roles = anima::joint_roles(c.skeleton());
    for (auto _ : state) benchmark::DoNotOptimize(anima::classify_motion(c, roles).type);
}

template <class T>
void contacts(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(anima::find_contacts(run<T>()).fast_foot_speed);
}

template <class T>
void symmetry(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(anima::symmetry_scores(run<T>()).score.data());
}

template <class T>
void crossfade(benchmark::State& state) {
    const auto& c = run<T>();
    for (auto _ : state) benchmark::DoNotOptimize(anima::crossfade(c, 70, c, 30, T(0.3)).motion.rotations().data());
}

template <class T>
void inertialize(benchmark::State& state) {
    const auto& c = run<T>();
    for (auto _ : state) benchmark::DoNotOptimize(anima::inertialize(c, 70, c, 30, T(0.1)).motion.rotations().data());
}

template <class T>
void plant(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(anima::plant_feet(run<T>()).planted.rotations().data());
}

template <class T>
void texture(benchmark::State& state) {
    anima::motion_texture_params<T> params;
    params.texton.m = 60;
    params.texton.overlap = 30;
    for (auto _ : state) benchmark::DoNotOptimize(anima::make_motion_texture(run<T>(), 300, params).motion.rotations().data());
}

}  // namespace

#define ANIMA_FLOAT_MOCAP(function, name, unit)                                                          \
    BENCHMARK_TEMPLATE(function, float)->Name("BM_float_mocap<" name ", float>")->Unit(benchmark::unit);   \
    BENCHMARK_TEMPLATE(function, double)->Name("BM_float_mocap<" name ", double>")->Unit(benchmark::unit);

ANIMA_FLOAT_MOCAP(resample, "resample", kMicrosecond)
ANIMA_FLOAT_MOCAP(positions, "global_positions", kMicrosecond)
ANIMA_FLOAT_MOCAP(features, "frame_features", kMicrosecond)
ANIMA_FLOAT_MOCAP(classify, "classify_motion", kMicrosecond)
ANIMA_FLOAT_MOCAP(contacts, "find_contacts", kMicrosecond)
ANIMA_FLOAT_MOCAP(symmetry, "symmetry_scores", kMicrosecond)
ANIMA_FLOAT_MOCAP(crossfade, "crossfade", kMicrosecond)
ANIMA_FLOAT_MOCAP(inertialize, "inertialize", kMicrosecond)
ANIMA_FLOAT_MOCAP(plant, "plant_feet", kMillisecond)
ANIMA_FLOAT_MOCAP(texture, "make_motion_texture", kMillisecond)
