// A seedable random source whose stream is the same on every platform.
// std::mt19937_64 is specified bit for bit by the standard, but the
// standard distributions are not, so the conversions to numbers are ours.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

namespace anima {

/// Reproducible random numbers: same seed, same stream, on every compiler.
class random_source {
public:
    explicit random_source(std::uint64_t seed = 1) : engine_(seed) {}

    /// Uniform in [0, 1) with 53 random bits.
    double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

    /// Uniform integer in [0, n) for n > 0, without modulo bias.
    std::uint64_t below(std::uint64_t n) {
        const std::uint64_t limit = ~std::uint64_t(0) - (~std::uint64_t(0) % n);
        std::uint64_t x = engine_();
        while (x >= limit) x = engine_();
        return x % n;
    }

    /// The next raw 64-bit value.
    std::uint64_t raw() { return engine_(); }

    /// A standard normal sample (Box-Muller on two uniforms): the same
    /// stream on every platform, unlike std::normal_distribution.
    double normal() {
        const double u = 1.0 - uniform();  // (0, 1]: the logarithm stays finite
        const double v = uniform();
        return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586476925 * v);
    }

private:
    std::mt19937_64 engine_;
};

}  // namespace anima
