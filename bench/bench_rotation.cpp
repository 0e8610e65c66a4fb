// Rotation interpolation throughput: anima next to GLM's and Eigen's own
// functions, on the same precomputed inputs in the same run.
//
//   BM_slerp<anima, glm, T>                 anima::slerp on glm::qua<T>
//   BM_slerp<glm_native, T>                 glm::slerp
//   BM_slerp<anima, eigen, T>               anima::slerp on Eigen::Quaternion<T>
//   BM_slerp<eigen_native, T>               Eigen's q1.slerp(t, q2)
//   BM_slerp_batch<anima, glm, T>           anima::slerp_batch over the batch into an array
//   BM_slerp_into<glm_native, T>            glm::slerp looped into an array
//   BM_slerp_batch<anima, eigen, T>         anima::slerp_batch on Eigen::Quaternion<T>
//   BM_slerp_into<eigen_native, T>          Eigen's slerp looped into an array
//   BM_squad<anima, glm, T>                 anima::squad, anima control points
//   BM_squad<glm_native, T>                 glm::squad, glm::intermediate control points
//   BM_squad_control_point<anima, glm, T>   anima::squad_control_point
//   BM_squad_control_point<glm_native, T>   glm::intermediate
//   BM_slerp_by_input<anima, glm, T>/k      anima::slerp on the mixed batch's k-th kind of input only
//   BM_slerp_by_input<glm_native, T>/k      glm::slerp on the same
//
// Each iteration processes a batch of 4096 items (items/s is per quaternion
// produced). slerp pairs are mixed, in turn: uniformly random, 1e-6 rad
// apart, nearly antipodal 4-vectors (the same rotation up to 1e-6 rad) and
// rotations 150 to 180 degrees apart. squad keys are a sequence of rotations
// up to 90 degrees apart, t uniform in [0, 1], all from a fixed seed. Before
// anything is timed, every anima result is checked against the peer's on the
// whole batch (up to the sign of the quaternion); the program aborts if they
// disagree. It then prints the worst angle error of each library's slerp
// against a long double slerp of the same inputs.

// glm::squad and glm::intermediate live in GLM's experimental extensions.
#define GLM_ENABLE_EXPERIMENTAL

#include <anima/rotation/quat_traits.hpp>
#include <anima/rotation/slerp.hpp>
#include <anima/rotation/slerp_batch.hpp>
#include <anima/rotation/squad.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtx/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

constexpr std::size_t batch_size = 4096;

template <class T>
using gquat = glm::qua<T, glm::defaultp>;
template <class T>
using equat = Eigen::Quaternion<T>;

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

template <class T>
gquat<T> make_glm(T w, T x, T y, T z) {
    gquat<T> q;
    q.w = w;
    q.x = x;
    q.y = y;
    q.z = z;
    return q;
}

/// All inputs of one scalar type, built once and checked before timing.
template <class T>
struct inputs {
    // slerp: pairs (a[i], b[i]) and t[i]
    std::vector<gquat<T>> ga, gb;
    std::vector<equat<T>> ea, eb;
    std::vector<T> t;
    // squad: a sequence of batch_size + 3 keys, each within 90 degrees of (and
    // in the hemisphere of) the previous one; segment i runs from key i + 1 to
    // key i + 2.
    std::vector<gquat<T>> keys;
    std::vector<gquat<T>> anima_cp, glm_cp;  // control point of every key but the ends
};

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "bench_rotation: %s\n", what.c_str());
    std::abort();
}

/// Largest component difference of two quaternions, up to sign (q ~ -q).
template <class T>
T quat_distance(const gquat<T>& a, const gquat<T>& b) {
    const T plus = std::max({std::abs(a.w - b.w), std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
    const T minus = std::max({std::abs(a.w + b.w), std::abs(a.x + b.x), std::abs(a.y + b.y), std::abs(a.z + b.z)});
    return std::min(plus, minus);
}
template <class T>
gquat<T> to_glm(const equat<T>& q) {
    return make_glm(q.w(), q.x(), q.y(), q.z());
}

template <class T>
T tolerance() {
    return std::is_same_v<T, float> ? T(1e-4) : T(1e-9);
}

template <class T>
void check(const char* what, T worst) {
    if (!(worst <= tolerance<T>()))
        fail(std::string(what) + "<" + type_name<T>() + ">: anima and the peer differ by " + std::to_string(worst));
}

/// Angle (radians) between the orientations a and b, in long double.
template <class T>
long double angle_error(const gquat<T>& a, const long double (&b)[4]) {
    const long double aw = a.w, ax = a.x, ay = a.y, az = a.z;
    const long double w = aw * b[0] + ax * b[1] + ay * b[2] + az * b[3];  // conj(a) * b
    const long double x = aw * b[1] - ax * b[0] - ay * b[3] + az * b[2];
    const long double y = aw * b[2] + ax * b[3] - ay * b[0] - az * b[1];
    const long double z = aw * b[3] - ax * b[2] + ay * b[1] - az * b[0];
    return 2 * std::atan2(std::sqrt(x * x + y * y + z * z), std::abs(w));
}

/// Prints the worst angle error of anima's, GLM's and Eigen's slerp against a
/// long double slerp of the same (rounded) inputs.
template <class T>
void report_accuracy(const inputs<T>& in) {
    long double worst_anima = 0, worst_batch = 0, worst_glm = 0, worst_eigen = 0;
    std::vector<gquat<T>> batch(batch_size);
    anima::slerp_batch(in.ga.data(), in.gb.data(), in.t.data(), batch_size, batch.data());
    for (std::size_t i = 0; i < batch_size; ++i) {
        const gquat<T>& a = in.ga[i];
        const gquat<T>& b = in.gb[i];
        const long double t = in.t[i];
        long double pa[4] = {a.w, a.x, a.y, a.z}, pb[4] = {b.w, b.x, b.y, b.z};
        long double d = 0;
        for (int k = 0; k < 4; ++k) d += pa[k] * pb[k];
        if (d < 0)
            for (long double& c : pb) c = -c;
        // a (a^-1 b)^t with the relative rotation's half angle from atan2.
        const long double rel[4] = {std::abs(d), pa[0] * pb[1] - pa[1] * pb[0] - pa[2] * pb[3] + pa[3] * pb[2],
                                    pa[0] * pb[2] + pa[1] * pb[3] - pa[2] * pb[0] - pa[3] * pb[1],
                                    pa[0] * pb[3] - pa[1] * pb[2] + pa[2] * pb[1] - pa[3] * pb[0]};
        const long double s = std::sqrt(rel[1] * rel[1] + rel[2] * rel[2] + rel[3] * rel[3]);
        const long double half = std::atan2(s, rel[0]);
        const long double k = s > 0 ? std::sin(t * half) / s : 0, c = std::cos(t * half);
        const long double p[4] = {c, k * rel[1], k * rel[2], k * rel[3]};
        const long double ref[4] = {pa[0] * p[0] - pa[1] * p[1] - pa[2] * p[2] - pa[3] * p[3],
                                    pa[0] * p[1] + pa[1] * p[0] + pa[2] * p[3] - pa[3] * p[2],
                                    pa[0] * p[2] - pa[1] * p[3] + pa[2] * p[0] + pa[3] * p[1],
                                    pa[0] * p[3] + pa[1] * p[2] - pa[2] * p[1] + pa[3] * p[0]};
        const T tt = in.t[i];
        worst_anima = std::max(worst_anima, angle_error(anima::slerp(a, b, tt), ref));
        worst_batch = std::max(worst_batch, angle_error(batch[i], ref));
        worst_glm = std::max(worst_glm, angle_error(glm::slerp(a, b, tt), ref));
        worst_eigen = std::max(worst_eigen, angle_error(to_glm(equat<T>(in.ea[i].slerp(tt, in.eb[i]))), ref));
    }
    std::fprintf(stderr,
                 "slerp<%s> worst angle error (rad) against long double: anima %.3Lg, anima slerp_batch %.3Lg, glm "
                 "%.3Lg, eigen %.3Lg\n",
                 type_name<T>(), worst_anima, worst_batch, worst_glm, worst_eigen);
}

template <class T>
inputs<T> make_inputs() {
    std::mt19937_64 rng(20240601);
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    const auto random_unit = [&] {
        const double w = normal(rng), x = normal(rng), y = normal(rng), z = normal(rng);
        const T n = static_cast<T>(std::sqrt(w * w + x * x + y * y + z * z));
        return make_glm(static_cast<T>(w) / n, static_cast<T>(x) / n, static_cast<T>(y) / n, static_cast<T>(z) / n);
    };

    const auto turned = [&](const gquat<T>& q, double angle) {  // q times a rotation by angle about a random axis
        double ax = normal(rng), ay = normal(rng), az = normal(rng);
        const double n = std::sqrt(ax * ax + ay * ay + az * az), s = std::sin(angle / 2) / n;
        const long double w = std::cos(angle / 2), x = s * ax, y = s * ay, z = s * az;
        const long double qw = q.w, qx = q.x, qy = q.y, qz = q.z;
        return make_glm(static_cast<T>(qw * w - qx * x - qy * y - qz * z), static_cast<T>(qw * x + qx * w + qy * z - qz * y),
                        static_cast<T>(qw * y - qx * z + qy * w + qz * x), static_cast<T>(qw * z + qx * y - qy * x + qz * w));
    };

    inputs<T> in;
    for (std::size_t i = 0; i < batch_size; ++i) {
        const gquat<T> a = random_unit();
        gquat<T> b;
        switch (i % 4) {
        case 0: b = random_unit(); break;
        case 1: b = turned(a, 1e-6); break;
        case 2: b = -turned(a, 1e-6); break;
        default: b = turned(a, (150.0 + 30.0 * uniform(rng)) * 3.14159265358979323846 / 180.0); break;
        }
        in.ga.push_back(a);
        in.gb.push_back(b);
        in.ea.emplace_back(a.w, a.x, a.y, a.z);
        in.eb.emplace_back(b.w, b.x, b.y, b.z);
        in.t.push_back(static_cast<T>(uniform(rng)));
    }
    // Keys like an animation's: each one a random rotation of up to 90 degrees
    // away from the previous, about a random axis.
    in.keys.push_back(random_unit());
    while (in.keys.size() < batch_size + 3) {
        const double half = 0.25 * 3.14159265358979323846 * uniform(rng);
        double ax = normal(rng), ay = normal(rng), az = normal(rng);
        const double n = std::sqrt(ax * ax + ay * ay + az * az);
        ax /= n, ay /= n, az /= n;
        const double s = std::sin(half);
        const gquat<T> step = make_glm(static_cast<T>(std::cos(half)), static_cast<T>(s * ax), static_cast<T>(s * ay),
                                       static_cast<T>(s * az));
        in.keys.push_back(glm::normalize(in.keys.back() * step));
    }
    // Control points of keys 1 .. batch_size + 1.
    in.anima_cp.resize(in.keys.size());
    in.glm_cp.resize(in.keys.size());
    for (std::size_t i = 1; i + 1 < in.keys.size(); ++i) {
        in.anima_cp[i] = anima::squad_control_point(in.keys[i - 1], in.keys[i], in.keys[i + 1]);
        in.glm_cp[i] = glm::intermediate(in.keys[i - 1], in.keys[i], in.keys[i + 1]);
    }

    // The comparison is only meaningful if both sides compute the same thing.
    T slerp_glm = 0, slerp_eigen = 0, batch_glm = 0, batch_eigen = 0, squad = 0, cp = 0;
    std::vector<gquat<T>> batch(batch_size);
    std::vector<equat<T>> ebatch(batch_size);
    anima::slerp_batch(in.ga.data(), in.gb.data(), in.t.data(), batch_size, batch.data());
    anima::slerp_batch(in.ea.data(), in.eb.data(), in.t.data(), batch_size, ebatch.data());
    for (std::size_t i = 0; i < batch_size; ++i) {
        const T t = in.t[i];
        slerp_glm = std::max(slerp_glm, quat_distance(anima::slerp(in.ga[i], in.gb[i], t), glm::slerp(in.ga[i], in.gb[i], t)));
        slerp_eigen = std::max(slerp_eigen, quat_distance(to_glm(anima::slerp(in.ea[i], in.eb[i], t)),
                                                          to_glm(equat<T>(in.ea[i].slerp(t, in.eb[i])))));
        batch_glm = std::max(batch_glm, quat_distance(batch[i], glm::slerp(in.ga[i], in.gb[i], t)));
        batch_eigen = std::max(batch_eigen, quat_distance(to_glm(ebatch[i]), to_glm(equat<T>(in.ea[i].slerp(t, in.eb[i])))));
        const std::size_t k = i + 1;
        cp = std::max(cp, quat_distance(in.anima_cp[k], in.glm_cp[k]));
        squad = std::max(squad, quat_distance(anima::squad(in.keys[k], in.keys[k + 1], in.anima_cp[k], in.anima_cp[k + 1], t),
                                              glm::squad(in.keys[k], in.keys[k + 1], in.glm_cp[k], in.glm_cp[k + 1], t)));
    }
    report_accuracy(in);
    std::fprintf(stderr,
                 "%s: largest component difference to the peer: slerp %.3g (glm) %.3g (eigen), "
                 "slerp_batch %.3g (glm) %.3g (eigen), squad_control_point %.3g, squad %.3g\n",
                 type_name<T>(), static_cast<double>(slerp_glm), static_cast<double>(slerp_eigen),
                 static_cast<double>(batch_glm), static_cast<double>(batch_eigen), static_cast<double>(cp),
                 static_cast<double>(squad));
    check("slerp (glm::slerp)", slerp_glm);
    check("slerp (Eigen slerp)", slerp_eigen);
    check("slerp_batch (glm::slerp)", batch_glm);
    check("slerp_batch (Eigen slerp)", batch_eigen);
    check("squad_control_point (glm::intermediate)", cp);
    check("squad (glm::squad)", squad);
    return in;
}

template <class T>
const inputs<T>& data() {
    static const inputs<T> in = make_inputs<T>();
    return in;
}

template <class Q, class T>
void accumulate(T& sink, const Q& q) {
    sink += anima::quat_traits<Q>::w(q) + anima::quat_traits<Q>::x(q) + anima::quat_traits<Q>::y(q) +
            anima::quat_traits<Q>::z(q);
}

void finish(benchmark::State& state) {
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(batch_size));
}

// ---------------------------------------------------------------------------
// slerp

template <class T>
void slerp_anima_glm(benchmark::State& state) {
    const auto& in = data<T>();
    for (auto _ : state) {
        T sink = 0;
        for (std::size_t i = 0; i < batch_size; ++i) accumulate(sink, anima::slerp(in.ga[i], in.gb[i], in.t[i]));
        benchmark::DoNotOptimize(sink);
    }
    finish(state);
}

template <class T>
void slerp_glm(benchmark::State& state) {
    const auto& in = data<T>();
    for (auto _ : state) {
        T sink = 0;
        for (std::size_t i = 0; i < batch_size; ++i) accumulate(sink, glm::slerp(in.ga[i], in.gb[i], in.t[i]));
        benchmark::DoNotOptimize(sink);
    }
    finish(state);
}

template <class T>
void slerp_anima_eigen(benchmark::State& state) {
    const auto& in = data<T>();
    for (auto _ : state) {
        T sink = 0;
        for (std::size_t i = 0; i < batch_size; ++i) accumulate(sink, anima::slerp(in.ea[i], in.eb[i], in.t[i]));
        benchmark::DoNotOptimize(sink);
    }
    finish(state);
}

template <class T>
void slerp_eigen(benchmark::State& state) {
    const auto& in = data<T>();
    for (auto _ : state) {
        T sink = 0;
        for (std::size_t i = 0; i < batch_size; ++i)
            accumulate(sink, equat<T>(in.ea[i].slerp(in.t[i], in.eb[i])));
        benchmark::DoNotOptimize(sink);
    }
    finish(state);
}

/// The mixed batch's pairs as quaternions of type Q (GLM's or Eigen's).
template <class Q, class T>
std::pair<const std::vector<Q>&, const std::vector<Q>&> pairs_of(const inputs<T>& in) {
    if constexpr (std::is_same_v<Q, gquat<T>>)
        return {in.ga, in.gb};
    else
        return {in.ea, in.eb};
}

/// The batch into an array, next to the peer's slerp looped into an array
/// of the same type: both store every result.
template <class T, class Q>
void slerp_batch_anima(benchmark::State& state) {
    const auto& in = data<T>();
    const auto [a, b] = pairs_of<Q>(in);
    std::vector<Q> out(batch_size);
    for (auto _ : state) {
        anima::slerp_batch(a.data(), b.data(), in.t.data(), batch_size, out.data());
        benchmark::ClobberMemory();
    }
    finish(state);
}

template <class T, class Q>
void slerp_into_peer(benchmark::State& state) {
    const auto& in = data<T>();
    const auto [a, b] = pairs_of<Q>(in);
    std::vector<Q> out(batch_size);
    for (auto _ : state) {
        if constexpr (std::is_same_v<Q, gquat<T>>)
            for (std::size_t i = 0; i < batch_size; ++i) out[i] = glm::slerp(a[i], b[i], in.t[i]);
        else
            for (std::size_t i = 0; i < batch_size; ++i) out[i] = a[i].slerp(in.t[i], b[i]);
        benchmark::ClobberMemory();
    }
    finish(state);
}

/// slerp on one kind of input of the mixed batch (its items i with i % 4 ==
/// kind: 0 random, 1 1e-6 rad apart, 2 nearly antipodal, 3 150 to 180
/// degrees), anima's or GLM's: shows where each one's time goes.
template <class T, bool anima_side>
void slerp_by_input(benchmark::State& state) {
    const auto& in = data<T>();
    const auto kind = static_cast<std::size_t>(state.range(0));
    for (auto _ : state) {
        T sink = 0;
        for (std::size_t i = kind; i < batch_size; i += 4) {
            if constexpr (anima_side)
                accumulate(sink, anima::slerp(in.ga[i], in.gb[i], in.t[i]));
            else
                accumulate(sink, glm::slerp(in.ga[i], in.gb[i], in.t[i]));
        }
        benchmark::DoNotOptimize(sink);
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(batch_size / 4));
}

// ---------------------------------------------------------------------------
// squad (control points precomputed by each library's own function)

template <class T>
void squad_anima(benchmark::State& state) {
    const auto& in = data<T>();
    for (auto _ : state) {
        T sink = 0;
        for (std::size_t i = 0; i < batch_size; ++i) {
            const std::size_t k = i + 1;
            accumulate(sink, anima::squad(in.keys[k], in.keys[k + 1], in.anima_cp[k], in.anima_cp[k + 1], in.t[i]));
        }
        benchmark::DoNotOptimize(sink);
    }
    finish(state);
}

template <class T>
void squad_glm(benchmark::State& state) {
    const auto& in = data<T>();
    for (auto _ : state) {
        T sink = 0;
        for (std::size_t i = 0; i < batch_size; ++i) {
            const std::size_t k = i + 1;
            accumulate(sink, glm::squad(in.keys[k], in.keys[k + 1], in.glm_cp[k], in.glm_cp[k + 1], in.t[i]));
        }
        benchmark::DoNotOptimize(sink);
    }
    finish(state);
}

template <class T>
void control_point_anima(benchmark::State& state) {
    const auto& in = data<T>();
    for (auto _ : state) {
        T sink = 0;
        for (std::size_t i = 0; i < batch_size; ++i)
            accumulate(sink, anima::squad_control_point(in.keys[i], in.keys[i + 1], in.keys[i + 2]));
        benchmark::DoNotOptimize(sink);
    }
    finish(state);
}

template <class T>
void control_point_glm(benchmark::State& state) {
    const auto& in = data<T>();
    for (auto _ : state) {
        T sink = 0;
        for (std::size_t i = 0; i < batch_size; ++i)
            accumulate(sink, glm::intermediate(in.keys[i], in.keys[i + 1], in.keys[i + 2]));
        benchmark::DoNotOptimize(sink);
    }
    finish(state);
}

// ---------------------------------------------------------------------------
// Registration: each anima benchmark directly above its peer.

template <class T>
void register_all() {
    const std::string ty = type_name<T>();
    benchmark::RegisterBenchmark(("BM_slerp<anima, glm, " + ty + ">").c_str(), slerp_anima_glm<T>);
    benchmark::RegisterBenchmark(("BM_slerp<glm_native, " + ty + ">").c_str(), slerp_glm<T>);
    benchmark::RegisterBenchmark(("BM_slerp<anima, eigen, " + ty + ">").c_str(), slerp_anima_eigen<T>);
    benchmark::RegisterBenchmark(("BM_slerp<eigen_native, " + ty + ">").c_str(), slerp_eigen<T>);
    benchmark::RegisterBenchmark(("BM_slerp_batch<anima, glm, " + ty + ">").c_str(), slerp_batch_anima<T, gquat<T>>);
    benchmark::RegisterBenchmark(("BM_slerp_into<glm_native, " + ty + ">").c_str(), slerp_into_peer<T, gquat<T>>);
    benchmark::RegisterBenchmark(("BM_slerp_batch<anima, eigen, " + ty + ">").c_str(), slerp_batch_anima<T, equat<T>>);
    benchmark::RegisterBenchmark(("BM_slerp_into<eigen_native, " + ty + ">").c_str(), slerp_into_peer<T, equat<T>>);
    benchmark::RegisterBenchmark(("BM_squad<anima, glm, " + ty + ">").c_str(), squad_anima<T>);
    benchmark::RegisterBenchmark(("BM_squad<glm_native, " + ty + ">").c_str(), squad_glm<T>);
    benchmark::RegisterBenchmark(("BM_squad_control_point<anima, glm, " + ty + ">").c_str(), control_point_anima<T>);
    benchmark::RegisterBenchmark(("BM_squad_control_point<glm_native, " + ty + ">").c_str(), control_point_glm<T>);
    benchmark::RegisterBenchmark(("BM_slerp_by_input<anima, glm, " + ty + ">").c_str(), slerp_by_input<T, true>)
        ->DenseRange(0, 3);
    benchmark::RegisterBenchmark(("BM_slerp_by_input<glm_native, " + ty + ">").c_str(), slerp_by_input<T, false>)
        ->DenseRange(0, 3);
}

const bool registered = [] {
    register_all<float>();
    register_all<double>();
    return true;
}();

}  // namespace
