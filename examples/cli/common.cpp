#include "common.hpp"

#include <anima/core/file_io.hpp>
#include <anima/core/text.hpp>

#include <algorithm>
#include <charconv>
#include <climits>
#include <limits>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <system_error>

#ifdef ANIMA_HAVE_STB
// The implementation lives here, static: no other file needs to define it.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb_image_write.h>
#endif

namespace anima_cli {

// ---------------------------------------------------------------------------
// Files
// ---------------------------------------------------------------------------

std::string read_text_file(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (status.type() == std::filesystem::file_type::not_found) throw failure("'" + path + "' does not exist");
    if (status.type() == std::filesystem::file_type::directory) throw failure("'" + path + "' is a directory");
    return anima::read_file(path);
}

document_t load_bvh_document(const std::string& path) {
    return anima::parse_bvh_document<double>(read_text_file(path), path);
}


clip_t load_clip(const std::string& path) { return anima::to_clip(load_bvh_document(path)); }

namespace {
anima::output_files& run_outputs() {
    static anima::output_files outputs;
    return outputs;
}

/// The report_written lines, printed once the outputs are in place.
std::vector<std::string>& written_lines() {
    static std::vector<std::string> lines;
    return lines;
}
}  // namespace

void report_written(std::string what) { written_lines().push_back("wrote " + std::move(what)); }

void write_text_file(const std::string& path, std::string_view text) {
    try {
        run_outputs().write(path, text);
    } catch (const anima::io_error& e) {
        throw failure(e.what());
    }
}

void commit_outputs() {
    try {
        run_outputs().commit();
    } catch (const anima::io_error& e) {
        written_lines().clear();
        throw failure(e.what());
    }
    for (const std::string& line : written_lines()) std::cout << line << '\n';
    written_lines().clear();
}

void discard_outputs() noexcept {
    run_outputs().discard();
    written_lines().clear();
}

void check_output(const std::string& path, std::string_view option) {
    try {
        anima::check_output_path(path, option);
    } catch (const anima::io_error& e) {
        throw failure(e.what());
    }
}

void check_outputs(std::initializer_list<std::pair<std::string_view, const std::string*>> outputs) {
    for (const auto& [option, path] : outputs)
        if (!path->empty()) check_output(*path, option);
}

// ---------------------------------------------------------------------------
// Option values
// ---------------------------------------------------------------------------

CLI::Validator integer_in(long long lo, long long hi) {
    return CLI::Validator(
        [lo, hi](std::string& value) -> std::string {
            std::size_t k = 0;
            bool negative = false;
            if (k < value.size() && (value[k] == '+' || value[k] == '-')) negative = value[k++] == '-';
            if (k == value.size() || value.find_first_not_of("0123456789", k) != std::string::npos) {
                // CLI11 cannot convert "1e8" to an integer: say how to write it.
                char* end = nullptr;
                const double d = std::strtod(value.c_str(), &end);
                if (!value.empty() && end == value.c_str() + value.size() && std::isfinite(d) && d == std::floor(d) &&
                    std::abs(d) < 9e18 && !std::isspace(static_cast<unsigned char>(value[0])))
                    return "'" + value + "' is not an integer: write it in digits (" +
                           std::to_string(static_cast<long long>(d)) + ")";
                return "'" + anima::escape_for_message(value, 60) + "' is not an integer";
            }
            // CLI11 reads "010" as octal eight: refuse rather than guess.
            if (value.size() - k > 1 && value[k] == '0')
                return "'" + value + "': write it without leading zeros";
            const std::string digits = value.substr(k);
            const auto outside = [&] {
                const std::string range = hi != LLONG_MAX ? "is outside " + std::to_string(lo) + ".." + std::to_string(hi)
                                          : negative      ? "must be " + std::to_string(lo) + " or more"
                                                          : "is larger than " + std::to_string(hi);
                return value + " " + range + (negative && lo >= 0 ? " (it must not be negative)" : "");
            };
            unsigned long long magnitude = 0;
            const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), magnitude);
            if (r.ec != std::errc()) return outside();
            constexpr unsigned long long most_negative = static_cast<unsigned long long>(LLONG_MAX) + 1;
            if (negative ? magnitude > most_negative : magnitude > static_cast<unsigned long long>(LLONG_MAX))
                return outside();
            const long long v = !negative ? static_cast<long long>(magnitude)
                                : magnitude == most_negative ? LLONG_MIN
                                                             : -static_cast<long long>(magnitude);
            if (v < lo || v > hi) return outside();
            return {};
        },
        hi == LLONG_MAX ? "INT >= " + std::to_string(lo) : "INT in [" + std::to_string(lo) + " - " + std::to_string(hi) + "]");
}

CLI::Validator count_up_to(unsigned long long hi) {
    const long long top = static_cast<long long>(std::min<unsigned long long>(hi, static_cast<unsigned long long>(LLONG_MAX)));
    return integer_in(0, top);
}

CLI::Validator number_in(double lo, double hi, bool lo_open, bool hi_open) {
    const auto range = [=] {
        const bool lo_inf = std::isinf(lo), hi_inf = std::isinf(hi);
        if (lo_inf && hi_inf) return std::string("finite");
        if (hi_inf) return std::string(lo_open ? "greater than " : "at least ") + format_number(lo);
        if (lo_inf) return std::string(hi_open ? "less than " : "at most ") + format_number(hi);
        return std::string(lo_open ? "greater than " : "at least ") + format_number(lo) + " and " +
               (hi_open ? "less than " : "at most ") + format_number(hi);
    };
    std::string description = "FLOAT ";
    if (std::isinf(hi)) description += lo_open ? "> " + format_number(lo) : ">= " + format_number(lo);
    else description += "in " + std::string(lo_open ? "(" : "[") + format_number(lo) + " - " + format_number(hi) + (hi_open ? ")" : "]");
    return CLI::Validator(
        [=](std::string& value) -> std::string {
            const char* begin = value.c_str();
            char* end = nullptr;
            errno = 0;
            const double v = std::strtod(begin, &end);
            if (value.empty() || end != begin + value.size() || std::isspace(static_cast<unsigned char>(value[0])))
                return "'" + anima::escape_for_message(value, 60) + "' is not a number";
            if (!std::isfinite(v)) return value + " is not finite";
            const bool above = lo_open ? v > lo : v >= lo;
            const bool below = hi_open ? v < hi : v <= hi;
            if (!above || !below) return value + " must be " + range();
            return {};
        },
        description);
}

CLI::Validator positive_number() {
    return number_in(0, std::numeric_limits<double>::infinity(), true, false);
}

CLI::Validator non_negative_number() { return number_in(0, std::numeric_limits<double>::infinity()); }

double bytes_per_frame(const skeleton_t& skeleton) {
    const double joints = static_cast<double>(skeleton.size()), channels = static_cast<double>(skeleton.channel_count());
    return joints * 7 * 8 * 3 + channels * (8 * 4 + 12);
}

void check_frames_memory(std::size_t frames, const skeleton_t& skeleton) {
    check_request_memory(static_cast<double>(frames), bytes_per_frame(skeleton),
                         "--frames " + std::to_string(frames) + " of " + std::to_string(skeleton.channel_count()) +
                             " channels",
                         "--frames");
}

void check_request_memory(double count, double bytes_each, const std::string& what, std::string_view option,
                          double limit) {
    const double bytes = count * bytes_each;
    if (!(bytes <= limit)) {
        const auto size = [](double b) {
            return b >= 1024.0 * 1024 * 1024 ? format_number(b / (1024.0 * 1024 * 1024), 3) + " GiB"
                                             : format_number(b / (1024.0 * 1024), 3) + " MiB";
        };
        throw failure(what + " needs about " + size(bytes) + " of memory, more than the " + size(limit) +
                      " allowed: make " + std::string(option) + " smaller");
    }
}

std::string file_name(const std::string& path) {
    const std::string name = std::filesystem::path(path).filename().string();
    return name.empty() ? path : name;
}

// ---------------------------------------------------------------------------
// Output
// ---------------------------------------------------------------------------

void print_json(const json& value) {
    // Invalid UTF-8 (say, in a joint name) is replaced rather than thrown on.
    std::cout << value.dump(2, ' ', false, json::error_handler_t::replace) << '\n';
}

std::string format_number(double value, int significant) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", significant, value);
    std::string s = buf;
    if (s == "-0") s = "0";
    return s;
}

std::string format_fixed(double value, int decimals) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
    std::string s = buf;
    if (!s.empty() && s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
    return s;
}

json to_json(const std::vector<anima::frame_interval>& runs) {
    json out = json::array();
    for (const auto& r : runs) out.push_back({r.first, r.last});
    return out;
}

json to_json(const anima::seam_smoothing_stats<double>& stats) {
    return {{"solves", stats.solves},
            {"iterations", stats.iterations},
            {"relative_residual", stats.relative_residual},
            {"converged", stats.converged}};
}

void warn_unconverged(const anima::seam_smoothing_stats<double>& stats) {
    if (!stats.converged)
        std::cerr << "anima: warning: a Poisson solve stopped at relative residual "
                  << format_number(stats.relative_residual, 3) << " above its tolerance\n";
}

json skate_json(double input, double output) {
    return {{"input", input}, {"output", output}, {"ratio", input > 0 ? json(output / input) : json(nullptr)}};
}

std::string join(const std::vector<std::string>& items, std::string_view separator) {
    std::string out;
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (i) out += separator;
        out += items[i];
    }
    return out;
}

// ---------------------------------------------------------------------------
// Axes and rotation orders
// ---------------------------------------------------------------------------

anima::signed_axis parse_signed_axis(std::string_view text) {
    if (const auto axis = anima::try_parse_signed_axis(text)) return *axis;
    throw failure("'" + std::string(text) + "' is not an axis: use +X, -X, +Y, -Y, +Z or -Z");
}

CLI::Validator signed_axis_validator() {
    return parse_check<failure>(parse_signed_axis, "{+X,-X,+Y,-Y,+Z,-Z}", "signed axis");
}

CLI::Option* add_up_option(CLI::App& sub, std::string& up, const std::string& help, const std::string& name) {
    return sub.add_option(name, up, help)->type_name("AXIS")->check(signed_axis_validator());
}

anima::signed_axis up_axis_or_guess(const std::string& given, const skeleton_t& skeleton, const std::string& path,
                                    std::string_view option) {
    if (!given.empty()) return parse_signed_axis(given);
    const anima::up_axis_guess guess = anima::guess_up_axis(skeleton);
    if (!guess.confident)
        std::cerr << "anima: warning: cannot tell the up axis of '" << path
                  << "' (no head, neck or foot joint); assuming " << anima::to_string(guess.up)
                  << ", use " << option << " to say otherwise\n";
    return guess.up;
}

CLI::Validator euler_order_validator() {
    return parse_check<anima::error>(
        anima::parse_euler_order,
        [](const std::string& value, const anima::error&) {
            return "'" + value + "' is not a rotation order: use " + anima::enum_choices<anima::euler_order>();
        },
        "{" + join(anima::enum_name_list<anima::euler_order>(), ",") + "}", "euler order");
}

CLI::Option* add_rotation_order_option(CLI::App& sub, std::string& order, const std::string& name) {
    return sub
        .add_option(name, order,
                    "Give every joint with rotation channels three, in this order, before writing: a joint with "
                    "one or two cannot spell every rotation")
        ->type_name("ORDER")
        ->check(euler_order_validator());
}

std::string format_bvh_suggesting(const clip_t& clip, const anima::bvh_write_options& options,
                                  std::string_view option) {
    try {
        return anima::format_bvh(clip, options);
    } catch (const anima::invalid_argument& e) {
        // A joint with one or two rotation channels cannot spell a turned
        // rotation; the option gives every rotating joint three channels.
        const std::string what = e.what();
        if (option.empty() || what.find("rotation channel") == std::string::npos) throw;
        throw failure(what + "; " + std::string(option) + " XYZ (or another order) does that");
    }
}

std::string bvh_text(const clip_t& clip, const std::string& order, const anima::bvh_write_options& options) {
    if (order.empty()) return format_bvh_suggesting(clip, options, "--rotation-order");
    return format_bvh_suggesting(anima::with_rotation_order(clip, anima::parse_euler_order(order)), options, {});
}

std::string rotation_order_summary(const skeleton_t& skeleton) {
    std::vector<std::string> full;
    for (const auto& o : anima::rotation_orders(skeleton))
        if (o.size() == 3) full.push_back(o);
    if (full.empty()) return "none";
    return full.size() == 1 ? full[0] : "mixed";
}

std::string channel_list(const std::vector<anima::channel>& channels) {
    std::vector<std::string> names;
    for (const anima::channel c : channels) names.emplace_back(anima::to_string(c));
    return join(names, " ");
}

// ---------------------------------------------------------------------------
// SVG
// ---------------------------------------------------------------------------

std::string xml_escape(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            default:
                // Control characters are not allowed in XML 1.0.
                if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n') out += '?';
                else out += c;
        }
    }
    return out;
}

std::string svg_number(double value) {
    if (!std::isfinite(value)) return "0";
    std::string s = format_fixed(value, 2);
    if (s.find('.') != std::string::npos) {
        while (s.back() == '0') s.pop_back();
        if (s.back() == '.') s.pop_back();
    }
    return s == "-0" ? "0" : s;
}

bool is_svg_path(const std::string& path) {
    return path.size() >= 4 && anima::ascii_equal_ignoring_case(std::string_view(path).substr(path.size() - 4), ".svg");
}

std::vector<double> nice_ticks(double lo, double hi, int count) {
    std::vector<double> out;
    const double span = hi - lo;
    if (!(span > 0)) return {lo};
    const double raw = span / count;
    const double power = std::pow(10.0, std::floor(std::log10(raw)));
    double step = power;
    for (const double m : {1.0, 2.0, 5.0, 10.0})
        if (m * power >= raw) {
            step = m * power;
            break;
        }
    for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * span; t += step) out.push_back(t);
    return out;
}

namespace {

std::string base64(std::string_view bytes) {
    static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
        unsigned v = 0;
        for (std::size_t k = 0; k < 3; ++k) v = v << 8 | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
        for (std::size_t k = 0; k < 4; ++k) out += k <= n ? digits[(v >> (18 - 6 * k)) & 63] : '=';
    }
    return out;
}

}  // namespace

svg_document::svg_document(double width, double height, std::string title)
    : width_(width), height_(height), title_(std::move(title)) {}

void svg_document::rect(double x, double y, double w, double h, std::string_view fill, std::string_view stroke,
                        double stroke_width) {
    body_ += "<rect x=\"" + svg_number(x) + "\" y=\"" + svg_number(y) + "\" width=\"" + svg_number(w) +
             "\" height=\"" + svg_number(h) + "\" fill=\"" + std::string(fill) + "\"";
    if (stroke != "none") body_ += " stroke=\"" + std::string(stroke) + "\" stroke-width=\"" + svg_number(stroke_width) + "\"";
    body_ += "/>\n";
}

void svg_document::line(double x1, double y1, double x2, double y2, std::string_view stroke, double stroke_width) {
    body_ += "<line x1=\"" + svg_number(x1) + "\" y1=\"" + svg_number(y1) + "\" x2=\"" + svg_number(x2) +
             "\" y2=\"" + svg_number(y2) + "\" stroke=\"" + std::string(stroke) + "\" stroke-width=\"" +
             svg_number(stroke_width) + "\"/>\n";
}

void svg_document::circle(double cx, double cy, double r, std::string_view fill) {
    body_ += "<circle cx=\"" + svg_number(cx) + "\" cy=\"" + svg_number(cy) + "\" r=\"" + svg_number(r) +
             "\" fill=\"" + std::string(fill) + "\"/>\n";
}

void svg_document::text(double x, double y, std::string_view content, double size, std::string_view fill,
                        std::string_view anchor, bool bold) {
    body_ += "<text x=\"" + svg_number(x) + "\" y=\"" + svg_number(y) + "\" font-size=\"" + svg_number(size) +
             "\" fill=\"" + std::string(fill) + "\"";
    if (anchor != "start") body_ += " text-anchor=\"" + std::string(anchor) + "\"";
    if (bold) body_ += " font-weight=\"bold\"";
    body_ += ">" + xml_escape(content) + "</text>\n";
}

void svg_document::image(double x, double y, double w, double h, std::string_view png) {
    body_ += "<image x=\"" + svg_number(x) + "\" y=\"" + svg_number(y) + "\" width=\"" + svg_number(w) + "\" height=\"" +
             svg_number(h) + "\" preserveAspectRatio=\"none\" style=\"image-rendering:pixelated\" xlink:href=\"data:image/png;base64," +
             base64(png) + "\"/>\n";
}

void svg_document::raw(std::string_view markup) {
    body_ += markup;
    if (!markup.empty() && markup.back() != '\n') body_ += '\n';
}

std::string svg_document::str() const {
    const std::string w = svg_number(width_), h = svg_number(height_);
    std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    out += "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" + w + "\" height=\"" + h +
           "\" viewBox=\"0 0 " + w + " " + h + "\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\">\n";
    out += "<title>" + xml_escape(title_) + "</title>\n";
    out += "<rect x=\"0\" y=\"0\" width=\"" + w + "\" height=\"" + h + "\" fill=\"#ffffff\"/>\n";
    out += body_;
    out += "</svg>\n";
    return out;
}

// ---------------------------------------------------------------------------
// PNG
// ---------------------------------------------------------------------------

void require_png(std::string_view what_for) {
#ifndef ANIMA_HAVE_STB
    throw failure(std::string(what_for) +
                  ": this anima was built without stb_image_write.h, so it cannot write PNG files (install stb, "
                  "e.g. Debian's libstb-dev, and rebuild)");
#else
    (void)what_for;
#endif
}

std::string png_bytes(int width, int height, int channels, const std::vector<unsigned char>& pixels,
                      std::string_view what_for) {
    require_png(what_for);
    if (width < 1 || height < 1 || channels < 1 || channels > 4 ||
        pixels.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(channels))
        throw failure(std::string(what_for) + ": " + std::to_string(pixels.size()) + " pixel values for a " +
                      std::to_string(width) + "x" + std::to_string(height) + " image with " + std::to_string(channels) +
                      " channels");
    std::string png;
#ifdef ANIMA_HAVE_STB
    const auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
    };
    if (!stbi_write_png_to_func(append, &png, width, height, channels, pixels.data(), width * channels))
        throw failure(std::string(what_for) + ": cannot encode a PNG image");
#endif
    return png;
}

void write_png(const std::string& path, int width, int height, int channels, const std::vector<unsigned char>& pixels,
               std::string_view what_for) {
    write_text_file(path, png_bytes(width, height, channels, pixels, what_for));
}

// ---------------------------------------------------------------------------
// Motion for the symmetry subcommands
// ---------------------------------------------------------------------------

void add_frame_range_options(CLI::App& sub, frame_range_options& o) {
    add_setting(sub, "--first", o.first, "First frame to use, e.g. to leave out a rest pose the clip starts with",
                count_up_to(max_frames))
        ->type_name("FRAME");
    o.last_opt = sub.add_option("--last", o.last, "Last frame to use (default: the clip's last)")
                     ->type_name("FRAME")
                     ->check(count_up_to(max_frames));
    add_up_option(sub, o.up);
}

void check_frame_in(std::size_t frame, std::size_t frames, const std::string& path, std::string_view option) {
    if (frame >= frames)
        throw failure(std::string(option) + " " + std::to_string(frame) + " is outside '" + path + "' (" +
                      std::to_string(frames) +
                      (frames == 1 ? " frame, 0)" : " frames, 0.." + std::to_string(frames ? frames - 1 : 0) + ")"));
}

motion_range load_motion_range(const std::string& path, const frame_range_options& o) {
    const std::string text = read_text_file(path);
    const clip_t whole = anima::to_clip(anima::parse_bvh_document<double>(text, path));
    const std::size_t n = whole.frames();
    if (n == 0) throw failure("'" + path + "' has no frames");
    const bool last_given = o.last_opt && o.last_opt->count() > 0;
    const std::size_t last = last_given ? o.last : n - 1;
    check_frame_in(o.first, n, path, "--first");
    check_frame_in(last, n, path, "--last");
    if (o.first > last)
        throw CLI::ValidationError("--first", "frame " + std::to_string(o.first) + " is after --last " + std::to_string(last));

    motion_range out;
    out.first = o.first;
    out.clip = o.first == 0 && last + 1 == n ? whole : whole.slice(o.first, last + 1);
    out.decimals = anima::bvh_value_decimals(text);
    out.up = up_axis_or_guess(o.up, whole.skeleton(), path);

    // A rest pose (T-pose) that an exporter put before the motion, often
    // followed by a few frames that swing out of it: their large steps would
    // inflate Eq 2's velocity variances, and they are no motion to play.
    if (const std::size_t settled = anima::rest_pose_lead_in(out.clip)) {
        std::cerr << "anima: warning: frame " << o.first << " of '" << path
                  << "' is the skeleton's rest pose, not motion";
        if (settled > 1)
            std::cerr << ", and the motion swings out of it until about frame " << o.first + settled;
        std::cerr << ": --first " << o.first + settled << " leaves " << (settled > 1 ? "them" : "it") << " out\n";
    }
    return out;
}

std::vector<CLI::Option*> add_symmetry_options(CLI::App& sub, symmetry_options& o) {
    return {add_setting(sub, "--metric", o.metric, "Frame distance: mahalanobis (Eq 2) or l2 (Eq 1)",
                        CLI::IsMember(anima::enum_name_list<anima::frame_metric>())),
            add_setting(sub, "--window", o.window, "n of Eq 3: frames i-r and i+r are compared for r = 1..N",
                        integer_in(1, 100000))
                ->type_name("N"),
            add_setting(sub, "--smoothness", o.smoothness, "s of Eq 3: the binomial weights peak at r = S, 0..(N+1)/2",
                        integer_in(0, 100000))
                ->type_name("S"),
            add_setting(sub, "--candidate-window", o.candidate_window,
                        "Eq 5: a candidate is the highest score within +-N frames (0: --window)", integer_in(0, 100000))
                ->type_name("N"),
            add_setting(sub, "--min-pairs", o.min_pairs,
                        "Frames compared on fewer pairs (near the ends) are never candidates (0: --window)",
                        integer_in(0, 100000))
                ->type_name("N")};
}

anima::symmetry_params<double> make_symmetry_params(const symmetry_options& o) {
    if (o.smoothness > (o.window + 1) / 2)
        throw CLI::ValidationError("--smoothness", std::to_string(o.smoothness) + " is outside 0.." +
                                                       std::to_string((o.window + 1) / 2) + " for --window " +
                                                       std::to_string(o.window));
    if (o.min_pairs > o.window)
        throw CLI::ValidationError("--min-pairs", std::to_string(o.min_pairs) + " is more than --window " +
                                                      std::to_string(o.window) + " (the most pairs a frame has)");
    anima::symmetry_params<double> p;
    p.distance.metric = anima::parse_frame_metric(o.metric);
    p.radius = o.window;
    p.smoothness = o.smoothness;
    p.candidate_radius = o.candidate_window;
    p.min_pairs = o.min_pairs;
    return p;
}

std::string describe(const symmetry_options& o, const anima::symmetry_params<double>& p) {
    return o.metric + ", window " + std::to_string(p.radius) + ", smoothness " + std::to_string(p.smoothness);
}

json settings_json(const symmetry_options& o, const anima::symmetry_params<double>& p, std::size_t frames) {
    return {{"metric", o.metric},
            {"window", p.radius},
            {"smoothness", p.smoothness},
            {"candidate_window", p.candidate_radius ? p.candidate_radius : p.radius},
            {"min_pairs", anima::candidate_min_pairs(p, frames)}};
}

}  // namespace anima_cli
