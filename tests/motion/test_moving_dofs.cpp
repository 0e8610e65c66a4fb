// moving_dofs against a brute-force reading of a matrix built by hand: the
// thresholds apply per kind of DOF, the root's ground position is left out
// whatever it does, and bad arguments are refused.
#include <anima/motion/moving_dofs.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <limits>
#include <vector>

namespace {

using anima::dof;

/// Root translation x, y, z; root rotation x, y, z; joint 1 rotation x, y, z.
template <class T>
anima::dof_layout<T> hand_layout() {
    anima::dof_layout<T> layout;
    for (int k = 0; k < 3; ++k) layout.dofs.push_back({0, dof::kind::translation, k});
    for (int k = 0; k < 3; ++k) layout.dofs.push_back({0, dof::kind::rotation, k});
    for (int k = 0; k < 3; ++k) layout.dofs.push_back({1, dof::kind::rotation, k});
    return layout;
}

TEST_CASE_TEMPLATE("moving_dofs keeps the DOFs whose range is over their kind's threshold", T, float, double) {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const auto layout = hand_layout<T>();
    // Column c ramps by step[c] per frame over 5 frames: its range is 4 * step.
    const T step[] = {T(10), T(0.5), T(3), T(0.1), T(0.001), T(0.02), T(0), T(0.3), T(0.0049)};
    matrix m(5, 9);
    for (Eigen::Index f = 0; f < 5; ++f)
        for (Eigen::Index c = 0; c < 9; ++c) m(f, c) = T(1) - step[c] * static_cast<T>(f);
    const anima::signed_axis up{anima::axis::y, 1};
    const T min_rotation = T(0.02), min_translation = T(1);
    const auto moving = anima::moving_dofs(m, layout, up, min_rotation, min_translation);
    // Brute force: each column's range against its threshold, the root's x and z skipped.
    std::vector<Eigen::Index> expected;
    for (Eigen::Index c = 0; c < 9; ++c) {
        if (c == 0 || c == 2) continue;
        const T range = 4 * step[c];
        if (range > (c < 3 ? min_translation : min_rotation)) expected.push_back(c);
    }
    REQUIRE(moving.size() == expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        CHECK(moving[i].column == expected[i]);
        CHECK(moving[i].lo == doctest::Approx(1 - 4 * step[expected[i]]).epsilon(1e-6));
        CHECK(moving[i].hi == doctest::Approx(1).epsilon(1e-6));
    }
    // Columns 1 (root height, 2 > 1), 3 (0.4 rad), 5 (0.08 rad), 7 (1.2 rad).
    CHECK(expected == std::vector<Eigen::Index>{1, 3, 5, 7});
    // Up along Z: the root's z is its height now, and y its ground position.
    const auto z_up = anima::moving_dofs(m, layout, anima::signed_axis{anima::axis::z, -1}, min_rotation, min_translation);
    REQUIRE(!z_up.empty());
    CHECK(z_up[0].column == 2);
    CHECK(anima::moving_dofs(matrix(0, 9), layout, up, min_rotation, min_translation).empty());
}

TEST_CASE_TEMPLATE("moving_dofs refuses a matrix of another layout and bad thresholds", T, float, double) {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const auto layout = hand_layout<T>();
    const anima::signed_axis up{anima::axis::y, 1};
    CHECK_THROWS_AS(anima::moving_dofs(matrix::Zero(2, 8), layout, up, T(0), T(0)), anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::moving_dofs(matrix::Zero(2, 9), layout, up, T(-1), T(0)),
                         doctest::Contains("min_rotation"), anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::moving_dofs(matrix::Zero(2, 9), layout, up, T(0), std::numeric_limits<T>::infinity()),
                         doctest::Contains("min_translation"), anima::invalid_argument);
}

}  // namespace
