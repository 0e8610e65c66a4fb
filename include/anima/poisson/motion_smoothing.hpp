// Moved to <anima/texture/motion_smoothing.hpp>, with the module it belongs to; this path
// forwards to it and will be removed in a later release.
#pragma once

#include <anima/texture/motion_smoothing.hpp>
