// The right Jacobian of the rotation-vector (exponential map) chart of
// SO(3): how a change of the rotation vector v turns into an angular
// velocity in the rotated (body) frame. Scalar-generic like exp_pure, so it
// also runs on automatic-derivative scalars.
#pragma once

#include <anima/core/scalar_value.hpp>
#include <anima/rotation/detail/quat4.hpp>

#include <Eigen/Core>

#include <cmath>

namespace anima::detail {

template <class T>
Eigen::Matrix<T, 3, 3> cross_matrix(const Eigen::Matrix<T, 3, 1>& v) {
    Eigen::Matrix<T, 3, 3> m;
    m << T(0), -v.z(), v.y(), v.z(), T(0), -v.x(), -v.y(), v.x(), T(0);
    return m;
}

/// Jr(v) = I - (1 - cos t)/t^2 [v]x + (t - sin t)/t^3 [v]x^2 with t = |v|,
/// so that exp(v + dv) = exp(v) exp(Jr(v) dv) to first order. Both closed
/// forms cancel catastrophically near 0 (relative error about epsilon / t^2).
/// The first is computed as (sin(t/2) / (t/2))^2 / 2, which does not cancel
/// (cos_and_sinc, with its series below small_angle); the second is a series in t^2
/// below t = 1, with terms down to t^16 / 19! (below double epsilon there),
/// and the closed form above, where it loses at most a few bits. Both
/// switch-overs go through select_less (core/scalar_value.hpp).
template <class T>
Eigen::Matrix<T, 3, 3> right_jacobian_so3(const Eigen::Matrix<T, 3, 1>& v) {
    using std::sin;
    using std::sqrt;
    const T t2 = v.squaredNorm();
    T cos_half, sinc_half;  // cos(t/2), sin(t/2) / (t/2)
    cos_and_sinc(T(t2 / T(4)), cos_half, sinc_half);
    const T a = sinc_half * sinc_half / T(2);  // (1 - cos t)/t^2
    const T b = select_less(  // (t - sin t)/t^3
        t2, T(1),
        [&] {
            // sum over k of (-1)^k t^2k / (2k + 3)!, k = 0..8, by Horner's rule.
            double factorial = 1;  // (2k + 3)!
            double coefficient[9];
            for (int k = 0; k < 9; ++k) {
                if (k == 0)
                    factorial = 6;
                else
                    factorial *= double(2 * k + 2) * double(2 * k + 3);
                coefficient[k] = (k % 2 == 0 ? 1.0 : -1.0) / factorial;
            }
            T sum = T(0);
            for (int k = 8; k >= 0; --k) sum = T(coefficient[k]) + t2 * sum;
            return sum;
        },
        [&] {
            const T t = sqrt(t2);
            return T((t - sin(t)) / (t2 * t));
        });
    const Eigen::Matrix<T, 3, 3> k = cross_matrix(v);
    return Eigen::Matrix<T, 3, 3>::Identity() - a * k + b * (k * k);
}

}  // namespace anima::detail
