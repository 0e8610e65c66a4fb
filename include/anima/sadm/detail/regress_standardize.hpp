// Per-column standardisation (x - mean) / scale, kept with a model so that
// prediction applies exactly what training did. A constant column keeps
// scale 1: it carries no information and must not divide by zero.
#pragma once

#include <anima/sadm/detail/regress_io.hpp>

#include <Eigen/Core>

#include <cmath>
#include <ostream>
#include <string>

namespace anima::detail {

template <class T>
struct regress_standardizer {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    using row = Eigen::Matrix<T, 1, Eigen::Dynamic>;

    row mean;
    row scale;

    /// Column means and (population) standard deviations of m (m.rows() > 0).
    static regress_standardizer fit(const matrix& m) {
        regress_standardizer s;
        s.mean = m.colwise().mean();
        s.scale.resize(m.cols());
        for (Eigen::Index c = 0; c < m.cols(); ++c) {
            const T sd = std::sqrt((m.col(c).array() - s.mean(c)).square().mean());
            s.scale(c) = sd > T(0) ? sd : T(1);
        }
        return s;
    }

    matrix apply(const matrix& m) const {
        return ((m.rowwise() - mean).array().rowwise() / scale.array()).matrix();
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
            if (!(s.scale(c) > T(0))) in.fail("'" + key + "_scale' must be positive");
        return s;
    }
};

}  // namespace anima::detail
