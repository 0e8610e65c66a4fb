// percentile_grey against a reference that sorts every value: the white
// level is the percentile's element, the grey levels scale to it and clip
// above it, and bad input is refused.
#include <anima/image/percentile_grey.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace {

TEST_CASE_TEMPLATE("percentile_grey: white at the percentile of the sorted values, levels scaled to it", T, float,
                   double) {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    // 7 x 9 values in no order: (37 k) mod 101 / 4, k in row-major order.
    matrix m(7, 9);
    for (Eigen::Index y = 0; y < 7; ++y)
        for (Eigen::Index x = 0; x < 9; ++x) m(y, x) = static_cast<T>((37 * (y * 9 + x)) % 101) / 4;
    for (const double p : {0.0, 50.0, 99.0, 100.0}) {
        std::vector<T> all(m.data(), m.data() + m.size());
        std::sort(all.begin(), all.end());
        const T white = all[static_cast<std::size_t>(62 * p / 100)];  // n - 1 = 62
        const auto g = anima::percentile_grey(m, p);
        CHECK(g.white == white);
        REQUIRE(g.bytes.size() == 63);
        for (Eigen::Index y = 0; y < 7; ++y)
            for (Eigen::Index x = 0; x < 9; ++x) {
                const double value = static_cast<double>(m(y, x));
                const double level = white > 0 ? std::min(1.0, value / static_cast<double>(white)) : 0.0;
                CHECK(g.bytes[static_cast<std::size_t>(y * 9 + x)] == std::lround(255 * level));
            }
    }
    // The largest value is white at 100, a value of half of it mid-grey.
    matrix two(1, 2);
    two << T(2), T(1);
    const auto g = anima::percentile_grey(two, 100);
    CHECK(g.bytes == std::vector<unsigned char>{255, 128});
    // All zero: black, white 0.
    const auto black = anima::percentile_grey(matrix::Zero(2, 3), 99);
    CHECK(black.white == T(0));
    CHECK(black.bytes == std::vector<unsigned char>(6, 0));
}

TEST_CASE_TEMPLATE("percentile_grey refuses empty, negative and non-finite input and a bad percentile", T, float,
                   double) {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    CHECK_THROWS_AS(anima::percentile_grey(matrix(0, 3), 99), anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::percentile_grey(matrix::Ones(2, 2), 101), doctest::Contains("percentile"),
                         anima::invalid_argument);
    CHECK_THROWS_AS(anima::percentile_grey(matrix::Ones(2, 2), -1), anima::invalid_argument);
    matrix bad = matrix::Ones(2, 3);
    bad(1, 2) = -1;
    CHECK_THROWS_WITH_AS(anima::percentile_grey(bad, 99), doctest::Contains("row 1, column 2"), anima::invalid_argument);
    bad(1, 2) = std::numeric_limits<T>::quiet_NaN();
    CHECK_THROWS_AS(anima::percentile_grey(bad, 99), anima::invalid_argument);
}

}  // namespace
