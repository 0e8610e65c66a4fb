// tile_grid against a pixel-by-pixel reading of where each tile must land.
#include <anima/image/tile_grid.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <vector>

namespace {

TEST_CASE_TEMPLATE("tile_grid puts each tile at the top-left of its cell, the rest background", T, float, double) {
    using grey = anima::grey_image<T>;
    // Tile (r, c) is filled with 10 r + c + 1, sizes differ; row 1 has one tile.
    const auto tile = [](Eigen::Index h, Eigen::Index w, T value) { return grey(grey::Constant(h, w, value)); };
    const std::vector<std::vector<grey>> tiles = {{tile(2, 3, 1), tile(4, 1, 2)}, {tile(1, 2, 11)}};
    const grey out = anima::tile_grid(tiles, 2, T(-1));
    // Cells 4 x 3, gap 2: 2 * 4 + 2 rows, 2 * 3 + 2 columns.
    REQUIRE(out.rows() == 10);
    REQUIRE(out.cols() == 8);
    for (Eigen::Index y = 0; y < out.rows(); ++y)
        for (Eigen::Index x = 0; x < out.cols(); ++x) {
            T expected = T(-1);
            if (y < 2 && x < 3) expected = 1;
            else if (y < 4 && x == 5) expected = 2;
            else if (y == 6 && x < 2) expected = 11;
            CHECK(out(y, x) == expected);
        }
    // No gap: the tiles touch.
    const grey touching = anima::tile_grid(std::vector<std::vector<grey>>{{tile(1, 1, 3), tile(1, 1, 4)}}, 0, T(0));
    CHECK(touching.rows() == 1);
    CHECK(touching.cols() == 2);
    CHECK(touching(0, 1) == T(4));
}

TEST_CASE_TEMPLATE("tile_grid refuses no tiles and a negative gap", T, float, double) {
    using grey = anima::grey_image<T>;
    CHECK_THROWS_AS(anima::tile_grid(std::vector<std::vector<grey>>{}, 1, T(0)), anima::invalid_argument);
    CHECK_THROWS_AS(anima::tile_grid(std::vector<std::vector<grey>>{{}, {}}, 1, T(0)), anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::tile_grid(std::vector<std::vector<grey>>{{grey::Zero(1, 1)}}, -1, T(0)),
                         doctest::Contains("gap -1"), anima::invalid_argument);
}

}  // namespace
