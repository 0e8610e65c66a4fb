// anima transition A.bvh B.bvh --at FRAME: the variable-timing transition from
// frame FRAME of A to frame --to of B (or one of the baselines), written as
// one clip A[..FRAME] + transition + B placed where the transition ends.
#include "commands.hpp"
#include "common.hpp"
#include "svg_chart.hpp"
#include "view_page.hpp"

#include <CLI/CLI.hpp>

#include <anima/motion/contacts.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iostream>
#include <string>
#include <vector>

namespace anima_cli {
namespace {

struct transition_options {
    std::string a, b, output, view, feet_plot, method = "variable", timing = "velocity";
    std::size_t at = 0, to = 0;
    double min_duration = 0.1, max_duration = 1.2, crossfade = 0.3, halflife = 0.1, root_speed_band = anima::transition_feet_params<double>{}.root_speed_band;
    bool json = false, no_plant_feet = false, root_from_feet = true;
};

/// --feet-plot: each foot's height above its standing height and, while it
/// is on the ground, its horizontal speed (the skate), through the window
/// and half a second either side, as the method left them and planted.
void write_feet_plot(const std::string& path, const std::string& title, const anima::joined_clip<double>& before,
                     const anima::joined_clip<double>* planted, double ratio_before, double ratio_after) {
    static const char* const colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};
    anima::contact_params<double> p;
    p.use_speed = false;  // on the ground by height, as plant_feet finds them: sliding counts
    const auto cb = anima::find_contacts(before.motion, p);
    const auto ca = planted ? anima::find_contacts(planted->motion, p) : cb;
    const double dt = before.motion.frame_time();
    const std::size_t n = before.motion.frames(), margin = static_cast<std::size_t>(std::lround(0.5 / dt));
    const std::size_t first = before.start_frame > margin ? before.start_frame - margin : 0;
    const std::size_t last = std::min(n - 1, before.end_frame + margin);
    // The speed axis fits the window: a foot that touches down or lifts off
    // outside it moves fast near the ground and would flatten the skate.
    double rise_peak = 0.02, speed_peak = 0.1;
    for (const auto* s : {&cb, &ca})
        for (const auto& foot : s->feet)
            for (std::size_t f = first; f <= last; ++f) {
                rise_peak = std::max(rise_peak, foot.rise[f]);
                if (foot.in_contact[f] && f >= before.start_frame && f <= before.end_frame)
                    speed_peak = std::max(speed_peak, foot.speed[f]);
            }
    std::string sub = "foot skate in the window: " + format_fixed(ratio_before, 2) + "x the clips' own";
    if (planted) sub += " as the method left it, " + format_fixed(ratio_after, 2) + "x planted";
    svg_chart chart(900, title, sub, 80, 20);
    const double t0 = static_cast<double>(first) * dt, t1 = static_cast<double>(last) * dt;
    const chart_panel rise = chart.panel(190, t0, t1, 0, rise_peak * 1.05, "foot height above standing (body heights)");
    chart.skip(28);
    const chart_panel speed = chart.panel(190, t0, t1, 0, speed_peak * 1.05,
                                          "horizontal speed on the ground: skate (body heights/s)");
    const double window_start = static_cast<double>(before.start_frame) * dt;
    for (const chart_panel* panel : {&rise, &speed}) {
        panel->shade(window_start, static_cast<double>(before.end_frame) * dt, "#fdebd0");
        panel->y_axis(4);
    }
    chart.x_axis(speed, 8, "time in the joined clip (s); shaded: the transition window");
    std::vector<legend_entry> legend;
    for (std::size_t i = 0; i < cb.feet.size(); ++i) {
        const char* colour = colours[i % 4];
        for (const bool dashed : {true, false}) {
            if (dashed && !planted) continue;
            const auto& foot = (dashed || !planted ? cb : ca).feet[i];
            std::vector<double> skate = foot.speed;  // on the ground only
            for (std::size_t f = 0; f < skate.size(); ++f)
                if (!foot.in_contact[f]) skate[f] = std::nan("");
            rise.series(foot.rise, 0, dt, colour, dashed ? 1.2 : 1.8, dashed ? mark::dashed : mark::line);
            speed.series(skate, 0, dt, colour, dashed ? 1.2 : 1.8, dashed ? mark::dashed : mark::line);
        }
        legend.push_back({colour, cb.feet[i].name});
    }
    chart.legend(legend, planted ? "dashed: as the method left them; solid: planted" : "");
    write_text_file(path, chart.str());
}

/// The text report of anima transition (what --json prints, for people).
void print_transition(const transition_options& o, const json& out, const std::string& page_written) {
    std::cout << o.method << " transition " << file_name(o.a) << " frame " << o.at << " -> " << file_name(o.b)
              << " frame " << o.to << ": " << format_fixed(out["duration"].get<double>(), 3) << " s, frames "
              << out["start_frame"].get<std::size_t>() << ".." << out["end_frame"].get<std::size_t>() << " of "
              << out["frames"].get<std::size_t>() << "\n";
    if (o.method == "variable") {
        std::cout << "classes: " << out["classes"]["a"].get<std::string>() << " -> "
                  << out["classes"]["b"].get<std::string>() << "; parameter "
                  << out["parameter"].get<std::string>() << "; root path " << out["root_path"].get<std::string>()
                  << "\nT = max t_i over the key joints = " << format_fixed(out["unclamped_duration"].get<double>(), 3)
                  << " s (" << out["limiting_joint"].get<std::string>() << "), clamped to ["
                  << format_number(o.min_duration) << ", " << format_number(o.max_duration) << "] s\n";
        std::cout << "  joint            angle(rad)  speed A  speed B   t_i(s)  method\n";
        for (const auto& j : out["joints"]) {
            if (!j["key"].get<bool>()) continue;
            std::string name = j["name"].get<std::string>();
            name.resize(std::max<std::size_t>(name.size(), 16), ' ');
            std::cout << "  " << name << ' ' << format_fixed(j["angle"].get<double>(), 3) << "       "
                      << format_fixed(j["speed_a"].get<double>(), 2) << "     " << format_fixed(j["speed_b"].get<double>(), 2)
                      << "    " << format_fixed(j["t"].get<double>(), 3) << "   " << j["method"].get<std::string>()
                      << '\n';
        }
    }
    std::cout << "foot skate in the window: " << format_fixed(out["foot_skate"]["ratio"].get<double>(), 2) << "x the clips' own";
    if (!o.no_plant_feet) std::cout << " (" << format_fixed(out["foot_skate_unplanted"]["ratio"].get<double>(), 2) << "x before planting)";
    std::cout << "\nroot's ground speed in the window: at least " << format_fixed(out["root_speed"]["ratio"].get<double>(), 2)
              << "x the slower end's (" << format_number(out["root_speed"]["min"].get<double>(), 3) << " of "
              << format_number(out["root_speed"]["ends"].get<double>(), 3) << " m/s)\n";
    if (!o.output.empty()) report_written(o.output + " (skeleton and offsets of " + file_name(o.a) + ")");
    if (!o.feet_plot.empty()) report_written(o.feet_plot + ": feet through the window, before and after planting");
    if (!o.view.empty()) report_written(page_written);
}

void run_transition(const transition_options& o) {
    check_outputs({{"--output", &o.output}, {"--view", &o.view}, {"--feet-plot", &o.feet_plot}});
    const clip_t a = load_clip(o.a);
    const clip_t b = load_clip(o.b);
    check_frame_in(o.at, a.frames(), o.a, "--at");
    check_frame_in(o.to, b.frames(), o.b, "--to");
    anima::check_same_hierarchy(a.skeleton(), b.skeleton());
    if (o.min_duration > o.max_duration) throw failure("--min-duration is larger than --max-duration");
    // The in-between frames of the shortest transition allowed (the longest
    // depends on the motion: the library clamps it to --max-duration).
    if (o.method == "variable")
        check_request_memory(o.min_duration / a.frame_time(), bytes_per_frame(a.skeleton()),
                             "a transition of at least " + format_number(o.min_duration) + " s at " +
                                 format_number(1 / a.frame_time()) + " frames per second",
                             "--min-duration");

    anima::transition_between_params<double> p;
    p.method = anima::parse_enum<anima::transition_method>(o.method);
    p.variable.timing.min_duration = o.min_duration;
    p.variable.timing.max_duration = o.max_duration;
    p.variable.timing.model = anima::parse_enum<anima::timing_model>(o.timing);
    p.crossfade_time = o.crossfade;
    p.halflife = o.halflife;
    p.plant_feet = !o.no_plant_feet;
    p.feet.root_from_feet = o.root_from_feet;
    p.feet.root_speed_band = o.root_speed_band;
    const auto r = anima::transition_between(a, o.at, b, o.to, p);
    const anima::joined_clip<double>& joined = r.joined;

    json out = {{"a", o.a}, {"b", o.b}, {"at", o.at}, {"to", o.to}, {"method", o.method}};
    // The variable method's own T; a baseline's window, as measure_transition has it.
    out["duration"] = r.variable ? r.variable->duration : r.quality.length;
    if (const auto& t = r.variable) {
        out["unclamped_duration"] = t->timing.unclamped;
        out["limiting_joint"] = a.skeleton()[t->timing.limiting_joint].name;
        out["classes"] = {{"a", anima::to_string(t->class_a.type)}, {"b", anima::to_string(t->class_b.type)}};
        out["parameter"] = anima::to_string(t->parameter);
        out["root_path"] = t->flight ? "Eq 13 (gravity)" : p.variable.continuous_root ? "Hermite to B's velocity" : "Eq 12";
        json joints = json::array();
        for (const auto& jt : t->timing.joints)
            joints.push_back({{"name", a.skeleton()[jt.joint].name},
                              {"role", anima::to_string(jt.role)},
                              {"key", jt.key},
                              {"angle", jt.angle},
                              {"speed_a", jt.speed_a},
                              {"speed_b", jt.speed_b},
                              {"t", jt.time},
                              {"method", anima::to_string(t->methods[jt.joint])}});
        out["joints"] = joints;
    }
    const auto skate = [](const anima::transition_quality<double>& q) {
        return json{{"window", q.foot_skate_window}, {"clips", q.foot_skate_clips}, {"ratio", q.foot_skate_ratio}};
    };
    out["feet_planted"] = p.plant_feet;
    out["root_from_feet"] = p.plant_feet && o.root_from_feet;
    out["foot_skate"] = skate(r.quality);
    out["root_speed"] = {{"min", r.quality.root_speed_min},
                         {"ends", r.quality.root_speed_ends},
                         {"ratio", r.quality.root_speed_ratio}};
    out["root_speed_band"] = p.plant_feet ? o.root_speed_band : 0.0;
    if (p.plant_feet) out["foot_skate_unplanted"] = skate(r.unplanted_quality);
    if (!o.feet_plot.empty()) {
        write_feet_plot(o.feet_plot,
                        "Feet through the " + o.method + " transition " + file_name(o.a) + " frame " + std::to_string(o.at) +
                            " -> " + file_name(o.b) + " frame " + std::to_string(o.to),
                        r.unplanted, p.plant_feet ? &joined : nullptr, r.unplanted_quality.foot_skate_ratio,
                        r.quality.foot_skate_ratio);
        out["feet_plot"] = o.feet_plot;
    }
    out["start_frame"] = joined.start_frame;
    out["end_frame"] = joined.end_frame;
    out["frames"] = joined.motion.frames();
    out["frame_time"] = joined.motion.frame_time();
    out["offsets_from"] = o.a;  // the output uses A's skeleton
    if (!o.output.empty()) {
        write_text_file(o.output, anima::format_bvh(joined.motion));
        out["output"] = o.output;
    }

    std::string page_written;
    if (!o.view.empty()) {
        // A, B and the joined clip; the switch, the arrival and the window marked.
        view_page page;
        page.title = o.method + " transition " + file_name(o.a) + " frame " + std::to_string(o.at) + " -> " +
                     file_name(o.b) + " frame " + std::to_string(o.to);
        page.clips = {{"A " + file_name(o.a), a}, {"B " + file_name(o.b), b}, {"joined", joined.motion}};
        page.markers = {{0, o.at, o.at, "transition", "A switches (--at)"},
                        {1, o.to, o.to, "transition", "B reached (--to)"},
                        {2, joined.start_frame, std::min(joined.end_frame, joined.motion.frames() - 1), "transition",
                         o.method + " transition, " + format_fixed(out["duration"].get<double>(), 3) + " s"}};
        page_written = write_view_page(o.view, page);
        out["view"] = o.view;
    }

    if (o.json) return print_json(out);
    print_transition(o, out, page_written);
}

}  // namespace
}  // namespace anima_cli

void register_transition(CLI::App& app) {
    using namespace anima_cli;
    const auto [sub, opts] = add_command<transition_options>(
        app, "transition", "Join two clips with a variable-timing hierarchical transition (or a baseline) at any frame",
        run_transition);
    sub->add_option("A", opts->a, "BVH clip playing first")->required();
    sub->add_option("B", opts->b, "BVH clip to switch to (same joint hierarchy)")->required();
    sub->add_option("--at", opts->at, "Frame of A at which the switch is triggered")
        ->required()
        ->type_name("FRAME")
        ->check(count_up_to(max_frames));
    add_setting(*sub, "--to", opts->to, "Frame of B the transition arrives at", count_up_to(max_frames))
        ->type_name("FRAME");
    sub->add_option("-o,--output", opts->output, "Write the joined clip to this BVH file")->type_name("OUT.bvh");
    add_view_option(*sub, opts->view, "A, B and the joined clip, the transition marked");
    sub->add_option("--feet-plot", opts->feet_plot,
                    "Plot each foot's height and skate through the window, before and after planting (SVG)")
        ->type_name("OUT.svg");
    add_setting(*sub, "--method", opts->method, "variable (the paper's method), cut, crossfade or inertialize",
                CLI::IsMember(anima::enum_name_list<anima::transition_method>()));
    add_setting(*sub, "--timing", opts->timing,
                "t_i from mean angular speeds (velocity) or accelerations (acceleration)",
                CLI::IsMember(anima::enum_name_list<anima::timing_model>()));
    add_setting(*sub, "--min-duration", opts->min_duration, "Shortest transition, seconds", non_negative_number());
    add_setting(*sub, "--max-duration", opts->max_duration, "Longest transition, seconds", non_negative_number());
    add_setting(*sub, "--crossfade-time", opts->crossfade, "Length of the crossfade baseline, seconds",
                non_negative_number());
    add_setting(*sub, "--halflife", opts->halflife, "Half-life of the inertialization spring, seconds",
                positive_number());
    sub->add_flag("--no-plant-feet", opts->no_plant_feet,
                  "Leave feet that are on the ground through the window sliding as the method left them");
    sub->add_flag("--root-from-feet,!--legs-only", opts->root_from_feet,
                  "Before the legs plant the feet, move the root through the window so that feet on the ground "
                  "stay put, within the clips' own root acceleration (default; --legs-only leaves the root's path "
                  "as the method made it)");
    add_setting(*sub, "--root-speed-band", opts->root_speed_band,
                "Planting: keep the root's ground speed through the window at least B x the slower end's (along "
                "their common way) and at most the faster end's / B, so that a run into a run does not stall; it "
                "costs skate (0: off)",
                number_in(0, 1))
        ->type_name("B");
    sub->add_flag("--json", opts->json, "Print a JSON object instead of text");
}
