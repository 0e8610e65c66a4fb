// anima contacts CLIP.bvh [--json] [--plot OUT.svg]: when each foot is
// planted, when the figure is airborne, and how fast planted feet slide
// (anima::find_contacts, anima::foot_skate).
#include "commands.hpp"
#include "common.hpp"

#include <anima/motion/contacts.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstddef>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace anima_cli {
namespace {

struct contacts_options {
    std::string input, plot, up;
    std::vector<std::string> feet;
    bool json = false;
};

json intervals_json(const std::vector<anima::frame_interval>& runs) {
    json out = json::array();
    for (const auto& r : runs) out.push_back({r.first, r.last});
    return out;
}

std::string intervals_text(const std::vector<anima::frame_interval>& runs, double dt) {
    if (runs.empty()) return "none";
    std::string out;
    for (const auto& r : runs)
        out += (out.empty() ? "" : ", ") + std::to_string(r.first) + "-" + std::to_string(r.last) + " (" +
               format_number(static_cast<double>(r.frames()) * dt, 3) + " s)";
    return out;
}

/// Each foot's rise above its standing height against time, contact frames
/// as bars under its curve, airborne phases shaded across the plot.
void write_plot(const std::string& path, const std::string& name, const anima::contact_set<double>& s) {
    static const char* const colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};
    const std::size_t frames = s.airborne.size(), feet = s.feet.size();
    const double w = 900, left = 70, right = 20, top = 50, plot_h = 260, bar_h = 14, bottom = 60;
    const double h = top + plot_h + 20 + static_cast<double>(feet) * (bar_h + 6) + bottom;
    double peak = 0.05;
    for (const auto& f : s.feet)
        for (const double r : f.rise) peak = std::max(peak, r);
    const double seconds = static_cast<double>(std::max<std::size_t>(frames, 2) - 1) * s.frame_time;
    const auto x_of = [&](double t) { return left + (w - left - right) * t / seconds; };
    const auto y_of = [&](double r) { return top + plot_h * (1 - std::max(0.0, r) / peak); };
    svg_document svg(w, h, "Foot contacts of " + name);
    svg.rect(0, 0, w, h, "#ffffff");
    svg.text(w / 2, 24, "Foot contacts of " + name + " (" + std::to_string(frames) + " frames)", 15, "#222", "middle", true);
    for (const auto& phase : s.airborne_phases)
        svg.rect(x_of(static_cast<double>(phase.first) * s.frame_time), top,
                 std::max(1.0, x_of(static_cast<double>(phase.last + 1) * s.frame_time) - x_of(static_cast<double>(phase.first) * s.frame_time)),
                 plot_h, "#fdebd0");
    for (int k = 0; k <= 4; ++k) {
        const double r = peak * k / 4;
        svg.line(left, y_of(r), w - right, y_of(r), "#e4e4e4", 1);
        svg.text(left - 6, y_of(r) + 4, format_number(r, 2), 11, "#444", "end");
    }
    const double tick = seconds > 8 ? 2 : seconds > 4 ? 1 : seconds > 1.5 ? 0.5 : 0.1;
    for (double t = 0; t <= seconds + 1e-9; t += tick) {
        svg.line(x_of(t), top + plot_h, x_of(t), top + plot_h + 4, "#444", 1);
        svg.text(x_of(t), h - bottom + 16, format_number(t, 3), 11, "#444", "middle");
    }
    svg.line(left, top + plot_h, w - right, top + plot_h, "#444", 1);
    svg.line(left, top, left, top + plot_h, "#444", 1);
    svg.text(left, top - 8, "rise above standing height (body heights)", 12, "#222", "start");
    svg.text(w / 2, h - 18, "time (s); shaded: airborne", 12, "#222", "middle");
    for (std::size_t i = 0; i < feet; ++i) {
        const auto& foot = s.feet[i];
        const char* colour = colours[i % 4];
        std::string points;
        for (std::size_t f = s.lead_in; f < frames; ++f)
            points += svg_number(x_of(static_cast<double>(f) * s.frame_time)) + "," + svg_number(y_of(foot.rise[f])) + " ";
        svg.raw("<polyline fill=\"none\" stroke=\"" + std::string(colour) + "\" stroke-width=\"1.5\" points=\"" + points + "\"/>");
        const double y = top + plot_h + 20 + static_cast<double>(i) * (bar_h + 6);
        svg.text(left - 6, y + bar_h - 3, foot.name, 11, colour, "end");
        for (const auto& run : foot.contacts)
            svg.rect(x_of(static_cast<double>(run.first) * s.frame_time), y,
                     std::max(1.0, x_of(static_cast<double>(run.last + 1) * s.frame_time) - x_of(static_cast<double>(run.first) * s.frame_time)),
                     bar_h, colour);
    }
    write_text_file(path, svg.str());
}

void run_contacts(const contacts_options& o) {
    check_outputs({{"--plot", &o.plot}});
    const clip_t c = load_clip(o.input);
    anima::contact_params<double> p;
    if (!o.up.empty()) p.up = parse_signed_axis(o.up);
    p.feet = o.feet;
    const auto s = anima::find_contacts(c, p);
    const auto skate = anima::foot_skate(s);
    if (!o.plot.empty()) write_plot(o.plot, file_name(o.input), s);
    if (o.json) {
        json feet = json::array();
        for (const auto& f : s.feet)
            feet.push_back({{"joint", f.name}, {"contacts", intervals_json(f.contacts)},
                            {"skate_median", anima::foot_skate(f).median}});
        print_json({{"input", o.input},
                    {"frames", c.frames()},
                    {"frame_time", c.frame_time()},
                    {"up", anima::to_string(s.up)},
                    {"body_height", s.body_height},
                    {"lead_in", s.lead_in},
                    {"speed_on", s.speed_on},
                    {"airborne", intervals_json(s.airborne_phases)},
                    {"feet", feet},
                    {"skate", {{"median", skate.median}, {"mean", skate.mean}, {"max", skate.max}, {"samples", skate.samples}}}});
        return;
    }
    const double dt = c.frame_time();
    std::cout << file_name(o.input) << ": " << c.frames() << " frames, up " << anima::to_string(s.up) << ", body height "
              << format_number(s.body_height, 4) << " units";
    if (s.lead_in) std::cout << ", frames 0-" << s.lead_in - 1 << " left out (rest pose)";
    std::cout << "\n";
    for (const auto& f : s.feet) std::cout << "  " << f.name << " planted: " << intervals_text(f.contacts, dt) << "\n";
    std::cout << "  airborne: " << intervals_text(s.airborne_phases, dt) << "\n";
    std::cout << "  foot skate (planted feet): median " << format_number(skate.median, 3) << ", max "
              << format_number(skate.max, 3) << " body heights/s\n";
}

}  // namespace
}  // namespace anima_cli

void register_contacts(CLI::App& app) {
    using namespace anima_cli;
    auto opts = std::make_shared<contacts_options>();
    CLI::App* sub = app.add_subcommand("contacts", "Foot contacts, airborne phases and foot skate of a clip");
    sub->add_option("CLIP", opts->input, "BVH clip")->required()->type_name("CLIP.bvh");
    sub->add_option("--foot", opts->feet, "A foot joint (repeat for each; default: found by name or as the lowest leaves)")
        ->type_name("NAME");
    sub->add_option("--up", opts->up, "Up axis (default: guessed from the skeleton)")
        ->check(signed_axis_validator())
        ->type_name("AXIS");
    sub->add_option("--plot", opts->plot, "Plot each foot's height and contacts against time (SVG)")->type_name("OUT.svg");
    sub->add_flag("--json", opts->json, "Print a JSON object instead of text");
    sub->callback([opts] { run_contacts(*opts); });
}
