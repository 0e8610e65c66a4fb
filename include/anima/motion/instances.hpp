// The motion module's heavy instantiations for double, for builds
// that compile them once: ANIMA_EXTERN_TEMPLATES makes them explicit
// instantiation declarations, ANIMA_INSTANTIATE_MOTION (in one unit) their
// definitions; neither, and nothing changes. See flight/instances.hpp and
// docs/building.md.
#pragma once

#include <anima/motion/contacts.hpp>

#if defined(ANIMA_INSTANTIATE_MOTION)
#define ANIMA_MOTION_INSTANCE template
#elif defined(ANIMA_EXTERN_TEMPLATES)
#define ANIMA_MOTION_INSTANCE extern template
#endif

#ifdef ANIMA_MOTION_INSTANCE
namespace anima {
ANIMA_MOTION_INSTANCE contact_set<double> find_contacts(const clip<double>&, const contact_params<double>&);
}  // namespace anima
#undef ANIMA_MOTION_INSTANCE
#endif
