// The linear mapping of Eq 5, b_g = A b_s (+ an intercept): A = G S^T
// (S S^T + lambda I)^-1 on centred data. The paper's S and G hold samples in
// columns; here rows are samples, so the coefficients stored are A^T.
// Eq 5 as printed needs S S^T invertible, which fails with fewer frames than
// shape parameters or with collinear parameters; the ridge keeps it defined
// and ridge = 0 falls back to the minimum-norm least-squares solution.
#pragma once

#include <anima/core/error.hpp>
#include <anima/sadm/detail/regress_io.hpp>
#include <anima/sadm/detail/regress_ridge.hpp>
#include <anima/sadm/regressor_base.hpp>

#include <Eigen/Core>

#include <cmath>
#include <ostream>
#include <string>

namespace anima {

template <class T>
class linear_regressor final : public regressor<T> {
public:
    using matrix = matrix_x<T>;
    using params = typename regressor_options<T>::linear_params;

    /// Throws anima::invalid_argument for a negative or non-finite ridge.
    explicit linear_regressor(const params& p = {}) : params_(p) { detail::check_ridge("anima::linear_regressor", p.ridge); }

    regressor_kind kind() const override { return regressor_kind::linear; }

    void fit(const matrix& inputs, const matrix& outputs) override {
        this->check_fit("anima::linear_regressor::fit", inputs, outputs);
        detail::ridge_solution<T> s = detail::ridge_fit<T>(inputs, outputs, params_.ridge);
        coefficients_ = std::move(s.weights);
        intercept_ = std::move(s.intercept);
        this->set_sizes(inputs, outputs);
    }

    matrix predict(const matrix& inputs) const override {
        this->check_predict("anima::linear_regressor::predict", inputs);
        return (inputs * coefficients_).rowwise() + intercept_;
    }

    void save(std::ostream& out) const override {
        const detail::regress_stream_format format(out, T());
        this->write_header("anima::linear_regressor::save", out);
        out << "ridge " << params_.ridge << '\n';
        detail::write_regress_values(out, "intercept", intercept_);
        detail::write_regress_matrix(out, "coefficients", coefficients_);
    }

    /// The body after the header line; used by load_regressor.
    static linear_regressor read_body(detail::regress_reader& in) {
        linear_regressor r;
        r.read_sizes(in);
        const T ridge = in.read_scalar<T>("ridge");
        if (ridge < T(0)) in.fail("'ridge' must be >= 0");
        r.params_.ridge = ridge;
        r.intercept_ = in.read_values<T>("intercept", r.output_size());
        r.coefficients_ = in.read_matrix<T>("coefficients", r.input_size(), r.output_size());
        return r;
    }

    /// A^T (d x m) and the intercept (1 x m): predict(x) = x A^T + intercept.
    const matrix& coefficients() const { return coefficients_; }
    const Eigen::Matrix<T, 1, Eigen::Dynamic>& intercept() const { return intercept_; }
    const params& parameters() const { return params_; }

private:
    params params_;
    matrix coefficients_;
    Eigen::Matrix<T, 1, Eigen::Dynamic> intercept_;
};

}  // namespace anima
