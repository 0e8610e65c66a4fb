// Shared by the SADM tests: random matrices and landmark sets, a synthetic
// face-like shape family and its rendering.
#pragma once

#include "../test_support.hpp"

#include <anima/core/random.hpp>
#include <anima/sadm/landmarks.hpp>

#include <Eigen/Core>

#include <cmath>

namespace sadm_test {

using namespace anima_test;

template <class T>
using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
template <class T>
using vector = Eigen::Matrix<T, Eigen::Dynamic, 1>;

template <class T>
matrix<T> random_matrix(anima::random_source& rng, Eigen::Index rows, Eigen::Index cols, double scale = 1) {
    matrix<T> m(rows, cols);
    for (Eigen::Index c = 0; c < cols; ++c)
        for (Eigen::Index r = 0; r < rows; ++r) m(r, c) = static_cast<T>(scale * (2 * rng.uniform() - 1));
    return m;
}

template <class T>
anima::landmark_set<T> random_points(anima::random_source& rng, Eigen::Index n, double scale = 10) {
    return random_matrix<T>(rng, n, 2, scale);
}

/// A standard normal sample (Box-Muller).
inline double gaussian(anima::random_source& rng) {
    const double u = 1.0 - rng.uniform(), v = rng.uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586 * v);
}

}  // namespace sadm_test
