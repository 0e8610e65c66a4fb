// The SVM regression of the paper's Table 1: epsilon-SVR with an RBF kernel,
// one model per output column, sharing one precomputed kernel matrix (n x n:
// meant for the few hundred frames of a face sequence, up to a few thousand
// samples). Inputs and outputs are standardised inside fit, so C and epsilon
// mean the same for every column and gamma <= 0 picks 1 / (d * variance).
// The dual is solved by SMO with second-order working-set selection
// (detail/regress_smo.hpp); only the support vectors are kept.
#pragma once

#include <anima/core/error.hpp>
#include <anima/sadm/detail/regress_io.hpp>
#include <anima/sadm/detail/regress_kernel.hpp>
#include <anima/sadm/detail/regress_smo.hpp>
#include <anima/sadm/detail/regress_standardize.hpp>
#include <anima/sadm/regressor_base.hpp>

#include <Eigen/Core>

#include <cmath>
#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace anima {

template <class T>
class svr_regressor final : public regressor<T> {
public:
    using matrix = matrix_x<T>;
    using params = typename regressor_options<T>::svr_params;

    /// Throws anima::invalid_argument for C <= 0, epsilon < 0, tolerance <=
    /// 0, max_iterations <= 0 or a non-finite value. progress, if set, is
    /// called once per fitted output column.
    explicit svr_regressor(const params& p = {}, std::function<void(const std::string&, int, int)> progress = {})
        : params_(p), progress_(std::move(progress)) {
        const auto finite = [](T v) { return std::isfinite(static_cast<double>(v)); };
        const auto bad = [](const char* name, T v, const char* rule) {
            throw invalid_argument(std::string("anima::svr_regressor: ") + name + " " + std::to_string(v) + " " + rule);
        };
        if (!(p.c > T(0)) || !finite(p.c)) bad("c", p.c, "must be finite and > 0");
        if (!(p.epsilon >= T(0)) || !finite(p.epsilon)) bad("epsilon", p.epsilon, "must be finite and >= 0");
        if (!finite(p.gamma)) bad("gamma", p.gamma, "must be finite (<= 0 picks 1 / (d * variance))");
        if (!(p.tolerance > T(0)) || !finite(p.tolerance)) bad("tolerance", p.tolerance, "must be finite and > 0");
        if (p.max_iterations <= 0)
            throw invalid_argument("anima::svr_regressor: max_iterations " + std::to_string(p.max_iterations) +
                                   " must be > 0");
    }

    regressor_kind kind() const override { return regressor_kind::svr; }

    void fit(const matrix& inputs, const matrix& outputs) override {
        const std::string who = "anima::svr_regressor::fit";
        this->check_fit(who.c_str(), inputs, outputs);
        auto in_scale = detail::regress_standardizer<T>::fit(inputs);
        auto out_scale = detail::regress_standardizer<T>::fit(outputs);
        const matrix x = in_scale.apply_checked(inputs, who, "inputs");
        const matrix z = out_scale.apply_checked(outputs, who, "outputs");
        T gamma = params_.gamma;
        if (!(gamma > T(0))) {
            const T variance = x.squaredNorm() / static_cast<T>(x.size());  // 1, or less with constant columns
            gamma = T(1) / (static_cast<T>(x.cols()) * (variance > T(0) ? variance : T(1)));
        }
        const matrix k = detail::rbf_kernel<T>(x, x, gamma);

        const Eigen::Index n = x.rows(), m = z.cols();
        matrix beta(n, m);
        Eigen::Matrix<T, 1, Eigen::Dynamic> bias(m);
        std::vector<int> iterations(static_cast<std::size_t>(m));
        bool converged = true;
        for (Eigen::Index col = 0; col < m; ++col) {
            const Eigen::Matrix<T, Eigen::Dynamic, 1> target = z.col(col);
            const detail::smo_result<T> s = detail::smo_epsilon_svr<T>(k, target, params_.c, params_.epsilon,
                                                                       params_.tolerance, params_.max_iterations);
            beta.col(col) = s.beta;
            bias(col) = s.bias;
            iterations[static_cast<std::size_t>(col)] = s.iterations;
            converged = converged && s.converged;
            if (progress_) progress_("svr", static_cast<int>(col + 1), static_cast<int>(m));
        }

        if (!beta.allFinite() || !bias.allFinite())
            throw error(who + ": the fitted dual coefficients are not finite in this precision");
        // Keep the samples some column uses.
        std::vector<Eigen::Index> kept;
        for (Eigen::Index i = 0; i < n; ++i)
            if ((beta.row(i).array() != T(0)).any()) kept.push_back(i);
        support_vectors_.resize(static_cast<Eigen::Index>(kept.size()), x.cols());
        coefficients_.resize(static_cast<Eigen::Index>(kept.size()), m);
        for (std::size_t r = 0; r < kept.size(); ++r) {
            support_vectors_.row(static_cast<Eigen::Index>(r)) = x.row(kept[r]);
            coefficients_.row(static_cast<Eigen::Index>(r)) = beta.row(kept[r]);
        }
        support_indices_ = std::move(kept);
        bias_ = bias;
        gamma_ = gamma;
        input_scale_ = std::move(in_scale);
        output_scale_ = std::move(out_scale);
        iterations_ = std::move(iterations);
        converged_ = converged;
        this->set_sizes(inputs, outputs);
    }

    matrix predict(const matrix& inputs) const override {
        this->check_predict("anima::svr_regressor::predict", inputs);
        const matrix z = support_vectors_.rows() == 0
                             ? matrix(matrix::Zero(inputs.rows(), coefficients_.cols()))
                             : matrix(detail::rbf_kernel<T>(input_scale_.apply(inputs), support_vectors_, gamma_) *
                                      coefficients_);
        return this->finite_prediction("anima::svr_regressor::predict", output_scale_.invert(z.rowwise() + bias_));
    }

    void save(std::ostream& out) const override {
        const detail::regress_stream_format format(out, T());
        this->write_header("anima::svr_regressor::save", out);
        out << "c " << params_.c << "\nepsilon " << params_.epsilon << "\ngamma " << gamma_ << '\n';
        input_scale_.write(out, "input");
        output_scale_.write(out, "output");
        detail::write_regress_values(out, "bias", bias_);
        out << "support_count " << support_vectors_.rows() << '\n';
        detail::write_regress_matrix(out, "support_vectors", support_vectors_);
        detail::write_regress_matrix(out, "coefficients", coefficients_);
    }

    /// The body after the header line; used by load_regressor.
    static svr_regressor read_body(detail::regress_reader& in) {
        svr_regressor r;
        r.read_sizes(in);
        r.params_.c = in.read_scalar<T>("c");
        r.params_.epsilon = in.read_scalar<T>("epsilon");
        r.gamma_ = in.read_scalar<T>("gamma");
        if (!(r.params_.c > T(0)) || r.params_.epsilon < T(0) || !(r.gamma_ > T(0)))
            in.fail("c and gamma must be > 0, epsilon >= 0");
        r.params_.gamma = r.gamma_;
        const Eigen::Index d = r.input_size(), m = r.output_size();
        r.input_scale_ = detail::regress_standardizer<T>::read(in, "input", d);
        r.output_scale_ = detail::regress_standardizer<T>::read(in, "output", m);
        r.bias_ = in.read_values<T>("bias", m);
        const Eigen::Index count = in.read_count("support_count");
        r.support_vectors_ = in.read_matrix<T>("support_vectors", count, d);
        r.coefficients_ = in.read_matrix<T>("coefficients", count, m);
        return r;
    }

    /// The standardised training inputs kept (rows) and their beta = alpha -
    /// alpha* per output column, in standardised output units.
    const matrix& support_vectors() const { return support_vectors_; }
    const matrix& coefficients() const { return coefficients_; }
    /// The training rows the support vectors came from (empty after load).
    const std::vector<Eigen::Index>& support_indices() const { return support_indices_; }
    /// Per output: f(x) = sum beta K + bias, before undoing the output scaling.
    const Eigen::Matrix<T, 1, Eigen::Dynamic>& bias() const { return bias_; }
    /// The RBF width used (the automatic one if the option was <= 0).
    T gamma() const { return gamma_; }
    /// SMO steps per output column of the last fit, and whether every column
    /// reached the tolerance before max_iterations.
    const std::vector<int>& iterations() const { return iterations_; }
    bool converged() const { return converged_; }
    const params& parameters() const { return params_; }

private:
    params params_;
    std::function<void(const std::string&, int, int)> progress_;
    detail::regress_standardizer<T> input_scale_, output_scale_;
    matrix support_vectors_, coefficients_;
    std::vector<Eigen::Index> support_indices_;
    Eigen::Matrix<T, 1, Eigen::Dynamic> bias_;
    T gamma_ = T(0);
    std::vector<int> iterations_;
    bool converged_ = false;
};

}  // namespace anima
