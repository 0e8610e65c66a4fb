// Time derivatives of sampled signals by finite differences, shared by every
// module that needs velocities (symmetry metrics, transitions, IK training).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>

#include <Eigen/Core>

#include <cmath>
#include <string>

namespace anima {

/// Derivative along the rows of `samples` (one row per frame, one column per
/// signal), sampled every dt: central differences (f[i+1] - f[i-1]) / 2dt
/// inside, one-sided differences at the first and last frame. One frame gives
/// a zero row (nothing moves), zero frames an empty matrix. Throws
/// anima::invalid_argument for dt <= 0 or non-finite.
template <class Derived>
Eigen::Matrix<typename Derived::Scalar, Eigen::Dynamic, Eigen::Dynamic> time_derivative(
    const Eigen::MatrixBase<Derived>& samples, typename Derived::Scalar dt) {
    using T = typename Derived::Scalar;
    check_positive("anima::time_derivative", "time step", dt);
    const Eigen::Index n = samples.rows();
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> d(n, samples.cols());
    if (n == 0) return d;
    if (n == 1) {
        d.setZero();
        return d;
    }
    d.row(0) = (samples.row(1) - samples.row(0)) / dt;
    d.row(n - 1) = (samples.row(n - 1) - samples.row(n - 2)) / dt;
    if (n > 2) d.middleRows(1, n - 2) = (samples.bottomRows(n - 2) - samples.topRows(n - 2)) / (T(2) * dt);
    return d;
}

}  // namespace anima
