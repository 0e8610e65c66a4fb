// slerp and squad of one set of keys at many parameters, as the in-between
// frames of a transition need them: what depends only on the keys (lengths,
// angles, which series) is found once, and several parameters are worked on
// side by side, so that their series' chains of dependent operations
// overlap. Each result is anima::slerp's or anima::squad's, bit for bit.
#pragma once

#include <anima/rotation/detail/lanes.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/slerp.hpp>
#include <anima/rotation/squad.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace anima::detail {

/// Parameters worked on side by side.
inline constexpr std::size_t blend_group = 4;

/// Runs group(u, results, stride) on the parameters t[0 .. n) blend_group
/// at a time, a last partial group padded with its last parameter, and
/// stores the results at out[0], out[stride], ... (one joint's frames in a
/// clip's storage have the joint count as stride); single(t) does a
/// parameter outside [0, 1] (where the fast paths do not hold) and, when
/// `fast` is false, every parameter.
template <class T, class Group, class Single>
ANIMA_FORCE_INLINE void blend_groups(const T* t, std::size_t n, bool fast, Eigen::Quaternion<T>* out,
                                     std::size_t stride, Group group, Single single) {
    for (std::size_t k = 0; k < n; k += blend_group) {
        const std::size_t m = std::min(blend_group, n - k);
        T u[blend_group];
        bool inside = fast;
        for (std::size_t i = 0; i < blend_group; ++i) {
            u[i] = t[k + std::min(i, m - 1)];
            inside = inside && u[i] * (T(1) - u[i]) >= T(0);
        }
        if (!inside) {
            for (std::size_t i = 0; i < m; ++i) out[(k + i) * stride] = single(t[k + i]);
            continue;
        }
        if (m == blend_group) {
            group(u, out + k * stride, stride);  // straight into place: a copy of a variable count becomes a slow memcpy
            continue;
        }
        Eigen::Quaternion<T> results[blend_group];
        group(u, results, std::size_t{1});
        for (std::size_t i = 0; i < m; ++i) out[(k + i) * stride] = results[i];
    }
}

/// out[k * stride] = the normalised blend (1 - t[k]) a + t[k] b for k < n,
/// with b on a's side (so the blend is at least 1/sqrt(2) long) and every
/// t[k] finite. The square roots and divisions of lane_count frames share
/// one vector instruction each: they, not the blends, bound the loop.
/// Each result is q / |q| rounded as Eigen's q * (1 / q.norm()).
template <class T>
void lerp_many(const Eigen::Quaternion<T>& a, const Eigen::Quaternion<T>& b, const T* t, std::size_t n,
               Eigen::Quaternion<T>* out, std::size_t stride = 1) {
    constexpr int width = 4, vectors = width / lane_count<T>;
    for (std::size_t k = 0; k < n; k += width) {
        const int m = static_cast<int>(std::min<std::size_t>(width, n - k));
        Eigen::Matrix<T, 4, 1> q[width];
        T squared[width], inverse[width];
        for (int i = 0; i < width; ++i) {
            const T u = t[k + static_cast<std::size_t>(std::min(i, m - 1))];
            q[i] = a.coeffs() * (T(1) - u) + b.coeffs() * u;
            squared[i] = q[i].squaredNorm();
        }
        for (int v = 0; v < vectors; ++v) {
            const lanes<T> r = splat(T(1)) / sqrt_lanes<T>(load_lanes(squared + v * lane_count<T>));
            for (int i = 0; i < lane_count<T>; ++i) inverse[v * lane_count<T> + i] = r[i];
        }
        for (int i = 0; i < m; ++i) out[(k + static_cast<std::size_t>(i)) * stride] = Eigen::Quaternion<T>(q[i] * inverse[i]);
    }
}

/// out[k * stride] = slerp(a, b, t[k]) for k < n: slerp4's fast paths (nearly
/// identical inputs or not) with the pair's part taken out of the loop. What
/// slerp4 would send to its general path (inputs far from unit length, t
/// outside [0, 1]) goes to slerp itself.
template <class T>
void slerp_many(const Eigen::Quaternion<T>& a_in, const Eigen::Quaternion<T>& b_in, const T* t, std::size_t n,
                Eigen::Quaternion<T>* out, std::size_t stride = 1) {
    const quat_lanes<T> a = to_lanes(load(a_in)), b = to_lanes(load(b_in));
    T na, nb, d;
    dot3_lanes(a, b, na, nb, d);
    const T ga = T(1.5) - T(0.5) * na, gb = T(1.5) - T(0.5) * nb;
    const T gbs = d < T(0) ? -gb : gb;  // the shorter arc
    const T cos_theta = std::abs(d) * ga * gb;
    constexpr T tolerance = near_unit_tolerance<T>(), identical = near_identity<T>();  // folded at compile time
    const bool fast = std::abs(na - T(1)) + std::abs(nb - T(1)) <= tolerance;
    const T y = cos_theta - T(1);
    const bool near = -y <= identical;
    const slerp_weight_keys<T, 1> weight_keys = prepare_slerp_weights<T, 1>({cos_theta});  // the same at every t
    blend_groups(
        t, n, fast, out, stride,
        [&](const T* u, Eigen::Quaternion<T>* results, std::size_t step) {
            if (near) {
                for (std::size_t i = 0; i < blend_group; ++i) {
                    T k0, k1;
                    near_identity_weights(u[i], y, k0, k1);
                    results[i * step] = store<Eigen::Quaternion<T>>(from_lanes(blend_lanes(a, k0 * ga, b, k1 * gbs)));
                }
                return;
            }
            T k0[blend_group][1], k1[blend_group][1];
            for (std::size_t i = 0; i < blend_group; ++i) slerp_weights<T, 1>(weight_keys, u[i], k0[i], k1[i]);
            for (std::size_t i = 0; i < blend_group; ++i) {
                // slerp4's correction of the result's length, then the blend.
                const T g = T(1.5) - T(0.5) * (k0[i][0] * k0[i][0] + k1[i][0] * k1[i][0] +
                                               T(2) * k0[i][0] * k1[i][0] * cos_theta);
                results[i * step] =
                    store<Eigen::Quaternion<T>>(from_lanes(blend_lanes(a, k0[i][0] * g * ga, b, k1[i][0] * g * gbs)));
            }
        },
        [&](T u) { return slerp(a_in, b_in, u); });
}

/// out[k * stride] = squad(q1, q2, s1, s2, t[k]) for k < n: squad4's fast path with
/// the keys' part taken out of the loop; the rest goes to squad itself.
template <class T>
void squad_many(const Eigen::Quaternion<T>& q1_in, const Eigen::Quaternion<T>& q2_in, const Eigen::Quaternion<T>& s1_in,
                const Eigen::Quaternion<T>& s2_in, const T* t, std::size_t n, Eigen::Quaternion<T>* out,
                std::size_t stride = 1) {
    const quat_lanes<T> lq1 = to_lanes(load(q1_in)), lq2 = to_lanes(load(q2_in)), ls1 = to_lanes(load(s1_in)),
                        ls2 = to_lanes(load(s2_in));
    T n1, n2, m1, m2, dq, ds_given;
    dot3_lanes(lq1, lq2, n1, n2, dq);
    dot3_lanes(ls1, ls2, m1, m2, ds_given);
    const T side = dq < T(0) ? T(-1) : T(1), ds = ds_given * side;
    constexpr T tolerance = near_unit_tolerance<T>();  // folded at compile time
    const bool fast =
        std::abs(n1 - T(1)) + std::abs(n2 - T(1)) + std::abs(m1 - T(1)) + std::abs(m2 - T(1)) <= tolerance && ds >= T(0);
    const T g1 = T(1.5) - T(0.5) * n1, g2 = (T(1.5) - T(0.5) * n2) * side;
    const T h1 = T(1.5) - T(0.5) * m1, h2 = (T(1.5) - T(0.5) * m2) * side;
    const T keys = dq * g1 * g2, controls = ds * h1 * h2 * side;
    const slerp_weight_keys<T, 2> weight_keys = prepare_slerp_weights<T, 2>({keys, controls});  // the same at every t
    blend_groups(
        t, n, fast, out, stride,
        [&](const T* u, Eigen::Quaternion<T>* results, std::size_t step) {
            T k0[blend_group][2], k1[blend_group][2];
            for (std::size_t i = 0; i < blend_group; ++i) slerp_weights<T, 2>(weight_keys, u[i], k0[i], k1[i]);
            quat4<T> a[blend_group], b[blend_group];
            for (std::size_t i = 0; i < blend_group; ++i) {
                a[i] = from_lanes(blend_lanes(lq1, k0[i][0] * g1, lq2, k1[i][0] * g2));
                b[i] = from_lanes(blend_lanes(ls1, k0[i][1] * h1, ls2, k1[i][1] * h2));
            }
            for (std::size_t i = 0; i < blend_group; ++i)
                results[i * step] = store<Eigen::Quaternion<T>>(
                    slerp4(a[i], b[i], T(2) * u[i] * (T(1) - u[i]), arc::as_given, "anima::squad"));
        },
        [&](T u) { return squad(q1_in, q2_in, s1_in, s2_in, u); });
}

}  // namespace anima::detail
