// The second-order polynomial mapping: b_g is linear in the monomials of
// degree <= 2 of b_s, i.e. 1, x_i and x_i x_j (i <= j), fitted by the same
// ridge least squares as Eq 5. The monomials are built on standardised
// inputs (stored with the model): the fitted function is still an exact
// quadratic of the raw inputs, but the columns have comparable scales, so
// the normal equations stay well conditioned and one relative ridge fits all.
#pragma once

#include <anima/core/error.hpp>
#include <anima/sadm/detail/regress_io.hpp>
#include <anima/sadm/detail/regress_ridge.hpp>
#include <anima/sadm/detail/regress_standardize.hpp>
#include <anima/sadm/regressor_base.hpp>

#include <Eigen/Core>

#include <cmath>
#include <ostream>
#include <string>

namespace anima {

/// The number of non-constant monomials of degree <= 2 in d variables.
inline Eigen::Index poly2_feature_count(Eigen::Index d) { return d + d * (d + 1) / 2; }

/// The monomials x_i, then x_i x_j for i <= j (row by row), of each row of x.
template <class T>
matrix_x<T> poly2_features(const matrix_x<T>& x) {
    const Eigen::Index d = x.cols();
    matrix_x<T> f(x.rows(), poly2_feature_count(d));
    f.leftCols(d) = x;
    Eigen::Index k = d;
    for (Eigen::Index i = 0; i < d; ++i)
        for (Eigen::Index j = i; j < d; ++j) f.col(k++) = x.col(i).cwiseProduct(x.col(j));
    return f;
}

template <class T>
class polynomial_regressor final : public regressor<T> {
public:
    using matrix = matrix_x<T>;
    using params = typename regressor_options<T>::poly2_params;

    /// Throws anima::invalid_argument for a negative or non-finite ridge.
    explicit polynomial_regressor(const params& p = {}) : params_(p) { detail::check_ridge("anima::polynomial_regressor", p.ridge); }

    regressor_kind kind() const override { return regressor_kind::poly2; }

    void fit(const matrix& inputs, const matrix& outputs) override {
        this->check_fit("anima::polynomial_regressor::fit", inputs, outputs);
        detail::regress_standardizer<T> scaler = detail::regress_standardizer<T>::fit(inputs);
        detail::ridge_solution<T> s = detail::ridge_fit<T>(poly2_features<T>(scaler.apply(inputs)), outputs,
                                                           params_.ridge);
        scaler_ = std::move(scaler);
        coefficients_ = std::move(s.weights);
        intercept_ = std::move(s.intercept);
        this->set_sizes(inputs, outputs);
    }

    matrix predict(const matrix& inputs) const override {
        this->check_predict("anima::polynomial_regressor::predict", inputs);
        return (poly2_features<T>(scaler_.apply(inputs)) * coefficients_).rowwise() + intercept_;
    }

    void save(std::ostream& out) const override {
        const detail::regress_stream_format format(out, T());
        this->write_header("anima::polynomial_regressor::save", out);
        out << "ridge " << params_.ridge << '\n';
        scaler_.write(out, "input");
        detail::write_regress_values(out, "intercept", intercept_);
        detail::write_regress_matrix(out, "coefficients", coefficients_);
    }

    /// The body after the header line; used by load_regressor.
    static polynomial_regressor read_body(detail::regress_reader& in) {
        polynomial_regressor r;
        r.read_sizes(in);
        const T ridge = in.read_scalar<T>("ridge");
        if (ridge < T(0)) in.fail("'ridge' must be >= 0");
        r.params_.ridge = ridge;
        r.scaler_ = detail::regress_standardizer<T>::read(in, "input", r.input_size());
        r.intercept_ = in.read_values<T>("intercept", r.output_size());
        r.coefficients_ = in.read_matrix<T>("coefficients", poly2_feature_count(r.input_size()), r.output_size());
        return r;
    }

    /// Weights of the monomials of the standardised inputs (poly2_features order) and the intercept.
    const matrix& coefficients() const { return coefficients_; }
    const Eigen::Matrix<T, 1, Eigen::Dynamic>& intercept() const { return intercept_; }
    const params& parameters() const { return params_; }

private:
    params params_;
    detail::regress_standardizer<T> scaler_;
    matrix coefficients_;
    Eigen::Matrix<T, 1, Eigen::Dynamic> intercept_;
};

}  // namespace anima
