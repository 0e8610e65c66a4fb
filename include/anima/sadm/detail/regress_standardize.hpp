// Per-column standardisation (x - mean) / scale, kept with a model so that
// prediction applies exactly what training did. A constant column (spread
// within rounding of its values) gets scale 0: apply only centres it, and
// invert maps anything back to the constant, so a model predicts a constant
// output exactly instead of amplifying rounding noise.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/sadm/detail/regress_io.hpp>

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <ostream>
#include <string>

namespace anima::detail {

template <class T>
struct regress_standardizer {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    using row = Eigen::Matrix<T, 1, Eigen::Dynamic>;

    row mean;
    row scale;

    /// Column means and (population) standard deviations of m (m.rows() > 0,
    /// finite). Each column is divided by its largest magnitude first: the
    /// squares of float values near 1e19 overflow (scale inf, predictions
    /// NaN), and those of tiny values underflow to a spread of 0.
    static regress_standardizer fit(const matrix& m) {
        regress_standardizer s;
        s.mean.resize(m.cols());
        s.scale.resize(m.cols());
        for (Eigen::Index c = 0; c < m.cols(); ++c) {
            // By a power of two, so that ordinary columns get the same mean
            // and deviation, bit for bit, as without the division.
            int e = 0;
            std::frexp(m.col(c).cwiseAbs().maxCoeff(), &e);
            const auto unit = (m.col(c).array() * std::ldexp(T(1), -e)).eval();
            const T unit_mean = unit.mean();
            const T sd = std::sqrt((unit - unit_mean).square().mean());
            s.mean(c) = std::ldexp(unit_mean, e);
            s.scale(c) = sd > T(16) * std::numeric_limits<T>::epsilon() ? std::ldexp(sd, e) : T(0);
        }
        return s;
    }

    matrix apply(const matrix& m) const {
        const row divisor = (scale.array() > T(0)).select(scale, row::Ones(scale.size()));
        return ((m.rowwise() - mean).array().rowwise() / divisor.array()).matrix();
    }

    /// apply(m), refused when centring overflows (a column spanning more
    /// than the scalar type holds, such as -3e38 and 3e38 in float).
    matrix apply_checked(const matrix& m, const std::string& who, const char* name) const {
        matrix out = apply(m);
        for (Eigen::Index c = 0; c < out.cols(); ++c)
            if (!out.col(c).allFinite())
                throw invalid_argument(who + ": " + name + " column " + std::to_string(c) +
                                       " spans more than the scalar type holds once centred (mean " +
                                       argument_text(mean(c)) + ")");
        return out;
    }

    matrix invert(const matrix& m) const {
        return ((m.array().rowwise() * scale.array()).matrix().rowwise() + mean);
    }

    void write(std::ostream& out, const std::string& key) const {
        write_regress_values(out, (key + "_mean").c_str(), mean);
        write_regress_values(out, (key + "_scale").c_str(), scale);
    }

    static regress_standardizer read(regress_reader& in, const std::string& key, Eigen::Index size) {
        regress_standardizer s;
        s.mean = in.read_values<T>((key + "_mean").c_str(), size);
        s.scale = in.read_values<T>((key + "_scale").c_str(), size);
        for (Eigen::Index c = 0; c < size; ++c)
            if (s.scale(c) < T(0)) in.fail("'" + key + "_scale' must not be negative");
        return s;
    }
};

}  // namespace anima::detail
