// anima info FILE.bvh [--json]: the skeleton, timing, channels and the
// guessed up axis and units of a BVH file.
#include "commands.hpp"
#include "common.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstddef>
#include <iostream>
#include <string>

namespace anima_cli {
namespace {

struct info_options {
    std::string input;
    bool json = false;
};

json vector_json(const vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

void run_info(const info_options& o) {
    const document_t doc = load_bvh_document(o.input);
    const clip_t clip = anima::to_clip(doc);
    const skeleton_t& sk = doc.skeleton;
    const std::size_t dof_view = anima::make_dof_layout(clip, anima::dof_reference::identity).size();
    const anima::up_axis_guess up = anima::guess_up_axis(sk);
    const anima::unit_guess units = anima::guess_units(sk, up.up);
    std::size_t end_sites = 0;
    for (const auto& j : sk.joints()) end_sites += j.end_site ? 1 : 0;

    if (o.json) {
        json joints = json::array();
        for (const auto& j : sk.joints()) {
            json channels = json::array();
            for (anima::channel c : j.channels) channels.push_back(std::string(anima::to_string(c)));
            joints.push_back({{"name", j.name},
                              {"parent", j.parent < 0 ? json(nullptr) : json(sk[static_cast<std::size_t>(j.parent)].name)},
                              {"channels", channels},
                              {"offset", vector_json(j.offset)},
                              {"end_site", j.end_site ? vector_json(*j.end_site) : json(nullptr)}});
        }
        print_json({{"file", o.input},
                    {"frames", doc.frames},
                    {"frame_time", doc.frame_time},
                    {"frame_rate", clip.frame_rate()},
                    {"duration", clip.duration()},
                    {"joints", joints},
                    {"end_sites", end_sites},
                    {"dofs", doc.channels()},
                    {"dof_view", dof_view},
                    {"rotation_order", rotation_order_summary(sk)},
                    {"up_axis", {{"axis", anima::to_string(up.up)}, {"confident", up.confident}}},
                    {"units",
                     {{"name", units.name},
                      {"metres_per_unit", units.metres_per_unit},
                      {"height", units.height},
                      {"height_metres", units.height * units.metres_per_unit},
                      {"confident", units.confident}}}});
        return;
    }

    std::cout << o.input << '\n';
    // Indentation stops at max_indent levels (deeper joints say their depth),
    // so the text of a deep hierarchy stays linear in its size.
    constexpr std::size_t max_indent = 32;
    for (const auto& [j, depth] : anima::depth_first_order(sk)) {
        const std::string indent(2 * (std::min(depth, max_indent) + 1), ' ');
        std::cout << indent;
        if (depth > max_indent) std::cout << "(depth " << depth << ") ";
        std::cout << sk[j].name;
        if (!sk[j].channels.empty()) std::cout << "  [" << channel_list(sk[j].channels) << ']';
        std::cout << '\n';
        if (sk[j].end_site) std::cout << indent << "  End Site\n";
    }
    std::string orders = rotation_order_summary(sk);
    if (orders == "mixed") orders += " (" + join(anima::rotation_orders(sk)) + ")";
    const std::size_t roots = static_cast<std::size_t>(
        std::count_if(sk.joints().begin(), sk.joints().end(), [](const auto& j) { return j.parent < 0; }));

    std::cout << '\n';
    std::cout << "joints        " << sk.size() << " (" << roots << (roots == 1 ? " root, " : " roots, ") << end_sites
              << " end sites)\n";
    std::cout << "frames        " << doc.frames << '\n';
    std::cout << "frame time    " << format_number(doc.frame_time) << " s (" << format_number(clip.frame_rate())
              << " frames per second)\n";
    std::cout << "duration      " << format_number(clip.duration()) << " s\n";
    std::cout << "DOFs          " << doc.channels() << " channels, " << dof_view << " in the DOF view\n";
    std::cout << "rotations     " << orders << '\n';
    std::cout << "up axis       " << anima::to_string(up.up)
              << (up.confident ? " (from where the head, neck or feet are)"
                               : " (assumed: no head, neck, foot, toe or ankle joint found)")
              << '\n';
    std::cout << "units         " << units.name;
    if (units.height > 0)
        std::cout << ", " << format_number(units.metres_per_unit) << " m per unit: the figure is "
                  << format_number(units.height, 4) << " units = " << format_number(units.height * units.metres_per_unit, 3)
                  << " m tall" << (units.confident ? "" : " (not a typical human height: unsure)");
    else
        std::cout << " (the figure has no height along " << anima::to_string(up.up) << ')';
    std::cout << '\n';
}

}  // namespace
}  // namespace anima_cli

void register_info(CLI::App& app) {
    const auto [sub, opts] = anima_cli::add_command<anima_cli::info_options>(
        app, "info", "Print a BVH file's skeleton, frame count and rate, channels, and guessed up axis and units",
        anima_cli::run_info);
    sub->add_option("FILE", opts->input, "BVH file")->required()->type_name("PATH");
    sub->add_flag("--json", opts->json, "Print one JSON object instead of text");
}
