// Helpers shared by the `anima` subcommands: loading BVH files with readable
// errors, writing output files, JSON and number formatting, option
// validators, left/right classification of joint names, a small SVG
// writer, a PNG writer, and the frame range and metric options the symmetry
// subcommands share.
#pragma once

#include <anima/anima.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace anima_cli {

using json = nlohmann::ordered_json;  // keys stay in the order they are added
using clip_t = anima::clip<double>;
using document_t = anima::bvh_document<double>;
using skeleton_t = anima::skeleton<double>;
using vec3 = Eigen::Vector3d;

/// An error found by the command line tool itself (a frame out of range, an
/// unwritable output...). main() prints it as "anima: <message>" and exits 1,
/// like any anima::error.
class failure : public std::runtime_error {
public:
    explicit failure(const std::string& what) : std::runtime_error(what) {}
};

// ---------------------------------------------------------------------------
// Files
// ---------------------------------------------------------------------------

/// Reads a BVH file. Throws failure for a missing file or a directory,
/// anima::io_error when it cannot be read and anima::parse_error
/// ("file:line: message") when it is malformed.
document_t load_bvh_document(const std::string& path);

/// Reads a BVH file into a clip (see load_bvh_document for the errors).
clip_t load_clip(const std::string& path);

/// The whole content of a file (anima::read_file, up to 1 GiB). Throws
/// failure for a missing file or a directory and anima::io_error when it
/// cannot be read.
std::string read_text_file(const std::string& path);

/// Writes text to a file as one of the run's outputs (anima::output_files):
/// the bytes go to a temporary next to it, and the run's outputs are renamed
/// into place together by commit_outputs when the command has succeeded, so
/// a run that fails - in any of its writes or after them - leaves every
/// existing file as it was. Throws failure naming the file and the system's
/// reason when it cannot be written.
void write_text_file(const std::string& path, std::string_view text);

/// Prints "wrote WHAT" on stdout once the run's outputs are in place
/// (commit_outputs), not when the command writes them, so that a run that
/// fails after its writes does not report files it did not leave. WHAT
/// starts with the file's path ("out.bvh (the texton)"). The lines come out
/// in the order reported, after everything else the command printed.
void report_written(std::string what);

/// Puts the run's outputs in place (main, after the command succeeded), then
/// prints the lines of report_written.
void commit_outputs();

/// Removes the temporaries of a failed run's outputs and forgets its
/// report_written lines.
void discard_outputs() noexcept;

/// The last component of a path ("walk.bvh" for "data/walk.bvh").
std::string file_name(const std::string& path);

/// Throws failure naming `option` unless a file can be written at `path`
/// (anima::check_output_path: not a folder, its folder exists). Commands call
/// it for every output path before any work or write, so that a bad path
/// costs nothing and leaves every other output as it was.
void check_output(const std::string& path, std::string_view option);

/// check_output for each (option, path) pair whose path is not empty.
void check_outputs(std::initializer_list<std::pair<std::string_view, const std::string*>> outputs);

// ---------------------------------------------------------------------------
// Option values
// ---------------------------------------------------------------------------

/// The largest frame number or frame count an option takes (10^8: more
/// frames than any clip a BVH file under a gigabyte can hold).
constexpr unsigned long long max_frames = 100000000;

/// CLI11 validators that check an option's text before CLI11 converts it, so
/// that the message names the option and says what is wrong: "-1" for a
/// count is not wrapped to 2^64 - 1, "abc" and "1.5" are "not an integer",
/// bounds print in short form ("1e+06", not 309 digits) and say whether they
/// are included. Integers are refused in exponent form ("1e8", which CLI11
/// cannot convert) and with leading zeros (which CLI11 reads as octal).
CLI::Validator integer_in(long long lo, long long hi);
/// A non-negative integer up to `hi` (frames, counts, seeds).
CLI::Validator count_up_to(unsigned long long hi);
/// A finite number in [lo, hi]; `lo_open` / `hi_open` exclude a bound.
CLI::Validator number_in(double lo, double hi, bool lo_open = false, bool hi_open = false);
/// A finite number > 0.
CLI::Validator positive_number();
/// A finite number >= 0.
CLI::Validator non_negative_number();

/// A validator that parses the option's text with `parse` and reports the
/// `Error` it throws, as `message(text, error)` says.
template <class Error, class Parse, class Message>
CLI::Validator parse_check(Parse parse, Message message, std::string description, std::string name) {
    return CLI::Validator(
        [parse, message](std::string& value) -> std::string {
            try {
                (void)parse(value);
                return {};
            } catch (const Error& e) {
                return message(value, e);
            }
        },
        std::move(description), std::move(name));
}

/// parse_check whose message is the error's own.
template <class Error, class Parse>
CLI::Validator parse_check(Parse parse, std::string description, std::string name) {
    return parse_check<Error>(
        parse, [](const std::string&, const Error& e) { return std::string(e.what()); }, std::move(description),
        std::move(name));
}

/// A subcommand of `app` whose options fill an `Options`, kept alive by the
/// subcommand's callback, which calls run(options) after parsing.
template <class Options, class Run>
std::pair<CLI::App*, std::shared_ptr<Options>> add_command(CLI::App& app, const std::string& name,
                                                           const std::string& about, Run run) {
    auto options = std::make_shared<Options>();
    CLI::App* sub = app.add_subcommand(name, about);
    sub->callback([options, run] { run(*options); });
    return {sub, options};
}

/// An option whose text `check` validates and whose default --help shows.
template <class T>
CLI::Option* add_setting(CLI::App& sub, const std::string& name, T& value, const std::string& help,
                         const CLI::Validator& check) {
    return sub.add_option(name, value, help)->check(check)->capture_default_str();
}

/// Bytes a request of `count` items of `bytes_each` needs; throws failure
/// naming the request, the memory it needs and `option` (the option to
/// change) when that is more than `limit` bytes (default 1 GiB).
void check_request_memory(double count, double bytes_each, const std::string& what, std::string_view option,
                          double limit = 1024.0 * 1024.0 * 1024.0);

/// Bytes one frame of a clip costs on its way through a subcommand: its
/// rotations and translations, a frames x DOF copy or two, and its BVH text.
double bytes_per_frame(const skeleton_t& skeleton);

/// check_request_memory for an output of `frames` frames of `skeleton`
/// asked for with --frames.
void check_frames_memory(std::size_t frames, const skeleton_t& skeleton);

// ---------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------

/// Prints a JSON value to stdout, indented, followed by a newline.
void print_json(const json& value);

/// A number with up to `significant` significant digits, no trailing zeros
/// ("120", "0.00833333", "1.23333").
std::string format_number(double value, int significant = 6);

/// A number with exactly `decimals` decimals ("0.333").
std::string format_fixed(double value, int decimals);

/// Frame intervals as [[first, last], ...].
json to_json(const std::vector<anima::frame_interval>& runs);

/// The Poisson solves of seam smoothing: solves, iterations, relative_residual, converged.
json to_json(const anima::seam_smoothing_stats<double>& stats);

/// Warns on stderr when a Poisson solve of seam smoothing stopped above its tolerance.
void warn_unconverged(const anima::seam_smoothing_stats<double>& stats);

/// The median foot skate of an input and of the motion made from it, and
/// their ratio (null when the input's is 0).
json skate_json(double input, double output);

/// "a, b, c".
std::string join(const std::vector<std::string>& items, std::string_view separator = ", ");

// ---------------------------------------------------------------------------
// Axes and rotation orders
// ---------------------------------------------------------------------------

/// "+Y", "-z", "Z" (sign optional, case-insensitive) to a signed axis;
/// throws failure for anything else.
anima::signed_axis parse_signed_axis(std::string_view text);

/// CLI11 validators for a signed axis (+Y, -Z...) and an Euler order (XYZ...),
/// so that a bad value is reported as a usage error naming the option.
CLI::Validator signed_axis_validator();
CLI::Validator euler_order_validator();

/// Adds --rotation-order ORDER (or another name): give every joint with
/// rotation channels three, in that order, before the clip is written. The
/// choices are the names of anima::euler_order.
CLI::Option* add_rotation_order_option(CLI::App& sub, std::string& order,
                                       const std::string& name = "--rotation-order");

/// anima::format_bvh(clip, options). When a joint's channels cannot spell
/// its rotations (one or two rotation channels, and the motion turns it
/// about another axis), throws failure with the library's message and that
/// `option` gives every joint three rotation channels; with `option` empty
/// (it was given) the library's error as it is.
std::string format_bvh_suggesting(const clip_t& clip, const anima::bvh_write_options& options,
                                  std::string_view option);

/// The BVH text of a clip a command made: its joints given three rotation
/// channels in `order` first (anima::with_rotation_order) unless `order` is
/// empty, in which case a joint that cannot spell its rotations is reported
/// as format_bvh_suggesting does, naming --rotation-order.
std::string bvh_text(const clip_t& clip, const std::string& order, const anima::bvh_write_options& options = {});

/// Adds --up AXIS (or another axis option), an empty string when not given.
CLI::Option* add_up_option(CLI::App& sub, std::string& up,
                           const std::string& help = "The clip's up axis, instead of the one guessed from the skeleton",
                           const std::string& name = "--up");

/// The axis `given` (by `option`), or when that is empty the one guessed from
/// the skeleton, with a warning naming `path` and `option` when the guess has
/// nothing to go on.
anima::signed_axis up_axis_or_guess(const std::string& given, const skeleton_t& skeleton, const std::string& path,
                                    std::string_view option = "--up");


/// The rotation order of a skeleton's joints with three rotation channels:
/// "ZXY" when they all agree, "mixed" when they differ, "none" when no joint
/// has three rotation channels.
std::string rotation_order_summary(const skeleton_t& skeleton);

/// "Zrotation Xrotation Yrotation".
std::string channel_list(const std::vector<anima::channel>& channels);


// ---------------------------------------------------------------------------
// SVG
// ---------------------------------------------------------------------------

/// Escapes text for XML character data and attribute values.
std::string xml_escape(std::string_view text);

/// A minimal SVG document builder: coordinates in pixels, y down, on white.
class svg_document {
public:
    svg_document(double width, double height, std::string title);

    void rect(double x, double y, double w, double h, std::string_view fill, std::string_view stroke = "none",
              double stroke_width = 0);
    void line(double x1, double y1, double x2, double y2, std::string_view stroke, double stroke_width);
    void circle(double cx, double cy, double r, std::string_view fill);
    /// anchor: "start", "middle" or "end".
    void text(double x, double y, std::string_view content, double size, std::string_view fill = "#222",
              std::string_view anchor = "start", bool bold = false);
    /// A PNG file's bytes (png_bytes) drawn into the box, pixels kept sharp.
    void image(double x, double y, double w, double h, std::string_view png);
    /// Raw markup (e.g. "<g>" / "</g>"), appended as is.
    void raw(std::string_view markup);

    double width() const noexcept { return width_; }
    double height() const noexcept { return height_; }
    void set_height(double height) noexcept { height_ = height; }
    /// The complete document, XML declaration included.
    std::string str() const;

private:
    double width_, height_;
    std::string title_;
    std::string body_;
};

/// A coordinate for SVG output, two decimals, no trailing zeros.
std::string svg_number(double value);

/// Whether a figure's path asks for SVG (ends in .svg, any case) rather than PNG.
bool is_svg_path(const std::string& path);

/// Tick positions 1, 2 or 5 times a power of ten apart, about `count` of
/// them over [lo, hi].
std::vector<double> nice_ticks(double lo, double hi, int count);

// ---------------------------------------------------------------------------
// PNG
// ---------------------------------------------------------------------------

/// Throws failure, naming `what_for` (e.g. "--matrix"), when this build
/// cannot write PNG files (stb_image_write was not found). Call it before
/// doing the work whose result is to be written.
void require_png(std::string_view what_for);

/// 8-bit pixels, rows top to bottom, `channels` values per pixel, encoded
/// as PNG (the bytes of the file). Throws failure as write_png does.
std::string png_bytes(int width, int height, int channels, const std::vector<unsigned char>& pixels,
                      std::string_view what_for);

/// Writes 8-bit pixels, rows top to bottom, `channels` values per pixel
/// (1 grey, 3 RGB, 4 RGBA), as a PNG file. Throws failure as require_png
/// does, for a pixel count that does not match, or when the file cannot be
/// written.
void write_png(const std::string& path, int width, int height, int channels, const std::vector<unsigned char>& pixels,
               std::string_view what_for);

// ---------------------------------------------------------------------------
// Motion for the symmetry subcommands (symmetry, playback)
// ---------------------------------------------------------------------------

/// Throws failure "OPTION FRAME is outside 'PATH' (N frames, 0..N-1)"
/// unless `frame` is one of the `frames` frames of the clip read from `path`.
void check_frame_in(std::size_t frame, std::size_t frames, const std::string& path, std::string_view option);

/// The part of a clip to analyse and the up axis to analyse it with.
struct frame_range_options {
    std::size_t first = 0, last = 0;
    std::string up;
    CLI::Option* last_opt = nullptr;
};

/// Adds --first, --last and --up.
void add_frame_range_options(CLI::App& sub, frame_range_options& o);

/// A clip's frames first..last, as the symmetry subcommands read them.
struct motion_range {
    clip_t clip;                 ///< frames first..last of the file
    std::size_t first = 0;       ///< the file's number of the range's frame 0
    anima::signed_axis up;       ///< guessed or --up
    int decimals = 0;            ///< bvh_value_decimals of the file
};

/// Reads a BVH file and cuts out the range. Throws failure for a range
/// outside the clip, CLI::ValidationError for --first after --last. Warns on
/// stderr when the up axis is a guess without evidence, and when the range
/// starts at the skeleton's rest pose (every joint that moves within 10
/// degrees of its rest orientation: the T-pose some exporters put before the
/// motion), suggesting the --first where the motion has settled.
motion_range load_motion_range(const std::string& path, const frame_range_options& o);

/// The metric and Eq 3 options.
struct symmetry_options {
    std::string metric = "mahalanobis";
    int window = 10, smoothness = 0, candidate_window = 0, min_pairs = 0;
};

/// Adds --metric, --window, --smoothness, --candidate-window and
/// --min-pairs; returns the options added, in that order.
std::vector<CLI::Option*> add_symmetry_options(CLI::App& sub, symmetry_options& o);

/// The library parameters for these options. Throws CLI::ValidationError for
/// a --smoothness outside [0, (window + 1) / 2] or a --min-pairs above
/// --window.
anima::symmetry_params<double> make_symmetry_params(const symmetry_options& o);

/// "mahalanobis, window 10, smoothness 0".
std::string describe(const symmetry_options& o, const anima::symmetry_params<double>& p);

/// The settings used on a range of `frames` frames: metric, window,
/// smoothness, candidate_window and min_pairs.
json settings_json(const symmetry_options& o, const anima::symmetry_params<double>& p, std::size_t frames);

}  // namespace anima_cli
