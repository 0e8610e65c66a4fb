// Landmark sets (one 2-D point per row, image coordinates: x right, y down)
// and the FGNet/IBUG .pts text format:
//   version: 1
//   n_points: 68
//   {
//   x y      (one line per point)
//   }
#pragma once

#include <anima/core/error.hpp>
#include <anima/core/file_io.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>

namespace anima {

/// n landmarks, row k = (x, y) of landmark k.
template <class T>
using landmark_set = Eigen::Matrix<T, Eigen::Dynamic, 2>;

/// A landmark set as the column vector (x0, y0, x1, y1, ...) of Eq 1.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, 1> to_shape_vector(const landmark_set<T>& s) {
    Eigen::Matrix<T, Eigen::Dynamic, 1> v(2 * s.rows());
    for (Eigen::Index k = 0; k < s.rows(); ++k) {
        v(2 * k) = s(k, 0);
        v(2 * k + 1) = s(k, 1);
    }
    return v;
}

/// The inverse of to_shape_vector. Throws anima::invalid_argument for an odd length.
template <class Derived>
landmark_set<typename Derived::Scalar> from_shape_vector(const Eigen::MatrixBase<Derived>& v) {
    if (v.size() % 2 != 0)
        throw invalid_argument("anima::from_shape_vector: the vector has odd length " + std::to_string(v.size()));
    landmark_set<typename Derived::Scalar> s(v.size() / 2, 2);
    for (Eigen::Index k = 0; k < s.rows(); ++k) {
        s(k, 0) = v(2 * k);
        s(k, 1) = v(2 * k + 1);
    }
    return s;
}

/// Throws anima::invalid_argument naming `who` unless every coordinate is finite.
template <class T>
void check_finite_landmarks(const landmark_set<T>& s, const std::string& who, const std::string& what = "landmark") {
    for (Eigen::Index k = 0; k < s.rows(); ++k)
        if (!std::isfinite(static_cast<double>(s(k, 0))) || !std::isfinite(static_cast<double>(s(k, 1))))
            throw invalid_argument(who + ": " + what + " " + std::to_string(k) + " is not finite");
}

/// Throws anima::invalid_argument naming `who` and the point unless every
/// landmark lies on a width x height image: 0 <= x <= width, 0 <= y <= height
/// (the image's area, edges included; a landmark may sit on a border pixel).
template <class T>
void check_landmarks_inside(const landmark_set<T>& s, Eigen::Index width, Eigen::Index height, const std::string& who) {
    check_finite_landmarks(s, who);
    for (Eigen::Index k = 0; k < s.rows(); ++k) {
        const double x = static_cast<double>(s(k, 0)), y = static_cast<double>(s(k, 1));
        if (!(x >= 0 && y >= 0 && x <= static_cast<double>(width) && y <= static_cast<double>(height))) {
            std::ostringstream m;
            m << who << ": landmark " << k << " (" << x << ", " << y << ") is outside the " << width << " x " << height
              << " image";
            throw invalid_argument(m.str());
        }
    }
}

/// Parses .pts text. `source` names it in errors. Throws
/// anima::parse_error ("source:line: message") for a missing header line,
/// a bad point count, a malformed or non-finite coordinate, a missing brace
/// or a point count that does not match n_points.
template <class T>
landmark_set<T> parse_pts(const std::string& text, const std::string& source = "<pts>") {
    std::istringstream in(text);
    std::string line;
    std::size_t line_no = 0;
    const auto next = [&](const char* expected) {
        while (std::getline(in, line)) {
            ++line_no;
            if (!line.empty() && line.back() == '\r') line.pop_back();
            if (line.find_first_not_of(" \t") != std::string::npos) return;
        }
        throw parse_error(source, line_no, std::string("file ends before ") + expected);
    };
    next("the 'version:' line");
    if (line.rfind("version:", 0) != 0) throw parse_error(source, line_no, "expected 'version: 1', found '" + line + "'");
    next("the 'n_points:' line");
    long count = -1;
    {
        std::istringstream f(line);
        std::string key;
        f >> key >> count;
        if (key != "n_points:" || !f || count <= 0 || count > 1000000)
            throw parse_error(source, line_no, "expected 'n_points: N' with N >= 1, found '" + line + "'");
    }
    // A point line takes at least 4 bytes ("0 0" and a line end): check the
    // count against the file before allocating.
    if (static_cast<std::size_t>(count) > text.size() / 4 + 1)
        throw parse_error(source, line_no, "n_points " + std::to_string(count) + " is more than the file's " +
                                               std::to_string(text.size()) + " bytes can hold");
    next("'{'");
    if (line.find('{') == std::string::npos) throw parse_error(source, line_no, "expected '{', found '" + line + "'");
    landmark_set<T> out(count, 2);
    for (long k = 0; k < count; ++k) {
        next("all n_points points were read");
        if (line.find('}') != std::string::npos)
            throw parse_error(source, line_no,
                              "'}' after " + std::to_string(k) + " points, n_points says " + std::to_string(count));
        std::istringstream f(line);
        double x = 0, y = 0;
        std::string rest;
        if (!(f >> x >> y) || (f >> rest))
            throw parse_error(source, line_no, "expected two numbers 'x y', found '" + line + "'");
        if (!std::isfinite(x) || !std::isfinite(y) || std::abs(x) > static_cast<double>(std::numeric_limits<T>::max()) ||
            std::abs(y) > static_cast<double>(std::numeric_limits<T>::max()))
            throw parse_error(source, line_no, "point " + std::to_string(k) + " is not finite: '" + line + "'");
        out(k, 0) = static_cast<T>(x);
        out(k, 1) = static_cast<T>(y);
    }
    next("'}'");
    if (line.find('}') == std::string::npos)
        throw parse_error(source, line_no, "expected '}' after " + std::to_string(count) + " points, found '" + line + "'");
    return out;
}

/// Reads a .pts file. Throws anima::io_error when it cannot be read (missing,
/// a folder) and
/// anima::parse_error ("path:line: message") when it is malformed.
template <class T>
landmark_set<T> read_pts(const std::string& path) {
    return parse_pts<T>(read_file(path), path);
}

/// .pts text for a landmark set, every coordinate with enough digits to read back exactly.
template <class T>
std::string format_pts(const landmark_set<T>& s) {
    check_finite_landmarks(s, "anima::format_pts");
    std::ostringstream out;
    out << std::setprecision(std::numeric_limits<T>::max_digits10);
    out << "version: 1\nn_points: " << s.rows() << "\n{\n";
    for (Eigen::Index k = 0; k < s.rows(); ++k) out << s(k, 0) << ' ' << s(k, 1) << '\n';
    out << "}\n";
    return out.str();
}

}  // namespace anima
