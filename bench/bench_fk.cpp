// Forward kinematics throughput on a real 31-joint clip (CMU 02_01 walk, 343
// frames): anima::forward_kinematics next to the same computation written by
// hand with GLM and with Eigen, in float and double.
//
//   BM_fk<anima, T>         anima::forward_kinematics(clip, f, pose) for every frame
//   BM_fk<glm_native, T>    glm::qua local rotations; position = parent position +
//                           parent orientation * local translation
//   BM_fk<eigen_native, T>  Eigen::Transform<T, 3, Isometry> per joint, built from
//                           the local translation and rotation and multiplied down
//                           the chain (global = parent global * local)
//
// One iteration computes every frame of the clip; items/s counts joint poses
// (joints x frames). The GLM and Eigen inputs are prepared from the same clip
// before timing, and all three results are compared once, before anything is
// timed: the program aborts if a position differs by more than 1e-6 (double)
// or 1e-3 (float) from anima's.

#include <anima/bvh/reader.hpp>
#include <anima/motion/forward_kinematics.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <glm/ext/quaternion_double.hpp>
#include <glm/ext/quaternion_float.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <type_traits>
#include <vector>

#ifndef ANIMA_BENCH_DATA_DIR
#error "ANIMA_BENCH_DATA_DIR must name the examples/data directory"
#endif

namespace {

template <class T>
const char* type_name();
template <>
const char* type_name<float>() {
    return "float";
}
template <>
const char* type_name<double>() {
    return "double";
}

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "bench_fk: %s\n", what.c_str());
    std::abort();
}

/// Hand-written GLM forward kinematics: the clip's data copied into GLM types.
template <class T>
struct glm_fk {
    using vec3 = glm::vec<3, T, glm::defaultp>;
    using quat = glm::qua<T, glm::defaultp>;
    std::size_t joints = 0, frames = 0, translated = 0;
    std::vector<int> parent, slot;   // per joint; slot < 0: translation is the rest offset
    std::vector<vec3> offset;        // per joint
    std::vector<quat> rotation;      // frames x joints
    std::vector<vec3> translation;   // frames x translated joints
    std::vector<vec3> positions;     // output of one frame
    std::vector<quat> orientations;  // output of one frame

    explicit glm_fk(const anima::clip<T>& c) {
        const auto& sk = c.skeleton();
        joints = sk.size();
        frames = c.frames();
        translated = sk.translated_joint_count();
        for (std::size_t j = 0; j < joints; ++j) {
            parent.push_back(sk[j].parent);
            slot.push_back(sk.translation_slot(j));
            offset.emplace_back(sk[j].offset.x(), sk[j].offset.y(), sk[j].offset.z());
        }
        for (const auto& q : c.rotations()) {
            quat g;
            g.w = q.w();
            g.x = q.x();
            g.y = q.y();
            g.z = q.z();
            rotation.push_back(g);
        }
        for (const auto& t : c.translations()) translation.emplace_back(t.x(), t.y(), t.z());
        positions.resize(joints);
        orientations.resize(joints);
    }

    void frame(std::size_t f) {
        const quat* rot = rotation.data() + f * joints;
        const vec3* tra = translation.data() + f * translated;
        for (std::size_t j = 0; j < joints; ++j) {
            const vec3& local_t = slot[j] < 0 ? offset[j] : tra[slot[j]];
            if (parent[j] < 0) {
                positions[j] = local_t;
                orientations[j] = rot[j];
            } else {
                const auto p = static_cast<std::size_t>(parent[j]);
                positions[j] = positions[p] + orientations[p] * local_t;
                orientations[j] = orientations[p] * rot[j];
            }
        }
    }
};

/// Hand-written Eigen forward kinematics with rigid transforms, the usual
/// matrix formulation: local = Translation(t) * rotation, global = parent * local.
template <class T>
struct eigen_fk {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    using iso3 = Eigen::Transform<T, 3, Eigen::Isometry>;
    std::size_t joints = 0, frames = 0, translated = 0;
    std::vector<int> parent, slot;
    std::vector<vec3> offset;
    std::vector<Eigen::Quaternion<T>> rotation;
    std::vector<vec3> translation;
    std::vector<iso3> global;  // output of one frame

    explicit eigen_fk(const anima::clip<T>& c) {
        const auto& sk = c.skeleton();
        joints = sk.size();
        frames = c.frames();
        translated = sk.translated_joint_count();
        for (std::size_t j = 0; j < joints; ++j) {
            parent.push_back(sk[j].parent);
            slot.push_back(sk.translation_slot(j));
            offset.push_back(sk[j].offset);
        }
        rotation = c.rotations();
        translation = c.translations();
        global.resize(joints);
    }

    void frame(std::size_t f) {
        const Eigen::Quaternion<T>* rot = rotation.data() + f * joints;
        const vec3* tra = translation.data() + f * translated;
        for (std::size_t j = 0; j < joints; ++j) {
            const vec3& local_t = slot[j] < 0 ? offset[j] : tra[slot[j]];
            const iso3 local = Eigen::Translation<T, 3>(local_t) * rot[j];
            if (parent[j] < 0)
                global[j] = local;
            else
                global[j] = global[static_cast<std::size_t>(parent[j])] * local;
        }
    }
};

template <class T>
struct fixture {
    anima::clip<T> clip;
    std::size_t items = 0;  // joints x frames
};

template <class T>
void check_same_positions(const anima::clip<T>& c) {
    const T tol = std::is_same_v<T, float> ? T(1e-3) : T(1e-6);
    glm_fk<T> g(c);
    eigen_fk<T> e(c);
    anima::global_pose<T> pose;
    T worst_glm = 0, worst_eigen = 0;
    for (std::size_t f = 0; f < c.frames(); ++f) {
        anima::forward_kinematics(c, f, pose);
        g.frame(f);
        e.frame(f);
        for (std::size_t j = 0; j < c.joints(); ++j) {
            const auto& p = pose.positions[j];
            const auto& q = g.positions[j];
            const auto r = e.global[j].translation();
            for (int k = 0; k < 3; ++k) {
                worst_glm = std::max(worst_glm, std::abs(p[k] - q[k]));
                worst_eigen = std::max(worst_eigen, std::abs(p[k] - r[k]));
            }
        }
    }
    if (!(worst_glm <= tol) || !(worst_eigen <= tol))
        fail(std::string("positions differ (") + type_name<T>() + "): GLM by " + std::to_string(worst_glm) +
             ", Eigen by " + std::to_string(worst_eigen));
}

template <class T>
fixture<T> load() {
    fixture<T> fx;
    const std::string path = std::string(ANIMA_BENCH_DATA_DIR) + "/walk_cmu31_02_01.bvh";
    try {
        fx.clip = anima::read_bvh<T>(path);
    } catch (const std::exception& e) {
        fail(e.what());
    }
    if (fx.clip.frames() == 0) fail(path + " has no frames");
    fx.items = fx.clip.joints() * fx.clip.frames();
    check_same_positions(fx.clip);
    return fx;
}

template <class T>
const fixture<T>& data() {
    static const fixture<T> fx = load<T>();
    return fx;
}

void finish(benchmark::State& state, std::size_t items) {
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(items));
}

template <class T>
void fk_anima(benchmark::State& state) {
    const auto& fx = data<T>();
    anima::global_pose<T> pose;
    for (auto _ : state) {
        for (std::size_t f = 0; f < fx.clip.frames(); ++f) {
            anima::forward_kinematics(fx.clip, f, pose);
            benchmark::DoNotOptimize(pose.positions.data());
            benchmark::DoNotOptimize(pose.orientations.data());
            benchmark::ClobberMemory();
        }
    }
    finish(state, fx.items);
}

template <class T>
void fk_glm(benchmark::State& state) {
    const auto& fx = data<T>();
    glm_fk<T> g(fx.clip);
    for (auto _ : state) {
        for (std::size_t f = 0; f < g.frames; ++f) {
            g.frame(f);
            benchmark::DoNotOptimize(g.positions.data());
            benchmark::DoNotOptimize(g.orientations.data());
            benchmark::ClobberMemory();
        }
    }
    finish(state, fx.items);
}

template <class T>
void fk_eigen(benchmark::State& state) {
    const auto& fx = data<T>();
    eigen_fk<T> e(fx.clip);
    for (auto _ : state) {
        for (std::size_t f = 0; f < e.frames; ++f) {
            e.frame(f);
            benchmark::DoNotOptimize(e.global.data());
            benchmark::ClobberMemory();
        }
    }
    finish(state, fx.items);
}

template <class T>
void register_all() {
    const std::string ty = type_name<T>();
    benchmark::RegisterBenchmark(("BM_fk<anima, " + ty + ">").c_str(), fk_anima<T>);
    benchmark::RegisterBenchmark(("BM_fk<glm_native, " + ty + ">").c_str(), fk_glm<T>);
    benchmark::RegisterBenchmark(("BM_fk<eigen_native, " + ty + ">").c_str(), fk_eigen<T>);
}

const bool registered = [] {
    register_all<float>();
    register_all<double>();
    return true;
}();

}  // namespace
