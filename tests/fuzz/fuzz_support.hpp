// Shared by the libFuzzer targets: the input size limit and a check that
// stops the fuzzer (as a crash it reports) when an invariant does not hold.
#pragma once

#include <cstddef>

namespace anima_fuzz {

/// Inputs above this size are skipped: they only slow the search down, and
/// the readers' limits are exercised by counts in small inputs.
constexpr std::size_t max_input = std::size_t{1} << 20;

inline void require(bool ok) {
    if (!ok) __builtin_trap();
}

}  // namespace anima_fuzz
