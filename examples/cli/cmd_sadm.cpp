// anima sadm train|eval|synth: shape-appearance dependence mapping.
//   train DIR --out MODEL   builds the shape and grey-level models and the
//                           b_s -> b_g regressor from DIR/images + DIR/points;
//   eval MODEL DIR          per-component NCC (Table 1) and PSNR (Eq 7,
//                           Table 2 with --noise) on DIR's frames;
//   synth MODEL LANDMARKS   a face for a landmark file, optionally pasted
//                           into a neutral frame with Poisson blending.
// DIR is laid out as ../shared/data/face: images/NAME.{jpg,png,pgm,ppm} and
// points/NAME.pts, frames taken in name order (anima/sadm/frame_folder.hpp
// reads it). JPEG and PNG need stb.
#include "commands.hpp"
#include "common.hpp"

#include <anima/core/stopwatch.hpp>
#include <anima/image.hpp>
#include <anima/sadm.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#if defined(ANIMA_HAVE_STB) && __has_include(<stb_image.h>)
#define ANIMA_HAVE_STB_IMAGE 1
// The decoder's implementation lives here, static: no other file needs it.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_JPEG
#define STBI_ONLY_PNG
#include <stb_image.h>
#endif

namespace anima_cli {
namespace {

using grey = anima::grey_image<double>;
using landmarks_t = anima::landmark_set<double>;

std::string lower_extension(const std::string& path) {
    return anima::ascii_lower(std::filesystem::path(path).extension().string());
}

/// Grey levels 0-255 of a PGM/PPM (library) or JPEG/PNG (stb) file.
grey load_grey(const std::string& path) {
    if (std::filesystem::is_directory(path)) throw failure("'" + path + "' is a directory, not an image");
    const std::string ext = lower_extension(path);
    if (ext == ".pgm" || ext == ".ppm" || ext == ".pnm") return anima::read_grey_pnm<double>(path);
    if (ext != ".jpg" && ext != ".jpeg" && ext != ".png")
        throw failure("'" + path + "': unknown image type; use .pgm, .ppm, .jpg or .png");
#ifdef ANIMA_HAVE_STB_IMAGE
    int w = 0, h = 0, channels = 0;
    // The header's size is checked before the decoder allocates the pixels.
    if (stbi_info(path.c_str(), &w, &h, &channels) &&
        static_cast<long long>(w) * static_cast<long long>(h) > anima::max_raster_pixels)
        throw failure("'" + path + "' is " + std::to_string(w) + " x " + std::to_string(h) + " pixels, more than the " +
                      std::to_string(anima::max_raster_pixels) + " an image may have here");
    unsigned char* px = stbi_load(path.c_str(), &w, &h, &channels, 1);
    if (!px) throw failure("cannot read '" + path + "': " + stbi_failure_reason());
    using bytes = Eigen::Matrix<unsigned char, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const grey g = Eigen::Map<const bytes>(px, h, w).cast<double>();
    stbi_image_free(px);
    return g;
#else
    throw failure("'" + path + "': this anima was built without stb_image.h, so it reads only PGM/PPM images");
#endif
}

/// Throws failure unless an image can be written at `path` (.pgm, or .png
/// with stb, in a folder that exists): called before any work.
void check_grey_output(const std::string& path, std::string_view what_for) {
    if (path.empty()) return;
    check_output(path, what_for);
    const std::string ext = lower_extension(path);
    if (ext != ".pgm" && ext != ".png") throw failure(std::string(what_for) + ": '" + path + "': write .pgm or .png");
    if (ext == ".png") require_png(what_for);
}

/// Writes grey levels as PGM (library) or PNG (stb), by extension.
void save_grey(const std::string& path, const grey& g, std::string_view what_for) {
    check_grey_output(path, what_for);
    if (lower_extension(path) == ".pgm") {
        anima::write_pgm(path, g);
        return;
    }
    write_png(path, static_cast<int>(g.cols()), static_cast<int>(g.rows()), 1, anima::to_bytes(g, std::string(what_for)),
              what_for);
}

/// Throws failure naming the landmark file and the point unless every
/// landmark lies inside the image.
void check_inside(const landmarks_t& lm, const grey& image, const std::string& pts, const std::string& image_path) {
    try {
        anima::check_landmarks_inside(lm, image.cols(), image.rows(), "'" + pts + "'");
    } catch (const anima::invalid_argument& e) {
        throw failure(std::string(e.what()) + " '" + image_path + "'");
    }
}

using frames_t = anima::frame_set<double>;

/// The frames of DIR a command uses (anima::load_frame_folder): with
/// --hold-out, train takes the frames the rule leaves and eval the ones it
/// holds out; without it both take every frame. JPEG and PNG go through stb.
frames_t load_frames(const std::string& dir, const std::string& hold_out, bool test, bool progress) {
    const auto which = hold_out.empty() ? anima::frame_selection::all
                       : test           ? anima::frame_selection::test
                                        : anima::frame_selection::training;
    anima::frame_load_options<double> options;
    options.decode = load_grey;
    if (progress)
        options.progress = [](std::size_t done, std::size_t) {
            if (done % 50 == 0) std::cerr << "anima: read " << done << " frames\n";
        };
    return anima::load_frame_folder(dir, anima::parse_frame_split(hold_out), which, options);
}

/// --hold-out is checked with the options, before any file is read.
CLI::Validator hold_out_rule() {
    return parse_check<anima::invalid_argument>(
        anima::parse_frame_split,
        [](const std::string&, const anima::invalid_argument& e) {
            const std::string what = e.what(), prefix = "anima::parse_frame_split: ";
            return what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what;
        },
        "", "hold-out rule");
}

anima::sadm_model<double> load_model(const std::string& path) {
    const std::string text = read_text_file(path);
    std::istringstream in(text);
    return anima::sadm_model<double>::load(in, path);
}

// ---------------------------------------------------------------------------
// train
// ---------------------------------------------------------------------------

struct train_options {
    std::string dir, output, regressor = "linear", hold_out;
    double shape_variance = 0.98, grey_variance = 0.95;
    int grey_components = 0;
    bool json = false, progress = false;
};

void run_train(const train_options& o) {
    check_outputs({{"--out", &o.output}});
    const anima::stopwatch timer;
    const frames_t frames = load_frames(o.dir, o.hold_out, false, o.progress);
    anima::sadm_options<double> options;
    options.mapping = anima::parse_regressor_kind(o.regressor);
    options.shape.pca = {o.shape_variance, 0};
    options.grey = {o.grey_variance, o.grey_components};
    if (o.progress)
        options.progress = [](const std::string& stage, int done, int total) {
            if (done == total || done % 50 == 0) std::cerr << "anima: " << stage << " " << done << "/" << total << "\n";
        };
    const auto model = anima::sadm_model<double>::train(frames.images, frames.landmarks, options);
    std::ostringstream text;
    model.save(text);
    write_text_file(o.output, text.str());
    const double seconds = timer.elapsed();
    if (o.json) {
        json j;
        j["frames"] = frames.images.size();
        j["regressor"] = o.regressor;
        j["shape_parameters"] = model.shape().size();
        j["grey_parameters"] = model.grey().size();
        j["face_pixels"] = model.grey().raster().size();
        j["seconds"] = seconds;
        j["model"] = o.output;
        print_json(j);
        return;
    }
    std::cout << "trained on " << frames.images.size() << " frames (" << frames.names.front() << " .. "
              << frames.names.back() << "): " << model.shape().size() << " shape parameters, " << model.grey().size()
              << " grey parameters over " << model.grey().raster().size() << " face pixels, " << o.regressor
              << " mapping, " << format_number(seconds, 3) << " s\n";
    report_written(o.output);
}

// ---------------------------------------------------------------------------
// eval
// ---------------------------------------------------------------------------

struct eval_options {
    std::string model, dir, hold_out, figure;
    double noise = 0;
    std::uint64_t seed = 1;
    bool json = false, progress = false;
};

/// A strip for the docs: ground truth, synthesis, synthesis with noisy
/// landmarks (rows) for up to 4 frames (columns), each cropped to the face.
/// The synthesised face is Poisson-pasted into its own frame.
void write_figure(const std::string& path, const anima::sadm_model<double>& model, const frames_t& f, double noise,
                  std::uint64_t seed) {
    require_png("--figure");
    const std::size_t count = std::min<std::size_t>(4, f.images.size());
    std::vector<std::size_t> picks;
    for (std::size_t c = 0; c < count; ++c) picks.push_back(c * (f.images.size() - 1) / std::max<std::size_t>(1, count - 1));
    anima::random_source rng(seed);
    std::vector<std::vector<grey>> rows(3);
    for (std::size_t k : picks) {
        const auto& img = f.images[k];
        const auto& lm = f.landmarks[k];
        landmarks_t noisy = lm;
        for (Eigen::Index p = 0; p < noisy.rows(); ++p)
            for (int c = 0; c < 2; ++c) noisy(p, c) += noise * rng.normal();
        const Eigen::Index x0 = std::max<Eigen::Index>(0, static_cast<Eigen::Index>(lm.col(0).minCoeff()) - 8);
        const Eigen::Index y0 = std::max<Eigen::Index>(0, static_cast<Eigen::Index>(lm.col(1).minCoeff()) - 8);
        const Eigen::Index x1 = std::min<Eigen::Index>(img.cols(), static_cast<Eigen::Index>(lm.col(0).maxCoeff()) + 9);
        const Eigen::Index y1 = std::min<Eigen::Index>(img.rows(), static_cast<Eigen::Index>(lm.col(1).maxCoeff()) + 9);
        const grey shown[] = {img, model.synthesize(lm, img), model.synthesize(noisy, img)};
        for (std::size_t r = 0; r < 3; ++r) rows[r].push_back(shown[r].block(y0, x0, y1 - y0, x1 - x0));
    }
    save_grey(path, anima::tile_grid(rows, 4, 255.0), "--figure");
}

void run_eval(const eval_options& o) {
    check_grey_output(o.figure, "--figure");
    const auto model = load_model(o.model);
    const frames_t frames = load_frames(o.dir, o.hold_out, true, o.progress);
    anima::sadm_evaluation_options<double> options;
    options.noise = o.noise;
    options.seed = o.seed;
    if (o.progress)
        options.progress = [](int done, int total) {
            if (done == total || done % 50 == 0) std::cerr << "anima: evaluated " << done << "/" << total << " frames\n";
        };
    const auto r = anima::evaluate_sadm(model, frames.images, frames.landmarks, options);
    if (!o.figure.empty()) write_figure(o.figure, model, frames, o.noise > 0 ? o.noise : 2.0, o.seed);
    if (o.json) {
        json j;
        j["frames"] = frames.images.size();
        j["regressor"] = std::string(anima::to_string(model.mapping().kind()));
        j["noise"] = o.noise;
        j["ncc"] = r.ncc;
        j["psnr"] = r.psnr;
        j["psnr_mean"] = r.psnr_mean;
        j["psnr_model_mean"] = r.psnr_model_mean;
        print_json(j);
        return;
    }
    std::cout << frames.images.size() << " frames (" << frames.names.front() << " .. " << frames.names.back() << "), "
              << anima::to_string(model.mapping().kind()) << " mapping, landmark noise " << format_number(o.noise)
              << " px\n\n b_g   NCC\n";
    for (std::size_t k = 0; k < r.ncc.size(); ++k)
        std::cout << (k < 9 ? "   " : "  ") << k + 1 << "   " << format_fixed(r.ncc[k], 4) << '\n';
    std::cout << "\nPSNR over the face: mean " << format_fixed(r.psnr_mean, 2) << " dB, min "
              << format_fixed(*std::min_element(r.psnr.begin(), r.psnr.end()), 2) << ", max "
              << format_fixed(*std::max_element(r.psnr.begin(), r.psnr.end()), 2) << " (grey model with the real b_g: "
              << format_fixed(r.psnr_model_mean, 2) << " dB)\n";
    if (!o.figure.empty()) report_written(o.figure + ": ground truth, synthesis, synthesis with noise");
}

// ---------------------------------------------------------------------------
// synth
// ---------------------------------------------------------------------------

struct synth_options {
    std::string model, landmarks, output, neutral;
};

void run_synth(const synth_options& o) {
    check_grey_output(o.output, "--out");
    const auto model = load_model(o.model);
    const landmarks_t lm = anima::read_pts<double>(o.landmarks);
    grey out;
    if (!o.neutral.empty()) {
        const grey neutral = load_grey(o.neutral);
        check_inside(lm, neutral, o.landmarks, o.neutral);
        out = model.synthesize(lm, neutral);
    } else {
        if (lm.minCoeff() < 0) throw failure("'" + o.landmarks + "' has negative coordinates: give --neutral FRAME");
        const double extent = (lm.col(1).maxCoeff() + 2) * (lm.col(0).maxCoeff() + 2);
        if (!(extent <= static_cast<double>(anima::max_raster_pixels)))
            throw failure("'" + o.landmarks + "' reaches (" + format_number(lm.col(0).maxCoeff()) + ", " +
                          format_number(lm.col(1).maxCoeff()) + "): the canvas would have more than " +
                          std::to_string(anima::max_raster_pixels) + " pixels; give --neutral FRAME");
        const auto rows = static_cast<Eigen::Index>(std::ceil(lm.col(1).maxCoeff())) + 2;
        const auto cols = static_cast<Eigen::Index>(std::ceil(lm.col(0).maxCoeff())) + 2;
        out = anima::paste_face(grey(grey::Zero(rows, cols)), model.render(lm, rows, cols));
    }
    save_grey(o.output, out, "--out");
    report_written(o.output + " (" + std::to_string(out.cols()) + "x" + std::to_string(out.rows()) + ")");
}

}  // namespace
}  // namespace anima_cli

void register_sadm(CLI::App& app) {
    using namespace anima_cli;
    CLI::App* sadm = app.add_subcommand("sadm", "Shape-appearance dependence mapping: facial texture from landmarks");
    sadm->require_subcommand(1);
    const char* dir_help = "Folder with images/NAME.{jpg,png,pgm} and points/NAME.pts, frames in name order";
    const char* split_help = "every:N holds out every Nth frame, last:N the last N frames (train skips them, eval uses only them)";

    const auto [train, t] = add_command<train_options>(
        *sadm, "train", "Build the shape and grey-level models and the b_s -> b_g mapping", run_train);
    train->add_option("DIR", t->dir, dir_help)->required()->type_name("DIR");
    train->add_option("--out", t->output, "Model file to write")->required()->type_name("MODEL");
    add_setting(*train, "--regressor", t->regressor, "b_s -> b_g mapping",
                CLI::IsMember(anima::enum_name_list<anima::regressor_kind>()));
    train->add_option("--hold-out", t->hold_out, split_help)->check(hold_out_rule())->type_name("every:N|last:N");
    add_setting(*train, "--shape-variance", t->shape_variance, "Fraction of shape variance kept",
                number_in(0, 1, true));
    add_setting(*train, "--grey-variance", t->grey_variance, "Fraction of grey-level variance kept",
                number_in(0, 1, true));
    train->add_option("--grey-components", t->grey_components, "Keep this many grey parameters instead (0: by variance)")
        ->check(integer_in(0, 100000));
    train->add_flag("--progress", t->progress, "Report progress on stderr");
    train->add_flag("--json", t->json, "Print a JSON object instead of text");

    const auto [eval, e] = add_command<eval_options>(
        *sadm, "eval", "NCC per grey parameter and PSNR per frame on a folder's frames", run_eval);
    eval->add_option("MODEL", e->model, "Model file from sadm train")->required()->type_name("MODEL");
    eval->add_option("DIR", e->dir, dir_help)->required()->type_name("DIR");
    eval->add_option("--noise", e->noise, "Gaussian noise (standard deviation, pixels) on the landmarks")
        ->check(number_in(0, 1000));
    eval->add_option("--seed", e->seed, "Seed of the noise")->check(count_up_to(~0ULL));
    eval->add_option("--hold-out", e->hold_out, split_help)->check(hold_out_rule())->type_name("every:N|last:N");
    eval->add_option("--figure", e->figure,
                     "PNG/PGM: ground truth, synthesis and synthesis with noise (--noise, else 2 px) for 4 frames")
        ->type_name("IMAGE");
    eval->add_flag("--progress", e->progress, "Report progress on stderr");
    eval->add_flag("--json", e->json, "Print a JSON object (ncc, psnr, psnr_mean, ...) instead of text");

    const auto [synth, s] =
        add_command<synth_options>(*sadm, "synth", "Synthesise the face for a landmark file", run_synth);
    synth->add_option("MODEL", s->model, "Model file from sadm train")->required()->type_name("MODEL");
    synth->add_option("LANDMARKS", s->landmarks, ".pts file, image coordinates")->required()->type_name("PTS");
    synth->add_option("--out", s->output, "Image to write (.png or .pgm)")->required()->type_name("IMAGE");
    synth->add_option("--neutral", s->neutral, "Frame to paste the face into (Poisson blending); else a black canvas")
        ->type_name("IMAGE");
}
