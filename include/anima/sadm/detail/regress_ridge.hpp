// Least squares with an intercept and a relative ridge, the solver behind
// Eq 5 and the polynomial mapping. The intercept is not penalised: both
// sides are centred, then W solves (Xc^T Xc + lambda I) W = Xc^T Yc by LDLT
// with lambda = ridge * trace(Xc^T Xc) / p, so the ridge means the same for
// any scale of the inputs. ridge = 0 is Eq 5 itself, solved on Xc by a
// complete orthogonal decomposition: the minimum-norm solution when the
// inputs are collinear or fewer than their dimension, without squaring the
// condition number.
#pragma once

#include <anima/core/error.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/QR>

#include <cmath>
#include <string>

namespace anima::detail {

/// Throws anima::invalid_argument unless the ridge is finite and >= 0.
template <class T>
void check_ridge(const char* who, T ridge) {
    if (!(ridge >= T(0)) || !std::isfinite(static_cast<double>(ridge)))
        throw invalid_argument(std::string(who) + ": ridge " + std::to_string(ridge) + " must be finite and >= 0");
}

template <class T>
struct ridge_solution {
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> weights;  ///< p x m
    Eigen::Matrix<T, 1, Eigen::Dynamic> intercept;             ///< 1 x m
};

/// Y ~ X W + 1 intercept for X: n x p, Y: n x m (n >= 1, finite), ridge >= 0.
template <class T>
ridge_solution<T> ridge_fit(const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& x,
                            const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& y, T ridge) {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const Eigen::Matrix<T, 1, Eigen::Dynamic> x_mean = x.colwise().mean();
    const Eigen::Matrix<T, 1, Eigen::Dynamic> y_mean = y.colwise().mean();
    const matrix xc = x.rowwise() - x_mean;
    const matrix yc = y.rowwise() - y_mean;

    ridge_solution<T> s;
    if (ridge > T(0)) {
        matrix normal = matrix::Zero(x.cols(), x.cols());
        normal.template selfadjointView<Eigen::Lower>().rankUpdate(xc.transpose());
        const T trace = normal.diagonal().sum();
        if (trace > T(0)) {
            const T lambda = ridge * trace / static_cast<T>(x.cols());
            normal.diagonal().array() += lambda;
            const Eigen::LDLT<matrix, Eigen::Lower> ldlt(normal);
            s.weights = ldlt.solve(xc.transpose() * yc);
        } else {
            s.weights = matrix::Zero(x.cols(), y.cols());  // every input constant: the mean is the fit
        }
    } else {
        s.weights = Eigen::CompleteOrthogonalDecomposition<matrix>(xc).solve(yc);
    }
    s.intercept = y_mean - x_mean * s.weights;
    if (!s.weights.allFinite() || !s.intercept.allFinite())
        throw error("anima::ridge_fit: the least-squares solution is not finite (inputs too large for the scalar type)");
    return s;
}

}  // namespace anima::detail
