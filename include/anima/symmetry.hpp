// Symmetry analysis of motion and the playback it enables: frame distances
// (Eq 1-2), symmetry scores and turning candidates (Eq 3-5), adaptive
// symmetric playback (Eq 6) and, for comparison, video-texture jumps.
#pragma once

#include <anima/motion/resequence.hpp>
#include <anima/symmetry/instances.hpp>
#include <anima/symmetry/play_clip.hpp>
#include <anima/symmetry/render_stream.hpp>
#include <anima/symmetry/symmetric_playback.hpp>
#include <anima/symmetry/symmetry_scores.hpp>
#include <anima/symmetry/video_texture.hpp>
