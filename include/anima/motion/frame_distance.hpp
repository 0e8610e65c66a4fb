// Distances between the frames of a clip's DOF matrix (one row per frame):
// the paper's L2 metric (Eq 1) and its Mahalanobis metric (Eq 2).
//
// Eq 2 weighs each DOF by the inverse variance of its velocity, so a joint
// that normally moves fast must differ a lot before two frames count as
// different, while a slow joint (the spine) is compared finely. Eq 1 sums the
// Euclidean norms of per-joint differences; turned into a similarity with
// exp(-d / sigma) it gives video-texture transition probabilities.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/finite_difference.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace anima {

/// Which frame distance to use.
enum class frame_metric : unsigned char {
    mahalanobis,  ///< Eq 2: sum_d (a_d - b_d)^2 / var(dM_d/dt), the default
    l2            ///< Eq 1's distance: sum over joints of ||a_k - b_k||
};

template <>
struct enum_names<frame_metric> {
    static constexpr const char* what = "metric";
    static constexpr enum_entry<frame_metric> entries[] = {{frame_metric::mahalanobis, "mahalanobis"},
                                                           {frame_metric::l2, "l2"}};
};

/// "mahalanobis" or "l2" (any case); throws anima::invalid_argument otherwise.
inline frame_metric parse_frame_metric(std::string_view name) {
    return parse_enum<frame_metric>(name, "anima::parse_frame_metric");
}

template <class T>
struct frame_distance_params {
    frame_metric metric = frame_metric::mahalanobis;
    /// Eq 2: each velocity variance is raised to at least this fraction of the
    /// largest one, so a DOF that never moves (variance 0) gets a finite weight.
    T regularization = T(1e-3);
    /// Eq 1: consecutive DOFs forming one joint (3 for anima's DOF view).
    int block_size = 3;
};

/// A frame distance ready to evaluate: the metric and, for Eq 2, the inverse
/// variances (the diagonal of C^-1).
template <class T>
struct frame_distance {
    frame_metric metric = frame_metric::mahalanobis;
    Eigen::Matrix<T, Eigen::Dynamic, 1> precision;  ///< per DOF, Mahalanobis only
    int block_size = 3;

    /// Distance between two frames given as vectors of the same size.
    template <class A, class B>
    T operator()(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) const {
        const Eigen::Index n = a.size();
        if (metric == frame_metric::mahalanobis) return (a - b).cwiseAbs2().dot(precision);
        T sum = T(0);
        for (Eigen::Index d = 0; d < n; d += block_size) {
            T block = T(0);
            for (Eigen::Index k = d; k < d + block_size; ++k) {
                const T e = a.derived().coeff(k) - b.derived().coeff(k);
                block += e * e;
            }
            sum += std::sqrt(block);
        }
        return sum;
    }
};

namespace detail {
template <class T>
void check_frame_time(T frame_time, const char* function) {
    check_positive(function, "frame time", frame_time);
}

template <class Derived>
void check_finite_dofs(const Eigen::MatrixBase<Derived>& dofs, const char* function) {
    for (Eigen::Index c = 0; c < dofs.cols(); ++c)
        for (Eigen::Index r = 0; r < dofs.rows(); ++r)
            if (!std::isfinite(static_cast<double>(dofs(r, c))))
                throw invalid_argument(std::string(function) + ": non-finite DOF value at frame " + std::to_string(r) +
                                       ", column " + std::to_string(c));
}

// velocity_precision after its arguments were checked, over `parts`
// motions of `cols` DOFs (part(p) gives one, frames x DOFs): each part's
// velocity is its own time derivative, the variance is over the frames of
// all of them together (a pooled variance: no velocity across the end of
// one part and the start of the next).
template <class T, class PartOf>
Eigen::Matrix<T, Eigen::Dynamic, 1> velocity_precision(std::size_t parts, Eigen::Index cols, T frame_time,
                                                      T regularization, const PartOf& part) {
    Eigen::Matrix<T, Eigen::Dynamic, 1> precision = Eigen::Matrix<T, Eigen::Dynamic, 1>::Ones(cols);
    std::size_t samples = 0;
    for (std::size_t p = 0; p < parts; ++p)
        if (part(p).rows() >= 2) samples += static_cast<std::size_t>(part(p).rows());
    if (samples < 2) return precision;
    // One column at a time: the whole velocity matrix would double the
    // memory a long clip needs.
    Eigen::Matrix<T, Eigen::Dynamic, 1> variance(cols), velocity(static_cast<Eigen::Index>(samples));
    for (Eigen::Index d = 0; d < cols; ++d) {
        Eigen::Index at = 0;
        for (std::size_t p = 0; p < parts; ++p) {
            const Eigen::Index n = part(p).rows();
            if (n < 2) continue;
            velocity.segment(at, n) = time_derivative(part(p).col(d), frame_time);
            at += n;
        }
        variance[d] = (velocity.array() - velocity.mean()).square().sum() / static_cast<T>(samples);
        if (!std::isfinite(variance[d]))
            throw invalid_argument("anima::velocity_precision: the velocity variance of column " + std::to_string(d) +
                                   " overflows the scalar type at a frame time of " + detail::argument_text(frame_time) +
                                   " s; scale the DOFs down or lengthen the frame time");
    }
    const T floor = regularization * (variance.size() ? variance.maxCoeff() : T(0));
    // A floor whose inverse overflows is motion below T's resolution.
    if (!(floor > T(0)) || !std::isfinite(T(1) / floor)) return precision;
    for (Eigen::Index d = 0; d < variance.size(); ++d) precision[d] = T(1) / std::max(variance[d], floor);
    return precision;
}

template <class T>
void check_regularization(T regularization, const char* function) {
    if (!(regularization > T(0)) || !(regularization <= T(1)))
        throw invalid_argument(std::string(function) + ": regularization must be in (0, 1], got " +
                               detail::argument_text(regularization));
}
}  // namespace detail

/// The diagonal of Eq 2's C^-1: 1 / max(var_d, regularization * max_d var_d)
/// with var_d the variance over frames (divided by the frame count) of DOF
/// d's velocity, anima::time_derivative. When nothing moves at all, or there
/// are fewer than two frames, every weight is 1 (every distance is then 0
/// anyway). Throws anima::invalid_argument for a regularization outside
/// (0, 1], a bad frame time, a non-finite value or a variance that
/// overflows the scalar type.
template <class Derived>
Eigen::Matrix<typename Derived::Scalar, Eigen::Dynamic, 1> velocity_precision(
    const Eigen::MatrixBase<Derived>& dofs, typename Derived::Scalar frame_time,
    typename Derived::Scalar regularization = typename Derived::Scalar(1e-3)) {
    detail::check_regularization(regularization, "anima::velocity_precision");
    detail::check_frame_time(frame_time, "anima::velocity_precision");
    detail::check_finite_dofs(dofs, "anima::velocity_precision");
    return detail::velocity_precision(1, dofs.cols(), frame_time, regularization,
                                      [&](std::size_t) -> const Derived& { return dofs.derived(); });
}

namespace detail {
// make_frame_distance of `parts` motions of `cols` DOFs (part(p) gives one):
// every argument checked, then Eq 2's weights from their pooled variances.
template <class T, class PartOf>
frame_distance<T> frame_distance_of(std::size_t parts, Eigen::Index cols, T frame_time,
                                    const frame_distance_params<T>& params, const PartOf& part) {
    const char* who = "anima::make_frame_distance";
    check_frame_time(frame_time, who);
    for (std::size_t p = 0; p < parts; ++p) check_finite_dofs(part(p), who);
    frame_distance<T> d;
    d.metric = params.metric;
    d.block_size = params.block_size;
    if (params.metric == frame_metric::l2) {
        if (params.block_size < 1 || cols % params.block_size != 0)
            throw invalid_argument(std::string(who) + ": L2 block size " + std::to_string(params.block_size) +
                                   " does not divide the " + std::to_string(cols) + " DOFs");
        return d;
    }
    check_regularization(params.regularization, who);
    d.precision = velocity_precision(parts, cols, frame_time, params.regularization, part);
    return d;
}
}  // namespace detail

/// The distance of `params.metric` for this DOF matrix (frames x DOFs, e.g.
/// anima::to_dof_matrix or anima::frame_features). Throws
/// anima::invalid_argument for a non-finite value, a bad frame time, a
/// regularization outside (0, 1] (Mahalanobis) or an L2 block size that does
/// not divide the DOF count.
template <class Derived>
frame_distance<typename Derived::Scalar> make_frame_distance(
    const Eigen::MatrixBase<Derived>& dofs, typename Derived::Scalar frame_time,
    const frame_distance_params<typename Derived::Scalar>& params = {}) {
    return detail::frame_distance_of(1, dofs.cols(), frame_time, params,
                                     [&](std::size_t) -> const Derived& { return dofs.derived(); });
}

/// The distance of `params.metric` for frames drawn from several motions
/// (DOF matrices of the same columns, e.g. the frame features of several
/// clips of one skeleton): Eq 2's velocity variances are pooled over all
/// of their frames, each motion's velocity taken within it, so no velocity
/// is taken across the end of one and the start of the next. With one
/// motion it is make_frame_distance of that motion. Throws
/// anima::invalid_argument for no motions, motions of different column
/// counts (naming the first that differs), and everything the one-motion
/// form refuses.
template <class T>
frame_distance<T> make_frame_distance(const std::vector<Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>>& parts,
                                      T frame_time, const frame_distance_params<T>& params = {}) {
    const char* who = "anima::make_frame_distance";
    if (parts.empty()) throw invalid_argument(std::string(who) + ": no motions to take the distance of");
    for (std::size_t p = 1; p < parts.size(); ++p)
        if (parts[p].cols() != parts[0].cols())
            throw invalid_argument(std::string(who) + ": motion " + std::to_string(p) + " has " +
                                   std::to_string(parts[p].cols()) + " DOFs, motion 0 has " +
                                   std::to_string(parts[0].cols()));
    return detail::frame_distance_of(parts.size(), parts[0].cols(), frame_time, params,
                                     [&](std::size_t p) -> const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& {
                                         return parts[p];
                                     });
}

/// The full frames x frames distance matrix (Fig 2 of the paper): O(frames^2)
/// time and memory, for plots and brute-force checks. Symmetry scores need
/// only a band of it (anima::symmetry_scores).
template <class Derived, class T = typename Derived::Scalar>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> distance_matrix(const Eigen::MatrixBase<Derived>& dofs,
                                                                 const frame_distance<T>& distance) {
    if (distance.metric == frame_metric::mahalanobis && distance.precision.size() != dofs.cols())
        throw invalid_argument("anima::distance_matrix: the distance has " + std::to_string(distance.precision.size()) +
                               " DOF weights, the matrix " + std::to_string(dofs.cols()) + " DOFs");
    if (distance.metric == frame_metric::l2 && (distance.block_size < 1 || dofs.cols() % distance.block_size != 0))
        throw invalid_argument("anima::distance_matrix: L2 block size " + std::to_string(distance.block_size) +
                               " does not divide the " + std::to_string(dofs.cols()) + " DOFs");
    // Frames as contiguous columns: each distance reads two of them.
    const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> frames = dofs.transpose();
    const Eigen::Index n = frames.cols();
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> out(n, n);
    for (Eigen::Index j = 0; j < n; ++j) {
        out(j, j) = T(0);
        for (Eigen::Index i = j + 1; i < n; ++i) out(i, j) = out(j, i) = distance(frames.col(i), frames.col(j));
    }
    return out;
}

/// Eq 1: the similarity exp(-distance / sigma) of an L2 distance, in [0, 1]
/// (1 for equal frames; 0 only where the exponential underflows). Throws
/// anima::invalid_argument for a negative or NaN distance or a bad sigma.
template <class T>
T l2_similarity(T distance, T sigma) {
    check_positive("anima::l2_similarity", "sigma", sigma);
    if (!(distance >= T(0)))
        throw invalid_argument("anima::l2_similarity: distance must be >= 0, got " +
                               detail::argument_text(distance));
    return std::exp(-distance / sigma);
}

}  // namespace anima
