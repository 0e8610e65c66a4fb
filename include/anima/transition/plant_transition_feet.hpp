// Feet planted through a transition: a foot on the ground when A hands over
// and still on it in B (or in the frames between) is held where it is, and
// the correction is released over the swing that follows (ik/plant_feet.hpp).
// Works on any joined clip: the variable-timing transition and the cut,
// crossfade and inertialization baselines alike.
#pragma once

#include <anima/ik/plant_feet.hpp>
#include <anima/transition/variable_timing_transition.hpp>

#include <utility>

namespace anima {

/// The joined clip with the contact runs that reach the transition (frames
/// start_frame..end_frame) planted; params.ranges is set here. Contacts are
/// found on the joined clip with params.contacts (height alone by default,
/// so a foot sliding on the ground through the window counts as planted).
/// A figure without feet to plant (has_feet_to_plant) comes back as it is.
template <class T>
joined_clip<T> plant_transition_feet(const joined_clip<T>& joined, plant_feet_params<T> params = {}) {
    joined_clip<T> out = joined;
    plant_feet_in_ranges(out.motion, {frame_interval{joined.start_frame, joined.end_frame}}, std::move(params), {});
    return out;
}

}  // namespace anima
