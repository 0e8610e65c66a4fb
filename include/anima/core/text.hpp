// Small text helpers shared by the readers and the name-based guesses.
#pragma once

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace anima {

/// s with ASCII letters in lower case (other bytes unchanged, no locale).
inline std::string ascii_lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

/// a == b with ASCII letters compared case-insensitively (no locale).
inline bool ascii_equal_ignoring_case(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t k = 0; k < a.size(); ++k)
        if (std::tolower(static_cast<unsigned char>(a[k])) != std::tolower(static_cast<unsigned char>(b[k]))) return false;
    return true;
}

/// The number that is the whole of `text` (strtod's syntax: NaN, infinities
/// and hexadecimal included; out of range gives 0 or infinity), or empty
/// when any of it is not part of the number. For the readers' fields.
inline std::optional<double> whole_number(std::string_view text) {
    const std::string s(text);
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    // strtod skips leading blanks; a field with them is not all number.
    if (s.empty() || std::isspace(static_cast<unsigned char>(s[0])) || end != s.c_str() + s.size()) return std::nullopt;
    return v;
}

/// The lines of a text, without their line ends (LF, CRLF or a lone CR, as
/// old Mac exporters write) and without a leading UTF-8 byte order mark.
inline std::vector<std::string> text_lines(std::string_view text) {
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    std::vector<std::string> lines;
    std::size_t pos = 0;
    while (pos < text.size()) {
        const std::size_t end = std::min(text.find_first_of("\r\n", pos), text.size());
        lines.emplace_back(text.substr(pos, end - pos));
        pos = end + (text.substr(end, 2) == "\r\n" ? 2 : 1);
    }
    return lines;
}

}  // namespace anima
