// Images: a small grey/RGB image type, PGM/PPM reading and writing,
// bilinear sampling, block-mean resampling, grey levels up to a
// percentile and grids of tiles.
#pragma once

#include <anima/image/bilinear.hpp>
#include <anima/image/block_mean.hpp>
#include <anima/image/image.hpp>
#include <anima/image/percentile_grey.hpp>
#include <anima/image/pnm.hpp>
#include <anima/image/tile_grid.hpp>
