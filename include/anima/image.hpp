// Images: a small grey/RGB image type, PGM/PPM reading and writing, and
// bilinear sampling.
#pragma once

#include <anima/image/bilinear.hpp>
#include <anima/image/image.hpp>
#include <anima/image/pnm.hpp>
