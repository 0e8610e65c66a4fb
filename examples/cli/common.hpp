// Helpers shared by the `anima` subcommands: loading BVH files with readable
// errors, writing output files, JSON and number formatting, option
// validators, left/right classification of joint names and a small SVG
// writer.
#pragma once

#include <anima/anima.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
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

/// The whole content of a file. Throws failure for a missing file or a
/// directory and anima::io_error when it cannot be read.
std::string read_text_file(const std::string& path);

/// The most decimals any OFFSET or channel value of BVH text is written with
/// in plain notation ("-0.0198488": 7), at most 17: with that many,
/// anima::format_bvh gives every such number back unchanged. Numbers in
/// exponent notation ("3.88251e-19", rounding noise in some exporters' files)
/// do not count, nor does the Frame Time (which the writer prints in its
/// shortest exact form).
int bvh_value_decimals(std::string_view text);

/// Writes text to a file, replacing it. Throws failure naming the file and
/// the system's reason when it cannot be opened or written.
void write_text_file(const std::string& path, std::string_view text);

/// The last component of a path ("walk.bvh" for "data/walk.bvh").
std::string file_name(const std::string& path);

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


/// The rotation order of a skeleton's joints with three rotation channels:
/// "ZXY" when they all agree, "mixed" when they differ, "none" when no joint
/// has three rotation channels.
std::string rotation_order_summary(const skeleton_t& skeleton);

/// The distinct rotation orders of a skeleton, in order of first appearance
/// (joints with fewer than three rotation channels give e.g. "Z" or "ZX").
std::vector<std::string> rotation_orders(const skeleton_t& skeleton);

/// "Zrotation Xrotation Yrotation".
std::string channel_list(const std::vector<anima::channel>& channels);

// ---------------------------------------------------------------------------
// Body sides
// ---------------------------------------------------------------------------

enum class body_side { centre, left, right };

/// The side of the body a joint is on, from its name: names containing
/// "left" / "right" (any case), or starting with l / L (r / R) followed by an
/// upper-case letter, a digit, '_', '-', '.' or ':' (lShldr, LHipJoint,
/// L_Foot). "LowerBack" and "Root" are centre joints.
body_side side_of(std::string_view joint_name);

// ---------------------------------------------------------------------------
// SVG
// ---------------------------------------------------------------------------

/// Escapes text for XML character data and attribute values.
std::string xml_escape(std::string_view text);

/// A minimal SVG document builder: coordinates in pixels, y down.
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
    /// Raw markup (e.g. "<g>" / "</g>"), appended as is.
    void raw(std::string_view markup);

    double width() const noexcept { return width_; }
    double height() const noexcept { return height_; }
    /// The complete document, XML declaration included.
    std::string str() const;

private:
    double width_, height_;
    std::string title_;
    std::string body_;
};

/// A coordinate for SVG output, two decimals, no trailing zeros.
std::string svg_number(double value);

}  // namespace anima_cli
