// The text format of saved regressors: one keyword per line followed by its
// values, matrices as a "key rows cols" line and one line per row. Values are
// written with max_digits10 significant digits in the classic locale, so a
// model read back predicts bit for bit what the saved one did. The reader
// counts lines and reports every problem as anima::parse_error.
#pragma once

#include <anima/core/error.hpp>

#include <Eigen/Core>

#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <istream>
#include <limits>
#include <locale>
#include <ostream>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace anima::detail {

/// Sets full precision and the classic locale on a stream for its lifetime.
class regress_stream_format {
public:
    template <class T>
    regress_stream_format(std::ostream& out, T /*scalar tag*/)
        : out_(out), precision_(out.precision()), flags_(out.flags()), locale_(out.imbue(std::locale::classic())) {
        out_.precision(std::numeric_limits<T>::max_digits10);
        out_.unsetf(std::ios_base::floatfield);
    }
    ~regress_stream_format() {
        out_.precision(precision_);
        out_.flags(flags_);
        out_.imbue(locale_);
    }
    regress_stream_format(const regress_stream_format&) = delete;
    regress_stream_format& operator=(const regress_stream_format&) = delete;

private:
    std::ostream& out_;
    std::streamsize precision_;
    std::ios_base::fmtflags flags_;
    std::locale locale_;
};

/// "key v0 v1 ...": a vector (or any dense expression, read row-major) on one line.
template <class Derived>
void write_regress_values(std::ostream& out, const char* key, const Eigen::DenseBase<Derived>& values) {
    out << key;
    for (Eigen::Index r = 0; r < values.rows(); ++r)
        for (Eigen::Index c = 0; c < values.cols(); ++c) out << ' ' << values(r, c);
    out << '\n';
}

/// "key rows cols", then one line per row.
template <class Derived>
void write_regress_matrix(std::ostream& out, const char* key, const Eigen::DenseBase<Derived>& m) {
    out << key << ' ' << m.rows() << ' ' << m.cols() << '\n';
    for (Eigen::Index r = 0; r < m.rows(); ++r) {
        for (Eigen::Index c = 0; c < m.cols(); ++c) out << (c == 0 ? "" : " ") << m(r, c);
        out << '\n';
    }
}

/// Reads the format above line by line; every error names source:line.
class regress_reader {
public:
    regress_reader(std::istream& in, std::string source) : in_(in), source_(std::move(source)) {}

    const std::string& source() const { return source_; }
    std::size_t line() const { return line_; }

    [[noreturn]] void fail(const std::string& message) const { throw parse_error(source_, line_, message); }

    /// The next line's whitespace-separated tokens; the file must not end here.
    std::vector<std::string> next_tokens(const char* what) {
        std::string text;
        if (!std::getline(in_, text)) {
            ++line_;
            fail(std::string("file ends where '") + what + "' was expected");
        }
        ++line_;
        std::istringstream words(text);
        std::vector<std::string> tokens;
        for (std::string w; words >> w;) tokens.push_back(w);
        return tokens;
    }

    /// The next line, which must start with key; returns the tokens after it.
    std::vector<std::string> expect(const char* key) {
        std::vector<std::string> tokens = next_tokens(key);
        if (tokens.empty() || tokens[0] != key)
            fail(std::string("expected '") + key + "', found '" + (tokens.empty() ? std::string() : tokens[0]) + "'");
        tokens.erase(tokens.begin());
        return tokens;
    }

    /// A non-negative integer token no larger than max_value.
    long parse_count(const std::string& token, const char* what, long max_value = 1L << 24) const {
        errno = 0;
        char* end = nullptr;
        const long v = std::strtol(token.c_str(), &end, 10);
        if (token.empty() || *end != '\0' || errno != 0 || v < 0 || v > max_value)
            fail(std::string("bad ") + what + " '" + token + "'");
        return v;
    }

    /// A finite number token, read at full precision for T.
    template <class T>
    T parse_value(const std::string& token, const char* what) const {
        char* end = nullptr;
        T v;
        if constexpr (std::is_same_v<T, float>) v = std::strtof(token.c_str(), &end);
        else if constexpr (std::is_same_v<T, double>) v = std::strtod(token.c_str(), &end);
        else v = static_cast<T>(std::strtold(token.c_str(), &end));
        // Underflow (ERANGE with a tiny or subnormal result) is the exact value
        // a saved subnormal reads back as; overflow shows as infinity.
        if (token.empty() || *end != '\0' || !std::isfinite(static_cast<double>(v)))
            fail(std::string("bad ") + what + " value '" + token + "'");
        return v;
    }

    /// "key n" with the count checked against expected (or any count if expected < 0).
    long read_count(const char* key, long expected = -1) {
        const std::vector<std::string> t = expect(key);
        if (t.size() != 1) fail(std::string("'") + key + "' takes one count");
        const long v = parse_count(t[0], key);
        if (expected >= 0 && v != expected)
            fail(std::string("'") + key + "' is " + std::to_string(v) + ", expected " + std::to_string(expected));
        return v;
    }

    template <class T>
    T read_scalar(const char* key) {
        const std::vector<std::string> t = expect(key);
        if (t.size() != 1) fail(std::string("'") + key + "' takes one value");
        return parse_value<T>(t[0], key);
    }

    /// "key v0 ... v(size-1)" as a row vector.
    template <class T>
    Eigen::Matrix<T, 1, Eigen::Dynamic> read_values(const char* key, Eigen::Index size) {
        const std::vector<std::string> t = expect(key);
        if (static_cast<Eigen::Index>(t.size()) != size)
            fail(std::string("'") + key + "' has " + std::to_string(t.size()) + " values, expected " +
                 std::to_string(size));
        Eigen::Matrix<T, 1, Eigen::Dynamic> v(size);
        for (Eigen::Index i = 0; i < size; ++i) v(i) = parse_value<T>(t[static_cast<std::size_t>(i)], key);
        return v;
    }

    /// "key rows cols" (checked against the expected shape) and its rows.
    template <class T>
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> read_matrix(const char* key, Eigen::Index rows,
                                                                 Eigen::Index cols) {
        const std::vector<std::string> t = expect(key);
        if (t.size() != 2) fail(std::string("'") + key + "' takes rows and columns");
        const long r = parse_count(t[0], "row count"), c = parse_count(t[1], "column count");
        if (r != rows || c != cols)
            fail(std::string("'") + key + "' is " + std::to_string(r) + " x " + std::to_string(c) + ", expected " +
                 std::to_string(rows) + " x " + std::to_string(cols));
        // The shape is not trusted to size memory: values are collected as
        // the rows are read, so a file claiming more than it holds fails at
        // its end rather than allocating first.
        std::vector<T> values;
        for (Eigen::Index i = 0; i < rows; ++i) {
            const std::vector<std::string> row = next_tokens(key);
            if (static_cast<Eigen::Index>(row.size()) != cols)
                fail(std::string("row ") + std::to_string(i) + " of '" + key + "' has " + std::to_string(row.size()) +
                     " values, expected " + std::to_string(cols));
            for (Eigen::Index j = 0; j < cols; ++j) values.push_back(parse_value<T>(row[static_cast<std::size_t>(j)], key));
        }
        return Eigen::Map<const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(values.data(), rows,
                                                                                                   cols);
    }

private:
    std::istream& in_;
    std::string source_;
    std::size_t line_ = 0;
};

}  // namespace anima::detail
