// The fit/predict interface shared by the SADM mappings b_s -> b_g (Eq 5 and
// its non-linear alternatives), their kinds and their options. Rows are
// samples everywhere: fit takes n x d inputs and n x m outputs, predict
// takes k x d inputs and returns k x m. <anima/sadm/regressor.hpp> adds the
// concrete regressors, make_regressor and load_regressor.
#pragma once

#include <anima/core/eigen_types.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/sadm/detail/regress_io.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace anima {

/// The four mappings of the paper's Table 1.
enum class regressor_kind : unsigned char { linear, poly2, mlp, svr };

template <>
struct enum_names<regressor_kind> {
    static constexpr const char* what = "regressor";
    static constexpr enum_entry<regressor_kind> entries[] = {{regressor_kind::linear, "linear"},
                                                             {regressor_kind::poly2, "poly2"},
                                                             {regressor_kind::mlp, "mlp"},
                                                             {regressor_kind::svr, "svr"}};
};

/// "linear", "poly2", "mlp" or "svr" (any case); throws anima::invalid_argument otherwise.
inline regressor_kind parse_regressor_kind(std::string_view name) {
    return parse_enum<regressor_kind>(name, "anima::parse_regressor_kind");
}

/// Options of every regressor, nested by kind; make_regressor picks the
/// ones of the kind it makes.
template <class T>
struct regressor_options {
    /// The default relative ridge of the least-squares mappings.
    static constexpr T default_ridge() { return std::is_same_v<T, float> ? T(1e-4) : T(1e-6); }

    struct linear_params {
        /// Ridge lambda relative to the mean input variance: A = G S^T (S S^T +
        /// lambda I)^-1 on centred data, lambda = ridge * trace(S S^T) / d.
        /// 0 gives Eq 5 itself (minimum-norm least squares when S S^T is
        /// singular). Default 1e-6, 1e-4 in float whose normal equations carry
        /// rounding near 1e-6 relative.
        T ridge = default_ridge();
    } linear;
    struct poly2_params {
        /// The same relative ridge, on the monomials x_i and x_i x_j (i <= j)
        /// of the standardised inputs.
        T ridge = default_ridge();
    } poly2;
    struct mlp_params {
        /// Sizes of the tanh hidden layers (one or two); the output layer is linear.
        std::vector<int> hidden = {16};
        /// Weight decay on the weights (not the biases), added to the mean squared error.
        T weight_decay = T(1e-4);
        int max_iterations = 500;
        std::uint64_t seed = 1;
    } mlp;
    struct svr_params {
        /// Box constraint C and tube half-width epsilon, both on standardised outputs.
        T c = T(10);
        T epsilon = T(0.05);
        /// RBF width: K(x, y) = exp(-gamma |x - y|^2) on standardised inputs;
        /// <= 0 picks 1 / (d * variance) = 1 / d.
        T gamma = T(0);
        /// Stop when the maximal KKT violation m(alpha) - M(alpha) is below it.
        T tolerance = T(1e-3);
        /// SMO iterations per output column.
        int max_iterations = 100000;
    } svr;
    /// Optional: called with a stage name, work done and total during long fits.
    std::function<void(const std::string& stage, int done, int total)> progress;
};

/// A regression b_s -> b_g. Fits are deterministic (seeded where random);
/// a failed fit leaves the regressor as it was.
template <class T>
class regressor {
public:
    using matrix = matrix_x<T>;

    virtual ~regressor() = default;

    virtual regressor_kind kind() const = 0;

    /// inputs: n x d, outputs: n x m, rows are samples. Throws
    /// anima::invalid_argument for n = 0, d = 0, m = 0, mismatched rows or a
    /// non-finite value.
    virtual void fit(const matrix& inputs, const matrix& outputs) = 0;

    /// k x d inputs -> k x m outputs. Throws anima::error before fit and
    /// anima::invalid_argument for a wrong column count or a non-finite value.
    virtual matrix predict(const matrix& inputs) const = 0;

    /// Text; the first line is "anima-regressor <kind> 1", values at full
    /// precision. Throws anima::error before fit.
    virtual void save(std::ostream& out) const = 0;

    /// d and m of the last fit; 0 before.
    int input_size() const { return input_size_; }
    int output_size() const { return output_size_; }
    bool fitted() const { return output_size_ > 0; }

protected:
    regressor() = default;
    regressor(const regressor&) = default;
    regressor& operator=(const regressor&) = default;

    /// The checks every fit starts with; function names the caller.
    static void check_fit(const char* function, const matrix& inputs, const matrix& outputs) {
        const std::string f(function);
        if (inputs.rows() == 0) throw invalid_argument(f + ": no samples (inputs has 0 rows)");
        if (inputs.cols() == 0) throw invalid_argument(f + ": inputs has 0 columns");
        if (outputs.cols() == 0) throw invalid_argument(f + ": outputs has 0 columns");
        if (outputs.rows() != inputs.rows())
            throw invalid_argument(f + ": inputs has " + std::to_string(inputs.rows()) + " rows but outputs has " +
                                   std::to_string(outputs.rows()));
        check_finite(f, "inputs", inputs);
        check_finite(f, "outputs", outputs);
    }

    /// The checks every predict starts with.
    void check_predict(const char* function, const matrix& inputs) const {
        const std::string f(function);
        if (!fitted()) throw error(f + ": the regressor has not been fitted");
        if (inputs.cols() != input_size_)
            throw invalid_argument(f + ": inputs has " + std::to_string(inputs.cols()) + " columns, the model takes " +
                                   std::to_string(input_size_));
        check_finite(f, "inputs", inputs);
    }

    /// A prediction, refused when it is not finite (inputs far outside the
    /// training data, outputs near the scalar type's limit).
    static matrix finite_prediction(const char* function, matrix predicted) {
        for (Eigen::Index c = 0; c < predicted.cols(); ++c)
            for (Eigen::Index r = 0; r < predicted.rows(); ++r)
                if (!std::isfinite(static_cast<double>(predicted(r, c))))
                    throw error(std::string(function) + ": the prediction (" + std::to_string(r) + ", " +
                                std::to_string(c) + ") is not finite in this precision");
        return predicted;
    }

    /// The header line and the sizes; throws anima::error before fit.
    void write_header(const char* function, std::ostream& out) const {
        if (!fitted()) throw error(std::string(function) + ": the regressor has not been fitted");
        out << "anima-regressor " << to_string(kind()) << " 1\n";
        out << "sizes " << input_size_ << ' ' << output_size_ << '\n';
    }

    /// Reads the "sizes d m" line that follows the header.
    void read_sizes(detail::regress_reader& in) {
        const std::vector<std::string> t = in.expect("sizes");
        if (t.size() != 2) in.fail("'sizes' takes the input and output sizes");
        const long d = in.parse_count(t[0], "input size"), m = in.parse_count(t[1], "output size");
        if (d == 0 || m == 0) in.fail("'sizes' must be positive");
        input_size_ = static_cast<int>(d);
        output_size_ = static_cast<int>(m);
    }

    void set_sizes(const matrix& inputs, const matrix& outputs) {
        input_size_ = static_cast<int>(inputs.cols());
        output_size_ = static_cast<int>(outputs.cols());
    }

    static void report(const regressor_options<T>& options, const std::string& stage, int done, int total) {
        if (options.progress) options.progress(stage, done, total);
    }

private:
    static void check_finite(const std::string& f, const char* name, const matrix& m) {
        for (Eigen::Index c = 0; c < m.cols(); ++c)
            for (Eigen::Index r = 0; r < m.rows(); ++r)
                if (!std::isfinite(static_cast<double>(m(r, c))))
                    throw invalid_argument(f + ": " + name + "(" + std::to_string(r) + ", " + std::to_string(c) +
                                           ") is not finite");
    }

    int input_size_ = 0;
    int output_size_ = 0;
};

}  // namespace anima
