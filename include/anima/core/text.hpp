// Small text helpers shared by the readers and the name-based guesses.
#pragma once

#include <cctype>
#include <string>
#include <string_view>

namespace anima {

/// s with ASCII letters in lower case (other bytes unchanged, no locale).
inline std::string ascii_lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

}  // namespace anima
