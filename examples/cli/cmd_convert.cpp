// anima convert IN.bvh OUT.bvh: reads, validates and writes a BVH file,
// optionally with another rotation order, up axis or scale.
#include "commands.hpp"
#include "common.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <string>

namespace anima_cli {
namespace {

struct convert_options {
    std::string input, output;
    std::string order, up, from_up, euler = "continuous";
    double scale = 1;
    int decimals = 6;  // when --decimals is not given: see run_convert
    bool json = false;
    // Set in register_convert; owned by the CLI::App.
    CLI::Option *order_opt = nullptr, *up_opt = nullptr, *from_up_opt = nullptr, *scale_opt = nullptr,
                *euler_opt = nullptr, *decimals_opt = nullptr;
};

void run_convert(const convert_options& o) {
    check_outputs({{"OUT", &o.output}});
    const std::string input_text = read_text_file(o.input);
    const document_t doc = anima::parse_bvh_document<double>(input_text, o.input);
    const anima::up_axis_guess guess = anima::guess_up_axis(doc.skeleton);
    const bool from_given = o.from_up_opt->count() > 0;
    const bool change_up = o.up_opt->count() > 0;
    // --from-up needs --up: without it the input's axis is the guess, unannounced.
    const anima::signed_axis from =
        change_up ? up_axis_or_guess(o.from_up, doc.skeleton, o.input, "--from-up") : guess.up;
    const bool change_order = o.order_opt->count() > 0;
    const bool change_scale = o.scale_opt->count() > 0;
    // Re-encoding the angles (--euler) also needs the clip; without any of
    // these the document is written as read, keeping the file's numbers.
    const bool via_clip = change_up || change_order || change_scale || o.euler_opt->count() > 0;
    const anima::signed_axis to = change_up ? parse_signed_axis(o.up) : from;

    anima::bvh_write_options options;
    // Unless told otherwise, a document is written with as many decimals as
    // the input has (so its numbers come back unchanged), a clip with 6.
    options.decimals = o.decimals_opt->count() > 0 ? o.decimals : via_clip ? 6 : anima::bvh_value_decimals(input_text);
    options.angles = anima::parse_enum<anima::euler_angles>(o.euler);

    std::string text;
    skeleton_t written;
    if (via_clip) {
        clip_t clip = anima::to_clip(doc);
        if (change_up && from != to) clip = anima::change_up_axis(clip, from, to);
        if (change_scale) clip = anima::scale_clip(clip, o.scale);
        if (change_order) clip = anima::with_rotation_order(clip, anima::parse_euler_order(o.order));
        text = format_bvh_suggesting(clip, options, change_order ? "" : "--order");
        written = clip.skeleton();
    } else {
        text = anima::format_bvh(doc, options);
        written = doc.skeleton;
    }
    write_text_file(o.output, text);

    const std::string order_in = rotation_order_summary(doc.skeleton), order_out = rotation_order_summary(written);
    if (o.json) {
        print_json({{"input", o.input},
                    {"output", o.output},
                    {"frames", doc.frames},
                    {"frame_time", doc.frame_time},
                    {"joints", written.size()},
                    {"channels", written.channel_count()},
                    {"order", {{"input", order_in}, {"output", order_out}}},
                    {"up_axis",
                     {{"input", anima::to_string(from)},
                      {"output", anima::to_string(to)},
                      {"guessed", !from_given},
                      {"confident", from_given || guess.confident}}},
                    {"scale", change_scale ? o.scale : 1.0},
                    {"decimals", options.decimals},
                    {"reencoded", via_clip},
                    {"euler", via_clip ? json(o.euler) : json(nullptr)}});
        return;
    }
    std::string line = o.output + ": " + std::to_string(doc.frames) + " frames, " +
                       std::to_string(written.size()) + " joints, " + std::to_string(written.channel_count()) +
                       " channels, order ";
    line += order_out == "mixed" ? "mixed (" + join(anima::rotation_orders(written)) + ")" : order_out;
    if (order_out != order_in) line += " (was " + order_in + ")";
    line += ", up " + anima::to_string(to);
    if (to != from) line += " (was " + anima::to_string(from) + ")";
    if (change_scale) line += ", scaled by " + format_number(o.scale);
    line += via_clip ? ", angles re-encoded (" + o.euler + ")" : ", channel values as read";
    line += ", " + std::to_string(options.decimals) + " decimals";
    report_written(line);
}

}  // namespace
}  // namespace anima_cli

void register_convert(CLI::App& app) {
    using namespace anima_cli;
    const auto [sub, opts] = add_command<convert_options>(
        app, "convert", "Read, validate and write a BVH file, optionally changing rotation order, up axis or scale",
        run_convert);
    sub->add_option("IN", opts->input, "BVH file to read")->required()->type_name("PATH");
    sub->add_option("OUT", opts->output, "BVH file to write")->required()->type_name("PATH");
    opts->order_opt = add_rotation_order_option(*sub, opts->order, "--order,--rotation-order");
    opts->up_opt = add_up_option(*sub, opts->up, "Turn the clip so that this axis is up (+X, -X, +Y, -Y, +Z, -Z)");
    opts->from_up_opt = add_up_option(*sub, opts->from_up,
                                      "The input's up axis, instead of the one guessed from the skeleton", "--from-up")
                            ->needs(opts->up_opt);
    opts->scale_opt = sub->add_option("--scale", opts->scale, "Multiply every length (offsets, translations) by S")
                          ->type_name("S")
                          ->check(CLI::Validator(
                              [](std::string& s) -> std::string {
                                  double v = 0;
                                  if (!CLI::detail::lexical_cast(s, v) || !(v > 0) || !std::isfinite(v))
                                      return "'" + s + "' is not a positive number";
                                  return {};
                              },
                              "> 0", "positive scale"));
    opts->decimals_opt = sub->add_option("--decimals", opts->decimals,
                                         "Decimals written for offsets and channel values (default: as many as the "
                                         "input has when its values are copied, 6 when they are re-encoded)")
                             ->type_name("N")
                             ->check(integer_in(0, 17));
    opts->euler_opt = add_setting(*sub, "--euler", opts->euler,
                                  "How rotations become angles when the clip is re-encoded: continuous (no "
                                  "360 degree jumps) or principal (each frame on its own); implies re-encoding",
                                  CLI::IsMember(anima::enum_name_list<anima::euler_angles>()))
                          ->type_name("MODE");
    sub->add_flag("--json", opts->json, "Print a JSON summary instead of a line of text");
}
