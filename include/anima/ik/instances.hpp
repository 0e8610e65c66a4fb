// The IK module's heavy instantiations for double, for builds that
// compile them once: ANIMA_EXTERN_TEMPLATES makes them explicit
// instantiation declarations, ANIMA_INSTANTIATE_IK (in one unit) their
// definitions; neither, and nothing changes. See flight/instances.hpp and
// docs/building.md.
#pragma once

#include <anima/ik/plant_feet.hpp>
#include <anima/motion/instances.hpp>  // plant_feet finds contacts: compiled with the motion module

#if defined(ANIMA_INSTANTIATE_IK)
#define ANIMA_IK_INSTANCE template
#elif defined(ANIMA_EXTERN_TEMPLATES)
#define ANIMA_IK_INSTANCE extern template
#endif

#ifdef ANIMA_IK_INSTANCE
namespace anima {
// clang-format off
ANIMA_IK_INSTANCE plant_feet_result<double> plant_feet(const clip<double>&, const contact_set<double>&, const plant_feet_params<double>&);
ANIMA_IK_INSTANCE plant_feet_result<double> plant_feet(const clip<double>&, const plant_feet_params<double>&);
// clang-format on
}  // namespace anima
#undef ANIMA_IK_INSTANCE
#endif
