// The whole SADM pipeline: training, synthesis, save/load and the paper's
// evaluation, on synthetic faces whose shading is a planted function of
// their shape and on the bundled FGNet frames (and the full 400-frame
// sequence when ../shared/data is present).
#include "sadm_test_support.hpp"

#include <anima/image/pnm.hpp>
#include <anima/sadm/evaluate_model.hpp>
#include <anima/sadm/sadm_model.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace sadm_test;

template <class T>
struct face_set {
    std::vector<matrix<T>> images;
    std::vector<anima::landmark_set<T>> landmarks;
    std::vector<T> a1, a2;  // the planted shape coefficients
};

/// Faces in random poses whose two shape modes drive two shading patterns:
/// mode 1 (mouth opening) darkens the lower half, mode 2 (brow raise) adds
/// forehead furrows. Shading is defined in the face's own frame, so it moves
/// with the face.
template <class T>
face_set<T> synthetic_faces(int count, std::uint64_t seed) {
    anima::random_source rng(seed);
    const int n = 16;
    anima::landmark_set<T> base(n + 2, 2), mode1 = anima::landmark_set<T>::Zero(n + 2, 2), mode2 = mode1;
    for (int k = 0; k < n; ++k) {
        const double a = 6.283185307179586 * k / n;
        base.row(k) << static_cast<T>(0.8 * std::cos(a)), static_cast<T>(std::sin(a));
        if (std::sin(a) > 0.3) mode1(k, 1) = T(0.15);                     // chin drops
        if (std::sin(a) < -0.3) mode2(k, 1) = static_cast<T>(-0.1 * -std::sin(a));  // brow rises
    }
    base.row(n) << T(0), T(0.4);
    mode1(n, 1) = T(0.12);
    base.row(n + 1) << T(0), T(-0.5);
    mode2(n + 1, 1) = T(-0.08);
    face_set<T> out;
    for (int f = 0; f < count; ++f) {
        const T a1 = static_cast<T>(2 * rng.uniform() - 1), a2 = static_cast<T>(2 * rng.uniform() - 1);
        anima::similarity2<T> pose;
        pose.scale = static_cast<T>(30 + 4 * rng.uniform());
        pose.angle = static_cast<T>(0.2 * rng.uniform() - 0.1);
        pose.translation << static_cast<T>(40 + 4 * rng.uniform()), static_cast<T>(42 + 4 * rng.uniform());
        out.landmarks.push_back(pose.apply(base + a1 * mode1 + a2 * mode2));
        const auto inv = pose.inverse();
        matrix<T> img(84, 80);
        for (Eigen::Index y = 0; y < img.rows(); ++y)
            for (Eigen::Index x = 0; x < img.cols(); ++x) {
                anima::landmark_set<T> p(1, 2);
                p << static_cast<T>(x), static_cast<T>(y);
                const auto q = inv.apply(p);
                const T u = q(0, 0), v = q(0, 1);
                const T lower = v > T(0.2) ? T(1) : T(0);
                const T furrows = v < T(-0.3) ? std::cos(T(25) * v) : T(0);
                img(y, x) = T(130) + T(25) * std::cos(T(3) * u) - T(30) * a1 * lower * (T(1) - u * u) +
                            T(20) * (a2 + T(1)) * furrows;
            }
        out.images.push_back(img);
        out.a1.push_back(a1);
        out.a2.push_back(a2);
    }
    return out;
}

template <class T>
face_set<T> slice(const face_set<T>& s, std::size_t first, std::size_t last) {
    face_set<T> out;
    for (std::size_t k = first; k < last; ++k) {
        out.images.push_back(s.images[k]);
        out.landmarks.push_back(s.landmarks[k]);
    }
    return out;
}

TEST_CASE_TEMPLATE("SADM on faces whose shading depends on their shape: high NCC and PSNR on held-out frames", T, float, double) {
    const auto all = synthetic_faces<T>(50, 7);
    const auto train = slice(all, 0, 40), test = slice(all, 40, 50);
    anima::sadm_options<T> options;
    options.grey = {T(0.99), 0};
    int warps = 0;
    options.progress = [&](const std::string& stage, int, int) { warps += stage == "warp"; };
    const auto model = anima::sadm_model<T>::train(train.images, train.landmarks, options);
    CHECK(warps == 40);
    REQUIRE(model.grey().size() >= 2);
    const auto eval = anima::evaluate_sadm(model, test.images, test.landmarks);
    // The two leading grey parameters are functions of the shape: well predicted.
    CHECK(eval.ncc[0] > T(0.9));
    CHECK(eval.ncc[1] > T(0.8));
    CHECK(eval.psnr_mean > T(28));
    CHECK(eval.psnr_model_mean >= eval.psnr_mean - T(0.5));
    // Noise on the landmarks hurts.
    anima::sadm_evaluation_options<T> noisy;
    noisy.noise = T(3);
    const auto worse = anima::evaluate_sadm(model, test.images, test.landmarks, noisy);
    CHECK(worse.psnr_mean < eval.psnr_mean);
    // A mean predictor (the grey model's mean face) does worse than SADM.
    std::vector<T> mean_psnr;
    for (std::size_t k = 0; k < test.images.size(); ++k) {
        const auto patch = anima::render_face(model.grey(), model.grey().model().mean(), test.landmarks[k], 84, 80);
        mean_psnr.push_back(anima::psnr(patch.values, test.images[k], patch.mask));
    }
    CHECK(anima::detail::finite_mean(mean_psnr) < eval.psnr_mean - T(1));
}

TEST_CASE_TEMPLATE("SADM clamps b_s and b_g (Eq 6) for shapes far from the training set", T, float, double) {
    const auto train = synthetic_faces<T>(30, 3);
    const auto model = anima::sadm_model<T>::train(train.images, train.landmarks);
    anima::landmark_set<T> wild = train.landmarks[0];
    wild.col(1) = wild.col(1).array().square() / T(10);  // a grotesque distortion
    const auto bs = model.shape_parameters(wild);
    const auto bg = model.grey_parameters(bs);
    for (Eigen::Index i = 0; i < bs.size(); ++i)
        CHECK(std::abs(bs(i)) <= T(3) * std::sqrt(model.shape().model().eigenvalues()(i)) * (T(1) + T(1e-6)));
    for (Eigen::Index i = 0; i < bg.size(); ++i)
        CHECK(std::abs(bg(i)) <= T(3) * std::sqrt(model.grey().model().eigenvalues()(i)) * (T(1) + T(1e-6)));
    const auto raw = model.shape().parameters(wild);
    bool any_clamped = false;
    for (Eigen::Index i = 0; i < raw.size(); ++i) any_clamped |= raw(i) != bs(i);
    CHECK(any_clamped);
    // Synthesis never writes a non-finite pixel.
    const matrix<T> frame = matrix<T>::Constant(84, 80, T(100));
    CHECK(model.synthesize(train.landmarks[3], frame).allFinite());
}

TEST_CASE_TEMPLATE("SADM model save/load: identical synthesis, errors with file:line", T, float, double) {
    const auto train = synthetic_faces<T>(20, 5);
    const auto model = anima::sadm_model<T>::train(train.images, train.landmarks);
    std::stringstream text;
    model.save(text);
    const std::string saved = text.str();
    CHECK(saved.rfind("anima-sadm 1\n", 0) == 0);
    std::istringstream in(saved);
    const auto back = anima::sadm_model<T>::load(in, "m.sadm");
    const auto a = model.render(train.landmarks[1], 84, 80), b = back.render(train.landmarks[1], 84, 80);
    CHECK((a.mask == b.mask).all());
    CHECK(a.values == b.values);
    // A broken line is reported where it is, also inside the regressor's part.
    std::vector<std::string> lines;
    {
        std::istringstream s(saved);
        for (std::string l; std::getline(s, l);) lines.push_back(l);
    }
    const auto error_of = [&](std::size_t line, const std::string& replacement) {
        auto copy = lines;
        copy[line] = replacement;
        std::string joined;
        for (const auto& l : copy) joined += l + "\n";
        std::istringstream s(joined);
        try {
            anima::sadm_model<T>::load(s, "m.sadm");
        } catch (const anima::parse_error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    CHECK(contains(error_of(0, "anima-sadm 2"), "m.sadm:1: unsupported SADM model version '2'"));
    CHECK(contains(error_of(1, "clamp_limit x"), "m.sadm:2: bad clamp_limit value 'x'"));
    // Values that are read but do not make a model: on their own line.
    CHECK(contains(error_of(1, "clamp_limit -1"), "m.sadm:2: clamp_limit must be finite and >= 0"));
    std::size_t raster_at = 0;
    while (lines[raster_at].rfind("raster ", 0) != 0) ++raster_at;
    std::istringstream raster_words(lines[raster_at].substr(7));
    long raster_rows = 0, raster_cols = 0;
    raster_words >> raster_rows >> raster_cols;
    // Half the raster's rows: fewer pixels than the grey PCA's dimension.
    CHECK(contains(error_of(raster_at, "raster " + std::to_string(raster_rows / 2) + " " + std::to_string(raster_cols)),
                   "the grey model does not fit the raster of line " + std::to_string(raster_at + 1)));
    std::size_t regressor_at = 0;
    while (lines[regressor_at].rfind("anima-regressor", 0) != 0) ++regressor_at;
    CHECK(contains(error_of(regressor_at, "anima-regressor nonsense 1"), "m.sadm:" + std::to_string(regressor_at + 1) + ":"));
    CHECK(contains(error_of(regressor_at + 1, "sizes 1"), "m.sadm:" + std::to_string(regressor_at + 2) + ":"));
    std::istringstream truncated(saved.substr(0, saved.size() / 2));
    CHECK_THROWS_AS(anima::sadm_model<T>::load(truncated, "m.sadm"), anima::parse_error);
}

TEST_CASE("SADM training refuses what it cannot use") {
    const auto train = synthetic_faces<double>(5, 1);
    CHECK(contains(invalid_argument_message([&] {
                       anima::sadm_model<double>::train(train.images, {train.landmarks[0]});
                   }),
                   "5 images and 1 landmark sets"));
    const std::vector<anima::landmark_set<double>> same(5, train.landmarks[0]);
    CHECK(contains(invalid_argument_message([&] { anima::sadm_model<double>::train(train.images, same); }),
                   "no shape parameter"));
}

// ---------------------------------------------------------------------------
// Real frames
// ---------------------------------------------------------------------------

struct real_frames {
    std::vector<matrix<double>> images;
    std::vector<anima::landmark_set<double>> landmarks;
};

real_frames load_frames(const std::string& dir, bool jpeg_ok) {
    real_frames out;
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir + "/points"))
        if (e.path().extension() == ".pts") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    for (const auto& name : names) {
        const std::string pgm = dir + "/images/" + name + ".pgm";
        if (!std::filesystem::exists(pgm)) {
            REQUIRE_MESSAGE(jpeg_ok, "missing " << pgm);
            continue;
        }
        out.images.push_back(anima::read_grey_pnm<double>(pgm));
        out.landmarks.push_back(anima::read_pts<double>(dir + "/points/" + name + ".pts"));
    }
    return out;
}

TEST_CASE("SADM on the bundled FGNet frames: every 4th frame held out") {
    const auto frames = load_frames(bundled("face"), false);
    REQUIRE(frames.images.size() == 36);
    real_frames train, test;
    for (std::size_t k = 0; k < frames.images.size(); ++k) {
        auto& to = k % 4 == 3 ? test : train;
        to.images.push_back(frames.images[k]);
        to.landmarks.push_back(frames.landmarks[k]);
    }
    const auto model = anima::sadm_model<double>::train(train.images, train.landmarks);
    CHECK(model.shape().points() == 68);
    const auto eval = anima::evaluate_sadm(model, test.images, test.landmarks);
    MESSAGE("bundled frames: " << model.shape().size() << " shape and " << model.grey().size()
                               << " grey parameters, NCC[0] " << eval.ncc[0] << ", PSNR " << eval.psnr_mean
                               << " dB (model " << eval.psnr_model_mean << " dB)");
    CHECK(eval.ncc[0] > 0.5);
    CHECK(eval.psnr_mean > 22);
    CHECK(eval.psnr_model_mean > eval.psnr_mean);
    anima::sadm_evaluation_options<double> noisy;
    noisy.noise = 3;
    CHECK(anima::evaluate_sadm(model, test.images, test.landmarks, noisy).psnr_mean < eval.psnr_mean);
    // A frame's own grey levels, rendered back onto its landmarks, reproduce it.
    const auto& grey = model.grey();
    const auto g = grey.sample(test.images[0], test.landmarks[0]);
    const auto patch = anima::render_face(grey, g, test.landmarks[0], test.images[0].rows(), test.images[0].cols());
    CHECK(anima::psnr(patch.values, test.images[0], patch.mask) > 30);
}

}  // namespace

TEST_CASE("PNM: a header claiming more pixels than the file holds fails before allocating") {
    const auto message = [](const std::string& bytes) {
        try {
            (void)anima::parse_pnm(bytes, "big.pgm");
        } catch (const anima::parse_error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    // 30000 x 30000 would be 1.8 GB of samples: refused from the header alone.
    for (const char* magic : {"P5", "P2", "P6", "P3"}) {
        const std::string m = message(std::string(magic) + "\n30000 30000\n255\n\x01\x02");
        CHECK(contains(m, "big.pgm:"));
        CHECK(contains(m, "30000 x 30000"));
    }
    // A file that has its samples is read.
    const auto ok = anima::parse_pnm("P2\n2 2\n9\n1 2 3 9\n", "ok.pgm");
    CHECK(ok.pixels.pixels.size() == 4);
    CHECK(ok.pixels.pixels[3] == 9);
}

TEST_CASE_TEMPLATE(".pts: a point count beyond the file's size and landmarks outside the image", T, float, double) {
    try {
        (void)anima::parse_pts<T>("version: 1\nn_points: 999999\n{\n1 2\n}\n", "many.pts");
        FAIL("no error");
    } catch (const anima::parse_error& e) {
        CHECK(e.line() == 2);
        CHECK(contains(e.message(), "999999"));
    }
    anima::landmark_set<T> s(3, 2);
    s << T(0), T(0), T(80), T(84), T(40), T(41.5);  // the corners of the image's area are on it
    CHECK_NOTHROW(anima::check_landmarks_inside(s, 80, 84, "f.pts"));
    s(1, 0) = T(300000);
    s(1, 1) = T(-300000);
    const std::string m = invalid_argument_message([&] { anima::check_landmarks_inside(s, 80, 84, "f.pts"); });
    CHECK(contains(m, "f.pts: landmark 1 (300000, -300000) is outside the 80 x 84 image"));
    s(1, 0) = T(80.5);  // beyond the right edge
    s(1, 1) = T(3);
    CHECK(contains(invalid_argument_message([&] { anima::check_landmarks_inside(s, 80, 84, "f.pts"); }), "landmark 1"));
}

TEST_CASE_TEMPLATE("SADM training refuses a landmark outside its image, naming the frame and point", T, float, double) {
    auto train = synthetic_faces<T>(6, 2);
    train.landmarks[4](7, 0) = T(300000);
    train.landmarks[4](7, 1) = T(-300000);
    const std::string m =
        invalid_argument_message([&] { (void)anima::sadm_model<T>::train(train.images, train.landmarks); });
    CHECK(contains(m, "frame 4: landmark 7"));
}

TEST_CASE_TEMPLATE("SADM model load: sizes are checked before allocating, with file:line", T, float, double) {
    const auto train = synthetic_faces<T>(20, 5);
    const auto model = anima::sadm_model<T>::train(train.images, train.landmarks);
    std::stringstream text;
    model.save(text);
    std::vector<std::string> lines;
    for (std::string l; std::getline(text, l);) lines.push_back(l);
    const auto error_of = [&](const std::string& key, const std::string& replacement, std::size_t* at = nullptr) {
        auto copy = lines;
        std::size_t k = 0;
        while (copy[k].rfind(key, 0) != 0) ++k;
        if (at) *at = k + 1;
        copy[k] = replacement;
        std::string joined;
        for (const auto& l : copy) joined += l + "\n";
        std::istringstream s(joined);
        try {
            (void)anima::sadm_model<T>::load(s, "m.sadm");
        } catch (const anima::parse_error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    std::size_t line = 0;
    const std::string raster = error_of("raster ", "raster 999999 999999", &line);
    CHECK(contains(raster, "m.sadm:" + std::to_string(line) + ": raster 999999 x 999999"));
    CHECK(contains(raster, "max_raster_pixels"));
    // A matrix claiming 10^7 rows ends with the file, not with bad_alloc.
    const std::string rows = error_of("components ", "components 10000000 16000000", &line);
    CHECK(contains(rows, "m.sadm:" + std::to_string(line) + ":"));
    const std::string tris = error_of("triangles ", "triangles 16000000 3", &line);
    CHECK(contains(tris, "m.sadm:"));
}
