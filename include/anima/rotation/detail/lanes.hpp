// Small fixed-width vectors for the rotation toolkit's hot paths: arithmetic
// applies lane by lane, so the four components of a quaternion, or the two
// weights of a slerp, are computed by one instruction each where the target
// has vector registers. Under GCC and Clang `lanes<float>` and
// `lanes<double>` are the compilers' generic vector types (16 bytes: SSE2 on
// x86-64, NEON on AArch64, lowered to scalar code elsewhere); with other
// compilers, for other scalars, or with ANIMA_NO_VECTOR_EXTENSIONS defined
// they are a plain array with the same operators. The results are the same
// either way: every operation is the scalar one, done per lane.
#pragma once

#include <anima/rotation/detail/quat4.hpp>

#include <cmath>
#include <type_traits>

#if (defined(__GNUC__) || defined(__clang__)) && !defined(ANIMA_NO_VECTOR_EXTENSIONS)
#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__aarch64__) && defined(__ARM_NEON)
#include <arm_neon.h>
#endif
#endif

namespace anima::detail {

/// N values of T with lane-wise +, -, * and / (+, -, * also with a scalar).
template <class T, int N>
struct lane_array {
    T v[N];

    T operator[](int i) const { return v[i]; }
    T& operator[](int i) { return v[i]; }

    template <class F>
    friend lane_array apply(const lane_array& a, const lane_array& b, F f) {
        lane_array r{};
        for (int i = 0; i < N; ++i) r.v[i] = f(a.v[i], b.v[i]);
        return r;
    }
    static lane_array all(T s) {
        lane_array r{};
        for (int i = 0; i < N; ++i) r.v[i] = s;
        return r;
    }
    friend lane_array operator+(const lane_array& a, const lane_array& b) {
        return apply(a, b, [](T x, T y) { return x + y; });
    }
    friend lane_array operator-(const lane_array& a, const lane_array& b) {
        return apply(a, b, [](T x, T y) { return x - y; });
    }
    friend lane_array operator*(const lane_array& a, const lane_array& b) {
        return apply(a, b, [](T x, T y) { return x * y; });
    }
    friend lane_array operator/(const lane_array& a, const lane_array& b) {
        return apply(a, b, [](T x, T y) { return x / y; });
    }
    friend lane_array operator+(const lane_array& a, T s) { return a + all(s); }
    friend lane_array operator+(T s, const lane_array& a) { return all(s) + a; }
    friend lane_array operator-(const lane_array& a, T s) { return a - all(s); }
    friend lane_array operator-(T s, const lane_array& a) { return all(s) - a; }
    friend lane_array operator*(const lane_array& a, T s) { return a * all(s); }
    friend lane_array operator*(T s, const lane_array& a) { return all(s) * a; }
};

template <class T, int N, class = void>
struct lanes_of {
    using type = lane_array<T, N>;
};

#if (defined(__GNUC__) || defined(__clang__)) && !defined(ANIMA_NO_VECTOR_EXTENSIONS)
template <class T, int N>
struct lanes_of<T, N, std::enable_if_t<std::is_same_v<T, float> || std::is_same_v<T, double>>> {
    typedef T type __attribute__((vector_size(N * sizeof(T))));
};
#endif

/// How many lanes of T fill 16 bytes: 4 floats, 2 doubles, 1 wider scalar.
template <class T>
inline constexpr int lane_count = sizeof(T) < 16 ? static_cast<int>(16 / sizeof(T)) : 1;

/// lane_count<T> values of T, as a vector register where there is one.
template <class T>
using lanes = typename lanes_of<T, lane_count<T>>::type;

/// s in every lane, usable in constant expressions.
template <class T>
ANIMA_FORCE_INLINE constexpr lanes<T> splat(T s) {
    if constexpr (lane_count<T> == 4)
        return lanes<T>{s, s, s, s};
    else if constexpr (lane_count<T> == 2)
        return lanes<T>{s, s};
    else
        return lanes<T>{s};
}

/// The lanes p[0 .. lane_count - 1].
template <class T>
ANIMA_FORCE_INLINE lanes<T> load_lanes(const T* p) {
    if constexpr (lane_count<T> == 4)
        return lanes<T>{p[0], p[1], p[2], p[3]};
    else if constexpr (lane_count<T> == 2)
        return lanes<T>{p[0], p[1]};
    else
        return lanes<T>{p[0]};
}

/// Square root in every lane: one instruction with SSE2 or AArch64 NEON. A
/// loop over std::sqrt does not vectorise, since std::sqrt may set errno.
template <class T>
ANIMA_FORCE_INLINE lanes<T> sqrt_lanes(const lanes<T>& x) {
    if constexpr (!std::is_class_v<lanes<T>>) {
#if defined(__SSE2__)
        if constexpr (std::is_same_v<T, float>)
            return reinterpret_cast<lanes<T>>(_mm_sqrt_ps(reinterpret_cast<__m128>(x)));
        else
            return reinterpret_cast<lanes<T>>(_mm_sqrt_pd(reinterpret_cast<__m128d>(x)));
#elif defined(__aarch64__) && defined(__ARM_NEON)
        if constexpr (std::is_same_v<T, float>)
            return reinterpret_cast<lanes<T>>(vsqrtq_f32(reinterpret_cast<float32x4_t>(x)));
        else
            return reinterpret_cast<lanes<T>>(vsqrtq_f64(reinterpret_cast<float64x2_t>(x)));
#endif
    }
    lanes<T> r = x;
    for (int i = 0; i < lane_count<T>; ++i) r[i] = std::sqrt(x[i]);
    return r;
}

/// A quaternion spread over 16-byte lanes: one vector of four floats, two of
/// two doubles. The lanes hold (x, y, z, w), the order in which GLM and
/// Eigen store their quaternions, so loading and storing need no shuffle.
template <class T>
struct quat_lanes {
    static constexpr int width = lane_count<T>;
    static constexpr int parts = 4 / width;
    lanes<T> p[parts];
};

template <class T>
ANIMA_FORCE_INLINE quat_lanes<T> to_lanes(const quat4<T>& q) {
    using L = lanes<T>;
    if constexpr (lane_count<T> == 4)
        return {{L{q.x, q.y, q.z, q.w}}};
    else if constexpr (lane_count<T> == 2)
        return {{L{q.x, q.y}, L{q.z, q.w}}};
    else
        return {{L{q.x}, L{q.y}, L{q.z}, L{q.w}}};
}

template <class T>
ANIMA_FORCE_INLINE quat4<T> from_lanes(const quat_lanes<T>& q) {
    if constexpr (lane_count<T> == 4)
        return {q.p[0][3], q.p[0][0], q.p[0][1], q.p[0][2]};
    else if constexpr (lane_count<T> == 2)
        return {q.p[1][1], q.p[0][0], q.p[0][1], q.p[1][0]};
    else
        return {q.p[3][0], q.p[0][0], q.p[1][0], q.p[2][0]};
}

/// a.b of two quaternions in lanes.
template <class T>
ANIMA_FORCE_INLINE T dot_lanes(const quat_lanes<T>& a, const quat_lanes<T>& b) {
    lanes<T> s = a.p[0] * b.p[0];
    for (int i = 1; i < quat_lanes<T>::parts; ++i) s = s + a.p[i] * b.p[i];
    if constexpr (lane_count<T> == 4)
        return (s[0] + s[1]) + (s[2] + s[3]);
    else if constexpr (lane_count<T> == 2)
        return s[0] + s[1];
    else
        return s[0];
}

#if defined(__has_builtin) && !defined(ANIMA_NO_VECTOR_EXTENSIONS)
#if __has_builtin(__builtin_shufflevector)
#define ANIMA_LANE_SHUFFLE 1
#endif
#endif

/// a.a, b.b and a.b at once. With four float lanes the three horizontal sums
/// share their shuffles (a transpose and two adds instead of three separate
/// reductions), which is most of a slerp's input work. Two double lanes gain
/// nothing from it (measured slower in squad), so they sum one by one.
template <class T>
ANIMA_FORCE_INLINE void dot3_lanes(const quat_lanes<T>& a, const quat_lanes<T>& b, T& aa, T& bb, T& ab) {
#ifdef ANIMA_LANE_SHUFFLE
    if constexpr (lane_count<T> == 4 && !std::is_class_v<lanes<T>>) {
        const lanes<T> pa = a.p[0] * a.p[0], pb = b.p[0] * b.p[0], pd = a.p[0] * b.p[0];
        // (aa0 + aa2, bb0 + bb2, aa1 + aa3, bb1 + bb3) and (ab0 + ab2, ab1 + ab3, ...)
        const lanes<T> u = __builtin_shufflevector(pa, pb, 0, 4, 1, 5) + __builtin_shufflevector(pa, pb, 2, 6, 3, 7);
        const lanes<T> v = pd + __builtin_shufflevector(pd, pd, 2, 3, 0, 1);
        const lanes<T> s = __builtin_shufflevector(u, v, 0, 1, 4, 4) + __builtin_shufflevector(u, v, 2, 3, 5, 5);
        aa = s[0];
        bb = s[1];
        ab = s[2];
        return;
    }
#endif
    aa = dot_lanes(a, a);
    bb = dot_lanes(b, b);
    ab = dot_lanes(a, b);
}

/// a k0 + b k1.
template <class T>
ANIMA_FORCE_INLINE quat_lanes<T> blend_lanes(const quat_lanes<T>& a, T k0, const quat_lanes<T>& b, T k1) {
    quat_lanes<T> r;
    for (int i = 0; i < quat_lanes<T>::parts; ++i) r.p[i] = a.p[i] * k0 + b.p[i] * k1;
    return r;
}

}  // namespace anima::detail
