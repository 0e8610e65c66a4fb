// A natural cubic spline through (t_k, y_k), vector-valued: C2, zero second
// derivative at both ends, one tridiagonal solve for all columns. Templated
// on the scalar so key times and values may carry derivatives (AutoDiff).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/scalar_value.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace anima {

template <class S>
class cubic_spline {
public:
    using matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
    using row = Eigen::Matrix<S, 1, Eigen::Dynamic>;

    cubic_spline() = default;

    /// times: n >= 2, finite, strictly increasing; values: n rows, one column per
    /// component, all finite. Throws anima::invalid_argument otherwise, and
    /// when keys so close together overflow the slopes or curvatures.
    cubic_spline(std::vector<S> times, matrix values) : t_(std::move(times)), y_(std::move(values)) {
        const std::size_t n = t_.size();
        if (n < 2) throw invalid_argument("anima::cubic_spline: needs at least 2 keys, got " + std::to_string(n));
        if (static_cast<std::size_t>(y_.rows()) != n)
            throw invalid_argument("anima::cubic_spline: " + std::to_string(y_.rows()) + " value rows for " +
                                   std::to_string(n) + " times");
        for (std::size_t i = 0; i < n; ++i)
            if (!std::isfinite(detail::scalar_value(t_[i])))
                throw invalid_argument("anima::cubic_spline: times must be finite; t[" + std::to_string(i) + "] = " +
                                       detail::argument_text(detail::scalar_value(t_[i])));
        for (std::size_t i = 0; i + 1 < n; ++i)
            if (!(t_[i + 1] > t_[i]))
                throw invalid_argument("anima::cubic_spline: times must increase strictly; t[" + std::to_string(i + 1) +
                                       "] = " + std::to_string((detail::scalar_value(t_[i + 1]))) +
                                       " after t[" + std::to_string(i) +
                                       "] = " + std::to_string((detail::scalar_value(t_[i]))));
        // Thomas algorithm on the interior second derivatives (natural ends).
        const Eigen::Index d = y_.cols();
        m_ = matrix::Zero(static_cast<Eigen::Index>(n), d);
        if (n == 2) {
            check_finite_derivatives();
            return;
        }
        std::vector<S> diag(n), upper(n);
        matrix rhs(static_cast<Eigen::Index>(n), d);
        for (std::size_t i = 1; i + 1 < n; ++i) {
            const S h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
            const auto I = static_cast<Eigen::Index>(i);
            diag[i] = S(2) * (h0 + h1);
            upper[i] = h1;
            rhs.row(I) = S(6) * ((y_.row(I + 1) - y_.row(I)) / h1 - (y_.row(I) - y_.row(I - 1)) / h0);
            if (i > 1) {
                const S w = h0 / diag[i - 1];
                diag[i] -= w * upper[i - 1];
                rhs.row(I) -= w * rhs.row(I - 1);
            }
        }
        for (std::size_t i = n - 2; i >= 1; --i) {
            const auto I = static_cast<Eigen::Index>(i);
            row r = rhs.row(I);
            if (i + 2 < n) r -= upper[i] * m_.row(I + 1);
            m_.row(I) = r / diag[i];
        }
        check_finite_derivatives();
    }

    std::size_t keys() const noexcept { return t_.size(); }
    Eigen::Index dimension() const noexcept { return y_.cols(); }
    const std::vector<S>& times() const noexcept { return t_; }

    /// Value and first and second derivatives at t (clamped to [t_0, t_n-1]:
    /// callers check the range).
    void evaluate(const S& t, row& value, row& first, row& second) const {
        const std::size_t i = interval(t);
        const auto I = static_cast<Eigen::Index>(i);
        const S h = t_[i + 1] - t_[i];
        const S a = (t_[i + 1] - t) / h, b = (t - t_[i]) / h;
        value = a * y_.row(I) + b * y_.row(I + 1) +
                ((a * a * a - a) * m_.row(I) + (b * b * b - b) * m_.row(I + 1)) * (h * h / S(6));
        first = (y_.row(I + 1) - y_.row(I)) / h - (S(3) * a * a - S(1)) * h / S(6) * m_.row(I) +
                (S(3) * b * b - S(1)) * h / S(6) * m_.row(I + 1);
        second = a * m_.row(I) + b * m_.row(I + 1);
    }

    /// Index i of the interval [t_i, t_i+1] holding t (the last one for t_n-1).
    std::size_t interval(const S& t) const {
        std::size_t lo = 0, hi = t_.size() - 1;
        while (hi - lo > 1) {
            const std::size_t mid = (lo + hi) / 2;
            if (t < t_[mid]) hi = mid;
            else lo = mid;
        }
        return lo;
    }

private:
    // Slopes grow as 1 / h and curvatures as 1 / h^2: keys a hair apart
    // overflow them (float at 1e-20 s, double at 1e-160 s), and evaluate()
    // would return NaN.
    void check_finite_derivatives() const {
        using R = detail::real_scalar_t<S>;
        const auto finite = [](const S& x) { return std::isfinite(detail::scalar_value(x)); };
        for (Eigen::Index i = 0; i < y_.rows(); ++i)
            for (Eigen::Index c = 0; c < y_.cols(); ++c)
                if (!finite(y_(i, c)))
                    throw invalid_argument("anima::cubic_spline: value (" + std::to_string(i) + ", " + std::to_string(c) +
                                           ") must be finite, got " + detail::argument_text(detail::scalar_value(y_(i, c))));
        bool ok = true;
        for (Eigen::Index i = 0; ok && i < m_.size(); ++i) ok = finite(m_.data()[i]);
        for (Eigen::Index i = 0; ok && i + 1 < y_.rows(); ++i)
            for (Eigen::Index c = 0; ok && c < y_.cols(); ++c) {
                const auto k = static_cast<std::size_t>(i);
                ok = finite((y_(i + 1, c) - y_(i, c)) / (t_[k + 1] - t_[k]));
            }
        if (ok) return;
        R shortest = static_cast<R>(detail::scalar_value(t_[1] - t_[0]));
        for (std::size_t k = 2; k < t_.size(); ++k)
            shortest = std::min(shortest, static_cast<R>(detail::scalar_value(t_[k] - t_[k - 1])));
        throw invalid_argument("anima::cubic_spline: the spline's derivatives are not finite in this precision "
                               "(shortest key interval " + detail::argument_text(shortest) + " s)");
    }

    std::vector<S> t_;
    matrix y_;
    matrix m_;
};

}  // namespace anima
