// Moved to <anima/motion/frame_features.hpp>, with the module it belongs to; this path
// forwards to it and will be removed in a later release.
#pragma once

#include <anima/motion/frame_features.hpp>
