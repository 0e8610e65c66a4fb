// The shape model (Eq 1), the grey-level model (Eq 2) on warped images,
// rendering a face onto landmarks, Poisson pasting, and the evaluation
// measures (normalised cross-correlation, PSNR of Eq 7).
#include "sadm_test_support.hpp"

#include <anima/sadm/appearance_model.hpp>
#include <anima/sadm/evaluation.hpp>
#include <anima/sadm/shape_model.hpp>
#include <anima/sadm/synthesis.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace {

using namespace sadm_test;

/// Shapes from a planted two-mode model, each in a random pose.
template <class T>
std::vector<anima::landmark_set<T>> planted_shapes(anima::random_source& rng, const anima::landmark_set<T>& base,
                                                   const anima::landmark_set<T>& mode1, const anima::landmark_set<T>& mode2,
                                                   int count, std::vector<anima::similarity2<T>>* poses = nullptr) {
    std::vector<anima::landmark_set<T>> out;
    for (int k = 0; k < count; ++k) {
        anima::similarity2<T> pose;
        pose.scale = static_cast<T>(40 + 20 * rng.uniform());
        pose.angle = static_cast<T>(0.4 * rng.uniform() - 0.2);
        pose.translation << static_cast<T>(60 + 5 * rng.uniform()), static_cast<T>(70 + 5 * rng.uniform());
        const anima::landmark_set<T> s =
            base + static_cast<T>(2 * rng.uniform() - 1) * mode1 + static_cast<T>(2 * rng.uniform() - 1) * mode2;
        out.push_back(pose.apply(s));
        if (poses) poses->push_back(pose);
    }
    return out;
}

template <class T>
anima::landmark_set<T> ring(int n) {
    anima::landmark_set<T> s(n + 1, 2);
    for (int k = 0; k < n; ++k) {
        const double a = 6.283185307179586 * k / n;
        s.row(k) << static_cast<T>(std::cos(a) * (1 + 0.2 * std::sin(3 * a))), static_cast<T>(std::sin(a));
    }
    s.row(n) << T(0.1), T(-0.05);
    return s;
}

TEST_CASE_TEMPLATE("shape model: a planted two-mode family gives two parameters, free of pose", T, float, double) {
    anima::random_source rng(31);
    const anima::landmark_set<T> base = ring<T>(12);
    anima::landmark_set<T> mode1 = anima::landmark_set<T>::Zero(13, 2), mode2 = mode1;
    mode1.col(1) = T(0.08) * base.col(1);                    // vertical stretch
    for (int k = 0; k < 13; ++k) mode2(k, 0) = T(0.05) * base(k, 1) * base(k, 1);  // a non-affine bend
    const auto shapes = planted_shapes<T>(rng, base, mode1, mode2, 40);
    const auto model = anima::shape_model<T>::fit(shapes, {{T(0.999), 0}, {}});
    // Two planted modes (plus the tangent-space curvature of alignment, which is tiny).
    CHECK(model.size() >= 2);
    CHECK(model.size() <= 4);
    CHECK(model.model().eigenvalues().head(2).sum() / model.model().total_variance() > T(0.99));
    // Parameters ignore the pose: moving a shape changes nothing.
    anima::similarity2<T> move;
    move.scale = T(2.5);
    move.angle = T(0.7);
    move.translation << T(-30), T(12);
    const T tol = tolerance<T>(1e-9, 1e-3);
    for (const auto& s : shapes) {
        const auto b = model.parameters(s);
        CHECK((model.parameters(move.apply(s)) - b).cwiseAbs().maxCoeff() < tol);
        // The model shape, posed like the input, lies on it.
        const auto fitted = model.shape(b);
        const auto back = model.pose(s).inverse().apply(fitted);
        CHECK((back - s).cwiseAbs().maxCoeff() < T(0.05) * s.col(0).maxCoeff() / T(50));
    }
    CHECK(contains(invalid_argument_message([&] { model.parameters(base.topRows(5)); }), "has 5 points, the model 13"));
}

/// A smooth synthetic image whose brightness pattern follows the landmarks.
template <class T>
matrix<T> smooth_image(Eigen::Index rows, Eigen::Index cols, T phase) {
    matrix<T> img(rows, cols);
    for (Eigen::Index y = 0; y < rows; ++y)
        for (Eigen::Index x = 0; x < cols; ++x)
            img(y, x) = T(120) + T(50) * std::sin(T(0.11) * static_cast<T>(x) + phase) * std::cos(T(0.07) * static_cast<T>(y));
    return img;
}

TEST_CASE_TEMPLATE("grey model: warping to the reference and back reproduces a smooth face", T, float, double) {
    anima::random_source rng(2);
    const anima::landmark_set<T> base = ring<T>(12);
    anima::landmark_set<T> mode1 = anima::landmark_set<T>::Zero(13, 2), mode2 = mode1;
    mode1.col(1) = T(0.08) * base.col(1);
    mode2.col(0) = T(0.05) * base.col(1);
    const auto shapes = planted_shapes<T>(rng, base, mode1, mode2, 12);
    std::vector<matrix<T>> images;
    for (std::size_t k = 0; k < shapes.size(); ++k) images.push_back(smooth_image<T>(140, 130, T(0.3) * static_cast<T>(k)));
    const auto shape = anima::shape_model<T>::fit(shapes);
    Eigen::Index rows = 0, cols = 0;
    const auto reference = anima::grey_model<T>::place_reference(shape.mean(), T(50), rows, cols);
    CHECK(reference.minCoeff() == doctest::Approx(1));
    int calls = 0;
    anima::grey_model_options<T> options;
    options.pca = {T(1), 0};
    options.progress = [&](int done, int total) { CHECK(done == ++calls); CHECK(total == 12); };
    const auto grey = anima::grey_model<T>::fit(images, shapes, reference, rows, cols, options);
    CHECK(calls == 12);
    CHECK(grey.size() == 11);  // 12 images: rank 11 with every component kept
    for (std::size_t k = 0; k < shapes.size(); ++k) {
        const vector<T> g = grey.sample(images[k], shapes[k]);
        CHECK((grey.grey_levels(grey.parameters(g)) - g).cwiseAbs().maxCoeff() < tolerance<T>(1e-8, 0.05));
        const auto patch = anima::render_face(grey, g, shapes[k], 140, 130);
        REQUIRE(patch.mask.count() > 500);
        // Two bilinear resamplings of a smooth image: close, but not exact.
        CHECK(anima::psnr(patch.values, images[k], patch.mask) > T(38));
    }
    // The same model from its parts.
    const anima::grey_model<T> copy(grey.reference(), grey.triangles(), rows, cols, grey.model());
    CHECK(copy.raster().pixel == grey.raster().pixel);
    CHECK(contains(invalid_argument_message([&] { grey.texture(vector<T>::Zero(3)); }), "g has size 3"));
}

TEST_CASE_TEMPLATE("Poisson pasting keeps the frame when the patch differs from it by a harmonic function", T, float, double) {
    const matrix<T> frame = smooth_image<T>(64, 72, T(0.5));
    anima::face_patch<T> patch;
    patch.mask = anima::poisson_mask::Constant(64, 72, false);
    for (Eigen::Index y = 0; y < 64; ++y)
        for (Eigen::Index x = 0; x < 72; ++x) patch.mask(y, x) = (x - 36) * (x - 36) + (y - 30) * (y - 30) < 400;
    patch.values = matrix<T>::Zero(64, 72);
    for (Eigen::Index y = 0; y < 64; ++y)
        for (Eigen::Index x = 0; x < 72; ++x)
            if (patch.mask(y, x)) patch.values(y, x) = frame(y, x) + T(30) + T(0.5) * static_cast<T>(x) - T(0.25) * static_cast<T>(y);
    const matrix<T> pasted = anima::paste_face(frame, patch);
    CHECK((pasted - frame).cwiseAbs().maxCoeff() > T(20));
    const matrix<T> blended = anima::blend_face(frame, patch);
    CHECK((blended - frame).cwiseAbs().maxCoeff() < tolerance<T>(1e-5, 0.05));
    // Detail survives: a bump inside the patch stays (less its harmonic part).
    patch.values(30, 36) += T(40);
    const matrix<T> bump = anima::blend_face(frame, patch);
    CHECK(bump(30, 36) - frame(30, 36) > T(30));
    CHECK((bump - frame).cwiseAbs().maxCoeff() < T(41));
}

TEST_CASE_TEMPLATE("normalised cross-correlation matches its definition and its invariances", T, float, double) {
    anima::random_source rng(6);
    const vector<T> a = random_matrix<T>(rng, 50, 1), noise = random_matrix<T>(rng, 50, 1);
    const vector<T> b = a + T(0.5) * noise;
    // Independent evaluation through a covariance matrix in double.
    Eigen::Matrix<double, 50, 2> m;
    m.col(0) = a.template cast<double>();
    m.col(1) = b.template cast<double>();
    const Eigen::Matrix<double, 50, 2> c = m.rowwise() - m.colwise().mean();
    const Eigen::Matrix2d cov = c.transpose() * c;
    const double expected = cov(0, 1) / std::sqrt(cov(0, 0) * cov(1, 1));
    CHECK(static_cast<double>(anima::normalized_cross_correlation(a, b)) == doctest::Approx(expected).epsilon(1e-5));
    const vector<T> scaled = (T(3) * b.array() + T(7)).matrix();
    CHECK(anima::normalized_cross_correlation(a, scaled) == doctest::Approx(anima::normalized_cross_correlation(a, b)));
    CHECK(anima::normalized_cross_correlation(a, (-a).eval()) == doctest::Approx(-1));
    CHECK(anima::normalized_cross_correlation(a, a) == doctest::Approx(1));
    CHECK(contains(invalid_argument_message([&] { anima::normalized_cross_correlation(a, vector<T>::Ones(50).eval()); }),
                   "second sequence is constant"));
    CHECK(contains(invalid_argument_message([&] { anima::normalized_cross_correlation(a, b.head(3).eval()); }),
                   "50 and 3"));
}

TEST_CASE_TEMPLATE("PSNR: Eq 7 on a known error, infinite for identical images, masks", T, float, double) {
    const matrix<T> a = matrix<T>::Constant(10, 10, T(100));
    matrix<T> b = a;
    CHECK(anima::psnr(a, b) == std::numeric_limits<T>::infinity());
    b(2, 3) += T(10);  // MSE = 100 / 100 = 1
    CHECK(anima::psnr(a, b) == doctest::Approx(10 * std::log10(255.0 * 255.0)));
    anima::poisson_mask mask = anima::poisson_mask::Constant(10, 10, false);
    mask(0, 0) = true;
    CHECK(anima::psnr(a, b, mask) == std::numeric_limits<T>::infinity());
    mask(2, 3) = true;  // MSE = 100 / 2
    CHECK(anima::psnr(a, b, mask) == doctest::Approx(10 * std::log10(255.0 * 255.0 / 50.0)));
    CHECK(contains(invalid_argument_message([&] { anima::psnr(a, b, anima::poisson_mask::Constant(10, 10, false)); }),
                   "region is empty"));
    b(0, 0) = std::numeric_limits<T>::quiet_NaN();
    CHECK(contains(invalid_argument_message([&] { anima::psnr(a, b); }), "pixel (x 0, y 0) is not finite"));
}

}  // namespace
