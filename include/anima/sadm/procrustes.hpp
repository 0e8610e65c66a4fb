// Similarity alignment of landmark sets (Procrustes) and generalised
// Procrustes analysis: every shape is rotated, scaled and translated onto a
// common mean, which is re-estimated until it settles. Rotations are proper
// (no reflection), so a mirrored face stays a different shape.
#pragma once

#include <anima/core/error.hpp>
#include <anima/sadm/landmarks.hpp>

#include <Eigen/Core>

#include <cmath>
#include <string>
#include <vector>

namespace anima {

/// x -> scale * R(angle) x + translation, R a proper 2-D rotation.
template <class T>
struct similarity2 {
    T scale = T(1);
    T angle = T(0);  ///< radians, counter-clockwise for y up (clockwise on screen, y down)
    Eigen::Matrix<T, 1, 2> translation = Eigen::Matrix<T, 1, 2>::Zero();

    Eigen::Matrix<T, 2, 2> linear() const {
        const T c = scale * std::cos(angle), s = scale * std::sin(angle);
        Eigen::Matrix<T, 2, 2> m;
        m << c, -s, s, c;
        return m;
    }
    landmark_set<T> apply(const landmark_set<T>& points) const {
        return (points * linear().transpose()).rowwise() + translation;
    }
    /// The map that undoes this one (scale must be non-zero).
    similarity2 inverse() const {
        similarity2 inv;
        inv.scale = T(1) / scale;
        inv.angle = -angle;
        inv.translation = -(translation * inv.linear().transpose());
        return inv;
    }
};

/// The similarity that takes `source` closest to `target` in the least-squares
/// sense (sum of squared point distances). Throws anima::invalid_argument for
/// sets of different sizes, fewer than two points, non-finite values or a
/// source whose points all coincide.
template <class T>
similarity2<T> align_similarity(const landmark_set<T>& source, const landmark_set<T>& target) {
    const std::string who = "anima::align_similarity";
    if (source.rows() != target.rows() || source.rows() < 2)
        throw invalid_argument(who + ": needs two sets of the same size >= 2, got " + std::to_string(source.rows()) +
                               " and " + std::to_string(target.rows()) + " points");
    check_finite_landmarks(source, who, "source point");
    check_finite_landmarks(target, who, "target point");
    const Eigen::Matrix<T, 1, 2> cs = source.colwise().mean(), ct = target.colwise().mean();
    const landmark_set<T> a = source.rowwise() - cs, b = target.rowwise() - ct;
    const T norm2 = a.squaredNorm();
    if (!(norm2 > T(0)))
        throw invalid_argument(who + ": the source's " + std::to_string(source.rows()) +
                               " points all coincide; no rotation or scale is defined");
    // For x' = s R x: minimise sum |s R a_k - b_k|^2. With dot = sum a.b and
    // cross = sum a x b the optimum angle is atan2(cross, dot), s = hypot / |a|^2.
    const T dot = (a.array() * b.array()).sum();
    const T cross = (a.col(0).array() * b.col(1).array() - a.col(1).array() * b.col(0).array()).sum();
    similarity2<T> t;
    t.angle = std::atan2(cross, dot);
    t.scale = std::hypot(dot, cross) / norm2;
    t.translation = ct - cs * t.linear().transpose();
    return t;
}

/// Settings of generalised_procrustes.
template <class T>
struct procrustes_params {
    int max_iterations = 100;
    /// Stop when the mean moves less than this (root-mean-square per point, unit-size mean).
    T tolerance = Eigen::NumTraits<T>::epsilon() * T(100);
};

/// What generalised_procrustes returns.
template <class T>
struct procrustes_result {
    landmark_set<T> mean;                 ///< centred at 0, unit centroid size (Frobenius norm 1)
    std::vector<landmark_set<T>> aligned;  ///< each input mapped onto the mean
    std::vector<similarity2<T>> transforms;  ///< input k -> aligned[k]
    int iterations = 0;
    bool converged = false;
};

/// Generalised Procrustes analysis. The mean starts as the first shape
/// (centred, unit size) and keeps its orientation: every re-estimated mean is
/// aligned back to the previous one before normalising, so the result does
/// not drift. Throws anima::invalid_argument for no shapes, shapes of
/// different sizes, degenerate shapes (see align_similarity) or bad params.
template <class T>
procrustes_result<T> generalized_procrustes(const std::vector<landmark_set<T>>& shapes,
                                            const procrustes_params<T>& params = {}) {
    const std::string who = "anima::generalized_procrustes";
    if (shapes.empty()) throw invalid_argument(who + ": no shapes");
    if (params.max_iterations < 1)
        throw invalid_argument(who + ": max_iterations must be >= 1, got " + std::to_string(params.max_iterations));
    for (std::size_t k = 0; k < shapes.size(); ++k)
        if (shapes[k].rows() != shapes[0].rows())
            throw invalid_argument(who + ": shape " + std::to_string(k) + " has " + std::to_string(shapes[k].rows()) +
                                   " points, shape 0 has " + std::to_string(shapes[0].rows()));
    const auto normalise = [&](const landmark_set<T>& s) -> landmark_set<T> {
        const landmark_set<T> c = s.rowwise() - s.colwise().mean();
        const T n = c.norm();
        if (!(n > T(0))) throw invalid_argument(who + ": a shape's points all coincide");
        return c / n;
    };
    procrustes_result<T> r;
    r.mean = normalise(shapes[0]);
    r.aligned.resize(shapes.size());
    r.transforms.resize(shapes.size());
    const T points = static_cast<T>(shapes[0].rows());
    for (r.iterations = 1; r.iterations <= params.max_iterations; ++r.iterations) {
        landmark_set<T> sum = landmark_set<T>::Zero(shapes[0].rows(), 2);
        for (std::size_t k = 0; k < shapes.size(); ++k) {
            r.transforms[k] = align_similarity(shapes[k], r.mean);
            r.aligned[k] = r.transforms[k].apply(shapes[k]);
            sum += r.aligned[k];
        }
        // Keep the previous mean's orientation and scale fixed: align, then normalise.
        landmark_set<T> next = normalise(sum);
        next = normalise(align_similarity(next, r.mean).apply(next));
        const T change = (next - r.mean).norm() / std::sqrt(points);
        r.mean = next;
        if (change <= params.tolerance) {
            r.converged = true;
            break;
        }
    }
    if (r.iterations > params.max_iterations) r.iterations = params.max_iterations;
    // The last alignment is against the final mean.
    for (std::size_t k = 0; k < shapes.size(); ++k) {
        r.transforms[k] = align_similarity(shapes[k], r.mean);
        r.aligned[k] = r.transforms[k].apply(shapes[k]);
    }
    return r;
}

}  // namespace anima
