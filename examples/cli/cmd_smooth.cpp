// anima smooth IN.bvh --seams F1,F2,... -o OUT.bvh: Poisson smoothing of a
// stitched clip (Eq 14). The jump at each seam (a frame where a new piece
// starts) is replaced by the trend of the neighbouring frame differences and
// the clip is rebuilt from those differences with its first and last frames
// fixed, per DOF along time (1d) or as the frames x DOF image (2d).
#include "commands.hpp"
#include "common.hpp"

#include <anima/poisson.hpp>
#include <anima/texture/motion_smoothing.hpp>

#include <CLI/CLI.hpp>

#include <iostream>
#include <string>
#include <vector>

namespace anima_cli {
namespace {

struct smooth_options {
    std::string input, output, mode = "1d", solver = "multigrid", dof_sides = "neumann";
    std::vector<std::size_t> seams;
    std::size_t radius = 0;
    bool json = false;
};

void run_smooth(const smooth_options& o) {
    check_outputs({{"--output", &o.output}});
    const clip_t c = load_clip(o.input);
    for (std::size_t s : o.seams)
        if (s < 1 || s + 1 > c.frames())
            throw failure("--seams: frame " + std::to_string(s) + " is outside 1.." +
                          std::to_string(c.frames() ? c.frames() - 1 : 0) + " of '" + o.input + "' (" +
                          std::to_string(c.frames()) + " frames; a seam is the first frame after a jump)");
    anima::seam_smoothing_params<double> prm;
    prm.form = anima::parse_seam_smoothing_form(o.mode);
    prm.solver = anima::parse_poisson_method(o.solver);
    prm.radius = o.radius;
    prm.dof_sides = anima::parse_boundary(o.dof_sides);
    const auto result = anima::smooth_seams(c, o.seams, prm);

    const auto measures = anima::measure_smoothing(c, result.motion, o.seams);
    const auto& layout = measures.layout;
    const double drift_rot = anima::degrees(measures.largest_change.rotation);
    const double drift_tr = measures.largest_change.translation;

    json seams = json::array();
    for (std::size_t i = 0; i < measures.seams.size(); ++i) {
        const auto &b = measures.before[i], &a = measures.after[i];
        seams.push_back({{"frame", measures.seams[i]},
                         {"rotation_jump_before", anima::degrees(b.rotation)},
                         {"rotation_jump_after", anima::degrees(a.rotation)},
                         {"translation_jump_before", b.translation},
                         {"translation_jump_after", a.translation},
                         {"worst_dof", b.rotation > 0 ? layout.name(c.skeleton(), b.worst_rotation_dof) : ""}});
    }
    json out = {{"input", o.input},
                {"frames", c.frames()},
                {"dofs", layout.size()},
                {"mode", anima::to_string(prm.form)},
                {"solver", anima::to_string(prm.solver)},
                {"radius", o.radius},
                {"seams", seams},
                {"largest_change", {{"rotation", drift_rot}, {"translation", drift_tr}}}};
    out.update(to_json(result.stats));
    if (prm.form == anima::seam_smoothing_form::image) out["dof_sides"] = anima::to_string(prm.dof_sides);
    if (!o.output.empty()) {
        write_text_file(o.output, anima::format_bvh(result.motion));
        out["output"] = o.output;
    }
    warn_unconverged(result.stats);
    if (o.json) return print_json(out);
    std::cout << "smoothed " << measures.seams.size() << " seam" << (measures.seams.size() == 1 ? "" : "s") << " of "
              << file_name(o.input) << " (" << c.frames() << " frames, " << layout.size() << " DOFs), "
              << anima::to_string(prm.form) << " form, " << anima::to_string(prm.solver) << ": "
              << result.stats.solves << " solve" << (result.stats.solves == 1 ? "" : "s") << ", relative residual <= "
              << format_number(result.stats.relative_residual, 3) << "\n";
    std::cout << "  seam   rotation jump (deg)   translation jump   largest before\n";
    for (const auto& s : seams)
        std::cout << "  " << s["frame"].get<std::size_t>() << "    " << format_fixed(s["rotation_jump_before"].get<double>(), 3)
                  << " -> " << format_fixed(s["rotation_jump_after"].get<double>(), 3) << "     "
                  << format_fixed(s["translation_jump_before"].get<double>(), 3) << " -> "
                  << format_fixed(s["translation_jump_after"].get<double>(), 3) << "     "
                  << s["worst_dof"].get<std::string>() << '\n';
    std::cout << "largest change of any frame: " << format_fixed(drift_rot, 3) << " deg, " << format_fixed(drift_tr, 3)
              << " units\n";
    if (!o.output.empty()) report_written(o.output);
}

}  // namespace
}  // namespace anima_cli

void register_smooth(CLI::App& app) {
    using namespace anima_cli;
    const auto [sub, opts] = add_command<smooth_options>(
        app, "smooth",
        "Remove the jumps at the seams of a stitched clip by Poisson smoothing (Eq 14), keeping its detail",
        run_smooth);
    sub->add_option("IN", opts->input, "BVH clip")->required();
    sub->add_option("--seams", opts->seams, "Frames where a new piece starts (the jump is between F-1 and F)")
        ->required()
        ->delimiter(',')
        ->check(count_up_to(max_frames))
        ->type_name("F1,F2,...");
    sub->add_option("-o,--output", opts->output, "Write the smoothed clip to this BVH file")->type_name("OUT.bvh");
    add_setting(*sub, "--mode", opts->mode,
                "1d: each DOF along time; 2d: the frames x DOF matrix as an image (the paper)",
                CLI::IsMember(anima::enum_name_list<anima::seam_smoothing_form>()));
    add_setting(*sub, "--solver", opts->solver, "multigrid or dst",
                CLI::IsMember(anima::enum_name_list<anima::poisson_method>()));
    add_setting(*sub, "--radius", opts->radius, "Also replace this many frame differences on each side of a seam",
                count_up_to(max_frames));
    add_setting(*sub, "--dof-sides", opts->dof_sides,
                "2d mode: beyond the first and last DOF, neumann (free) or dirichlet (the paper's zero padding)",
                CLI::IsMember(anima::enum_name_list<anima::boundary>()));
    sub->add_flag("--json", opts->json, "Print a JSON object instead of text");
}
