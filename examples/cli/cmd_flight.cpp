// anima flight KEYS.json | --example somersault: the spacetime flight
// objective T^-1 * integral of sum F_i^2 (F1..F6 the root's generalised
// forces). Model (2) moves the key times, model (1) also the key poses within
// tolerances. Writes the motion (-o), a plot of the key times before and
// after (--plot, the paper's Fig 7) and the figures (--json).
#include "commands.hpp"
#include "common.hpp"
#include "svg_chart.hpp"
#include "view_page.hpp"

#include <anima/core/stopwatch.hpp>
#include <anima/flight.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace anima_cli {

/// The CMU 31-joint hierarchy as BVH text (generated from examples/data).
extern const char* const cmu31_skeleton_bvh;

namespace {

struct flight_options {
    std::string keys_path, example, clip, output, plot, view;
    int model = 2, iterations = 100, quadrature = 4;
    std::size_t keys = 8;
    double body_mass = 70;
    bool json = false, progress = false;
};

/// Fig 7: key index against key time, initial (down triangles) and
/// optimised (up triangles).
void write_plot(const std::string& path, const std::vector<double>& before, const std::vector<double>& after,
                const std::string& title) {
    const double keys = static_cast<double>(before.size());
    // Wide enough for the title (about 0.6 em a character, 14 px bold).
    svg_chart chart(std::max(640.0, 24 + 8.6 * static_cast<double>(title.size())), title, {}, 60, 20);
    const chart_panel p = chart.panel(300, 1, keys, 0, std::max(before.back(), after.back()), "time (s)");
    p.y_axis(4);
    for (std::size_t k = 0; k < before.size(); ++k) {
        p.marker(static_cast<double>(k + 1), before[k], mark::down, "#999999");
        p.marker(static_cast<double>(k + 1), after[k], mark::up, "#c0392b");
    }
    // Whole keys: steps of at least 1.
    chart.x_axis(p, static_cast<int>(std::min(keys - 1, 12.0)), "key frame");
    chart.legend({{"#999999", "initial timing", mark::down}, {"#c0392b", "optimised timing", mark::up}});
    write_text_file(path, chart.str());
}

// Work of a run, in evaluations of one joint's dynamics at one quadrature
// node with automatic derivatives (about 2.3 us each, measured): each
// iteration (anima::flight_work_per_iteration) takes one Jacobian and
// solves its normal equations (about 9000 flops a unit).
constexpr double max_flight_work = 4e6;  // about 10 s
constexpr double flops_per_work_unit = 9000;

/// Refuses up front a run that would need more than 1 GiB or, for keys read
/// from a file or a clip, more than max_flight_work with --iterations: both
/// grow with the square of the keys. The built-in example is the paper's
/// figure, whose model (1) takes about 40 s with progress shown: not refused.
void check_flight_size(const anima::flight_problem<double>& problem, const anima::flight_optimization_params<double>& p,
                       const flight_options& o) {
    const std::string keys = std::to_string(problem.key_count()) + " keys (model " + std::to_string(o.model) + ", " +
                             std::to_string(o.quadrature) + " quadrature points)";
    const double residuals = static_cast<double>(problem.residual_count());
    const double parameters = static_cast<double>(anima::flight_parameter_count(problem, p.model));
    check_request_memory(anima::flight_solver_bytes(problem, p.model), 1,
                         "flight: " + keys + ", a " + format_number(residuals) + " x " + format_number(parameters) +
                             " Jacobian,",
                         "the key count (KEYS.json or --keys) or --quadrature");
    const anima::flight_iteration_work iteration = anima::flight_work_per_iteration(problem, p.model);
    const double per_iteration = iteration.joint_evaluations + iteration.flops / flops_per_work_unit;
    const double work = per_iteration * (o.iterations + 1);
    if (!o.example.empty() || work <= max_flight_work) return;
    const double fit = std::floor(max_flight_work / per_iteration) - 1;
    throw failure("flight: " + keys + " need up to " + std::to_string(o.iterations + 1) + " Jacobians of " +
                  format_number(iteration.passes) + " passes over the " + std::to_string(problem.model().size()) +
                  "-joint body at " + format_number(residuals / 6) + " quadrature nodes, about " +
                  format_number(work, 3) + " joint evaluations (some " + format_number(work * 2.3e-6, 3) +
                  " s), more than the " + format_number(max_flight_work) + " allowed: " +
                  (fit >= 1 ? "give --iterations " + format_number(fit) + " or fewer, or use fewer keys"
                            : std::string("use fewer keys or a smaller --quadrature")));
}

void run_flight(const flight_options& o) {
    check_outputs({{"--output", &o.output}, {"--plot", &o.plot}, {"--view", &o.view}});
    if (!o.keys_path.empty() + !o.example.empty() + !o.clip.empty() != 1)
        throw CLI::ValidationError("flight", "give one of KEYS.json, --example somersault or --clip CLIP.bvh");
    const anima::flight_key_set_defaults<double> defaults{o.body_mass};
    std::optional<anima::clip_flight_keys<double>> from_clip;
    if (!o.clip.empty()) {
        anima::clip_flight_params<double> cp;
        cp.keys = o.keys;
        cp.body.body_mass = o.body_mass;
        from_clip = anima::flight_keys_from_clip(load_clip(o.clip), cp);
        from_clip->key_set.name = file_name(o.clip) + " (" + from_clip->key_set.name + ")";
    }
    auto in = from_clip ? from_clip->key_set
              : o.example.empty()
                  ? anima::read_flight_key_set<double>(o.keys_path, defaults)
                  : anima::somersault_key_set<double>(
                        anima::parse_bvh<double>(cmu31_skeleton_bvh, "cmu31_skeleton").skeleton(), defaults);
    in.settings.quadrature_points = o.quadrature;
    const anima::flight_problem<double> problem(in.model, in.keys, in.settings);
    anima::flight_optimization_params<double> params;
    params.model = o.model == 1 ? anima::flight_model::timing_and_poses : anima::flight_model::timing;
    params.solver.max_iterations = o.iterations;
    check_flight_size(problem, params, o);
    // Progress on request, and by itself once a run has taken 2 s.
    const anima::stopwatch timer;
    params.solver.on_iteration = [&](int iteration, double value) {
        const double seconds = timer.elapsed();
        if (o.progress || seconds > 2.0)
            std::cerr << "anima: flight: iteration " << iteration << ": objective " << format_number(2 * value, 6)
                      << " (" << format_number(seconds, 3) << " s)\n";
        return true;
    };
    if (o.progress || o.model == 1)
        std::cerr << "anima: flight: model (" << o.model << "), " << problem.key_count() << " keys, "
                  << (o.model == 1 ? problem.full_size() : problem.timing_size()) << " parameters\n";
    const auto r = anima::optimize_flight(problem, params);
    if (!std::isfinite(r.objective_initial) || !std::isfinite(r.objective_final))
        throw failure("the objective is not finite (" + format_number(r.objective_initial) + " -> " +
                      format_number(r.objective_final) + "): check the key times and root positions of " + in.name);
    // The drift is a diagnostic: where it is not defined the run goes on and says so.
    const auto drift_json = [](const std::optional<double>& d) { return d ? json(*d) : json(nullptr); };
    const auto drift_text = [](const std::optional<double>& d) { return d ? format_number(*d, 3) : std::string("not defined"); };

    constexpr double frame_time = 1.0 / 60.0;
    const auto clip_of = [&](const auto& solution) {
        return anima::flight_clip(problem, solution, in.skeleton, in.metres_per_unit, frame_time);
    };
    std::optional<clip_t> optimised;  // made once, for -o and --view
    if (!o.output.empty() || !o.view.empty()) optimised = clip_of(r.optimized);
    if (!o.output.empty()) write_text_file(o.output, anima::format_bvh(*optimised));
    std::string page_written;
    if (!o.view.empty()) {
        // The initial and the optimised timing side by side, each key marked.
        view_page page;
        page.title = "Flight of " + in.name + ": initial and optimised key times (model " + std::to_string(o.model) + ")";
        page.clips = {{"initial timing", clip_of(r.initial)}, {"optimised", *optimised}};
        for (std::size_t clip = 0; clip < 2; ++clip) {
            const auto& times = clip == 0 ? r.initial.times : r.optimized.times;
            const std::size_t last = page.clips[clip].motion.frames() - 1;
            for (std::size_t k = 0; k < times.size(); ++k) {
                const auto frame = std::min(last, static_cast<std::size_t>(std::llround(std::max(0.0, times[k]) / frame_time)));
                page.markers.push_back({clip, frame, frame, "key",
                                        "key " + std::to_string(k + 1) + " at " + format_fixed(times[k], 3) + " s"});
            }
        }
        page_written = write_view_page(o.view, page);
    }
    if (!o.plot.empty())
        write_plot(o.plot, r.initial.times, r.optimized.times,
                   "Key times of " + in.name + ": initial and optimised (model " + std::to_string(o.model) + ")");

    if (o.json) {
        json out;
        out["input"] = in.name;
        out["model"] = o.model;
        out["objective_initial"] = r.objective_initial;
        out["objective_final"] = r.objective_final;
        out["key_times_initial"] = r.initial.times;
        out["key_times_final"] = r.optimized.times;
        out["momentum_drift_initial"] = drift_json(r.momentum_drift_initial);
        out["momentum_drift_final"] = drift_json(r.momentum_drift_final);
        out["iterations"] = r.iterations;
        out["status"] = std::string(anima::to_string(r.status));
        out["seconds"] = r.seconds;
        if (from_clip) {
            out["airborne"] = {from_clip->phase.first, from_clip->phase.last};
            out["key_frames"] = from_clip->key_frames;
        }
        out["objective_history"] = r.history;
        if (!o.view.empty()) out["view"] = o.view;
        print_json(out);
        return;
    }
    std::cout << in.name << ": model (" << o.model << "), " << r.iterations << " iterations ("
              << anima::to_string(r.status) << "), " << format_number(r.seconds, 3) << " s\n";
    std::cout << "  objective T^-1 int sum F^2: " << format_number(r.objective_initial) << " -> "
              << format_number(r.objective_final) << "\n";
    std::cout << "  angular momentum drift about the centre of mass: " << drift_text(r.momentum_drift_initial)
              << " -> " << drift_text(r.momentum_drift_final);
    if (!r.momentum_drift_initial || !r.momentum_drift_final) std::cout << " (the mean angular momentum is zero)";
    std::cout << "\n";
    std::cout << "  key  time before  time after\n";
    for (std::size_t k = 0; k < r.initial.times.size(); ++k)
        std::cout << "  " << k + 1 << (k + 1 < 10 ? "    " : "   ") << format_fixed(r.initial.times[k], 3) << "        "
                  << format_fixed(r.optimized.times[k], 3) << "\n";
    if (!o.output.empty()) report_written(o.output + " (the optimised flight)");
    if (!o.plot.empty()) report_written(o.plot + ": initial and optimised key times");
    if (!o.view.empty()) report_written(page_written);
}

}  // namespace
}  // namespace anima_cli

void register_flight(CLI::App& app) {
    using namespace anima_cli;
    const auto [sub, opts] = add_command<flight_options>(
        app, "flight",
        "Optimise the key times (and poses) of a motion in flight: minimise T^-1 int sum F_i^2 over the root's "
        "generalised forces", run_flight);
    sub->add_option("KEYS", opts->keys_path, "Key set (JSON, see docs/flight.md)")->type_name("KEYS.json");
    sub->add_option("--example", opts->example, "A built-in key set instead of KEYS.json")
        ->check(CLI::IsMember({"somersault"}));
    sub->add_option("--clip", opts->clip, "Keys from the longest airborne phase of a recorded clip instead of KEYS.json")
        ->type_name("CLIP.bvh");
    add_setting(*sub, "--keys", opts->keys, "Keys placed on the airborne phase of --clip", integer_in(2, 1000));
    add_setting(*sub, "--model", opts->model, "1: key times and poses within tolerances; 2: key times only",
                CLI::IsMember({1, 2}));
    add_setting(*sub, "--iterations", opts->iterations, "Most Levenberg-Marquardt iterations", integer_in(0, 100000));
    add_setting(*sub, "--quadrature", opts->quadrature, "Gauss-Legendre points per key interval (1..5)",
                integer_in(1, 5));
    add_setting(*sub, "--body-mass", opts->body_mass, "Body mass in kg (when KEYS.json does not give one)",
                number_in(1, 1000));
    sub->add_option("-o,--output", opts->output, "Write the optimised motion (60 frames/s) to this BVH file")
        ->type_name("OUT.bvh");
    sub->add_option("--plot", opts->plot, "Plot initial and optimised key times (SVG)")->type_name("OUT.svg");
    add_view_option(*sub, opts->view, "the initial and the optimised timing, the keys marked");
    sub->add_flag("--progress", opts->progress, "Report every iteration on stderr (runs longer than 2 s always do)");
    sub->add_flag("--json", opts->json, "Print a JSON object instead of text");
}
