#include "common.hpp"

#include <algorithm>
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

namespace anima_cli {

// ---------------------------------------------------------------------------
// Files
// ---------------------------------------------------------------------------

std::string read_text_file(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (status.type() == std::filesystem::file_type::not_found) throw failure("'" + path + "' does not exist");
    if (status.type() == std::filesystem::file_type::directory) throw failure("'" + path + "' is a directory");
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        const int err = errno;
        throw anima::io_error("cannot open '" + path + "' for reading" + (err ? std::string(": ") + std::strerror(err) : ""));
    }
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw anima::io_error("error while reading '" + path + "'");
    return text.str();
}

document_t load_bvh_document(const std::string& path) {
    return anima::parse_bvh_document<double>(read_text_file(path), path);
}

int bvh_value_decimals(std::string_view text) {
    const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; };
    const auto digit = [](char c) { return c >= '0' && c <= '9'; };
    int best = 0;
    std::size_t i = 0;
    bool after_time = false;
    while (i < text.size()) {
        while (i < text.size() && space(text[i])) ++i;
        const std::size_t b = i;
        while (i < text.size() && !space(text[i])) ++i;
        const std::string_view t = text.substr(b, i - b);
        const bool frame_time = after_time;
        after_time = t == "Time:";
        if (frame_time) continue;
        // [sign] digits . digits, nothing else
        std::size_t k = 0;
        if (k < t.size() && (t[k] == '+' || t[k] == '-')) ++k;
        std::size_t digits = 0;
        while (k < t.size() && digit(t[k])) ++k, ++digits;
        if (k == t.size() || t[k] != '.') continue;
        int decimals = 0;
        for (++k; k < t.size() && digit(t[k]); ++k) ++decimals;
        if (k != t.size() || digits + static_cast<std::size_t>(decimals) == 0) continue;
        best = std::max(best, std::min(decimals, 17));
    }
    return best;
}

clip_t load_clip(const std::string& path) { return anima::to_clip(load_bvh_document(path)); }

void write_text_file(const std::string& path, std::string_view text) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw failure("cannot write '" + path + "': it is a directory");
    errno = 0;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) {
        const int err = errno;
        throw failure("cannot open '" + path + "' for writing" + (err ? std::string(": ") + std::strerror(err) : ""));
    }
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) {
        const int err = errno;
        throw failure("error while writing '" + path + "'" + (err ? std::string(": ") + std::strerror(err) : ""));
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
    std::string_view s = text;
    int sign = 1;
    if (!s.empty() && (s[0] == '+' || s[0] == '-')) {
        sign = s[0] == '-' ? -1 : 1;
        s.remove_prefix(1);
    }
    if (s.size() == 1) {
        const char c = static_cast<char>(std::tolower(static_cast<unsigned char>(s[0])));
        if (c >= 'x' && c <= 'z') return {static_cast<anima::axis>(c - 'x'), sign};
    }
    throw failure("'" + std::string(text) + "' is not an axis: use +X, -X, +Y, -Y, +Z or -Z");
}

CLI::Validator signed_axis_validator() {
    return CLI::Validator(
        [](std::string& value) -> std::string {
            try {
                (void)parse_signed_axis(value);
                return {};
            } catch (const failure& e) {
                return e.what();
            }
        },
        "{+X,-X,+Y,-Y,+Z,-Z}", "signed axis");
}

CLI::Validator euler_order_validator() {
    return CLI::Validator(
        [](std::string& value) -> std::string {
            try {
                (void)anima::parse_euler_order(value);
                return {};
            } catch (const anima::error&) {
                return "'" + value + "' is not a rotation order: use XYZ, XZY, YXZ, YZX, ZXY or ZYX";
            }
        },
        "{XYZ,XZY,YXZ,YZX,ZXY,ZYX}", "euler order");
}

std::vector<std::string> rotation_orders(const skeleton_t& skeleton) {
    std::vector<std::string> out;
    for (std::size_t j = 0; j < skeleton.size(); ++j) {
        std::string order;
        for (anima::axis a : skeleton.rotation_axes(j)) order += static_cast<char>('X' + static_cast<int>(a));
        if (!order.empty() && std::find(out.begin(), out.end(), order) == out.end()) out.push_back(order);
    }
    return out;
}

std::string rotation_order_summary(const skeleton_t& skeleton) {
    std::vector<std::string> full;
    for (const auto& o : rotation_orders(skeleton))
        if (o.size() == 3) full.push_back(o);
    if (full.empty()) return "none";
    return full.size() == 1 ? full[0] : "mixed";
}

std::string channel_list(const std::vector<anima::channel>& channels) {
    std::string out;
    for (std::size_t i = 0; i < channels.size(); ++i) {
        if (i) out += ' ';
        out += anima::to_string(channels[i]);
    }
    return out;
}

// ---------------------------------------------------------------------------
// Body sides
// ---------------------------------------------------------------------------

body_side side_of(std::string_view name) {
    std::string lower(name);
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (lower.find("left") != std::string::npos) return body_side::left;
    if (lower.find("right") != std::string::npos) return body_side::right;
    if (name.size() >= 2) {
        const char second = name[1];
        const bool separated = std::isupper(static_cast<unsigned char>(second)) ||
                               std::isdigit(static_cast<unsigned char>(second)) || second == '_' || second == '-' ||
                               second == '.' || second == ':';
        if (separated && (name[0] == 'l' || name[0] == 'L')) return body_side::left;
        if (separated && (name[0] == 'r' || name[0] == 'R')) return body_side::right;
    }
    return body_side::centre;
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

void svg_document::raw(std::string_view markup) {
    body_ += markup;
    if (!markup.empty() && markup.back() != '\n') body_ += '\n';
}

std::string svg_document::str() const {
    const std::string w = svg_number(width_), h = svg_number(height_);
    std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    out += "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" + w + "\" height=\"" + h +
           "\" viewBox=\"0 0 " + w + " " + h + "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\">\n";
    out += "<title>" + xml_escape(title_) + "</title>\n";
    out += body_;
    out += "</svg>\n";
    return out;
}

}  // namespace anima_cli
