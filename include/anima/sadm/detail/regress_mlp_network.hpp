// The feed-forward network of the MLP mapping: tanh hidden layers and a
// linear output layer, its parameters packed into one vector for the
// optimiser (per layer: W column-major, then b), and the training objective
//   L = 1/(2n) sum_i |f(x_i) - y_i|^2 + decay/2 sum_l |W_l|^2
// with its gradient by back-propagation. Samples are columns inside: one
// matrix product per layer for the whole batch.
#pragma once

#include <anima/core/random.hpp>
#include <anima/core/eigen_types.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <vector>

namespace anima::detail {

template <class T>
struct mlp_network {
    std::vector<int> sizes;  ///< input, hidden..., output
    std::vector<matrix_x<T>> weights;
    std::vector<vector_x<T>> biases;

    std::size_t layers() const { return weights.size(); }

    static Eigen::Index parameter_count(const std::vector<int>& sizes) {
        Eigen::Index count = 0;
        for (std::size_t l = 0; l + 1 < sizes.size(); ++l) count += Eigen::Index(sizes[l + 1]) * (sizes[l] + 1);
        return count;
    }

    /// Zero biases and Xavier-uniform weights, U(-r, r) with r = sqrt(6 / (in + out)).
    static mlp_network initial(const std::vector<int>& sizes, std::uint64_t seed) {
        random_source rng(seed);
        mlp_network net;
        net.sizes = sizes;
        for (std::size_t l = 0; l + 1 < sizes.size(); ++l) {
            const double r = std::sqrt(6.0 / double(sizes[l] + sizes[l + 1]));
            matrix_x<T> w(sizes[l + 1], sizes[l]);
            for (Eigen::Index c = 0; c < w.cols(); ++c)
                for (Eigen::Index i = 0; i < w.rows(); ++i) w(i, c) = static_cast<T>(r * (2 * rng.uniform() - 1));
            net.weights.push_back(std::move(w));
            net.biases.push_back(vector_x<T>::Zero(sizes[l + 1]));
        }
        return net;
    }

    vector_x<T> pack() const {
        vector_x<T> theta(parameter_count(sizes));
        Eigen::Index k = 0;
        for (std::size_t l = 0; l < layers(); ++l) {
            theta.segment(k, weights[l].size()) = Eigen::Map<const vector_x<T>>(weights[l].data(), weights[l].size());
            k += weights[l].size();
            theta.segment(k, biases[l].size()) = biases[l];
            k += biases[l].size();
        }
        return theta;
    }

    void unpack(const vector_x<T>& theta) {
        Eigen::Index k = 0;
        for (std::size_t l = 0; l < layers(); ++l) {
            Eigen::Map<vector_x<T>>(weights[l].data(), weights[l].size()) = theta.segment(k, weights[l].size());
            k += weights[l].size();
            biases[l] = theta.segment(k, biases[l].size());
            k += biases[l].size();
        }
    }

    /// The activations of every layer for inputs as columns (d x n); the last is the output.
    std::vector<matrix_x<T>> activations(const matrix_x<T>& columns) const {
        std::vector<matrix_x<T>> a;
        a.reserve(layers() + 1);
        a.push_back(columns);
        for (std::size_t l = 0; l < layers(); ++l) {
            matrix_x<T> z = weights[l] * a.back();
            z.colwise() += biases[l];
            if (l + 1 < layers()) z = z.array().tanh().matrix();
            a.push_back(std::move(z));
        }
        return a;
    }

    /// Outputs (n x m) for inputs as rows (n x d).
    matrix_x<T> evaluate(const matrix_x<T>& rows) const { return activations(rows.transpose()).back().transpose(); }
};

/// The training objective over packed parameters, callable by bfgs_minimize.
template <class T>
class mlp_objective {
public:
    /// inputs: n x d, targets: n x m, both as rows; layout gives the sizes.
    mlp_objective(const mlp_network<T>& layout, const matrix_x<T>& inputs, const matrix_x<T>& targets, T decay)
        : net_(layout), x_(inputs.transpose()), y_(targets.transpose()), decay_(decay) {}

    /// L(theta); writes dL/dtheta into gradient (sized by the caller).
    T operator()(const vector_x<T>& theta, vector_x<T>& gradient) {
        net_.unpack(theta);
        const std::vector<matrix_x<T>> a = net_.activations(x_);
        const T n = static_cast<T>(x_.cols());
        matrix_x<T> delta = (a.back() - y_) / n;
        T value = (a.back() - y_).squaredNorm() / (T(2) * n);
        // Walk the layers backwards; the gradient has the packing order.
        std::vector<Eigen::Index> offsets(net_.layers());
        Eigen::Index k = 0;
        for (std::size_t l = 0; l < net_.layers(); ++l) {
            offsets[l] = k;
            k += net_.weights[l].size() + net_.biases[l].size();
        }
        for (std::size_t l = net_.layers(); l-- > 0;) {
            const matrix_x<T>& w = net_.weights[l];
            value += decay_ / T(2) * w.squaredNorm();
            const matrix_x<T> gw = delta * a[l].transpose() + decay_ * w;
            gradient.segment(offsets[l], w.size()) = Eigen::Map<const vector_x<T>>(gw.data(), gw.size());
            gradient.segment(offsets[l] + w.size(), w.rows()) = delta.rowwise().sum();
            if (l > 0) delta = ((w.transpose() * delta).array() * (T(1) - a[l].array().square())).matrix();
        }
        return value;
    }

    /// L(theta) alone.
    T value(const vector_x<T>& theta) {
        vector_x<T> g(theta.size());
        return (*this)(theta, g);
    }

private:
    mlp_network<T> net_;
    matrix_x<T> x_, y_;
    T decay_;
};

}  // namespace anima::detail
