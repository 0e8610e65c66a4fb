// anima texture IN.bvh [IN2.bvh ...] --frames N -o OUT.bvh: a long motion
// from a short clip. The clip's last m frames are laid over its first m
// where they overlap best, every joint switches between them at its own
// frame (a graph cut), fades over a few frames, and the textons this makes
// are played end to end and Poisson-smoothed (the graph-cut motion
// texture). Several clips of one skeleton make one loop through all of
// them, with such a seam from each into the next. --plot draws the input
// and the texture as (DOF x frame) images with the seams marked, as the
// paper's Fig 3 does.
#include "commands.hpp"
#include "common.hpp"
#include "svg_chart.hpp"
#include "view_page.hpp"

#include <anima/core/stopwatch.hpp>
#include <anima/texture.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace anima_cli {
namespace {

struct texture_options {
    std::vector<std::string> inputs;
    std::string output, plot, texton_output, view, rotation_order;
    std::size_t frames = 0, m = 100, overlap = 50, blend = 0, first = 0;
    std::uint64_t seed = 1;
    std::string capacity = "normalized", metric = "mahalanobis", smoothing = "1d", solver = "multigrid", order = "given";
    std::string root = "accumulated", up;
    double neighbour_weight = 0.5, mix_probability = 0.5;
    bool json = false, hard_cut = false, symmetric = false, keep_heading = false, progress = false;
    bool plant_feet = true;
    CLI::Option *m_opt = nullptr, *overlap_opt = nullptr, *first_opt = nullptr;
};

/// The plot's colours, for its pixels and for the SVG's legend and colour bar.
using rgb_colour = std::array<unsigned char, 3>;
constexpr rgb_colour viridis[] = {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
constexpr rgb_colour m1_colour{40, 160, 70}, m2_colour{40, 90, 200}, overlap_colour{240, 140, 20}, seam_colour{230, 20, 20};

std::string css(const rgb_colour& c) {
    return "rgb(" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + ")";
}

/// Viridis-like colour map, t in [0, 1].
void colour(double t, unsigned char* rgb) {
    t = std::clamp(t, 0.0, 1.0) * 4;
    const int i = std::min(3, static_cast<int>(t));
    const double u = t - i;
    for (int k = 0; k < 3; ++k)
        rgb[k] = static_cast<unsigned char>(std::lround(viridis[i][k] * (1 - u) + viridis[i + 1][k] * u));
}

/// The input (top) and the texture (bottom) as DOF x frame images, one row
/// per DOF coloured by its value within the input's range, the root's
/// ground position left out (the texture's grows without bound), and DOFs
/// that move less than 2 degrees. A strip
/// above the input marks M1 (green) and M2 (blue), one above the texture
/// the passes through the overlap (orange); red pixels are each DOF's
/// graph-cut seam.
struct plot_image {
    std::vector<unsigned char> rgb;
    int width = 0, height = 0, in_width = 0, row_h = 0, panel = 0;
    double scale = 1;                  ///< pixels per frame
    std::vector<Eigen::Index> shown;   ///< the DOF columns drawn, top to bottom
    static constexpr int strip = 4, gap = 10;
    int texture_top() const { return strip + panel + gap + strip; }
};

plot_image make_plot_image(const std::vector<clip_t>& inputs, const anima::motion_texture<double>& t,
                           anima::signed_axis up) {
    const auto& layout = t.texton.layout;
    const clip_t& input = inputs.front();
    // The inputs one after another.
    std::size_t n_in = 0;
    for (const clip_t& c : inputs) n_in += c.frames();
    Eigen::MatrixXd a(static_cast<Eigen::Index>(n_in), static_cast<Eigen::Index>(layout.size()));
    for (std::size_t i = 0, row = 0; i < inputs.size(); row += inputs[i].frames(), ++i)
        a.middleRows(static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(inputs[i].frames())) =
            anima::to_dof_matrix(inputs[i], layout);
    const Eigen::MatrixXd b = anima::to_dof_matrix(t.motion, layout);
    plot_image img;
    // DOFs that barely move in the input (uncaptured fingers: rounding
    // noise) would show noise stretched to full contrast: left out.
    const std::vector<anima::dof_range<double>> moving = anima::moving_dofs(
        a, layout, up, anima::radians(2.0), 1e-3 * anima::figure_height(input.skeleton(), up));
    if (moving.empty()) throw failure("--plot: no DOF of the input moves by 2 degrees or more");
    for (const auto& d : moving) img.shown.push_back(d.column);
    const auto& shown = img.shown;
    const std::size_t n_out = t.motion.frames();
    img.scale = std::min(1.0, 1200.0 / static_cast<double>(n_out));
    const double scale = img.scale;
    img.width = std::max(1, static_cast<int>(std::lround(static_cast<double>(n_out) * scale)));
    img.in_width = std::max(1, static_cast<int>(std::lround(static_cast<double>(n_in) * scale)));
    img.row_h = std::max(3, 270 / static_cast<int>(shown.size()));
    img.panel = img.row_h * static_cast<int>(shown.size());
    const int width = img.width, height = img.texture_top() + img.panel, strip = plot_image::strip, row_h = img.row_h;
    img.height = height;
    std::vector<unsigned char>& px = img.rgb;
    px.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3, 255);
    // Pixels x0..x1 (inclusive) of rows y0..y1 - 1, clipped to the image.
    const auto fill = [&](int x0, int x1, int y0, int y1, const unsigned char* rgb) {
        for (int y = std::max(y0, 0); y < std::min(y1, height); ++y)
            for (int x = std::max(x0, 0); x <= std::min(x1, width - 1); ++x)
                std::copy(rgb, rgb + 3, px.begin() + (static_cast<std::ptrdiff_t>(y) * width + x) * 3);
    };
    const auto draw = [&](const Eigen::MatrixXd& m, std::size_t frames, int pixels, int top) {
        unsigned char rgb[3];
        for (int x = 0; x < pixels; ++x) {
            const auto f = static_cast<Eigen::Index>(std::min<std::size_t>(frames - 1, static_cast<std::size_t>(x / scale)));
            for (std::size_t i = 0; i < moving.size(); ++i) {
                const double range = moving[i].hi - moving[i].lo;
                colour(range > 1e-9 ? (m(f, moving[i].column) - moving[i].lo) / range : 0.5, rgb);
                fill(x, x, top + static_cast<int>(i) * row_h, top + static_cast<int>(i + 1) * row_h, rgb);
            }
        }
    };
    draw(a, n_in, img.in_width, strip);
    draw(b, n_out, width, img.texture_top());
    const auto x_of = [&](std::size_t frame) { return static_cast<int>(static_cast<double>(frame) * scale); };
    const std::size_t m = t.texton.m;
    for (std::size_t i = 0, first = 0; i < inputs.size(); first += inputs[i].frames(), ++i) {
        const std::size_t last = first + inputs[i].frames() - 1;
        fill(x_of(first), x_of(first + m - 1), 0, strip, m1_colour.data());
        fill(x_of(last + 1 - m), x_of(last), 0, strip, m2_colour.data());
    }
    for (const auto& [first, last] : t.overlap_spans)
        fill(x_of(first), x_of(last), img.texture_top() - strip, img.texture_top(), overlap_colour.data());
    const auto crossings = anima::seam_crossings(t.texton, t.stream, anima::seam_mark::cut);
    for (std::size_t i = 0; i < shown.size(); ++i) {
        const std::size_t r = static_cast<std::size_t>(shown[i]) / 3;
        const int y = img.texture_top() + static_cast<int>(i) * row_h;
        for (std::size_t k : crossings[r]) fill(x_of(k), x_of(k), y, y + row_h, seam_colour.data());
    }
    return img;
}

/// The plot as an SVG figure: the image with a title, frame axes (and
/// seconds), the joints each group of rows belongs to, a colour bar and a
/// legend of the marks.
std::string plot_svg(const plot_image& img, const std::string& name, const std::vector<clip_t>& inputs,
                     const anima::motion_texture<double>& t) {
    const bool several = inputs.size() > 1;
    std::size_t input_frames = 0;
    std::string sizes;
    for (const clip_t& c : inputs) {
        sizes += (input_frames ? " + " : "") + std::to_string(c.frames());
        input_frames += c.frames();
    }
    const std::string caption = std::string("one row per DOF; colour: each DOF's value within its range in the ") +
                                (several ? "inputs" : "input") +
                                " (rotations in the file's Euler angles, the root's height); still DOFs and the root's "
                                "ground position left out";
    const double left = 150, w = img.width, strip = plot_image::strip, panel = img.panel;
    // Wide enough for the caption too (about 0.6 em a character).
    const double width = std::max(left + w + 200, 24 + 0.6 * 11 * static_cast<double>(caption.size()));
    svg_chart chart(width, "Motion texture of " + name + ": DOF x frame", caption, left, width - left - w);
    svg_document& svg = chart.svg();
    const std::string png = png_bytes(img.width, img.height, 3, img.rgb, "--plot");
    const double rate = inputs.front().frame_rate();
    const auto& layout = t.texton.layout;
    // The image holds both panels: each shows its part of it, whole.
    const auto image_panel = [&](std::size_t frames, int pixel_top, const std::string& label, const std::string& what) {
        const auto n = static_cast<double>(frames);
        const chart_panel p = chart.panel(strip + panel, 0, n, 0, 1, label, n * img.scale);
        svg.raw("<svg x=\"" + svg_number(left) + "\" y=\"" + svg_number(p.top) + "\" width=\"" + svg_number(w) +
                "\" height=\"" + svg_number(strip + panel) + "\" viewBox=\"0 " + std::to_string(pixel_top) + " " +
                svg_number(w) + " " + svg_number(strip + panel) + "\" preserveAspectRatio=\"none\">");
        svg.image(0, 0, img.width, img.height, png);
        svg.raw("</svg>");
        chart.x_axis(p, 10, "frame of the " + what + " (" + format_number(rate, 4) + " per second: " +
                                format_number(n / rate, 3) + " s)");
        // Joint names at their groups of rows (the rows of one joint are adjacent).
        for (std::size_t i = 0; i < img.shown.size();) {
            const std::size_t joint = layout.dofs[static_cast<std::size_t>(img.shown[i])].joint;
            std::size_t j = i;
            while (j + 1 < img.shown.size() && layout.dofs[static_cast<std::size_t>(img.shown[j + 1])].joint == joint) ++j;
            const double y0 = p.top + strip + static_cast<double>(i * static_cast<std::size_t>(img.row_h));
            const double y1 = p.top + strip + static_cast<double>((j + 1) * static_cast<std::size_t>(img.row_h));
            svg.line(left - 4, y0 + 0.5, left - 4, y1 - 0.5, i % 2 ? "#999" : "#555", 2);
            const double size = std::min(9.0, std::max(6.0, y1 - y0));
            const std::string& joint_name = inputs[0].skeleton()[joint].name;
            if (y1 - y0 >= 6) svg.text(left - 8, (y0 + y1) / 2 + size / 3, joint_name, size, "#333", "end");
            i = j + 1;
        }
        return p;
    };
    const chart_panel in = image_panel(input_frames, 0,
                                       several ? "the inputs one after another (" + sizes + " frames)"
                                               : "the input (" + sizes + " frames)",
                                       several ? "inputs" : "input");
    image_panel(t.motion.frames(), img.texture_top() - plot_image::strip,
                "the texture (" + std::to_string(t.motion.frames()) + " frames)", "texture");
    colour_bar(svg, left + w + 24, in.top + strip, panel, "viridis",
               {css(viridis[0]), css(viridis[1]), css(viridis[2]), css(viridis[3]), css(viridis[4])},
               {{"the DOF's", 9}, {"largest value", 21}, {"(per row)", panel / 2 + 4}, {"smallest value", panel - 12},
                {several ? "in the inputs" : "in the input", panel}});
    const std::string of_each = several ? " of each" : "";
    chart.legend({{css(m1_colour), "M1: first " + std::to_string(t.texton.m) + " frames" + of_each, mark::box},
                  {css(m2_colour), "M2: last " + std::to_string(t.texton.m) + " frames" + of_each, mark::box},
                  {css(overlap_colour), "pass through the overlap", mark::box},
                  {css(seam_colour), "graph-cut seam of the row", mark::box}});
    return chart.str();
}

void write_plot(const std::string& path, const std::vector<clip_t>& inputs, const anima::motion_texture<double>& t,
                anima::signed_axis up, const std::string& name) {
    const plot_image img = make_plot_image(inputs, t, up);
    if (is_svg_path(path)) write_text_file(path, plot_svg(img, name, inputs, t));
    else write_png(path, img.width, img.height, 3, img.rgb, "--plot");
}

/// The library's parameters from the options; the up axis is the given one
/// or the guess from the skeleton.
anima::motion_texture_params<double> texture_params(const texture_options& o, const std::vector<clip_t>& clips) {
    anima::motion_texture_params<double> p;
    if (!o.up.empty()) p.texton.up = parse_signed_axis(o.up);
    if (!p.texton.up) p.texton.up = anima::guess_up_axis(clips[0].skeleton()).up;
    std::size_t shortest = clips[0].frames();
    for (const clip_t& c : clips) shortest = std::min(shortest, c.frames());
    // Defaults shrink to fit the shortest clip; given values are taken as they are.
    const auto given = [](const CLI::Option* opt, std::size_t value) {
        return opt->count() > 0 ? std::optional<std::size_t>(value) : std::nullopt;
    };
    p.texton = anima::choose_texton_lengths(p.texton, shortest, given(o.m_opt, o.m), given(o.overlap_opt, o.overlap));
    p.texton.blend.enabled = !o.hard_cut;
    p.texton.blend.frames = o.blend;
    p.texton.align_heading = !o.keep_heading;
    p.texton.distance.metric = anima::parse_frame_metric(o.metric);
    p.texton.cut.cost.capacity = anima::parse_seam_capacity(o.capacity);
    p.texton.cut.neighbour_weight = o.neighbour_weight;
    p.smoothing.enabled = o.smoothing != "none";
    if (p.smoothing.enabled) p.smoothing.poisson.form = anima::parse_seam_smoothing_form(o.smoothing);
    p.smoothing.poisson.solver = anima::parse_poisson_method(o.solver);
    p.root = anima::parse_root_path(o.root);
    p.mixing.symmetric = o.symmetric;
    p.mixing.probability = o.mix_probability;
    p.mixing.playback.seed = o.seed;
    p.planting.enabled = o.plant_feet;
    return p;
}

/// The page of --view: the inputs (M1 and M2 marked) beside the texture
/// (each pass through an overlap, the frames where the graph-cut seams are
/// crossed, and the symmetric passages' turns).
view_page texture_page(const texture_options& o, const std::vector<clip_t>& clips, const anima::motion_texture<double>& t) {
    view_page page;
    const bool several = clips.size() > 1;
    page.title = "Motion texture of " + (several ? std::to_string(clips.size()) + " clips" : file_name(o.inputs[0])) + ": " +
                 std::to_string(t.motion.frames()) + " frames";
    const std::size_t m = t.texton.m, texture = clips.size();
    for (std::size_t i = 0; i < clips.size(); ++i) {
        page.clips.push_back({"input " + file_name(o.inputs[i]), clips[i]});
        const std::size_t n = clips[i].frames();
        page.markers.push_back({i, 0, m - 1, "m1", "M1, the clip's first " + std::to_string(m) + " frames"});
        page.markers.push_back({i, n - m, n - 1, "m2",
                                several ? "M2, laid over the next clip's M1 where they overlap best"
                                        : "M2, laid over M1 where they overlap best"});
    }
    page.clips.push_back({"texture", t.motion});
    const std::vector<anima::pass_seams> seams = anima::seams_per_pass(t, anima::seam_mark::cut);
    for (std::size_t pass = 0; pass < t.overlap_spans.size(); ++pass) {
        const auto [first, last] = t.overlap_spans[pass];
        page.markers.push_back({texture, first, last, "overlap", "pass " + std::to_string(pass + 1) + " through an overlap"});
        const anima::pass_seams& crossed = seams[pass];
        if (crossed.crossings == 0) continue;
        page.markers.push_back({texture, crossed.first, crossed.last, "seam",
                                "graph-cut seams crossed in pass " + std::to_string(pass + 1) + " (" +
                                    std::to_string(crossed.crossings) + " joint switches)"});
    }
    for (const auto& marker : frame_markers(texture, t.turns, "turn", "symmetric passage turns")) page.markers.push_back(marker);
    return page;
}

/// The joint of the seams' largest joint speed ratio.
std::string worst_joint_name(const clip_t& c, const anima::texture_measures<double>& check) {
    return check.worst.joint_ratio > 0 ? c.skeleton()[check.worst.worst_joint].name : "";
}

struct stage_times {
    double read = 0, write = 0, total = 0;
};

/// The inputs as read (path, first frame used, frames) and the seams
/// between them (several clips only).
json inputs_json(const texture_options& o, const std::vector<std::size_t>& firsts, const std::vector<clip_t>& clips,
                 const anima::motion_texton<double>& texton) {
    json inputs = json::array(), joins = json::array();
    for (std::size_t i = 0; i < clips.size(); ++i)
        inputs.push_back({{"path", o.inputs[i]}, {"first", firsts[i]}, {"frames", clips[i].frames()}});
    for (const auto& j : texton.joins)
        joins.push_back({{"from", o.inputs[j.from]},
                         {"to", o.inputs[j.to]},
                         {"offsets", {{"m2", j.offset_a}, {"m1", j.offset_b}}},
                         {"overlap_start", j.overlap_start},
                         {"heading_turn_degrees", anima::degrees(j.heading_turn)},
                         {"search_cost", j.search_cost},
                         {"cut_cost", j.cut.cost}});
    return {{"inputs", inputs}, {"joins", joins}};
}

json texture_json(const texture_options& o, const std::vector<std::size_t>& firsts, const std::vector<clip_t>& clips,
                  const anima::motion_texton<double>& texton, const anima::motion_texture<double>& t,
                  const anima::texture_measures<double>& check, const stage_times& times) {
    const clip_t& c = clips[0];
    const double dt = c.frame_time();
    json seams = json::array();
    for (std::size_t col = 0; col < texton.layout.size(); ++col) {
        const std::size_t r = col / 3;
        seams.push_back({{"dof", texton.layout.name(c.skeleton(), col)},
                         {"overlap_frame", texton.cut.seam[r]},
                         {"texton_frame", texton.seam_frame(r)},
                         {"cost", texton.cut.row_cost[r]}});
    }
    json spans = json::array();
    for (const auto& s : check.seams)
        spans.push_back({{"first", s.first},
                         {"last", s.last},
                         {"joint_speed_ratio", s.joint_ratio},
                         {"worst_joint", c.skeleton()[s.worst_joint].name},
                         {"root_speed_ratio", s.root_ratio}});
    json out = {{"input", o.inputs[0]},
                {"first", firsts[0]},
                {"input_frames", c.frames()},
                {"frames", t.motion.frames()},
                {"seconds", static_cast<double>(t.motion.frames()) * dt},
                {"frame_time", dt},
                {"m", texton.m},
                {"overlap", texton.overlap},
                {"blend_frames", texton.blend_frames},
                {"offsets", {{"m2", texton.offset_m2}, {"m1", texton.offset_m1}}},
                {"texton", {{"frames", texton.motion.frames()},
                            {"overlap_start", texton.overlap_start},
                            {"heading_turn_degrees", anima::degrees(texton.heading_turn)}}},
                {"search_cost", texton.search_cost},
                {"cut_cost", texton.cut.cost},
                {"neighbour_cost", texton.cut.neighbour_cost},
                {"capacity", o.capacity},
                {"metric", o.metric},
                {"smoothing", o.smoothing},
                {"seams", seams},
                {"overlap_passes", spans},
                {"foot_skate", skate_json(check.input_skate.median, check.skate.median)},
                {"feet_planted", o.plant_feet},
                {"planted_runs", t.planted_runs},
                {"seam_check", {{"joint_speed_ratio", check.worst.joint_ratio},
                                {"worst_joint", worst_joint_name(c, check)},
                                {"root_speed_ratio", check.worst.root_ratio},
                                {"finite", true}}},  // a clip holds finite values only: its setters refuse others
                {"poisson", to_json(t.smoothing)},
                {"stage_seconds", {{"read", times.read},
                                   {"features", t.timings.features},
                                   {"search", t.timings.search},
                                   {"cut", t.timings.cut},
                                   {"blend", t.timings.blend},
                                   {"patch", t.timings.patch},
                                   {"smoothing", t.timings.smoothing},
                                   {"planting", t.timings.planting},
                                   {"write", times.write},
                                   {"total", times.total}}}};
    out.update(inputs_json(o, firsts, clips, texton));
    if (o.symmetric)
        out["symmetric"] = {{"seed", o.seed}, {"probability", o.mix_probability}, {"passages", t.passages}, {"turns", t.turns}};
    if (!o.output.empty()) out["output"] = o.output;
    if (!o.texton_output.empty()) out["texton_output"] = o.texton_output;
    if (!o.plot.empty()) out["plot"] = o.plot;
    if (!o.view.empty()) out["view"] = o.view;
    return out;
}

/// One input as the texture uses it: from --first, or after a rest pose it
/// starts with.
clip_t read_texture_input(const texture_options& o, const std::string& input, std::size_t& first, int& decimals) {
    const std::string text = read_text_file(input);
    const clip_t whole = anima::to_clip(anima::parse_bvh_document<double>(text, input));
    decimals = std::max(decimals, anima::bvh_value_decimals(text));
    if (whole.frames() == 0) throw failure("'" + input + "' has no frames");
    first = o.first;
    const bool first_given = o.first_opt->count() > 0;
    if (first_given) check_frame_in(first, whole.frames(), input, "--first");
    if (!first_given) {
        first = anima::rest_pose_lead_in(whole);
        if (first > 0)
            std::cerr << "anima: note: frame 0 of '" << input << "' is the skeleton's rest pose"
                      << (first > 1 ? " and frames 1.." + std::to_string(first - 1) + " swing out of it" : "")
                      << "; the texture starts from frame " << first << " (--first 0 keeps them)\n";
    }
    return first ? whole.slice(first, whole.frames()) : whole;
}

/// "walk.bvh frames 6..342" for each input, joined.
std::string describe_inputs(const texture_options& o, const std::vector<std::size_t>& firsts,
                            const std::vector<clip_t>& clips) {
    std::string out;
    for (std::size_t i = 0; i < clips.size(); ++i)
        out += (i == 0 ? "" : i + 1 == clips.size() ? " and " : ", ") + file_name(o.inputs[i]) + " frames " +
               std::to_string(firsts[i]) + ".." + std::to_string(firsts[i] + clips[i].frames() - 1);
    return out;
}

/// --order least-cost: the clips (and their names and first frames) put in
/// the order whose loop costs least; the costs of that order and the given one.
std::pair<double, double> reorder_clips(texture_options& o, std::vector<clip_t>& clips, std::vector<std::size_t>& firsts) {
    const auto best = anima::least_cost_clip_order(clips, texture_params(o, clips).texton);
    const auto reorder = [&](auto& items) {
        std::remove_reference_t<decltype(items)> ordered;
        for (const std::size_t i : best.order) ordered.push_back(std::move(items[i]));
        items = std::move(ordered);
    };
    reorder(clips);
    reorder(o.inputs);
    reorder(firsts);
    return {best.cost, best.given_cost};
}

/// The text output: inputs and texture, the order and joins, the texton,
/// its seams, the seam check, symmetric passages, planting and skate, and
/// the stages' times.
void print_texture_summary(const texture_options& o, const std::vector<std::size_t>& firsts,
                           const std::vector<clip_t>& clips, const anima::motion_texton<double>& texton,
                           const anima::motion_texture<double>& t, const anima::texture_measures<double>& check,
                           const std::optional<std::pair<double, double>>& order_costs) {
    const clip_t& c = clips[0];
    const double dt = c.frame_time();
    std::size_t input_frames = 0;
    for (const clip_t& clip : clips) input_frames += clip.frames();
    std::cout << "texture of " << describe_inputs(o, firsts, clips) << " (" << input_frames << " at "
              << format_number(c.frame_rate()) << " fps): " << t.motion.frames() << " frames, "
              << format_number(static_cast<double>(t.motion.frames()) * dt, 4) << " s\n";
    if (order_costs)
        std::cout << "order of least seam cost: summed overlap distance " << format_number(order_costs->first, 4)
                  << " (" << format_number(order_costs->second, 4) << " in the order given)\n";
    for (const auto& j : texton.joins)
        std::cout << "join " << file_name(o.inputs[j.from]) << " -> " << file_name(o.inputs[j.to]) << ": M2 frame "
                  << j.offset_a << " over M1 frame " << j.offset_b << ", heading turn "
                  << format_number(anima::degrees(j.heading_turn), 3) << " deg, cut cost " << format_number(j.cut.cost, 4)
                  << "\n";
    std::cout << "texton: m = " << texton.m << ", overlap " << texton.overlap << " (M2 frame " << texton.offset_m2
              << " over M1 frame " << texton.offset_m1
              << (clips.size() > 1 ? " of " + file_name(o.inputs.front()) + " to close the loop" : std::string()) << "), "
              << texton.motion.frames() << " frames, fades of " << texton.blend_frames << " frames, heading turn "
              << format_number(anima::degrees(texton.heading_turn), 3) << " deg per loop\n";
    std::size_t lo = texton.overlap, hi = 0;
    for (std::size_t s : texton.cut.seam) {
        lo = std::min(lo, s);
        hi = std::max(hi, s);
    }
    std::cout << "seams: " << texton.rows() << " rows switch at overlap frames " << lo << ".." << hi << ", cut cost "
              << format_number(texton.cut.cost, 4) << " (" << format_number(texton.cut.neighbour_cost, 4)
              << " between neighbouring joints)\n";
    std::cout << "seam check over " << check.seams.size() << " pass" << (check.seams.size() == 1 ? "" : "es")
              << " through " << (clips.size() > 1 ? "the overlaps" : "the overlap") << ": joint speed <= "
              << format_fixed(check.worst.joint_ratio, 3) << " x the input's fastest"
              << (check.worst.joint_ratio > 0 ? " (" + worst_joint_name(c, check) + ")" : "") << ", root speed <= "
              << format_fixed(check.worst.root_ratio, 3) << " x\n";
    if (o.symmetric) std::cout << t.passages << " symmetric passages, " << t.turns.size() << " turns\n";
    std::cout << (o.plant_feet ? "feet planted in " + std::to_string(t.planted_runs) + " contact runs" : "feet not planted")
              << "; foot skate " << format_number(check.skate.median, 3) << " body heights/s"
              << (check.input_skate.median > 0
                      ? ", " + format_fixed(check.skate.median / check.input_skate.median, 2) + " x the input's"
                      : "")
              << "\n";
    std::cout << "stages (s): search " << format_number(t.timings.search, 3) << ", cut " << format_number(t.timings.cut, 3)
              << ", fades " << format_number(t.timings.blend, 3) << ", patch " << format_number(t.timings.patch, 3)
              << ", Poisson " << format_number(t.timings.smoothing, 3)
              << (o.plant_feet ? ", planting " + format_number(t.timings.planting, 3) : "") << ", total "
              << format_number(t.timings.total, 3) << "\n";
}

void run_texture(texture_options o) {
    check_outputs({{"--output", &o.output}, {"--plot", &o.plot}, {"--texton", &o.texton_output}, {"--view", &o.view}});
    if (!o.plot.empty()) require_png("--plot");
    anima::stopwatch timer, total;
    std::vector<clip_t> clips;
    std::vector<std::size_t> firsts(o.inputs.size());
    int decimals = 6;
    for (std::size_t i = 0; i < o.inputs.size(); ++i) clips.push_back(read_texture_input(o, o.inputs[i], firsts[i], decimals));
    for (std::size_t i = 1; i < clips.size(); ++i) try {
            anima::check_same_hierarchy(clips[0].skeleton(), clips[i].skeleton());
        } catch (const anima::invalid_argument& e) {
            throw failure("'" + o.inputs[i] + "' is not of the skeleton of '" + o.inputs[0] + "': " + e.what());
        }
    std::optional<std::pair<double, double>> order_costs;
    if (o.order == "least-cost" && clips.size() > 1) order_costs = reorder_clips(o, clips, firsts);
    const clip_t& c = clips[0];
    // The texture, its DOF matrix, the Poisson solve over it and its BVH text.
    check_frames_memory(o.frames, c.skeleton());
    const double read_seconds = timer.lap();

    anima::motion_texture_params<double> p = texture_params(o, clips);
    const anima::signed_axis up = *p.texton.up;
    p.progress = [&](std::string_view stage, double seconds) {
        if (o.progress || seconds > 1.0) std::cerr << "anima: " << stage << ": " << format_number(seconds, 3) << " s\n";
    };
    const anima::motion_texture<double> t = anima::make_motion_texture(clips, o.frames, p);
    const anima::motion_texton<double>& texton = t.texton;

    timer.lap();
    anima::bvh_write_options write;
    write.decimals = decimals;
    if (!o.output.empty()) write_text_file(o.output, bvh_text(t.motion, o.rotation_order, write));
    if (!o.texton_output.empty()) write_text_file(o.texton_output, bvh_text(texton.motion, o.rotation_order, write));
    if (!o.plot.empty()) {
        std::string name;
        for (const std::string& input : o.inputs) name += (name.empty() ? "" : " + ") + file_name(input);
        write_plot(o.plot, clips, t, up, name);
    }
    std::string page_written;
    if (!o.view.empty()) page_written = write_view_page(o.view, texture_page(o, clips, t));
    const double write_seconds = timer.lap();

    const anima::texture_measures<double> check = anima::measure_texture(clips, t, up);
    warn_unconverged(t.smoothing);
    if (o.json) {
        const stage_times times{read_seconds, write_seconds, total.elapsed()};
        json out = texture_json(o, firsts, clips, texton, t, check, times);
        if (clips.size() > 1) out["offsets_from"] = o.inputs[0];  // the output uses the first clip's skeleton
        if (clips.size() > 1)
            out["order"] = {{"rule", o.order},
                            {"paths", o.inputs},
                            {"cost", order_costs ? json(order_costs->first) : json(nullptr)},
                            {"given_cost", order_costs ? json(order_costs->second) : json(nullptr)}};
        print_json(out);
        return;
    }
    print_texture_summary(o, firsts, clips, texton, t, check, order_costs);
    if (!o.output.empty())
        report_written(o.output +
                       (clips.size() > 1 ? " (skeleton and offsets of " + file_name(o.inputs[0]) + ")" : std::string()));
    if (!o.texton_output.empty()) report_written(o.texton_output + " (the texton)");
    if (!o.plot.empty())
        report_written(o.plot + ": input and texture as DOF x frame images, seams in red" +
                       (is_svg_path(o.plot) ? " (with axes, joints, colour bar and legend)" : ""));
    if (!o.view.empty()) report_written(page_written);
}

}  // namespace
}  // namespace anima_cli

void register_texture(CLI::App& app) {
    using namespace anima_cli;
    const auto [sub, opts] = add_command<texture_options>(
        app, "texture",
        "Make a long, seamless motion from a clip (or several): graph-cut textons patched end to end, Poisson-smoothed",
        run_texture);
    sub->add_option("IN", opts->inputs,
                    "BVH clip; several clips of one skeleton and frame rate make one loop through all of them, in the "
                    "order given")
        ->required()
        ->type_name("PATH...");
    sub->add_option("--frames", opts->frames, "Length of the texture in frames")
        ->required()
        ->type_name("N")
        ->check(integer_in(1, max_frames));
    sub->add_option("-o,--output", opts->output, "Write the texture to this BVH file")->type_name("OUT.bvh");
    sub->add_option("--plot", opts->plot, "Draw input and texture as DOF x frame images with the seams: an SVG figure with axes, joint labels, colour bar and legend, or the bare image as PNG")
        ->type_name("OUT.svg|OUT.png");
    add_view_option(*sub, opts->view, "the input and the texture, seams and overlap passes on the timeline");
    sub->add_option("--texton", opts->texton_output, "Write the texton (one loop) to this BVH file")->type_name("OUT.bvh");
    add_rotation_order_option(*sub, opts->rotation_order);
    opts->m_opt = sub->add_option("-m", opts->m, "Frames of M1 (the clip's first) and M2 (its last); default 100, or half a shorter clip")
                      ->type_name("M")
                      ->check(integer_in(2, max_frames));
    opts->overlap_opt = sub->add_option("--overlap", opts->overlap, "Frames where M2 and M1 overlap (2..M); default 50, or M / 2")
                            ->type_name("N")
                            ->check(integer_in(2, max_frames));
    add_setting(*sub, "--blend", opts->blend, "Frames of each fade (0: half the overlap)", count_up_to(max_frames))
        ->type_name("K");
    sub->add_flag("--hard-cut", opts->hard_cut, "Switch at the seam without a fade");
    add_setting(*sub, "--order", opts->order,
                "Several clips: loop through them in the order given, or in the order whose seams cost least "
                "(least-cost: every clip's end searched against every other's start)",
                CLI::IsMember({"given", "least-cost"}));
    add_setting(*sub, "--capacity", opts->capacity,
                "Seam capacity: normalized (Kwatra's M / grad), exponential or plain",
                CLI::IsMember(anima::enum_name_list<anima::seam_capacity>()));
    add_setting(*sub, "--metric", opts->metric, "Frame distance of the offset search: mahalanobis (Eq 2) or l2 (Eq 1)",
                CLI::IsMember(anima::enum_name_list<anima::frame_metric>()));
    add_setting(*sub, "--neighbour-weight", opts->neighbour_weight,
                "Tie between neighbouring joints' seams (0: independent)", number_in(0, 1e6))
        ->type_name("W");
    add_setting(*sub, "--smoothing", opts->smoothing,
                "Poisson smoothing: 1d (per DOF), 2d (the DOF x frame image) or none",
                CLI::IsMember({"1d", "2d", "none"}));
    add_setting(*sub, "--solver", opts->solver, "Poisson solver: multigrid or dst",
                CLI::IsMember(anima::enum_name_list<anima::poisson_method>()));
    sub->add_flag("--keep-heading", opts->keep_heading,
                  "Compare and blend the figure's heading like any rotation (it then turns back in the overlap)");
    add_setting(*sub, "--root", opts->root, "The root's ground path: accumulated, keep_direction, in_place or recorded",
                CLI::IsMember(anima::enum_name_list<anima::root_path>()));
    auto* symmetric = sub->add_flag("--symmetric", opts->symmetric,
                                    "Mix in symmetric playback: at turning candidates play backwards for a while");
    add_setting(*sub, "--mix-probability", opts->mix_probability, "Chance of a symmetric passage at each candidate",
                number_in(0, 1))
        ->type_name("P")
        ->needs(symmetric);
    add_setting(*sub, "--seed", opts->seed, "Seed of the symmetric passages (same seed, same motion)",
                count_up_to(~0ULL));
    opts->first_opt = sub->add_option("--first", opts->first,
                                      "First frame to use of every clip (default: after a rest pose the clip starts with, if any)")
                          ->type_name("FRAME")
                          ->check(count_up_to(max_frames));
    add_up_option(*sub, opts->up);
    sub->add_flag("--plant-feet,!--no-plant-feet", opts->plant_feet,
                  "Hold feet that are on the ground across seams and turns in place, IK on the legs (the "
                  "default; --no-plant-feet leaves them as the seams left them)");
    sub->add_flag("--progress", opts->progress, "Report the time of each stage on stderr");
    sub->add_flag("--json", opts->json, "Print a JSON object instead of text");
}
