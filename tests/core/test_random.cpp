// anima::random_source: the same stream for the same seed, uniform numbers
// in [0, 1), and normal samples whose distribution is the standard normal's.
#include <anima/core/random.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

TEST_CASE("random_source: a seed gives one stream; normal() is standard normal (Kolmogorov-Smirnov)") {
    anima::random_source a(42), b(42), c(43);
    bool same = true, differs = false;
    for (int i = 0; i < 100; ++i) {
        const double x = a.normal(), y = b.normal(), z = c.normal();
        same = same && x == y;
        differs = differs || x != z;
    }
    CHECK(same);
    CHECK(differs);

    constexpr std::size_t n = 100000;
    anima::random_source rng(7);
    std::vector<double> samples(n);
    double sum = 0, squares = 0;
    for (double& s : samples) {
        s = rng.normal();
        REQUIRE(std::isfinite(s));
        sum += s;
        squares += s * s;
    }
    const double mean = sum / n, variance = squares / n - mean * mean;
    CHECK(std::abs(mean) < 4 / std::sqrt(double(n)));   // four standard errors
    CHECK(std::abs(variance - 1) < 4 * std::sqrt(2.0 / n));
    // Largest gap between the samples' distribution and the normal's
    // (erf), against the Kolmogorov-Smirnov bound at the 0.1 % level.
    std::sort(samples.begin(), samples.end());
    double gap = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double cdf = 0.5 * (1 + std::erf(samples[i] / std::sqrt(2.0)));
        gap = std::max({gap, std::abs(cdf - double(i) / n), std::abs(cdf - double(i + 1) / n)});
    }
    CHECK(gap < 1.95 / std::sqrt(double(n)));
    // A uniform source would fail the same test: the check has teeth.
    double uniform_gap = 0;
    for (std::size_t i = 0; i < n; ++i) samples[i] = 6 * rng.uniform() - 3;
    std::sort(samples.begin(), samples.end());
    for (std::size_t i = 0; i < n; ++i)
        uniform_gap = std::max(uniform_gap, std::abs(0.5 * (1 + std::erf(samples[i] / std::sqrt(2.0))) - double(i) / n));
    CHECK(uniform_gap > 1.95 / std::sqrt(double(n)));
}

TEST_CASE("random_source: uniform() is in [0, 1) and below(n) in [0, n)") {
    anima::random_source rng(3);
    for (int i = 0; i < 10000; ++i) {
        const double u = rng.uniform();
        CHECK((u >= 0 && u < 1));
        CHECK(rng.below(7) < 7);
    }
}
