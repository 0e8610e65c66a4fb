// Transitions between clips: the variable-timing hierarchical method and the
// baselines it is compared with (direct cut, crossfade, inertialization).
#pragma once

#include <anima/transition/baselines.hpp>
#include <anima/transition/classify.hpp>
#include <anima/transition/instances.hpp>
#include <anima/transition/metrics.hpp>
#include <anima/transition/placement.hpp>
#include <anima/transition/plant_transition_feet.hpp>
#include <anima/transition/timing.hpp>
#include <anima/transition/transition_between.hpp>
#include <anima/transition/variable_timing_transition.hpp>
