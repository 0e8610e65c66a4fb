// The right Jacobian of the rotation-vector (exponential map) chart of
// SO(3): how a change of the rotation vector v turns into an angular
// velocity in the rotated (body) frame.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <limits>

namespace anima::detail {

template <class T>
Eigen::Matrix<T, 3, 3> cross_matrix(const Eigen::Matrix<T, 3, 1>& v) {
    Eigen::Matrix<T, 3, 3> m;
    m << T(0), -v.z(), v.y(), v.z(), T(0), -v.x(), -v.y(), v.x(), T(0);
    return m;
}

/// Jr(v) = I - (1 - cos t)/t^2 [v]x + (t - sin t)/t^3 [v]x^2 with t = |v|,
/// so that exp(v + dv) = exp(v) exp(Jr(v) dv) to first order. Below a
/// threshold set by the scalar's epsilon both coefficients use their Taylor
/// series (their closed forms cancel catastrophically near 0).
template <class T>
Eigen::Matrix<T, 3, 3> right_jacobian_so3(const Eigen::Matrix<T, 3, 1>& v) {
    const T t2 = v.squaredNorm();
    const T small = std::sqrt(std::sqrt(std::numeric_limits<T>::epsilon()));
    T a, b;  // (1 - cos t)/t^2, (t - sin t)/t^3
    if (t2 < small * small) {
        a = T(0.5) - t2 / T(24) + t2 * t2 / T(720);
        b = T(1) / T(6) - t2 / T(120) + t2 * t2 / T(5040);
    } else {
        const T t = std::sqrt(t2);
        a = (T(1) - std::cos(t)) / t2;
        b = (t - std::sin(t)) / (t2 * t);
    }
    const Eigen::Matrix<T, 3, 3> k = cross_matrix(v);
    return Eigen::Matrix<T, 3, 3>::Identity() - a * k + b * (k * k);
}

}  // namespace anima::detail
