// Central finite differences: the reference that analytic derivatives are
// tested against, and a fallback when none are available.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <anima/optimize/result.hpp>

namespace anima {

/// The default relative step: the cube root of epsilon balances the
/// truncation error of central differences (h^2) against rounding (eps / h).
template <class T>
T default_difference_step() {
    return std::cbrt(std::numeric_limits<T>::epsilon());
}

/// Gradient of a scalar function by central differences. The step for
/// component i is step * max(1, |x_i|). F: T(const vector_x<T>&).
template <class T, class F>
vector_x<T> numeric_gradient(F&& f, const vector_x<T>& x, T step = default_difference_step<T>()) {
    if (!(step > T(0))) {
        throw invalid_argument("numeric_gradient: step must be positive");
    }
    vector_x<T> gradient(x.size());
    vector_x<T> probe = x;
    for (Eigen::Index i = 0; i < x.size(); ++i) {
        const T h = step * std::max(T(1), std::abs(x[i]));
        probe[i] = x[i] + h;
        const T plus = f(static_cast<const vector_x<T>&>(probe));
        probe[i] = x[i] - h;
        const T minus = f(static_cast<const vector_x<T>&>(probe));
        probe[i] = x[i];
        gradient[i] = (plus - minus) / (T(2) * h);
    }
    return gradient;
}

/// Jacobian (rows: residuals, columns: variables) of a vector function by
/// central differences. R: void(const vector_x<T>& x, vector_x<T>& residuals).
template <class T, class R>
matrix_x<T> numeric_jacobian(R&& r, const vector_x<T>& x, T step = default_difference_step<T>()) {
    if (!(step > T(0))) {
        throw invalid_argument("numeric_jacobian: step must be positive");
    }
    vector_x<T> plus, minus;
    vector_x<T> probe = x;
    matrix_x<T> jacobian;
    for (Eigen::Index i = 0; i < x.size(); ++i) {
        const T h = step * std::max(T(1), std::abs(x[i]));
        probe[i] = x[i] + h;
        r(static_cast<const vector_x<T>&>(probe), plus);
        probe[i] = x[i] - h;
        r(static_cast<const vector_x<T>&>(probe), minus);
        probe[i] = x[i];
        if (plus.size() != minus.size()) {
            throw invalid_argument("numeric_jacobian: the function returned residual vectors of different sizes");
        }
        if (i == 0) {
            jacobian.resize(plus.size(), x.size());
        } else if (plus.size() != jacobian.rows()) {
            throw invalid_argument("numeric_jacobian: the function returned residual vectors of different sizes");
        }
        jacobian.col(i) = (plus - minus) / (T(2) * h);
    }
    return jacobian;
}

}  // namespace anima
