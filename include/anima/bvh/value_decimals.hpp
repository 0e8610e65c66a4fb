// How many decimals a BVH file's values are written with, so that a tool
// that reads and rewrites a file keeps its precision without inventing any.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string_view>

namespace anima {

/// The most decimals any OFFSET or channel value of BVH text is written with
/// in plain notation ("-0.0198488": 7), at most 17: with that many,
/// anima::format_bvh gives every such number back unchanged. Numbers in
/// exponent notation ("3.88251e-19", rounding noise in some exporters' files)
/// do not count, nor does the Frame Time (which the writer prints in its
/// shortest exact form). 0 for text without such numbers.
inline int bvh_value_decimals(std::string_view text) {
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

}  // namespace anima
