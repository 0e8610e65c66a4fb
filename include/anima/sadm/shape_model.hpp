// The shape model of Eq 1: s = s_mean + P_s b_s, a PCA of landmark sets
// aligned by generalised Procrustes. b_s describes a shape without its pose:
// a new landmark set is first aligned to the mean by a similarity.
#pragma once

#include <anima/core/error.hpp>
#include <anima/sadm/landmarks.hpp>
#include <anima/sadm/pca.hpp>
#include <anima/sadm/procrustes.hpp>

#include <Eigen/Core>

#include <string>
#include <utility>
#include <vector>

namespace anima {

/// Settings of shape_model::fit.
template <class T>
struct shape_model_options {
    pca_options<T> pca{T(0.98), 0};
    procrustes_params<T> procrustes{};
};

template <class T>
class shape_model {
public:
    using vector = Eigen::Matrix<T, Eigen::Dynamic, 1>;

    shape_model() = default;
    /// From a PCA of shape vectors (x0, y0, x1, y1, ...) whose mean is the
    /// model's mean shape. Throws anima::invalid_argument for an odd dimension
    /// or a mean with fewer than 3 points.
    explicit shape_model(pca<T> model) : pca_(std::move(model)) {
        if (pca_.dimension() % 2 != 0 || pca_.dimension() < 6)
            throw invalid_argument("anima::shape_model: the PCA's dimension " + std::to_string(pca_.dimension()) +
                                   " is not that of 3 or more 2-D points");
    }

    /// Aligns the shapes (generalised Procrustes) and fits the PCA. Throws
    /// anima::invalid_argument as generalized_procrustes and pca::fit do.
    static shape_model fit(const std::vector<landmark_set<T>>& shapes, const shape_model_options<T>& options = {}) {
        const auto gpa = generalized_procrustes(shapes, options.procrustes);
        Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> rows(static_cast<Eigen::Index>(shapes.size()),
                                                              2 * shapes[0].rows());
        for (std::size_t k = 0; k < shapes.size(); ++k)
            rows.row(static_cast<Eigen::Index>(k)) = to_shape_vector(gpa.aligned[k]).transpose();
        return shape_model(pca<T>::fit(rows, options.pca));
    }

    const pca<T>& model() const noexcept { return pca_; }
    Eigen::Index points() const noexcept { return pca_.dimension() / 2; }
    Eigen::Index size() const noexcept { return pca_.size(); }  ///< number of shape parameters
    landmark_set<T> mean() const { return from_shape_vector(pca_.mean()); }

    /// The similarity that takes `landmarks` onto the model frame (the mean).
    similarity2<T> pose(const landmark_set<T>& landmarks) const {
        check_points(landmarks, "anima::shape_model::pose");
        return align_similarity(landmarks, mean());
    }

    /// b_s of a landmark set (Eq 1 solved for b_s after removing the pose).
    /// Throws anima::invalid_argument for a wrong point count, non-finite
    /// points or points that all coincide.
    vector parameters(const landmark_set<T>& landmarks) const {
        check_points(landmarks, "anima::shape_model::parameters");
        return pca_.project(to_shape_vector(pose(landmarks).apply(landmarks)));
    }

    /// The shape of Eq 1 in the model frame for parameters b_s.
    landmark_set<T> shape(const vector& b) const { return from_shape_vector(pca_.reconstruct(b)); }

private:
    void check_points(const landmark_set<T>& s, const char* who) const {
        if (s.rows() != points())
            throw invalid_argument(std::string(who) + ": the landmark set has " + std::to_string(s.rows()) +
                                   " points, the model " + std::to_string(points()));
    }

    pca<T> pca_;
};

}  // namespace anima
