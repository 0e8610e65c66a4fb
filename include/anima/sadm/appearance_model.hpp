// The grey-level model of Eq 2: g = g_mean + P_g b_g, a PCA of face images
// warped to a reference shape (the mean shape, in pixels) by the
// piecewise-affine warp over its Delaunay triangulation. g holds the grey
// levels of the reference raster's pixels inside the triangles (the face
// mask), in scan-line order.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/sadm/delaunay.hpp>
#include <anima/sadm/landmarks.hpp>
#include <anima/sadm/pca.hpp>
#include <anima/sadm/piecewise_affine_warp.hpp>

#include <Eigen/Core>

#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace anima {

/// Settings of grey_model::fit.
template <class T>
struct grey_model_options {
    pca_options<T> pca{T(0.98), 0};
    /// Called after each image is warped (done, total): the slow part of training.
    std::function<void(int, int)> progress;
};

template <class T>
class grey_model {
public:
    using vector = Eigen::Matrix<T, Eigen::Dynamic, 1>;
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

    grey_model() = default;

    /// A model on a rows x cols reference raster where `reference` (pixels)
    /// and its triangles define the face; `model` must have one dimension per
    /// covered pixel. Throws anima::invalid_argument otherwise.
    grey_model(landmark_set<T> reference, std::vector<triangle_indices> triangles, Eigen::Index rows,
               Eigen::Index cols, pca<T> model)
        : reference_(std::move(reference)), triangles_(std::move(triangles)), pca_(std::move(model)) {
        raster_ = rasterize_triangles(reference_, triangles_, rows, cols);
        if (static_cast<Eigen::Index>(raster_.size()) != pca_.dimension())
            throw invalid_argument("anima::grey_model: the reference covers " + std::to_string(raster_.size()) +
                                   " pixels, the PCA has dimension " + std::to_string(pca_.dimension()));
    }

    /// The reference frame for a mean shape (any pose and size): scaled by
    /// `scale` pixels per unit, rotated and placed so that the shape sits one
    /// pixel inside the raster, which is returned through rows and cols.
    static landmark_set<T> place_reference(const landmark_set<T>& mean, T scale, Eigen::Index& rows, Eigen::Index& cols) {
        check_positive("anima::grey_model::place_reference", "scale", scale);
        landmark_set<T> r = mean * scale;
        const Eigen::Matrix<T, 1, 2> shift = Eigen::Matrix<T, 1, 2>::Constant(T(1)) - r.colwise().minCoeff();
        r.rowwise() += shift;
        cols = static_cast<Eigen::Index>(std::ceil(r.col(0).maxCoeff())) + 2;
        rows = static_cast<Eigen::Index>(std::ceil(r.col(1).maxCoeff())) + 2;
        return r;
    }

    /// Warps every image (grey levels, rows = y) from its landmarks onto the
    /// reference shape and fits the PCA. Throws anima::invalid_argument for
    /// no images, counts that differ, a landmark set of the wrong size or an
    /// empty image.
    template <class Image>
    static grey_model fit(const std::vector<Image>& images, const std::vector<landmark_set<T>>& landmarks,
                          const landmark_set<T>& reference, Eigen::Index rows, Eigen::Index cols,
                          const grey_model_options<T>& options = {}) {
        const std::string who = "anima::grey_model::fit";
        if (images.empty() || images.size() != landmarks.size())
            throw invalid_argument(who + ": needs one landmark set per image and at least one image, got " +
                                   std::to_string(images.size()) + " images and " + std::to_string(landmarks.size()) +
                                   " landmark sets");
        grey_model m;
        m.reference_ = reference;
        m.triangles_ = delaunay_triangulation(reference);
        m.raster_ = rasterize_triangles(reference, m.triangles_, rows, cols);
        matrix samples(static_cast<Eigen::Index>(images.size()), static_cast<Eigen::Index>(m.raster_.size()));
        for (std::size_t k = 0; k < images.size(); ++k) {
            if (landmarks[k].rows() != reference.rows())
                throw invalid_argument(who + ": landmark set " + std::to_string(k) + " has " +
                                       std::to_string(landmarks[k].rows()) + " points, the reference " +
                                       std::to_string(reference.rows()));
            samples.row(static_cast<Eigen::Index>(k)) = m.sample(images[k], landmarks[k]).transpose();
            if (options.progress) options.progress(static_cast<int>(k) + 1, static_cast<int>(images.size()));
        }
        m.pca_ = pca<T>::fit(samples, options.pca);
        return m;
    }

    /// g of an image with the given landmarks: its grey levels warped onto the reference.
    template <class Derived>
    vector sample(const Eigen::MatrixBase<Derived>& img, const landmark_set<T>& landmarks) const {
        if (landmarks.rows() != reference_.rows())
            throw invalid_argument("anima::grey_model::sample: the landmark set has " +
                                   std::to_string(landmarks.rows()) + " points, the reference " +
                                   std::to_string(reference_.rows()));
        return sample_warped(raster_, triangles_, landmarks, img);
    }

    vector parameters(const vector& g) const { return pca_.project(g); }   ///< b_g of Eq 2
    vector grey_levels(const vector& b) const { return pca_.reconstruct(b); }  ///< g of Eq 2

    /// g as an image on the reference raster. Pixels outside the face take
    /// the mean of their face neighbours over `rings` dilation steps (so that
    /// bilinear sampling at the face's edge never mixes in unrelated values),
    /// then g's mean.
    matrix texture(const vector& g, int rings = 2) const {
        if (g.size() != static_cast<Eigen::Index>(raster_.size()))
            throw invalid_argument("anima::grey_model::texture: g has size " + std::to_string(g.size()) +
                                   ", the model " + std::to_string(raster_.size()));
        matrix img = matrix::Zero(raster_.rows, raster_.cols);
        Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> set = raster_.mask();
        for (std::size_t k = 0; k < raster_.size(); ++k) img(raster_.y(k), raster_.x(k)) = g(static_cast<Eigen::Index>(k));
        for (int ring = 0; ring < rings; ++ring) {
            auto next = set;
            for (Eigen::Index y = 0; y < img.rows(); ++y)
                for (Eigen::Index x = 0; x < img.cols(); ++x) {
                    if (set(y, x)) continue;
                    T sum = 0;
                    int count = 0;
                    const auto add = [&](Eigen::Index yy, Eigen::Index xx) {
                        if (yy >= 0 && xx >= 0 && yy < img.rows() && xx < img.cols() && set(yy, xx)) sum += img(yy, xx), ++count;
                    };
                    add(y - 1, x), add(y + 1, x), add(y, x - 1), add(y, x + 1);
                    if (count) img(y, x) = sum / static_cast<T>(count), next(y, x) = true;
                }
            set = next;
        }
        const T fill = g.size() ? g.mean() : T(0);
        for (Eigen::Index y = 0; y < img.rows(); ++y)
            for (Eigen::Index x = 0; x < img.cols(); ++x)
                if (!set(y, x)) img(y, x) = fill;
        return img;
    }

    const pca<T>& model() const noexcept { return pca_; }
    Eigen::Index size() const noexcept { return pca_.size(); }  ///< number of grey parameters
    const landmark_set<T>& reference() const noexcept { return reference_; }
    const std::vector<triangle_indices>& triangles() const noexcept { return triangles_; }
    const triangle_raster<T>& raster() const noexcept { return raster_; }

private:
    landmark_set<T> reference_;
    std::vector<triangle_indices> triangles_;
    triangle_raster<T> raster_;
    pca<T> pca_;
};

}  // namespace anima
