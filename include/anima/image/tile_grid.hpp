// Grey images laid out in a grid, a contact sheet: each at the top-left of
// its cell, every cell as large as the largest image, a gap between cells.
// What the figures comparing frames side by side are made of.
#pragma once

#include <anima/core/error.hpp>
#include <anima/image/image.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace anima {

/// `tiles[r][c]` at the top-left of cell (r, c). Cells are as tall as the
/// tallest tile and as wide as the widest; `gap` pixels separate them, and
/// every pixel no tile covers is `background`. A row may hold fewer tiles
/// than the longest (its last cells stay background). Throws
/// anima::invalid_argument for no tiles at all or a negative gap.
template <class T>
grey_image<T> tile_grid(const std::vector<std::vector<grey_image<T>>>& tiles, Eigen::Index gap, T background) {
    if (gap < 0) throw invalid_argument("anima::tile_grid: gap " + std::to_string(gap) + " is negative");
    Eigen::Index h = 0, w = 0, columns = 0;
    for (const auto& row : tiles) {
        columns = std::max(columns, static_cast<Eigen::Index>(row.size()));
        for (const auto& tile : row) {
            h = std::max(h, tile.rows());
            w = std::max(w, tile.cols());
        }
    }
    if (columns == 0) throw invalid_argument("anima::tile_grid: no tiles");
    const auto rows = static_cast<Eigen::Index>(tiles.size());
    grey_image<T> out = grey_image<T>::Constant(rows * (h + gap) - gap, columns * (w + gap) - gap, background);
    for (Eigen::Index r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < tiles[static_cast<std::size_t>(r)].size(); ++c) {
            const grey_image<T>& tile = tiles[static_cast<std::size_t>(r)][c];
            out.block(r * (h + gap), static_cast<Eigen::Index>(c) * (w + gap), tile.rows(), tile.cols()) = tile;
        }
    return out;
}

}  // namespace anima
