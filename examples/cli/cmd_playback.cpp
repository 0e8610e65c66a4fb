// anima playback IN.bvh --frames N: a new motion of N frames that plays the
// clip forwards and backwards, reversing at its turning candidates (adaptive
// probabilities of Eq 6, or fixed ones), or, for comparison, jumping between
// similar frames like a video texture.
#include "commands.hpp"
#include "common.hpp"
#include "view_page.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

namespace anima_cli {
namespace {

struct playback_options {
    std::string input, output, view, rotation_order, root = "accumulated";
    frame_range_options range;
    symmetry_options symmetry;
    std::size_t frames = 0, start = 0;
    std::uint64_t seed = 1;
    double gain = 1.25, penalty = 0.2;
    bool fixed = false, video_texture = false, json = false, plant_feet = true;
    CLI::Option* start_opt = nullptr;
};

/// "12, 80, 151, ... (85 in all)": the first few of a list of positions.
std::string some_positions(const std::vector<std::size_t>& positions, std::size_t shown = 8) {
    std::vector<std::string> items;
    for (std::size_t k = 0; k < std::min(shown, positions.size()); ++k) items.push_back(std::to_string(positions[k]));
    std::string out = join(items);
    if (positions.size() > shown) out += ", ... (" + std::to_string(positions.size()) + " in all)";
    return out;
}

/// "feet planted in N contact runs" or "feet not planted".
std::string planting_note(const playback_options& o, const json& out) {
    if (!o.plant_feet) return "feet not planted";
    return "feet planted in " + std::to_string(out.value("planted_runs", 0)) + " contact runs";
}

// The video texture's jump search compares every frame with every other
// (anima::video_texture_jumps): frames^2 distances of (DOFs + 8) steps each,
// measured at about 1e9 steps a second. This many take some 4 s.
constexpr double max_jump_search_steps = 4e9;

/// Refuses up front a clip too long for the quadratic jump search.
void check_jump_search(const motion_range& m) {
    // The features' columns: the DOF view's (no reference rotations needed to count them).
    const double frames = static_cast<double>(m.clip.frames());
    const double dofs = static_cast<double>(anima::make_dof_layout(m.clip, anima::dof_reference::identity).size());
    const double steps = frames * frames * (dofs + 8);
    if (steps <= max_jump_search_steps) return;
    const double most = std::floor(std::sqrt(max_jump_search_steps / (dofs + 8)));
    throw failure("--video-texture: the jump search compares all " + format_number(frames, 12) +
                  " frames with each other (" + format_number(frames * frames, 3) + " pairs of " + format_number(dofs) +
                  " DOFs, about " + format_number(steps, 3) + " steps), more than the " +
                  format_number(max_jump_search_steps) + " allowed: choose at most " + format_number(most, 12) +
                  " frames with --first and --last");
}

void run_playback(const playback_options& o) {
    check_outputs({{"--output", &o.output}, {"--view", &o.view}});
    const anima::symmetry_params<double> params = make_symmetry_params(o.symmetry);
    const motion_range m = load_motion_range(o.input, o.range);
    check_frames_memory(o.frames, m.clip.skeleton());
    if (o.video_texture) check_jump_search(m);
    const std::size_t n = m.clip.frames();
    const std::size_t last = m.first + n - 1;
    const double dt = m.clip.frame_time();
    const bool start_given = o.start_opt->count() > 0;
    if (start_given && (o.start < m.first || o.start > last))
        throw failure("--start " + std::to_string(o.start) + " is outside the frames used (" + std::to_string(m.first) +
                      ".." + std::to_string(last) + ")");
    const std::size_t start = start_given ? o.start - m.first : 0;

    anima::play_clip_params<double> p;
    p.method = o.video_texture ? anima::playback_method::video_texture
               : o.fixed       ? anima::playback_method::fixed
                               : anima::playback_method::adaptive;
    p.features.up = m.up;
    p.symmetry = params;
    p.playback.gain = o.gain;
    p.playback.turn_penalty = o.penalty;
    p.playback.seed = o.seed;
    p.playback.start_frame = start;
    p.render.resequence.root = anima::parse_root_path(o.root);
    p.render.plant_feet = o.plant_feet;
    p.make_clip = !o.output.empty() || o.json || !o.view.empty();
    anima::played_clip<double> played;
    try {
        played = anima::play_clip(m.clip, o.frames, p);
    } catch (const anima::invalid_argument& e) {
        if (std::string(e.what()).find("turning candidate") == std::string::npos) throw;
        throw failure("'" + o.input + "' (frames " + std::to_string(m.first) + ".." + std::to_string(last) + "): " +
                      e.what() + " (here --window, --candidate-window and --min-pairs)");
    }
    const std::vector<std::size_t>& stream = played.stream;

    const std::string mode = anima::to_string(p.method);
    json out = {{"input", o.input}, {"mode", mode}, {"seed", o.seed}, {"root", o.root},
                {"first", m.first}, {"last", last}, {"frames", o.frames}, {"frame_time", dt}};
    std::string summary;  // the text lines about turns or jumps
    if (o.video_texture) {
        out["metric"] = "l2";
        out["sigma"] = played.sigma;
        out["jumps"] = played.events;
        summary = std::to_string(played.events.size()) + " jumps" +
                  (played.events.empty() ? "" : " (after output frames " + some_positions(played.events) + ")");
    } else {
        json candidates = json::array();
        for (std::size_t i = 0; i < played.candidates.size(); ++i)
            candidates.push_back({{"frame", m.first + played.candidates[i].frame},
                                  {"probability", played.candidates[i].probability},
                                  {"final_probability", played.final_probabilities[i]}});
        out.update(settings_json(o.symmetry, params, n));
        if (!o.fixed) {
            out["gain"] = o.gain;
            out["penalty"] = o.penalty;
        }
        out["candidates"] = candidates;
        out["span"] = {m.first + played.first_turning_frame, m.first + played.last_turning_frame};
        out["turns"] = played.events;
        summary = std::to_string(played.candidates.size()) + " turning candidates (playback stays within frames " +
                  std::to_string(m.first + played.first_turning_frame) + ".." +
                  std::to_string(m.first + played.last_turning_frame) + "), " + std::to_string(played.events.size()) +
                  " turns" + (played.events.empty() ? "" : " (at output frames " + some_positions(played.events) + ")");
    }

    const auto& cov = played.coverage;
    const auto distinct = static_cast<std::size_t>(std::lround(cov.visited * static_cast<double>(n)));
    out["start"] = m.first + stream.front();
    out["coverage"] = {{"distinct", distinct}, {"fraction", cov.visited}, {"evenness", cov.evenness}};

    anima::bvh_write_options write;
    write.decimals = std::max(6, m.decimals);
    std::string page_written;
    if (p.make_clip) {
        const clip_t& result = played.motion;
        if (played.planted_runs > 0) out["planted_runs"] = played.planted_runs;
        out["feet_planted"] = o.plant_feet;
        if (!o.output.empty()) {
            write_text_file(o.output, bvh_text(result, o.rotation_order, write));
            out["output"] = o.output;
            out["decimals"] = write.decimals;
        }
        out["foot_skate"] =
            skate_json(anima::clip_foot_skate(m.clip, m.up).median, anima::clip_foot_skate(result, m.up).median);
        if (!o.view.empty()) {
            view_page page;
            page.title = mode + " playback of " + file_name(o.input) + ", seed " + std::to_string(o.seed);
            page.clips = {{"input " + file_name(o.input), m.clip}, {"played", result}};
            page.markers = o.video_texture ? frame_markers(1, played.events, "jump", "jump to a similar frame")
                                           : frame_markers(1, played.events, "turn", "turn: plays the other way");
            page_written = write_view_page(o.view, page);
            out["view"] = o.view;
        }
    }

    if (o.json) return print_json(out);
    const std::string how = o.video_texture ? "video-texture playback (L2 jumps)"
                                            : mode + " symmetric playback (" + describe(o.symmetry, params) + ")";
    std::cout << how << " of " << file_name(o.input) << " frames " << m.first << ".." << last << ", seed " << o.seed
              << ": " << o.frames << " frames from frame " << m.first + stream.front() << "\n"
              << summary << "\ncoverage: " << distinct << " of " << n << " source frames shown ("
              << format_fixed(100 * cov.visited, 1) << "%), evenness " << format_fixed(cov.evenness, 3) << "\n";
    if (!o.output.empty())
        report_written(o.output + ": " + std::to_string(o.frames) + " frames, root path " + o.root + ", " +
                       std::to_string(write.decimals) + " decimals, " + planting_note(o, out));
    if (!o.view.empty()) report_written(page_written);
}

}  // namespace
}  // namespace anima_cli

void register_playback(CLI::App& app) {
    using namespace anima_cli;
    const auto [sub, opts] = add_command<playback_options>(
        app, "playback",
        "Play a clip forwards and backwards, turning at its symmetric frames, into a motion of any length",
        run_playback);
    sub->add_option("IN", opts->input, "BVH file to play")->required()->type_name("PATH");
    sub->add_option("--frames", opts->frames, "Length of the new motion in frames")
        ->required()
        ->type_name("N")
        ->check(integer_in(1, max_frames));
    sub->add_option("-o,--output", opts->output, "Write the new motion to this BVH file")->type_name("OUT.bvh");
    add_rotation_order_option(*sub, opts->rotation_order);
    add_view_option(*sub, opts->view, "the input and the new motion, the turns marked");
    add_setting(*sub, "--seed", opts->seed, "Seed of the random turns (same seed, same motion)", count_up_to(~0ULL));
    add_setting(*sub, "--root", opts->root,
                "The root's ground path: recorded (the source frame's), in_place, accumulated (the source's "
                "steps added up) or keep_direction (reversed steps negated)",
                CLI::IsMember(anima::enum_name_list<anima::root_path>()));
    opts->start_opt = sub->add_option("--start", opts->start,
                                      "Frame to start at (default: the first candidate, or the first frame with "
                                      "--video-texture)")
                          ->type_name("FRAME")
                          ->check(count_up_to(max_frames));
    auto* fixed = sub->add_flag("--fixed", opts->fixed, "Keep every candidate's Eq 5 probability (no adaptation)");
    auto* gain = add_setting(*sub, "--gain", opts->gain,
                             "k of Eq 6: a passed candidate's probability is multiplied by K", number_in(1, 1000))
                     ->type_name("K")
                     ->excludes(fixed);
    auto* penalty = add_setting(*sub, "--penalty", opts->penalty,
                                "Subtracted from a candidate's probability when it turns", number_in(0, 1))
                        ->type_name("P")
                        ->excludes(fixed);
    std::vector<CLI::Option*> symmetric = add_symmetry_options(*sub, opts->symmetry);
    symmetric.insert(symmetric.end(), {fixed, gain, penalty});
    auto* video = sub->add_flag("--video-texture", opts->video_texture,
                                "Jump between similar frames (video textures, L2 distance) instead of turning");
    for (CLI::Option* option : symmetric) video->excludes(option);
    add_frame_range_options(*sub, opts->range);
    sub->add_flag("--plant-feet,!--no-plant-feet", opts->plant_feet,
                  "Hold feet that are on the ground through a turn or jump in place, IK on the legs (the "
                  "default; --no-plant-feet leaves them as the turns left them)");
    sub->add_flag("--json", opts->json, "Print a JSON object instead of text");
}
