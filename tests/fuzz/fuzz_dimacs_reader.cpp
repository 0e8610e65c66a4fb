// libFuzzer target for the DIMACS max-flow reader. Any input must either
// parse or raise an anima::error, without allocating more than its counts
// justify; a parsed problem must satisfy its invariants and be solvable.
#include <anima/core/error.hpp>
#include <anima/maxflow/dimacs.hpp>

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using anima_fuzz::require;
    if (size > anima_fuzz::max_input) return 0;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const auto p = anima::parse_dimacs_max_flow<long long>(text, "fuzz");
        require(p.nodes >= 2);
        require(p.source < p.nodes && p.sink < p.nodes && p.source != p.sink);
        // The node count is bounded by the arcs (or the documented limit).
        require(p.nodes <= anima::dimacs_max_isolated_nodes || p.nodes / 2 <= p.arcs.size() + 1);
        for (const auto& a : p.arcs) require(a.from < p.nodes && a.to < p.nodes && a.capacity >= 0);
        const auto r = anima::solve_max_flow(p);
        require(r.flow >= 0);
    } catch (const anima::error&) {
    }
    try {
        (void)anima::parse_dimacs_max_flow<double>(text, "fuzz");
    } catch (const anima::error&) {
    }
    return 0;
}
