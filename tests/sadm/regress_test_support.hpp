// Data for the regressor tests: seeded random matrices with the uneven
// column scales of PCA parameters, and a save/load round trip.
#pragma once

#include "../test_support.hpp"

#include <anima/core/random.hpp>
#include <anima/sadm/regressor.hpp>

#include <Eigen/Core>

#include <memory>
#include <sstream>
#include <string>

namespace regress_test {

using namespace anima_test;

template <class T>
using matrix = anima::matrix_x<T>;

/// Uniform in [-scale, scale) per entry, column c additionally scaled by
/// 1 / (1 + c) like the falling standard deviations of PCA parameters.
template <class T>
matrix<T> random_matrix(anima::random_source& rng, Eigen::Index rows, Eigen::Index cols, double scale = 1,
                        bool pca_like = false) {
    matrix<T> m(rows, cols);
    for (Eigen::Index c = 0; c < cols; ++c) {
        const double s = pca_like ? scale / static_cast<double>(1 + c) : scale;
        for (Eigen::Index r = 0; r < rows; ++r) m(r, c) = static_cast<T>(s * (2 * rng.uniform() - 1));
    }
    return m;
}

/// The largest absolute difference, relative to max(1, largest |b|).
template <class T>
double relative_difference(const matrix<T>& a, const matrix<T>& b) {
    const double scale = std::max(1.0, static_cast<double>(b.cwiseAbs().maxCoeff()));
    return static_cast<double>((a - b).cwiseAbs().maxCoeff()) / scale;
}

/// Saves r and loads it back through the common entry point.
template <class T>
std::unique_ptr<anima::regressor<T>> round_trip(const anima::regressor<T>& r, std::string* text = nullptr) {
    std::stringstream s;
    r.save(s);
    if (text) *text = s.str();
    return anima::load_regressor<T>(s, "model.txt");
}

/// The message of the anima::parse_error thrown by loading text ("" if none).
template <class T>
std::string load_error(const std::string& text) {
    std::istringstream in(text);
    try {
        anima::load_regressor<T>(in, "model.txt");
    } catch (const anima::parse_error& e) {
        return e.what();
    }
    return "";
}

}  // namespace regress_test
