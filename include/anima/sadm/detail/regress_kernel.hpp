// The RBF kernel matrix K(a_i, b_j) = exp(-gamma |a_i - b_j|^2) between the
// rows of two matrices, from |a|^2 + |b|^2 - 2 a.b (one matrix product, the
// costly part of SVR training and prediction); rounding can make the
// distance slightly negative, so it is clamped at 0.
#pragma once

#include <Eigen/Core>

namespace anima::detail {

template <class T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> rbf_kernel(const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& a,
                                                            const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& b,
                                                            T gamma) {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const Eigen::Matrix<T, Eigen::Dynamic, 1> a2 = a.rowwise().squaredNorm();
    const Eigen::Matrix<T, 1, Eigen::Dynamic> b2 = b.rowwise().squaredNorm().transpose();
    matrix d = T(-2) * a * b.transpose();
    d.colwise() += a2;
    d.rowwise() += b2;
    return (d.array().max(T(0)) * -gamma).exp().matrix();
}

}  // namespace anima::detail
