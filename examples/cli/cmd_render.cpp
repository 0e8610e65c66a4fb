// anima render IN.bvh OUT.svg: a filmstrip of stick figures at chosen frames.
#include "commands.hpp"
#include "common.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace anima_cli {
namespace {

struct render_options {
    std::string input, output;
    std::string frames;  // "0,40,80"
    int count = 8;
    std::string view = "front";
    std::string up;
    int width = 0, height = 0;
    bool animate = false;
    double fps = 25;
    std::string span;  // "A-B" for --animate
    CLI::Option *frames_opt = nullptr, *width_opt = nullptr, *height_opt = nullptr, *span_opt = nullptr;
};

// Layout in pixels.
constexpr double title_height = 34;   // title line at the top
constexpr double caption_height = 50; // frame number and time under each panel, the scale bar
constexpr double padding = 12;        // around each figure
constexpr double default_height = 360;
constexpr double min_panel_width = 110;
constexpr double min_default_width = 420;

constexpr const char* colour_left = "#1f63c6";
constexpr const char* colour_right = "#d0342c";
constexpr const char* colour_centre = "#2b2b2b";

/// "0, 40,80" to numbers; throws failure naming the first bad item.
std::vector<long long> parse_frame_list(const std::string& text) {
    std::vector<long long> out;
    std::size_t pos = 0;
    for (;;) {
        const std::size_t comma = text.find(',', pos);
        std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
        item.erase(0, item.find_first_not_of(" \t"));
        item.erase(item.find_last_not_of(" \t") + 1);
        long long v = 0;
        const char* end = item.data() + item.size();
        const auto r = std::from_chars(item.data(), end, v);
        if (item.empty() || r.ec != std::errc() || r.ptr != end)
            throw failure("'" + item + "' is not a frame number (in '" + text + "')");
        out.push_back(v);
        if (comma == std::string::npos) return out;
        pos = comma + 1;
    }
}

std::vector<std::size_t> choose_frames(const render_options& o, std::size_t frames) {
    std::vector<std::size_t> out;
    if (o.frames_opt->count() > 0) {
        for (const long long f : parse_frame_list(o.frames)) {
            if (f < 0 || static_cast<unsigned long long>(f) >= frames)
                throw failure("frame " + std::to_string(f) + " is out of range: '" + o.input + "' has " +
                              std::to_string(frames) + (frames == 1 ? " frame (0)" : " frames (0.." + std::to_string(frames - 1) + ")"));
            out.push_back(static_cast<std::size_t>(f));
        }
        return out;
    }
    const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(o.count), frames);
    for (std::size_t i = 0; i < n; ++i)
        out.push_back(n == 1 ? 0
                             : static_cast<std::size_t>(std::llround(static_cast<double>(i) *
                                                                     static_cast<double>(frames - 1) /
                                                                     static_cast<double>(n - 1))));
    return out;
}

using segment = anima::stick_segment<double>;
using view_basis = anima::stick_view_basis<double>;

/// The box segments span in view coordinates.
struct view_box {
    double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, ymin = xmin, ymax = -xmin;
    void extend(const segment& s) {
        xmin = std::min({xmin, s.x1, s.x2}), xmax = std::max({xmax, s.x1, s.x2});
        ymin = std::min({ymin, s.y1, s.y2}), ymax = std::max({ymax, s.y1, s.y2});
    }
};

struct panel {
    std::size_t frame;
    std::vector<segment> segments;
};

const char* colour(anima::body_side s) {
    return s == anima::body_side::left ? colour_left : s == anima::body_side::right ? colour_right : colour_centre;
}

/// The chosen frames' bones, far bones first, and the box they span.
struct projection {
    std::vector<panel> panels;
    view_box box;
};

projection project_frames(const clip_t& clip, const std::vector<std::size_t>& frames, const view_basis& basis) {
    projection out;
    const std::vector<anima::stick_bone> bones = anima::stick_bones(clip.skeleton());
    for (const std::size_t f : frames) {
        panel pn{f, {}};
        for (const segment& s : anima::project_stick_figure(clip, f, bones, basis))
            if (s.length >= 1e-9) {
                pn.segments.push_back(s);
                out.box.extend(s);
            }
        // Far segments first, so that near limbs are drawn over them.
        std::stable_sort(pn.segments.begin(), pn.segments.end(),
                         [](const segment& a, const segment& b) { return a.depth < b.depth; });
        out.panels.push_back(std::move(pn));
    }
    if (!std::isfinite(out.box.xmin)) out.box = {-1, 1, -1, 1};  // no bones at all: a single joint, say
    return out;
}

/// A bar of a round length (in metres when the unit guess is confident,
/// else in file units) at (x, y), `scale` pixels per file unit.
void scale_bar(svg_document& svg, double x, double y, double scale, const skeleton_t& sk, anima::signed_axis up) {
    const anima::unit_guess units = anima::guess_units(sk, up);
    const double per_unit = units.confident ? units.metres_per_unit : 1.0;
    // The largest of 1, 2, 5 x 10^k (metres or units) under 90 pixels.
    double length = 1e-6;
    for (double power = 1e-6; power < 1e9; power *= 10)
        for (const double m : {1.0, 2.0, 5.0})
            if (m * power / per_unit * scale <= 90) length = m * power;
    const double pixels = length / per_unit * scale;
    svg.line(x, y, x + pixels, y, "#444", 2);
    svg.line(x, y - 4, x, y + 4, "#444", 1);
    svg.line(x + pixels, y - 4, x + pixels, y + 4, "#444", 1);
    const std::string label = units.confident ? (length >= 1 ? format_number(length) + " m" : format_number(length * 100) + " cm")
                                              : format_number(length) + " file units";
    svg.text(x + pixels + 6, y + 4, label, 11, "#444");
}

/// "A-B" to frames, within the clip (the whole clip when not given).
std::pair<std::size_t, std::size_t> animate_span(const render_options& o, std::size_t frames) {
    if (o.span_opt->count() == 0) return {0, frames - 1};
    const failure bad("--span '" + o.span + "' is not a range A-B within 0.." + std::to_string(frames - 1) + " of '" +
                      o.input + "'");
    std::string list = o.span;
    std::replace(list.begin(), list.end(), '-', ',');
    std::vector<long long> ends;
    try {
        ends = parse_frame_list(list);
    } catch (const failure&) {
        throw bad;
    }
    if (ends.size() != 2 || ends[1] < ends[0] || static_cast<unsigned long long>(ends[1]) >= frames) throw bad;
    return {static_cast<std::size_t>(ends[0]), static_cast<std::size_t>(ends[1])};
}

/// --animate: one line per bone whose ends move through the sampled frames
/// (SMIL <animate>, looping), the figure kept centred over its root as in
/// the filmstrip; a ground line, a scale bar and a time axis whose bar
/// fills as the animation plays.
void run_animate(const render_options& o, const clip_t& clip, const view_basis& basis, anima::signed_axis up) {
    const skeleton_t& sk = clip.skeleton();
    const auto [first, last] = animate_span(o, clip.frames());
    const std::size_t step = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(clip.frame_rate() / o.fps)));
    std::vector<std::size_t> frames;
    for (std::size_t f = first; f <= last; f += step) frames.push_back(f);
    check_request_memory(static_cast<double>(frames.size()) * static_cast<double>(sk.size() * 2), sizeof(segment),
                         "an animation of " + std::to_string(frames.size()) + " frames", "--span or --fps");
    // Bones in a fixed order (each <line> is one bone all along): the
    // figure's left side first, its right side last.
    std::vector<anima::stick_bone> bones = anima::stick_bones(sk);
    const auto rank = [](anima::body_side s) { return s == anima::body_side::left ? 0 : s == anima::body_side::right ? 2 : 1; };
    std::stable_sort(bones.begin(), bones.end(),
                     [&](const anima::stick_bone& a, const anima::stick_bone& b) { return rank(a.side) < rank(b.side); });
    std::vector<std::vector<segment>> ends;  // per frame and bone
    view_box box;
    for (const std::size_t f : frames) {
        ends.push_back(anima::project_stick_figure(clip, f, bones, basis));
        for (const segment& e : ends.back()) box.extend(e);
    }
    if (!std::isfinite(box.xmin)) throw failure("'" + o.input + "' has no bones to animate");
    const double xmin = box.xmin, xmax = box.xmax, ymin = box.ymin, ymax = box.ymax;
    const double extent = std::max({xmax - xmin, ymax - ymin, 1e-9});
    const double height = o.height_opt->count() ? o.height : default_height;
    const double top = title_height + padding, bottom = 58;  // under the figure: scale bar, time axis
    const double area_h = std::max(10.0, height - top - bottom);
    const double scale = area_h / std::max(ymax - ymin, extent * 0.05);
    const double width = o.width_opt->count() ? o.width : std::max(min_default_width, (xmax - xmin) * scale + 2 * padding + 40);
    const double cx = width / 2 - (xmin + xmax) / 2 * scale, base = top + area_h;
    const auto px = [&](double x) { return cx + x * scale; };
    const auto py = [&](double y) { return base - (y - ymin) * scale; };
    const double seconds = static_cast<double>(frames.size()) * static_cast<double>(step) * clip.frame_time();
    const std::string dur = svg_number(seconds) + "s";

    const std::string name = file_name(o.input), view_name = o.view + " view";
    svg_document svg(width, height, name + ": " + view_name + ", animated");
    svg.text(10, 22, name + " (" + view_name + ", frames " + std::to_string(first) + "-" + std::to_string(last) + " at " +
                         format_number(clip.frame_rate(), 4) + " fps)",
             13, "#222", "start", true);
    if (basis.vertical) svg.line(6, py(ymin), width - 6, py(ymin), "#9a9a9a", 1);
    const double stroke = std::clamp((ymax - ymin) * scale / 70, 1.2, 4.0);
    svg.raw("<g stroke-linecap=\"round\">");
    for (std::size_t b = 0; b < bones.size(); ++b) {
        const segment& e0 = ends[0][b];
        std::string line = "<line x1=\"" + svg_number(px(e0.x1)) + "\" y1=\"" + svg_number(py(e0.y1)) + "\" x2=\"" +
                           svg_number(px(e0.x2)) + "\" y2=\"" + svg_number(py(e0.y2)) + "\" stroke=\"" +
                           colour(bones[b].side) + "\" stroke-width=\"" + svg_number(stroke) + "\">";
        static const char* const attributes[] = {"x1", "y1", "x2", "y2"};
        for (std::size_t k = 0; k < 4; ++k) {
            line += "<animate attributeName=\"" + std::string(attributes[k]) + "\" dur=\"" + dur +
                    "\" repeatCount=\"indefinite\" values=\"";
            for (std::size_t i = 0; i < frames.size(); ++i) {
                const segment& e = ends[i][b];
                const double v = k == 0 ? e.x1 : k == 1 ? e.y1 : k == 2 ? e.x2 : e.y2;
                line += (i ? ";" : "") + svg_number(k % 2 ? py(v) : px(v));
            }
            line += "\"/>";
        }
        svg.raw(line + "</line>");
    }
    svg.raw("</g>");
    scale_bar(svg, 12, base + 18, scale, sk, up);
    // Time axis: a bar that fills as the animation plays, ticks in seconds.
    const double ax = 12, aw = width - 24, ay = height - 22;
    svg.rect(ax, ay - 4, aw, 4, "#e6e6e6");
    svg.raw("<rect x=\"" + svg_number(ax) + "\" y=\"" + svg_number(ay - 4) + "\" width=\"0\" height=\"4\" fill=\"#666\">"
            "<animate attributeName=\"width\" from=\"0\" to=\"" + svg_number(aw) + "\" dur=\"" + dur +
            "\" repeatCount=\"indefinite\"/></rect>");
    for (const double t : nice_ticks(0, seconds, 6)) {
        svg.line(ax + aw * t / seconds, ay, ax + aw * t / seconds, ay + 3, "#666", 1);
        svg.text(ax + aw * t / seconds, ay + 14, format_number(t, 4) + " s", 10, "#444", "middle");
    }
    write_text_file(o.output, svg.str());
    report_written(o.output + ": " + std::to_string(frames.size()) + " frames of " + o.input + " (" +
                   std::to_string(first) + "-" + std::to_string(last) + ", every " + std::to_string(step) +
                   (step == 1 ? "st" : "th") + "), " + view_name + ", looping every " + format_number(seconds, 4) +
                   " s, " + svg_number(width) + "x" + svg_number(height) + " px");
}

void run_render(const render_options& o) {
    check_outputs({{"OUT", &o.output}});
    std::error_code same_ec;
    if (std::filesystem::equivalent(o.input, o.output, same_ec))
        throw failure("OUT '" + o.output + "' is the input clip: render writes an SVG, give it another name");
    const clip_t clip = load_clip(o.input);
    if (clip.empty()) throw failure("'" + o.input + "' has no frames to render");
    const skeleton_t& sk = clip.skeleton();
    const anima::signed_axis up = up_axis_or_guess(o.up, sk, o.input);
    const view_basis basis =
        anima::make_stick_view<double>(anima::parse_stick_view(o.view), up, anima::left_axis(sk, up));
    if (o.animate) return run_animate(o, clip, basis, up);
    const std::vector<std::size_t> frames = choose_frames(o, clip.frames());

    projection projected = project_frames(clip, frames, basis);
    const std::vector<panel>& panels = projected.panels;
    double xmin = projected.box.xmin, xmax = projected.box.xmax, ymin = projected.box.ymin, ymax = projected.box.ymax;
    // The ground: the lowest point the figure reaches anywhere in the clip.
    if (basis.vertical) ymin = std::min(ymin, anima::lowest_along(clip, basis.up));
    const double ground = ymin;
    double xrange = xmax - xmin, yrange = ymax - ymin;
    const double extent = std::max({xrange, yrange, 1e-9});
    xrange = std::max(xrange, extent * 0.05);
    yrange = std::max(yrange, extent * 0.05);

    // Scale and panel size: one scale for all panels.
    const std::size_t n = panels.size();
    const double height = o.height_opt->count() ? o.height : default_height;
    const double area_h = std::max(10.0, height - title_height - caption_height - 2 * padding);
    double scale = area_h / yrange;
    double panel_w = 0, width = 0;
    if (o.width_opt->count()) {
        width = o.width;
        panel_w = width / static_cast<double>(n);
        scale = std::min(scale, std::max(1e-9, panel_w - 2 * padding) / xrange);
    } else {
        // At most twice as wide as high (a figure lying down, say): the
        // scale then shrinks to fit the width.
        panel_w = std::ceil(std::clamp(xrange * scale + 2 * padding, min_panel_width, 2 * height));
        scale = std::min(scale, (panel_w - 2 * padding) / xrange);
        width = std::max(min_default_width, panel_w * static_cast<double>(n));
        panel_w = width / static_cast<double>(n);
    }
    const double area_w = panel_w - 2 * padding;
    const double stroke = std::clamp(yrange * scale / 70, 1.2, 4.0);

    const std::string name = file_name(o.input);
    const std::string view_name = o.view + " view";
    svg_document svg(width, height, name + ": " + view_name);
    svg.text(10, 22, name + " (" + view_name + ", " + std::to_string(clip.frames()) + " frames at " +
                         format_number(clip.frame_rate(), 4) + " fps)",
             14, "#222", "start", true);
    svg.text(width - 10, height - 4, "right", 12, colour_right, "end", true);
    svg.text(width - 52, height - 4, "left", 12, colour_left, "end", true);

    for (std::size_t i = 0; i < n; ++i) {
        const panel& pn = panels[i];
        const double x0 = static_cast<double>(i) * panel_w;
        // Figure box of xrange x yrange at `scale`, centred horizontally; the
        // ground sits at the bottom of the drawing area in vertical views.
        const double bx = x0 + padding + (area_w - xrange * scale) / 2;
        const double by = basis.vertical ? title_height + padding + area_h
                                         : title_height + padding + (area_h + yrange * scale) / 2;
        const auto px = [&](double x) { return bx + (x - xmin) * scale; };
        const auto py = [&](double y) { return by - (y - ymin) * scale; };

        if (i > 0) svg.line(x0, title_height, x0, height - 6, "#e2e2e2", 1);
        if (basis.vertical) svg.line(x0 + 6, py(ground), x0 + panel_w - 6, py(ground), "#9a9a9a", 1);
        svg.raw("<g stroke-linecap=\"round\">");
        for (const segment& s : pn.segments) svg.line(px(s.x1), py(s.y1), px(s.x2), py(s.y2), colour(s.side), stroke);
        svg.raw("</g>");
        const double cx = x0 + panel_w / 2, cy = title_height + 2 * padding + area_h + 12;
        svg.text(cx, cy, "frame " + std::to_string(pn.frame), 12, "#222", "middle", true);
        svg.text(cx, cy + 15, format_fixed(static_cast<double>(pn.frame) * clip.frame_time(), 3) + " s", 11, "#666",
                 "middle");
    }
    scale_bar(svg, 10, height - 8, scale, sk, up);
    write_text_file(o.output, svg.str());

    std::vector<std::string> listed;
    for (const panel& p : panels) listed.push_back(std::to_string(p.frame));
    report_written(o.output + ": " + std::to_string(n) + (n == 1 ? " frame" : " frames") + " of " + o.input + " (" +
                   join(listed) + "), " + view_name + ", up " + anima::to_string(up) + ", " + svg_number(width) + "x" +
                   svg_number(height) + " px");
}

}  // namespace
}  // namespace anima_cli

void register_render(CLI::App& app) {
    using namespace anima_cli;
    const auto [sub, opts] = add_command<render_options>(
        app, "render", "Draw stick figures of chosen frames side by side into an SVG file", run_render);
    sub->add_option("IN", opts->input, "BVH file to read")->required()->type_name("PATH");
    sub->add_option("OUT", opts->output, "SVG file to write")->required()->type_name("PATH");
    opts->frames_opt = sub->add_option("--frames", opts->frames, "Frames to draw, comma-separated (0-based), e.g. 0,40,80")
                           ->type_name("F,F,...")
                           ->check(parse_check<failure>(parse_frame_list, "", "frame list"));
    auto* count = add_setting(*sub, "--count", opts->count,
                              "Number of evenly spaced frames to draw, first and last included", integer_in(1, 1000))
                      ->type_name("N");
    opts->frames_opt->excludes(count);
    add_setting(*sub, "--view", opts->view,
                "front: up and the figure's left-right axis; side: up and its front-back axis (seen from its "
                "right); top: seen from above",
                CLI::IsMember(anima::enum_name_list<anima::stick_view>()))
        ->type_name("VIEW");
    add_up_option(*sub, opts->up);
    opts->width_opt = sub->add_option("--width", opts->width, "Width of the image (default: from the figure's proportions)")
                          ->type_name("PX")
                          ->check(integer_in(50, 100000));
    opts->height_opt = sub->add_option("--height", opts->height, "Height of the image (default: 360)")
                           ->type_name("PX")
                           ->check(integer_in(120, 100000));
    auto* animate = sub->add_flag("--animate", opts->animate,
                                  "Write one stick figure that moves through the frames (an animated SVG that loops, for web "
                                  "pages and READMEs) instead of a filmstrip")
                        ->excludes(opts->frames_opt)
                        ->excludes(count);
    add_setting(*sub, "--fps", opts->fps, "--animate: frames per second kept from the clip (every k-th frame)",
                number_in(1, 240))
        ->needs(animate);
    opts->span_opt = sub->add_option("--span", opts->span, "--animate: the frames to play, A-B (default: all)")
                         ->type_name("A-B")
                         ->needs(animate);
}
