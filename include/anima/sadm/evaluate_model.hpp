// The paper's evaluation of a trained SADM on held-out frames: for each grey
// parameter, the normalised cross-correlation between the b_g predicted from
// the landmarks and the b_g of the real frame (Table 1); for each frame, the
// PSNR (Eq 7) of the synthesised face against the real frame over the face
// region (Fig 3), optionally with Gaussian noise on the landmarks (Table 2).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/random.hpp>
#include <anima/sadm/evaluation.hpp>
#include <anima/sadm/sadm_model.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace anima {

/// Settings of evaluate_sadm.
template <class T>
struct sadm_evaluation_options {
    T noise = T(0);              ///< standard deviation (pixels) of the noise added to each landmark coordinate
    std::uint64_t seed = 1;      ///< of the noise
    std::function<void(int done, int total)> progress;
};

/// What evaluate_sadm measures.
template <class T>
struct sadm_evaluation {
    std::vector<T> ncc;            ///< per grey parameter: predicted vs real b_g over the frames (Table 1)
    std::vector<T> psnr;           ///< per frame: synthesis vs the real frame over the face region (dB)
    std::vector<T> psnr_model;     ///< per frame: the grey model's own reconstruction (real b_g, real landmarks)
    T psnr_mean = T(0);            ///< mean of psnr (over the finite values; +inf only if all are)
    T psnr_model_mean = T(0);
};

namespace detail {

template <class T>
T finite_mean(const std::vector<T>& v) {
    double sum = 0;
    std::size_t n = 0;
    for (T x : v)
        if (std::isfinite(x)) sum += static_cast<double>(x), ++n;
    return n ? static_cast<T>(sum / static_cast<double>(n)) : std::numeric_limits<T>::infinity();
}

}  // namespace detail

/// Evaluates a model on frames it was not trained on (grey levels 0-255).
/// The synthesised face is warped onto the landmarks given to the model
/// (noisy ones when noise > 0); PSNR is taken over the pixels inside both
/// the real landmarks' triangles and the synthesised face. A grey parameter
/// that does not vary over the frames gets NCC 0. Throws
/// anima::invalid_argument for fewer than 2 frames, counts that differ or a
/// negative noise.
template <class T, class Image>
sadm_evaluation<T> evaluate_sadm(const sadm_model<T>& model, const std::vector<Image>& images,
                                 const std::vector<landmark_set<T>>& landmarks,
                                 const sadm_evaluation_options<T>& options = {}) {
    const std::string who = "anima::evaluate_sadm";
    if (images.size() < 2 || images.size() != landmarks.size())
        throw invalid_argument(who + ": needs at least 2 frames with one landmark set each, got " +
                               std::to_string(images.size()) + " images and " + std::to_string(landmarks.size()) +
                               " landmark sets");
    if (!(options.noise >= T(0)) || !std::isfinite(options.noise))
        throw invalid_argument(who + ": noise must be finite and >= 0, got " + detail::argument_text(options.noise));
    const auto& grey = model.grey();
    const Eigen::Index n = static_cast<Eigen::Index>(images.size()), m = grey.size();
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> predicted(n, m), real(n, m);
    random_source rng(options.seed);
    sadm_evaluation<T> out;
    for (std::size_t k = 0; k < images.size(); ++k) {
        const auto i = static_cast<Eigen::Index>(k);
        const auto& img = images[k];
        landmark_set<T> input = landmarks[k];
        if (options.noise > T(0))
            for (Eigen::Index p = 0; p < input.rows(); ++p)
                for (int c = 0; c < 2; ++c) input(p, c) += options.noise * static_cast<T>(rng.normal());
        const auto bg_real = grey.parameters(grey.sample(img, landmarks[k]));
        const auto bg = model.grey_parameters(model.shape_parameters(input));
        real.row(i) = bg_real.transpose();
        predicted.row(i) = bg.transpose();
        const grey_image<T> frame = img.template cast<T>();
        const auto synth = render_face(grey, grey.grey_levels(bg), input, img.rows(), img.cols());
        const auto truth = render_face(grey, grey.grey_levels(bg_real), landmarks[k], img.rows(), img.cols());
        const poisson_mask region = synth.mask && truth.mask;
        out.psnr.push_back(region.any() ? psnr(synth.values, frame, region) : T(0));
        out.psnr_model.push_back(psnr(truth.values, frame, truth.mask));
        if (options.progress) options.progress(static_cast<int>(k) + 1, static_cast<int>(images.size()));
    }
    for (Eigen::Index j = 0; j < m; ++j) {
        const bool varies = (real.col(j).array() != real(0, j)).any() && (predicted.col(j).array() != predicted(0, j)).any();
        out.ncc.push_back(varies ? normalized_cross_correlation(predicted.col(j), real.col(j)) : T(0));
    }
    out.psnr_mean = detail::finite_mean(out.psnr);
    out.psnr_model_mean = detail::finite_mean(out.psnr_model);
    return out;
}

}  // namespace anima
