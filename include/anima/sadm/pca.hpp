// Principal component analysis for few samples of many dimensions (a few
// hundred face images of tens of thousands of pixels): with n samples of
// dimension d, the n x n Gram matrix is decomposed when n <= d and the d x d
// covariance otherwise, so the cost is O(n^2 d + min(n, d)^3). Components are
// kept by retained variance or by count; the eigenvalues stay with the
// model for the +-3 sqrt(lambda) clamp of the parameters (Eq 6).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace anima {

/// How many components a PCA keeps.
template <class T>
struct pca_options {
    /// Keep the fewest leading components whose variance reaches this
    /// fraction of the total (0 < f <= 1). Ignored when `components` > 0.
    T retained_variance = T(0.98);
    /// > 0: keep this many components (fewer when the data has lower rank).
    int components = 0;
};

/// A fitted PCA: x ~ mean + P b, P with orthonormal columns.
template <class T>
class pca {
public:
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    using vector = Eigen::Matrix<T, Eigen::Dynamic, 1>;

    pca() = default;
    /// A PCA from its parts (as read from a file). Throws
    /// anima::invalid_argument when the sizes disagree or a value is not finite.
    pca(vector mean, matrix components, vector eigenvalues, T total_variance)
        : mean_(std::move(mean)), components_(std::move(components)), eigenvalues_(std::move(eigenvalues)),
          total_variance_(total_variance) {
        const std::string who = "anima::pca";
        if (components_.rows() != mean_.size() || components_.cols() != eigenvalues_.size())
            throw invalid_argument(who + ": components are " + std::to_string(components_.rows()) + " x " +
                                   std::to_string(components_.cols()) + " for a mean of " +
                                   std::to_string(mean_.size()) + " and " + std::to_string(eigenvalues_.size()) +
                                   " eigenvalues");
        if (!mean_.allFinite() || !components_.allFinite() || !eigenvalues_.allFinite() ||
            !std::isfinite(total_variance_) || (eigenvalues_.size() && eigenvalues_.minCoeff() < T(0)))
            throw invalid_argument(who + ": the mean, components and eigenvalues must be finite, eigenvalues >= 0");
    }

    /// Fits samples given as rows (n x d). Throws anima::invalid_argument for
    /// no samples, a zero dimension, a non-finite value or bad options.
    template <class Derived>
    static pca fit(const Eigen::MatrixBase<Derived>& samples, const pca_options<T>& options = {}) {
        const std::string who = "anima::pca::fit";
        const Eigen::Index n = samples.rows(), d = samples.cols();
        if (n == 0 || d == 0)
            throw invalid_argument(who + ": needs at least one sample of dimension >= 1, got " + std::to_string(n) +
                                   " x " + std::to_string(d));
        if (options.components < 0)
            throw invalid_argument(who + ": options.components must be >= 0, got " + std::to_string(options.components));
        if (options.components == 0 && !(options.retained_variance > T(0) && options.retained_variance <= T(1)))
            throw invalid_argument(who + ": options.retained_variance must be in (0, 1], got " +
                                   detail::argument_text(options.retained_variance));
        for (Eigen::Index j = 0; j < d; ++j)
            for (Eigen::Index i = 0; i < n; ++i)
                if (!std::isfinite(static_cast<double>(samples(i, j))))
                    throw invalid_argument(who + ": sample " + std::to_string(i) + ", element " + std::to_string(j) +
                                           " is not finite");
        pca out;
        out.mean_ = samples.colwise().mean().transpose().template cast<T>();
        const matrix centred = samples.template cast<T>().rowwise() - out.mean_.transpose();
        // Sample covariance (divide by n - 1); a single sample has no variance.
        const T denom = n > 1 ? static_cast<T>(n - 1) : T(1);
        // Before the eigensolver, which would meet infinite entries.
        out.total_variance_ = centred.squaredNorm() / denom;
        if (!std::isfinite(out.total_variance_))
            throw invalid_argument(who + ": the samples' squared spread overflows in this precision (largest |value| " +
                                   detail::argument_text(samples.template cast<T>().cwiseAbs().maxCoeff()) +
                                   "): scale them down");
        matrix basis;  // d x r, unit columns, descending variance
        vector values;
        if (n <= d) {
            const matrix gram = centred * centred.transpose();
            Eigen::SelfAdjointEigenSolver<matrix> eig(gram);
            values = eig.eigenvalues().reverse();
            const matrix u = eig.eigenvectors().rowwise().reverse();
            basis = centred.transpose() * u;
            for (Eigen::Index k = 0; k < basis.cols(); ++k) {
                const T norm = basis.col(k).norm();
                if (norm > T(0)) basis.col(k) /= norm;
            }
        } else {
            const matrix cov = centred.transpose() * centred;
            Eigen::SelfAdjointEigenSolver<matrix> eig(cov);
            values = eig.eigenvalues().reverse();
            basis = eig.eigenvectors().rowwise().reverse();
        }
        // Numerically zero directions carry no information: drop them. Two
        // rounding levels: the eigensolver's, relative to the largest
        // eigenvalue, and centring's, each centred value off by about
        // |value| epsilon, so that samples equal but for rounding give no
        // components while a spread of 1e-3 about an offset of 1e6 is kept.
        const T eps = Eigen::NumTraits<T>::epsilon();
        const T size = static_cast<T>(std::max(n, d));
        const T largest = values.size() ? std::max(values(0), T(0)) : T(0);
        const T centring = samples.template cast<T>().cwiseAbs().maxCoeff() * eps * size;
        const T floor = std::max(largest * size * eps, static_cast<T>(n) * static_cast<T>(d) * centring * centring);
        Eigen::Index rank = 0;
        while (rank < values.size() && values(rank) > floor && values(rank) > T(0)) ++rank;
        Eigen::Index keep = rank;
        if (options.components > 0) {
            keep = std::min<Eigen::Index>(rank, options.components);
        } else {
            const T target = options.retained_variance * values.head(rank).sum();
            T sum = 0;
            keep = 0;
            while (keep < rank && sum < target * (T(1) - Eigen::NumTraits<T>::epsilon())) sum += values(keep++);
        }
        out.components_ = basis.leftCols(keep);
        out.eigenvalues_ = values.head(keep) / denom;
        // A deterministic sign: each component's largest-magnitude entry is positive.
        for (Eigen::Index k = 0; k < keep; ++k) {
            Eigen::Index at = 0;
            out.components_.col(k).cwiseAbs().maxCoeff(&at);
            if (out.components_(at, k) < T(0)) out.components_.col(k) *= T(-1);
        }
        return out;
    }

    Eigen::Index dimension() const noexcept { return mean_.size(); }
    Eigen::Index size() const noexcept { return components_.cols(); }  ///< number of components
    const vector& mean() const noexcept { return mean_; }
    const matrix& components() const noexcept { return components_; }  ///< d x k, orthonormal columns
    const vector& eigenvalues() const noexcept { return eigenvalues_; }  ///< variance along each component
    /// Variance of the data over all directions (trace of the covariance).
    T total_variance() const noexcept { return total_variance_; }
    /// The fraction of the total variance the kept components explain (1 for constant data).
    T explained_fraction() const noexcept {
        return total_variance_ > T(0) ? eigenvalues_.sum() / total_variance_ : T(1);
    }

    /// b = P^T (x - mean). Throws anima::invalid_argument for a wrong size.
    template <class Derived>
    vector project(const Eigen::MatrixBase<Derived>& x) const {
        check_size(x.size(), dimension(), "anima::pca::project", "x");
        return components_.transpose() * (x.template cast<T>() - mean_);
    }

    /// Every row projected: n x k. Throws anima::invalid_argument for a wrong width.
    template <class Derived>
    matrix project_rows(const Eigen::MatrixBase<Derived>& rows) const {
        check_size(rows.cols(), dimension(), "anima::pca::project_rows", "the rows' width");
        return (rows.template cast<T>().rowwise() - mean_.transpose()) * components_;
    }

    /// x = mean + P b. Throws anima::invalid_argument for a wrong size.
    template <class Derived>
    vector reconstruct(const Eigen::MatrixBase<Derived>& b) const {
        check_size(b.size(), size(), "anima::pca::reconstruct", "b");
        return mean_ + components_ * b.template cast<T>();
    }

    /// Eq 6: every b_i limited to +-limit sqrt(lambda_i) (limit 3 in the
    /// paper). A NaN parameter becomes 0 (the mean). Throws
    /// anima::invalid_argument for a wrong size or a negative limit.
    template <class Derived>
    vector clamp(const Eigen::MatrixBase<Derived>& b, T limit = T(3)) const {
        check_size(b.size(), size(), "anima::pca::clamp", "b");
        if (!(limit >= T(0)))
            throw invalid_argument("anima::pca::clamp: limit must be >= 0, got " +
                                   detail::argument_text(limit));
        vector out(b.size());
        for (Eigen::Index i = 0; i < b.size(); ++i) {
            const T bound = limit * std::sqrt(eigenvalues_(i));
            const T v = static_cast<T>(b(i));
            out(i) = std::isnan(v) ? T(0) : std::clamp(v, -bound, bound);
        }
        return out;
    }

private:
    static void check_size(Eigen::Index got, Eigen::Index expected, const char* who, const char* what) {
        if (got != expected)
            throw invalid_argument(std::string(who) + ": " + what + " has size " + std::to_string(got) + ", expected " +
                                   std::to_string(expected));
    }

    vector mean_;
    matrix components_;
    vector eigenvalues_;
    T total_variance_ = 0;
};

}  // namespace anima
