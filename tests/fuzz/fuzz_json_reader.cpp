// libFuzzer target for the JSON reader behind flight key sets. Any input must
// either parse or raise an anima::error; a parsed tree has finite numbers,
// unique member names and line numbers within the input.
#include <anima/core/error.hpp>
#include <anima/core/json_reader.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"

namespace {

void check(const anima::json_value& v, std::size_t lines, std::size_t depth) {
    using anima_fuzz::require;
    require(depth <= 65);
    require(v.line() >= 1 && v.line() <= lines);
    if (v.is_number()) require(std::isfinite(v.number()));
    if (v.is_array())
        for (const auto& item : v.array()) check(item, lines, depth + 1);
    if (v.is_object()) {
        const auto& members = v.object();
        for (std::size_t k = 0; k < members.size(); ++k) {
            for (std::size_t m = 0; m < k; ++m) require(members[m].first != members[k].first);
            require(v.find(members[k].first) == &members[k].second);
            check(members[k].second, lines, depth + 1);
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > anima_fuzz::max_input) return 0;
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const auto doc = anima::parse_json(text, "fuzz");
        check(doc, static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1, 0);
    } catch (const anima::error&) {
    }
    return 0;
}
