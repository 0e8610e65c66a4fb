// The epsilon-SVR dual solved by SMO with second-order working-set selection
// (Fan, Chen & Lin 2005, WSS2). The dual has 2n variables alpha_t in [0, C]
// with signs y_t = +1 (t < n, alpha_i) and -1 (t >= n, alpha*_i):
//   min 1/2 a^T Q a + p^T a,  y^T a = 0,
//   Q_ts = y_t y_s K(t mod n, s mod n),  p_t = eps - z_i (t < n), eps + z_i (t >= n).
// Only beta = alpha - alpha* matters: Q a = (+-) K beta, so the gradient is
// kept as u = K beta (n values) and each step updates it with two kernel
// columns. A step moves alpha_i by y_i s and alpha_j by -y_j s, which keeps
// y^T a fixed; along it the objective is a parabola in s.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

namespace anima::detail {

template <class T>
struct smo_result {
    Eigen::Matrix<T, Eigen::Dynamic, 1> beta;  ///< alpha_i - alpha*_i
    T bias = T(0);                             ///< f(x) = sum beta_i K(x_i, x) + bias
    int iterations = 0;
    bool converged = false;
    T violation = T(0);  ///< the final maximal KKT violation m(a) - M(a)
};

/// k: n x n kernel matrix, z: n targets. Stops when the maximal violating
/// pair's violation is below tolerance or after max_iterations steps.
template <class T>
smo_result<T> smo_epsilon_svr(const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& k,
                              const Eigen::Matrix<T, Eigen::Dynamic, 1>& z, T c, T epsilon, T tolerance,
                              int max_iterations) {
    const Eigen::Index n = z.size(), l = 2 * n;
    Eigen::Matrix<T, Eigen::Dynamic, 1> alpha = Eigen::Matrix<T, Eigen::Dynamic, 1>::Zero(l);
    Eigen::Matrix<T, Eigen::Dynamic, 1> u = Eigen::Matrix<T, Eigen::Dynamic, 1>::Zero(n);  // K beta
    const auto sign = [n](Eigen::Index t) { return t < n ? T(1) : T(-1); };
    const auto sample = [n](Eigen::Index t) { return t < n ? t : t - n; };
    // Gradient of the dual: (Q a)_t + p_t.
    const auto gradient = [&](Eigen::Index t) {
        const Eigen::Index i = sample(t);
        return t < n ? u(i) + epsilon - z(i) : -u(i) + epsilon + z(i);
    };
    const auto in_up = [&](Eigen::Index t) { return t < n ? alpha(t) < c : alpha(t) > T(0); };
    const auto in_low = [&](Eigen::Index t) { return t < n ? alpha(t) > T(0) : alpha(t) < c; };
    const T tau = T(1e-12);

    smo_result<T> r;
    for (;;) {
        // i: the most violating index that may move up (largest -y G).
        Eigen::Index i = -1;
        T g_max = -std::numeric_limits<T>::infinity();
        for (Eigen::Index t = 0; t < l; ++t)
            if (in_up(t) && -sign(t) * gradient(t) > g_max) {
                g_max = -sign(t) * gradient(t);
                i = t;
            }
        // j: among those that may move down, the largest second-order decrease.
        Eigen::Index j = -1;
        T g_max2 = -std::numeric_limits<T>::infinity();
        T best = std::numeric_limits<T>::infinity();
        for (Eigen::Index t = 0; t < l; ++t) {
            if (!in_low(t)) continue;
            const T yg = sign(t) * gradient(t);
            g_max2 = std::max(g_max2, yg);
            if (i < 0) continue;
            const T b = g_max + yg;
            if (b <= T(0)) continue;
            const Eigen::Index si = sample(i), st = sample(t);
            T a = k(si, si) + k(st, st) - T(2) * k(si, st);
            if (a <= T(0)) a = tau;
            if (-b * b / a < best) {
                best = -b * b / a;
                j = t;
            }
        }
        r.violation = g_max + g_max2;
        if (i < 0 || j < 0 || r.violation < tolerance) {
            r.converged = true;
            break;
        }
        if (r.iterations >= max_iterations) break;
        ++r.iterations;

        const Eigen::Index si = sample(i), sj = sample(j);
        const T yi = sign(i), yj = sign(j);
        T a = k(si, si) + k(sj, sj) - T(2) * k(si, sj);
        if (a <= T(0)) a = tau;
        // f(s) = f0 + s (y_i G_i - y_j G_j) + s^2 a / 2, the slope is negative here.
        T s = (yj * gradient(j) - yi * gradient(i)) / a;
        s = std::min(s, yi > T(0) ? c - alpha(i) : alpha(i));
        s = std::min(s, yj > T(0) ? alpha(j) : c - alpha(j));
        const T old_i = alpha(i), old_j = alpha(j);
        alpha(i) = std::clamp(old_i + yi * s, T(0), c);
        alpha(j) = std::clamp(old_j - yj * s, T(0), c);
        // beta_si changes by y_i * delta alpha_i, beta_sj by y_j * delta alpha_j.
        const T dbi = yi * (alpha(i) - old_i), dbj = yj * (alpha(j) - old_j);
        u += k.col(si) * dbi + k.col(sj) * dbj;
    }

    r.beta = alpha.head(n) - alpha.tail(n);
    // rho from the free variables (y_t G_t = rho there), else the middle of
    // the interval the bounded ones allow.
    T free_sum = T(0);
    Eigen::Index free_count = 0;
    T upper = std::numeric_limits<T>::infinity(), lower = -std::numeric_limits<T>::infinity();
    for (Eigen::Index t = 0; t < l; ++t) {
        const T yg = sign(t) * gradient(t);
        if (alpha(t) > T(0) && alpha(t) < c) {
            free_sum += yg;
            ++free_count;
        } else if ((alpha(t) >= c) == (sign(t) > T(0))) {
            lower = std::max(lower, yg);
        } else {
            upper = std::min(upper, yg);
        }
    }
    const T rho = free_count > 0 ? free_sum / static_cast<T>(free_count) : (upper + lower) / T(2);
    r.bias = -rho;
    return r;
}

}  // namespace anima::detail
