// libFuzzer target for the .pts landmark reader. Any input must either parse
// or raise an anima::error; parsed landmarks are finite, no more than the
// file's bytes justify, and read back the same after format_pts.
#include <anima/core/error.hpp>
#include <anima/sadm/landmarks.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using anima_fuzz::require;
    if (size > anima_fuzz::max_input) return 0;
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const auto s = anima::parse_pts<double>(text, "fuzz");
        require(s.rows() >= 1 && static_cast<std::size_t>(s.rows()) <= size / 4 + 1);
        require(s.allFinite());
        const auto back = anima::parse_pts<double>(anima::format_pts(s), "back");
        require(back == s);
    } catch (const anima::error&) {
    }
    try {
        const auto f = anima::parse_pts<float>(text, "fuzz");
        require(f.allFinite());
    } catch (const anima::error&) {
    }
    return 0;
}
