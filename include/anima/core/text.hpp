// Small text helpers shared by the readers and the name-based guesses.
#pragma once

#include <cctype>
#include <cstddef>
#include <string>
#include <string_view>

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

}  // namespace anima
