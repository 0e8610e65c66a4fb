// Graph-cut motion textures: overlap search, seam costs (Eq 7-9), the
// (row x frame) min-cut, C1 blending (Eq 11-13), textons, long textures
// (Eq 10) with Poisson smoothing (Eq 14), a seam-speed check and the
// texture measured against its inputs.
#pragma once

#include <anima/texture/clip_order.hpp>
#include <anima/texture/instances.hpp>
#include <anima/texture/measure_texture.hpp>
#include <anima/texture/motion_smoothing.hpp>
#include <anima/texture/motion_texture.hpp>
#include <anima/texture/overlap_search.hpp>
#include <anima/texture/seam_blend.hpp>
#include <anima/texture/seam_cost.hpp>
#include <anima/texture/seam_cut.hpp>
#include <anima/texture/seam_speed.hpp>
#include <anima/texture/texton.hpp>
