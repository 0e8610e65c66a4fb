// Standard normal samples from anima::random_source (Box-Muller), the same
// stream on every platform.
#pragma once

#include <anima/core/random.hpp>

#include <cmath>

namespace anima::detail {

inline double standard_normal(random_source& rng) {
    const double u = 1.0 - rng.uniform();  // (0, 1]: the logarithm stays finite
    const double v = rng.uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586476925 * v);
}

}  // namespace anima::detail
