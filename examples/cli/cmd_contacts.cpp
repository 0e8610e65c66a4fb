// anima contacts CLIP.bvh [--json] [--plot OUT.svg]: when each foot is
// planted, when the figure is airborne, and how fast planted feet slide
// (anima::find_contacts, anima::foot_skate).
#include "commands.hpp"
#include "common.hpp"
#include "svg_chart.hpp"

#include <anima/motion/contacts.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iostream>
#include <string>
#include <vector>

namespace anima_cli {
namespace {

struct contacts_options {
    std::string input, plot, up;
    std::vector<std::string> feet;
    bool json = false;
};

std::string intervals_text(const std::vector<anima::frame_interval>& runs, double dt) {
    if (runs.empty()) return "none";
    std::string out;
    for (const auto& r : runs)
        out += (out.empty() ? "" : ", ") + std::to_string(r.first) + "-" + std::to_string(r.last) + " (" +
               format_number(static_cast<double>(r.frames()) * dt, 3) + " s)";
    return out;
}

/// Each foot's rise above its standing height against time, airborne
/// phases shaded, and under it each foot's contact frames as bars.
void write_plot(const std::string& path, const std::string& name, const anima::contact_set<double>& s) {
    static const char* const colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};
    const std::size_t frames = s.airborne.size();
    const double dt = s.frame_time, seconds = static_cast<double>(std::max<std::size_t>(frames, 2) - 1) * dt;
    double peak = 0.05;
    for (const auto& f : s.feet)
        for (const double r : f.rise) peak = std::max(peak, r);
    svg_chart chart(900, "Foot contacts of " + name + " (" + std::to_string(frames) + " frames)");
    const chart_panel plot = chart.panel(260, 0, seconds, 0, peak, "rise above standing height (body heights)");
    for (const auto& phase : s.airborne_phases)
        plot.shade(static_cast<double>(phase.first) * dt, static_cast<double>(phase.last + 1) * dt, "#fdebd0");
    plot.y_axis(4);
    chart.skip(10);
    chart_panel axis = plot;
    for (std::size_t i = 0; i < s.feet.size(); ++i) {
        std::vector<double> rise = s.feet[i].rise;
        std::fill_n(rise.begin(), std::min(s.lead_in, rise.size()), std::nan(""));  // the rest pose left out
        plot.series(rise, 0, dt, colours[i % 4]);
        axis = chart.panel(14, 0, seconds, 0, 1);
        chart.svg().text(axis.left - 6, axis.bottom() - 3, s.feet[i].name, 11, colours[i % 4], "end");
        for (const auto& run : s.feet[i].contacts)
            axis.shade(static_cast<double>(run.first) * dt, static_cast<double>(run.last + 1) * dt, colours[i % 4]);
    }
    chart.x_axis(axis, 8, "time (s); shaded: airborne");
    write_text_file(path, chart.str());
}

void run_contacts(const contacts_options& o) {
    check_outputs({{"--plot", &o.plot}});
    const clip_t c = load_clip(o.input);
    anima::contact_params<double> p;
    if (!o.up.empty()) p.up = parse_signed_axis(o.up);
    p.feet = o.feet;
    if (p.feet.empty() && anima::find_feet(c.skeleton(), p.up ? *p.up : anima::guess_up_axis(c.skeleton()).up).empty())
        throw failure("'" + o.input + "' has no joint found as a foot (by name or as a lowest leaf): name the feet with --foot");
    const auto s = anima::find_contacts(c, p);
    const auto skate = anima::foot_skate(s);
    if (!o.plot.empty()) write_plot(o.plot, file_name(o.input), s);
    if (o.json) {
        json feet = json::array();
        for (const auto& f : s.feet)
            feet.push_back({{"joint", f.name}, {"contacts", to_json(f.contacts)},
                            {"skate_median", anima::foot_skate(f).median}});
        print_json({{"input", o.input},
                    {"frames", c.frames()},
                    {"frame_time", c.frame_time()},
                    {"up", anima::to_string(s.up)},
                    {"body_height", s.body_height},
                    {"lead_in", s.lead_in},
                    {"speed_on", s.speed_on},
                    {"airborne", to_json(s.airborne_phases)},
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
    if (!o.plot.empty()) report_written(o.plot + ": each foot's rise above standing height, planted runs shaded");
}

}  // namespace
}  // namespace anima_cli

void register_contacts(CLI::App& app) {
    using namespace anima_cli;
    const auto [sub, opts] = add_command<contacts_options>(
        app, "contacts", "Foot contacts, airborne phases and foot skate of a clip", run_contacts);
    sub->add_option("CLIP", opts->input, "BVH clip")->required()->type_name("CLIP.bvh");
    sub->add_option("--foot", opts->feet, "A foot joint (repeat for each; default: found by name or as the lowest leaves)")
        ->type_name("NAME");
    add_up_option(*sub, opts->up, "Up axis (default: guessed from the skeleton)");
    sub->add_option("--plot", opts->plot, "Plot each foot's height and contacts against time (SVG)")->type_name("OUT.svg");
    sub->add_flag("--json", opts->json, "Print a JSON object instead of text");
}
