// anima symmetry IN.bvh: where a clip can be played backwards without a
// visible seam. Prints the turning candidates (Eq 5) with their
// probabilities; optionally plots the Eq 4 scores (SVG) and draws the full
// frame distance matrix (PNG, the paper's Fig 2).
#include "commands.hpp"
#include "common.hpp"
#include "svg_chart.hpp"

#include <anima/image/block_mean.hpp>
#include <anima/image/percentile_grey.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iostream>
#include <string>
#include <vector>

namespace anima_cli {
namespace {

struct symmetry_cli_options {
    std::string input, plot, matrix;
    frame_range_options range;
    symmetry_options symmetry;
    int matrix_size = 0;
    bool json = false;
};

// The distance matrix is held in memory as doubles: 8 * frames^2 bytes.
constexpr std::size_t max_matrix_frames = 8192;
constexpr int default_matrix_pixels = 1024;
// Bytes a pixel of the --matrix image costs at the peak: the block means,
// their row-major copy and the sorted copy for the percentile (doubles),
// then the grey bytes, the filtered rows, the compressed stream and the
// PNG (or SVG) text.
constexpr double matrix_bytes_per_pixel = 24;
// Labels on the score plot: at most this many, the highest scores first.
constexpr std::size_t max_plot_labels = 12;

void write_score_plot(const std::string& path, const std::string& input, const motion_range& m,
                      const anima::symmetry_result<double>& r, const std::string& settings, int min_pairs) {
    const std::size_t n = m.clip.frames();
    const double x0 = static_cast<double>(m.first), x1 = static_cast<double>(m.first + (n > 1 ? n - 1 : 1));
    const std::string range = std::to_string(m.first) + ".." + std::to_string(m.first + n - 1);
    svg_chart chart(900, "Symmetry of " + file_name(input) + ", frames " + range + " (" + settings + ")",
                    "Eq 4 score per frame (1 = the frames around it mirror each other best); dots: the " +
                        std::to_string(r.candidates.size()) + " turning candidates (Eq 5)" +
                        (r.candidates.size() > max_plot_labels
                             ? ", the " + std::to_string(max_plot_labels) + " highest labelled"
                             : ""),
                    62, 24);
    const chart_panel p = chart.panel(266, x0, x1, 0, 1, "symmetry score");
    // Frames compared on too few pairs to be candidates (near the ends).
    std::vector<bool> few(n);
    for (std::size_t k = 0; k < n; ++k) few[k] = r.pairs[k] < min_pairs;
    const auto shaded = anima::true_runs(few);
    for (const auto& run : shaded)
        p.shade(x0 + static_cast<double>(run.first) - 0.5, x0 + static_cast<double>(run.last) + 0.5, "#eeeeee");
    p.y_axis(5);
    // The curve, over the frames that have pairs (not the first and last).
    std::vector<double> score(n);
    for (std::size_t k = 0; k < n; ++k) score[k] = r.pairs[k] ? r.score[static_cast<Eigen::Index>(k)] : std::nan("");
    p.series(score, x0, 1, "#1f63c6", 1.4);

    // Candidates: every one a dot; labels for the highest that do not
    // collide with a label already placed (candidates are sorted by score).
    std::vector<double> labelled;
    for (const auto& c : r.candidates) {
        const double frame = static_cast<double>(m.first + c.frame), x = p.x(frame);
        p.marker(frame, c.score, mark::dot, "#d0342c");
        if (labelled.size() >= max_plot_labels) continue;
        const bool clear = std::none_of(labelled.begin(), labelled.end(), [x](double lx) { return std::abs(lx - x) < 28; });
        if (!clear) continue;
        labelled.push_back(x);
        // Near the plot's sides the label leans inwards, clear of the axis.
        const char* anchor = x < p.left + 10 ? "start" : x > p.right() - 10 ? "end" : "middle";
        chart.svg().text(x, p.y(c.score) - 7, std::to_string(m.first + c.frame), 10, "#a0231c", anchor);
    }
    chart.x_axis(p, 10, "frame (" + format_number(m.clip.frame_rate(), 4) + " frames per second, as the file says)");
    if (!shaded.empty())
        chart.legend({{"#eeeeee", "fewer than " + std::to_string(min_pairs) + " pairs, never candidates", mark::box}});
    write_text_file(path, chart.str());
}

/// The distance matrix as an SVG figure: the image, frame axes, a title
/// and a grey scale bar with the distance's units.
std::string matrix_svg(const std::string& png, const std::string& name, const motion_range& m,
                       const anima::symmetry_params<double>& params, double white) {
    const double side = 560;
    const std::size_t n = m.clip.frames();
    const bool mahalanobis = params.distance.metric == anima::frame_metric::mahalanobis;
    svg_chart chart(70 + side + 180, "Frame distances of " + name,
                    "frames " + std::to_string(m.first) + ".." + std::to_string(m.first + n - 1) + ": " +
                        (mahalanobis ? "square root of Eq 2 (Mahalanobis)" : "Eq 1 (L2)") +
                        " between every two frames; dark valleys across the diagonal: where the motion mirrors itself",
                    70, 180);
    // Pixel edges half a frame either side; row 0 (the first frame) at the top.
    const double first = static_cast<double>(m.first) - 0.5, last = first + static_cast<double>(n);
    const chart_panel p = chart.panel(side, first, last, last, first, "frame, top to bottom");
    chart.svg().image(p.left, p.top, side, side, png);
    chart.svg().rect(p.left, p.top, side, side, "none", "#444", 1);
    p.y_axis(8, false);
    chart.x_axis(p, 8, "frame (" + format_number(m.clip.frame_rate(), 4) + " per second)");
    colour_bar(chart.svg(), p.right() + 24, p.top, side / 2, "grey", {"#000", "#fff"},
               {{format_number(white, 3) + " or more", 9},
                {"(99th percentile)", 22},
                {"0: the same pose", side / 2},
                {mahalanobis ? "distance: sqrt of Eq 2," : "distance: Eq 1,", side / 2 + 22},
                {mahalanobis ? "feature standard deviations" : "the features' units", side / 2 + 35}});
    return chart.str();
}

struct matrix_image {
    int size = 0;
    double white = 0;  // the distance drawn white (and everything above it)
};

/// Width and height of the --matrix image of n frames.
int matrix_side(std::size_t n, int requested_size) {
    return requested_size > 0 ? requested_size : static_cast<int>(std::min<std::size_t>(n, default_matrix_pixels));
}

/// Refuses up front a --matrix that would need more than 1 GiB: the n x n
/// distances and the image's pixels.
void check_matrix_memory(std::size_t n, int requested_size) {
    const double side = matrix_side(n, requested_size), frames = static_cast<double>(n);
    check_request_memory(8 * frames * frames + matrix_bytes_per_pixel * side * side, 1,
                         "--matrix: a " + format_number(side) + "x" + format_number(side) + " image of the " +
                             std::to_string(n) + "x" + std::to_string(n) + " distance matrix",
                         "--matrix-size");
}

matrix_image write_distance_matrix(const std::string& path, const std::string& input, const motion_range& m,
                                   const Eigen::MatrixXd& features, const anima::symmetry_params<double>& params,
                                   int requested_size) {
    const std::size_t n = m.clip.frames();
    const auto distance = anima::make_frame_distance(features, m.clip.frame_time(), params.distance);
    Eigen::MatrixXd d = anima::distance_matrix(features, distance);
    // Eq 2 is a squared distance: its root is on the scale of a length, like Eq 1.
    if (params.distance.metric == anima::frame_metric::mahalanobis) d = d.cwiseSqrt();

    matrix_image out;
    out.size = matrix_side(n, requested_size);
    // Block means of frames when shrinking, repeated frames when enlarging;
    // row-major, as the pixels are written.
    using row_major = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const row_major value = anima::block_mean_resample(d, out.size, out.size);
    // Black = identical frames, white = the 99th percentile of the pixels and
    // above: a few extreme frames should not leave everything else black.
    const anima::grey_levels<double> grey = anima::percentile_grey(value, 99);
    out.white = grey.white;
    const std::vector<unsigned char>& pixels = grey.bytes;
    if (is_svg_path(path))
        write_text_file(path, matrix_svg(png_bytes(out.size, out.size, 1, pixels, "--matrix"), file_name(input), m, params, out.white));
    else
        write_png(path, out.size, out.size, 1, pixels, "--matrix");
    return out;
}

void run_symmetry(const symmetry_cli_options& o) {
    check_outputs({{"--plot", &o.plot}, {"--matrix", &o.matrix}});
    const anima::symmetry_params<double> params = make_symmetry_params(o.symmetry);
    if (!o.matrix.empty()) require_png("--matrix");
    const motion_range m = load_motion_range(o.input, o.range);
    const std::size_t n = m.clip.frames();
    if (!o.matrix.empty() && n > max_matrix_frames)
        throw failure("--matrix: " + std::to_string(n) + " frames are too many for the full distance matrix (at most " +
                      std::to_string(max_matrix_frames) + "); choose a range with --first and --last");
    if (!o.matrix.empty()) check_matrix_memory(n, o.matrix_size);
    anima::frame_feature_params feature_params;
    feature_params.up = m.up;
    const Eigen::MatrixXd features = anima::frame_features(m.clip, feature_params);
    const anima::symmetry_result<double> r = anima::symmetry_scores(features, m.clip.frame_time(), params);
    if (!r.score.allFinite()) throw failure("'" + o.input + "': the symmetry scores are not finite");
    const int candidate_window = params.candidate_radius ? params.candidate_radius : params.radius;
    const int min_pairs = anima::candidate_min_pairs(params, n);
    const std::string settings = describe(o.symmetry, params);
    const double dt = m.clip.frame_time();

    if (!o.plot.empty()) write_score_plot(o.plot, o.input, m, r, settings, min_pairs);
    matrix_image image;
    if (!o.matrix.empty()) image = write_distance_matrix(o.matrix, o.input, m, features, params, o.matrix_size);

    if (o.json) {
        json candidates = json::array();
        for (const auto& c : r.candidates)
            candidates.push_back({{"frame", m.first + c.frame},
                                  {"time", static_cast<double>(m.first + c.frame) * dt},
                                  {"score", c.score},
                                  {"probability", c.probability},
                                  {"pairs", r.pairs[c.frame]}});
        json scores = json::array();
        for (Eigen::Index k = 0; k < r.score.size(); ++k) scores.push_back(r.score[k]);
        json out = {{"file", o.input},
                    {"first", m.first},
                    {"last", m.first + n - 1},
                    {"frames", n},
                    {"frame_time", dt},
                    {"up_axis", anima::to_string(m.up)}};
        out.update(settings_json(o.symmetry, params, n));
        out["candidates"] = candidates;
        out["scores"] = scores;
        if (!o.plot.empty()) out["plot"] = o.plot;
        if (!o.matrix.empty())
            out["matrix"] = {{"file", o.matrix}, {"pixels", image.size}, {"white_distance", image.white}};
        print_json(out);
        return;
    }

    std::cout << o.input << ": frames " << m.first << ".." << m.first + n - 1 << " (" << n << " at "
              << format_number(m.clip.frame_rate(), 6) << " fps), " << settings << "\n";
    if (r.candidates.empty()) {
        std::cout << "no turning candidates: no frame compared on at least " << min_pairs << " pair"
                  << (min_pairs == 1 ? "" : "s") << " has the highest score within +-" << candidate_window
                  << " frames\n";
    } else {
        std::cout << r.candidates.size() << " turning candidate" << (r.candidates.size() == 1 ? "" : "s")
                  << " (the highest score within +-" << candidate_window << " frames, on at least " << min_pairs
                  << " pair" << (min_pairs == 1 ? "" : "s") << "), highest first:\n";
        std::cout << "   frame   time(s)   score   probability   pairs\n";
        const auto right = [](std::string text, std::size_t width) {
            return std::string(width > text.size() ? width - text.size() : 0, ' ') + text;
        };
        for (const auto& c : r.candidates)
            std::cout << right(std::to_string(m.first + c.frame), 8)
                      << right(format_fixed(static_cast<double>(m.first + c.frame) * dt, 3), 10)
                      << right(format_fixed(c.score, 3), 8) << right(format_fixed(c.probability, 3), 14)
                      << right(std::to_string(r.pairs[c.frame]), 8) << '\n';
        if (std::any_of(r.candidates.begin(), r.candidates.end(),
                        [&](const auto& c) { return r.pairs[c.frame] < params.radius; }))
            std::cout << "(pairs: the frame pairs i-r, i+r inside the range; fewer than " << params.radius
                      << " near its ends, where the score rests on fewer comparisons)\n";
    }
    if (!o.plot.empty()) report_written(o.plot + ": the score curve with the candidates marked");
    if (!o.matrix.empty())
        report_written(o.matrix + ": the " + std::to_string(n) + "x" + std::to_string(n) + " distance matrix as " +
                       std::to_string(image.size) + "x" + std::to_string(image.size) +
                       " px (black: identical frames, white: distance " + format_number(image.white, 4) +
                       " and above)");
}

}  // namespace
}  // namespace anima_cli

void register_symmetry(CLI::App& app) {
    using namespace anima_cli;
    const auto [sub, opts] = add_command<symmetry_cli_options>(
        app, "symmetry", "Find the frames where a clip can be played backwards without a seam (turning candidates)",
        run_symmetry);
    sub->add_option("IN", opts->input, "BVH file to analyse")->required()->type_name("PATH");
    add_symmetry_options(*sub, opts->symmetry);
    add_frame_range_options(*sub, opts->range);
    sub->add_option("--plot", opts->plot, "Draw the score curve with the candidates marked into this SVG file")
        ->type_name("OUT.svg");
    auto* matrix = sub->add_option("--matrix", opts->matrix, "Draw the frames x frames distance matrix: an SVG figure with axes and a scale bar, or the bare image as PNG")
                       ->type_name("OUT.png");
    sub->add_option("--matrix-size", opts->matrix_size,
                    "Width and height of the --matrix image in pixels (default: one per frame, at most 1024)")
        ->type_name("PX")
        ->check(integer_in(1, 8192))
        ->needs(matrix);
    sub->add_flag("--json", opts->json, "Print a JSON object instead of text");
}
