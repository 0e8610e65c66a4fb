// Images: a small grey/RGB image type, PGM/PPM reading and writing,
// bilinear sampling and block-mean resampling.
#pragma once

#include <anima/image/bilinear.hpp>
#include <anima/image/block_mean.hpp>
#include <anima/image/image.hpp>
#include <anima/image/pnm.hpp>
