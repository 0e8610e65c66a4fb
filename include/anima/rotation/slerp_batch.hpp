// Slerp of many pairs at once: out[i] = slerp(a[i], b[i], t[i]), or one t for
// every pair (blending two poses joint by joint).
//
// Why a batch. The scalar slerp (slerp.hpp) picks a branch per pair (a short
// series near identity, the quartered angle elsewhere) and keeps a cold path
// for invalid input, so calls cannot be spread over a vector's lanes. Here
// the pairs are taken a block at a time in structure-of-arrays form, every
// pair of a valid block takes the same branch-free arithmetic - the series
// in cos(theta/4) - 1 of detail/angle_series.hpp, exact as theta tends to 0,
// so t is honoured at every angle with no near-identity switch - and the
// compiler spreads each step over the lanes of the target's vectors (square
// roots through detail::sqrt_lanes, since std::sqrt may set errno and does
// not vectorise). A block is valid when every input is within
// sqrt(epsilon)/4 of unit length and every t is in [0, 1] (one reduction
// over the block); any other block - extrapolation, far from unit, zero or
// non-finite input - runs pair by pair through the scalar slerp, so the
// results and the errors are the scalar function's.
#pragma once

#include <anima/core/error.hpp>
#include <anima/rotation/detail/angle_series.hpp>
#include <anima/rotation/detail/lanes.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>
#include <anima/rotation/slerp.hpp>

#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>

namespace anima {
namespace detail {

/// Pairs per block: four vectors' worth, enough independent work to hide
/// the latency of the square roots and the division.
template <class T>
inline constexpr int slerp_block_size = 4 * lane_count<T>;

/// The sum of a block, a vector at a time (a loop's floating-point sum is
/// not reordered into vectors without -ffast-math).
template <class T, int B>
ANIMA_FORCE_INLINE T sum_block(const T (&x)[B]) {
    constexpr int width = lane_count<T>;
    lanes<T> sum = load_lanes(x);
    for (int v = width; v < B; v += width) sum = sum + load_lanes(x + v);
    T total = sum[0];
    for (int i = 1; i < width; ++i) total += sum[i];
    return total;
}

/// One block of B pairs, starting at a, b, out; time(i) is pair i's t.
/// Returns false, having written nothing, when the block is not valid for
/// the vector path.
template <class T, int B, class Q, class Time>
ANIMA_FORCE_INLINE bool slerp_block(const Q* a, const Q* b, const Time& time, Q* out) {
    constexpr T tolerance = near_unit_tolerance<T>();
    T aw[B], ax[B], ay[B], az[B], bw[B], bx[B], by[B], bz[B], t[B];
    for (int i = 0; i < B; ++i) {
        const quat4<T> p = load(a[i]), q = load(b[i]);
        aw[i] = p.w, ax[i] = p.x, ay[i] = p.y, az[i] = p.z;
        bw[i] = q.w, bx[i] = q.x, by[i] = q.y, bz[i] = q.z;
        t[i] = time(i);
    }
    T ga[B], gb[B], cos_theta[B];
    // The block's validity as two sums, which vectorise where a chain of
    // tests does not: the inputs' length errors (one pair near the limit
    // may send a block to the scalar path, which gives the same results)
    // and t (1 - t) - |t (1 - t)|, zero when every t is in [0, 1]. NaN and
    // infinities make a sum NaN or infinite and fail the test.
    T length_error[B], outside[B];
    for (int i = 0; i < B; ++i) {
        const T na = aw[i] * aw[i] + ax[i] * ax[i] + ay[i] * ay[i] + az[i] * az[i];
        const T nb = bw[i] * bw[i] + bx[i] * bx[i] + by[i] * by[i] + bz[i] * bz[i];
        const T d = aw[i] * bw[i] + ax[i] * bx[i] + ay[i] * by[i] + az[i] * bz[i];
        const T inside = t[i] * (T(1) - t[i]);
        length_error[i] = std::abs(na - T(1)) + std::abs(nb - T(1));
        outside[i] = inside - std::abs(inside);
        // One Newton step towards 1/|q| from 1, folded into the weights; the
        // sign of b's factor picks the shorter arc.
        ga[i] = T(1.5) - T(0.5) * na;
        const T g = T(1.5) - T(0.5) * nb;
        cos_theta[i] = std::abs(d) * ga[i] * g;
        gb[i] = d < T(0) ? -g : g;
    }
    if (!(sum_block(length_error) <= tolerance && sum_block(outside) >= T(0))) return false;
    // The weights a vector at a time (the series' unrolled terms inside a
    // loop over pairs do not vectorise on their own).
    T k0[B], k1[B];
    using L = lanes<T>;
    constexpr int width = lane_count<T>;
    for (int v = 0; v < B; v += width) {
        // k = tau sin(phi) S / sin(theta) with tau = 4t, phi = theta / 4 and
        // sin(theta) / sin(phi) = 4c(2c^2 - 1), as in slerp_weights.
        const L cs = load_lanes(cos_theta + v), cv = cos_quarter_angle_lanes<T>(cs), tv = load_lanes(t + v);
        const L y = cv - T(1), tau1 = tv * T(4), tau0 = T(4) - tau1;
        const L inv = splat(T(1)) / (cv * (cv * cv * T(2) - T(1)));
        L w0 = (T(1) - tv) * angle_series_lanes<T>(tau0 * tau0, y) * inv;
        L w1 = tv * angle_series_lanes<T>(tau1 * tau1, y) * inv;
        // |k0 a + k1 b| from the weights: one Newton step to unit length.
        const L g = T(1.5) - (w0 * w0 + w1 * w1 + w0 * w1 * cs * T(2)) * T(0.5);
        w0 = w0 * g;
        w1 = w1 * g;
        for (int i = 0; i < width; ++i) {
            k0[v + i] = w0[i] * ga[v + i];
            k1[v + i] = w1[i] * gb[v + i];
        }
    }
    for (int i = 0; i < B; ++i) {
        aw[i] = k0[i] * aw[i] + k1[i] * bw[i];
        ax[i] = k0[i] * ax[i] + k1[i] * bx[i];
        ay[i] = k0[i] * ay[i] + k1[i] * by[i];
        az[i] = k0[i] * az[i] + k1[i] * bz[i];
    }
    for (int i = 0; i < B; ++i) out[i] = store<Q>(quat4<T>{aw[i], ax[i], ay[i], az[i]});
    return true;
}

/// Pairs [first, last) one by one through the scalar slerp; its errors name
/// the pair.
template <class Q, class Time>
ANIMA_COLD void slerp_pairs(const Q* a, const Q* b, const Time& time, Q* out, std::size_t first, std::size_t last) {
    for (std::size_t i = first; i < last; ++i) {
        try {
            out[i] = store<Q>(slerp4(load(a[i]), load(b[i]), time(i), arc::shortest, "anima::slerp"));
        } catch (const invalid_argument& e) {
            throw invalid_argument("anima::slerp_batch: pair " + std::to_string(i) + ": " + e.what());
        }
    }
}

template <class Q, class Time>
void slerp_batch(const Q* a, const Q* b, const Time& time, std::size_t n, Q* out) {
    using T = quat_scalar_t<Q>;
    if (n > 0 && (a == nullptr || b == nullptr || out == nullptr))
        throw invalid_argument("anima::slerp_batch: null array for " + std::to_string(n) + " pairs");
    constexpr std::size_t B = slerp_block_size<T>;
    std::size_t i = 0;
    for (; n - i >= B; i += B) {
        const auto block_time = [&](int k) { return time(i + static_cast<std::size_t>(k)); };
        if (!slerp_block<T, static_cast<int>(B)>(a + i, b + i, block_time, out + i))
            slerp_pairs(a, b, time, out, i, i + B);
    }
    if (i < n) slerp_pairs(a, b, time, out, i, n);
}

}  // namespace detail

/// out[i] = slerp(a[i], b[i], t[i]) for i < n: the same results as the
/// scalar slerp (shorter arc, unit result, exact near identity, t honoured
/// at every angle, extrapolation and non-unit inputs handled), at several
/// pairs per instruction where the target has vector registers. out may be
/// a or b (an in-place blend) but must not overlap them otherwise. Throws
/// anima::invalid_argument naming the pair for a zero or non-finite
/// quaternion or t (out then holds the results of the pairs before it), and for
/// a null array when n > 0.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
void slerp_batch(const Q* a, const Q* b, const quat_scalar_t<Q>* t, std::size_t n, Q* out) {
    if (n > 0 && t == nullptr) throw invalid_argument("anima::slerp_batch: null t for " + std::to_string(n) + " pairs");
    detail::slerp_batch(a, b, [t](std::size_t i) { return t[i]; }, n, out);
}

/// out[i] = slerp(a[i], b[i], t) for i < n: one t for every pair, as when
/// blending two poses joint by joint. Otherwise as above.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
void slerp_batch(const Q* a, const Q* b, quat_scalar_t<Q> t, std::size_t n, Q* out) {
    detail::slerp_batch(a, b, [t](std::size_t) { return t; }, n, out);
}

}  // namespace anima
