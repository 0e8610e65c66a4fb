// A grid of numbers as CSV text, one grid row a line: the right-hand side f
// of a Poisson problem read from a file, and a solution u written back.
#pragma once

#include <anima/core/error.hpp>
#include <anima/core/text.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace anima {

/// Reads `rows` lines of `cols` numbers separated by commas, semicolons,
/// tabs or spaces; blank lines are skipped (line ends and a byte order mark
/// as text_lines reads them). Throws anima::parse_error ("path:line:
/// message") for a field that is not a finite number in T (NaN, infinities,
/// 1e300 for float), a line with too few or too many numbers, and too few
/// or too many lines; anima::invalid_argument for a grid size below 1.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> parse_grid_csv(std::string_view text, const std::string& path,
                                                                 Eigen::Index rows, Eigen::Index cols) {
    if (rows < 1 || cols < 1)
        throw invalid_argument("anima::parse_grid_csv: a " + std::to_string(rows) + " x " + std::to_string(cols) +
                               " grid");
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> f(rows, cols);
    Eigen::Index row = 0;
    std::size_t line_number = 0;
    for (std::string line : text_lines(text)) {
        ++line_number;
        for (char& c : line)
            if (c == ',' || c == ';' || c == '\t' || c == '\r') c = ' ';
        if (line.find_first_not_of(' ') == std::string::npos) continue;
        if (row == rows) throw parse_error(path, line_number, "more than the " + std::to_string(rows) + " rows of the grid");
        std::istringstream fields(line);
        std::string field;
        Eigen::Index col = 0;
        while (fields >> field) {
            if (col == cols) throw parse_error(path, line_number, "more than " + std::to_string(cols) + " numbers");
            const std::optional<double> v = whole_number(field);
            if (!v) throw parse_error(path, line_number, "'" + field + "' is not a number");
            const T value = static_cast<T>(*v);
            if (!std::isfinite(value))
                throw parse_error(path, line_number,
                                  "'" + field + "' (number " + std::to_string(col + 1) + ") is not a finite number" +
                                      (std::isfinite(*v) ? " in this precision" : ""));
            f(row, col++) = value;
        }
        if (col != cols)
            throw parse_error(path, line_number, std::to_string(col) + " numbers, expected " + std::to_string(cols));
        ++row;
    }
    if (row != rows)
        throw parse_error(path, line_number,
                          "the file has " + std::to_string(row) + " rows, the grid " + std::to_string(rows));
    return f;
}

/// The grid as CSV: one line per row, values comma-separated with 17
/// significant digits (read back exactly by parse_grid_csv<double>).
template <class Derived>
std::string format_grid_csv(const Eigen::MatrixBase<Derived>& u) {
    std::string out;
    char buf[32];
    for (Eigen::Index i = 0; i < u.rows(); ++i) {
        for (Eigen::Index j = 0; j < u.cols(); ++j) {
            std::snprintf(buf, sizeof buf, "%.17g", static_cast<double>(u(i, j)));
            if (j) out += ',';
            out += buf;
        }
        out += '\n';
    }
    return out;
}

}  // namespace anima
