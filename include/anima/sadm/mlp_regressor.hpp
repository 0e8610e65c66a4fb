// The neural-network mapping of the paper's Table 1: a small feed-forward
// network (one or two tanh hidden layers, linear output) trained full-batch
// on the mean squared error plus weight decay by L-BFGS (bfgs_minimize with
// memory > 0). Inputs and outputs are standardised inside fit; the weights
// start Xavier-uniform from the seed, so a fit is a deterministic function
// of the data and the options.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/optimize/bfgs.hpp>
#include <anima/sadm/detail/regress_io.hpp>
#include <anima/sadm/detail/regress_mlp_network.hpp>
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
class mlp_regressor final : public regressor<T> {
public:
    using matrix = matrix_x<T>;
    using params = typename regressor_options<T>::mlp_params;

    /// L-BFGS correction pairs kept.
    static constexpr int lbfgs_memory = 10;

    /// Throws anima::invalid_argument unless there are one or two hidden
    /// layers of positive size, weight_decay is finite and >= 0 and
    /// max_iterations > 0. progress, if set, is called after each iteration.
    explicit mlp_regressor(const params& p = {}, std::function<void(const std::string&, int, int)> progress = {})
        : params_(p), progress_(std::move(progress)) {
        if (p.hidden.empty() || p.hidden.size() > 2)
            throw invalid_argument("anima::mlp_regressor: hidden has " + std::to_string(p.hidden.size()) +
                                   " layers, use one or two");
        for (int h : p.hidden)
            if (h <= 0 || h > 100000)
                throw invalid_argument("anima::mlp_regressor: hidden layer size " + std::to_string(h) +
                                       " must be in [1, 100000]");
        if (!(p.weight_decay >= T(0)) || !std::isfinite(static_cast<double>(p.weight_decay)))
            throw invalid_argument("anima::mlp_regressor: weight_decay " + detail::argument_text(p.weight_decay) +
                                   " must be finite and >= 0");
        if (p.max_iterations <= 0)
            throw invalid_argument("anima::mlp_regressor: max_iterations " + std::to_string(p.max_iterations) +
                                   " must be > 0");
    }

    regressor_kind kind() const override { return regressor_kind::mlp; }

    void fit(const matrix& inputs, const matrix& outputs) override {
        const std::string who = "anima::mlp_regressor::fit";
        this->check_fit(who.c_str(), inputs, outputs);
        auto in_scale = detail::regress_standardizer<T>::fit(inputs);
        auto out_scale = detail::regress_standardizer<T>::fit(outputs);
        std::vector<int> sizes{static_cast<int>(inputs.cols())};
        sizes.insert(sizes.end(), params_.hidden.begin(), params_.hidden.end());
        sizes.push_back(static_cast<int>(outputs.cols()));
        detail::mlp_network<T> net = detail::mlp_network<T>::initial(sizes, params_.seed);
        detail::mlp_objective<T> objective(net, in_scale.apply_checked(inputs, who, "inputs"),
                                           out_scale.apply_checked(outputs, who, "outputs"), params_.weight_decay);

        bfgs_params<T> solver;
        solver.max_iterations = params_.max_iterations;
        solver.memory = lbfgs_memory;
        if (progress_) {
            solver.on_iteration = [this](int iteration, T) {
                progress_("mlp", iteration, params_.max_iterations);
                return true;
            };
        }
        const optimize_result<T> result = bfgs_minimize(objective, net.pack(), solver);
        if (!result.x.allFinite()) throw error(who + ": the trained weights are not finite in this precision");
        net.unpack(result.x);

        network_ = std::move(net);
        input_scale_ = std::move(in_scale);
        output_scale_ = std::move(out_scale);
        status_ = result.status;
        iterations_ = result.iterations;
        loss_ = result.value;
        this->set_sizes(inputs, outputs);
    }

    matrix predict(const matrix& inputs) const override {
        this->check_predict("anima::mlp_regressor::predict", inputs);
        return this->finite_prediction("anima::mlp_regressor::predict",
                                       output_scale_.invert(network_.evaluate(input_scale_.apply(inputs))));
    }

    void save(std::ostream& out) const override {
        const detail::regress_stream_format format(out, T());
        this->write_header("anima::mlp_regressor::save", out);
        out << "hidden";
        for (int h : params_.hidden) out << ' ' << h;
        out << "\nweight_decay " << params_.weight_decay << '\n';
        input_scale_.write(out, "input");
        output_scale_.write(out, "output");
        for (std::size_t l = 0; l < network_.layers(); ++l) {
            detail::write_regress_matrix(out, "weights", network_.weights[l]);
            detail::write_regress_values(out, "bias", network_.biases[l].transpose());
        }
    }

    /// The body after the header line; used by load_regressor.
    static mlp_regressor read_body(detail::regress_reader& in) {
        mlp_regressor r;
        r.read_sizes(in);
        const std::vector<std::string> hidden = in.expect("hidden");
        if (hidden.empty() || hidden.size() > 2) in.fail("'hidden' takes one or two layer sizes");
        r.params_.hidden.clear();
        for (const std::string& h : hidden) {
            const long size = in.parse_count(h, "hidden layer size", 100000);
            if (size == 0) in.fail("a hidden layer size must be positive");
            r.params_.hidden.push_back(static_cast<int>(size));
        }
        r.params_.weight_decay = in.read_scalar<T>("weight_decay");
        const Eigen::Index d = r.input_size(), m = r.output_size();
        r.input_scale_ = detail::regress_standardizer<T>::read(in, "input", d);
        r.output_scale_ = detail::regress_standardizer<T>::read(in, "output", m);
        std::vector<int> sizes{static_cast<int>(d)};
        sizes.insert(sizes.end(), r.params_.hidden.begin(), r.params_.hidden.end());
        sizes.push_back(static_cast<int>(m));
        r.network_.sizes = sizes;
        for (std::size_t l = 0; l + 1 < sizes.size(); ++l) {
            r.network_.weights.push_back(in.read_matrix<T>("weights", sizes[l + 1], sizes[l]));
            r.network_.biases.push_back(in.read_values<T>("bias", sizes[l + 1]).transpose());
        }
        return r;
    }

    /// How the last training stopped, its iterations and its final objective
    /// (standardised units: half the mean squared error plus the decay term).
    optimize_status status() const { return status_; }
    int iterations() const { return iterations_; }
    T training_loss() const { return loss_; }
    const params& parameters() const { return params_; }

private:
    params params_;
    std::function<void(const std::string&, int, int)> progress_;
    detail::regress_standardizer<T> input_scale_, output_scale_;
    detail::mlp_network<T> network_;
    optimize_status status_ = optimize_status::max_iterations;
    int iterations_ = 0;
    T loss_ = T(0);
};

}  // namespace anima
