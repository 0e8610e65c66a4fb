// A rectangular self-organising map (Kohonen) over column vectors: nodes on
// a rows x cols grid pull toward each sample's best-matching node with a
// Gaussian neighbourhood whose radius and learning rate shrink
// exponentially over the epochs.
#pragma once

#include <anima/core/random.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

namespace anima::detail {

template <class T>
using som_matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

/// Index of the column of `nodes` nearest to x (squared Euclidean).
template <class T, class V>
Eigen::Index nearest_column(const som_matrix<T>& nodes, const V& x) {
    Eigen::Index best = 0;
    T dist = std::numeric_limits<T>::infinity();
    for (Eigen::Index k = 0; k < nodes.cols(); ++k) {
        const T d = (nodes.col(k) - x).squaredNorm();
        if (d < dist) {
            dist = d;
            best = k;
        }
    }
    return best;
}

/// Trains rows x cols nodes on the samples (columns) and returns them (one
/// column per node, node (r, c) at column r * cols + c). Nodes start at
/// distinct random samples (repeated when there are fewer samples).
template <class T>
som_matrix<T> train_som(const som_matrix<T>& samples, int rows, int cols, int epochs, T rate0, T radius0,
                        std::uint64_t seed) {
    const Eigen::Index n = samples.cols(), k = static_cast<Eigen::Index>(rows) * cols;
    random_source rng(seed);
    std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), Eigen::Index(0));
    for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);
    som_matrix<T> nodes(samples.rows(), k);
    for (Eigen::Index i = 0; i < k; ++i) nodes.col(i) = samples.col(order[static_cast<std::size_t>(i % n)]);

    const long total = static_cast<long>(epochs) * n;
    const T final_radius = T(0.5), final_rate = T(0.01) * rate0;
    long step = 0;
    for (int e = 0; e < epochs; ++e) {
        for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);
        for (Eigen::Index s : order) {
            const T t = total > 1 ? static_cast<T>(step) / static_cast<T>(total - 1) : T(1);
            ++step;
            const T rate = rate0 * std::pow(final_rate / rate0, t);
            const T radius = radius0 > final_radius ? radius0 * std::pow(final_radius / radius0, t) : radius0;
            const Eigen::Index b = nearest_column<T>(nodes, samples.col(s));
            const int br = static_cast<int>(b) / cols, bc = static_cast<int>(b) % cols;
            for (Eigen::Index i = 0; i < k; ++i) {
                const int dr = static_cast<int>(i) / cols - br, dc = static_cast<int>(i) % cols - bc;
                const T d2 = static_cast<T>(dr * dr + dc * dc);
                const T h = std::exp(-d2 / (T(2) * radius * radius));
                if (h < T(1e-4)) continue;
                nodes.col(i) += rate * h * (samples.col(s) - nodes.col(i));
            }
        }
    }
    return nodes;
}

}  // namespace anima::detail
