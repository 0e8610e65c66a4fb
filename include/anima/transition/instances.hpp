// The transition module's heavy instantiations for double, for
// builds that compile them once: ANIMA_EXTERN_TEMPLATES makes them explicit
// instantiation declarations, ANIMA_INSTANTIATE_TRANSITION (in one unit)
// their definitions; neither, and nothing changes. See flight/instances.hpp
// and docs/building.md.
#pragma once

#include <anima/ik/instances.hpp>  // transitions plant feet: its instances are compiled there
#include <anima/motion/instances.hpp>
#include <anima/transition/metrics.hpp>
#include <anima/transition/plant_transition_feet.hpp>
#include <anima/transition/variable_timing_transition.hpp>

#if defined(ANIMA_INSTANTIATE_TRANSITION)
#define ANIMA_TRANSITION_INSTANCE template
#elif defined(ANIMA_EXTERN_TEMPLATES)
#define ANIMA_TRANSITION_INSTANCE extern template
#endif

#ifdef ANIMA_TRANSITION_INSTANCE
namespace anima {
// clang-format off
ANIMA_TRANSITION_INSTANCE transition<double> make_transition(const clip<double>&, std::size_t, const clip<double>&, std::size_t, const transition_params&);
ANIMA_TRANSITION_INSTANCE transition_quality<double> measure_transition(const joined_clip<double>&, const std::vector<joint_role>&, signed_axis, double, std::size_t);
ANIMA_TRANSITION_INSTANCE joined_clip<double> plant_transition_feet(const joined_clip<double>&, transition_feet_params<double>);
// clang-format on
}  // namespace anima
#undef ANIMA_TRANSITION_INSTANCE
#endif
