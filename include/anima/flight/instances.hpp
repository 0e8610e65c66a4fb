// The flight module's heavy instantiations for double (the scalar of the
// CLI, the examples and most callers; other scalars are instantiated where
// they are used), for builds that compile them once instead of in every unit
// that calls them. With ANIMA_EXTERN_TEMPLATES defined, a unit that includes
// this header does not instantiate them (explicit instantiation
// declarations); the one unit that defines ANIMA_INSTANTIATE_FLIGHT before
// including it compiles them. Neither defined (the default): nothing
// changes, the library stays header-only. docs/building.md says how to set
// this up.
#pragma once

#include <anima/flight/clip_keys.hpp>
#include <anima/flight/flight_clip.hpp>
#include <anima/flight/optimize_flight.hpp>
#include <anima/motion/instances.hpp>  // clip keys find contacts: compiled with the motion module

#if defined(ANIMA_INSTANTIATE_FLIGHT)
#define ANIMA_FLIGHT_INSTANCE template
#elif defined(ANIMA_EXTERN_TEMPLATES)
#define ANIMA_FLIGHT_INSTANCE extern template
#endif

#ifdef ANIMA_FLIGHT_INSTANCE
namespace anima {
// clang-format off
ANIMA_FLIGHT_INSTANCE flight_optimization_result<double> optimize_flight(const flight_problem<double>&, const flight_optimization_params<double>&);
ANIMA_FLIGHT_INSTANCE clip_flight_keys<double> flight_keys_from_clip(const clip<double>&, const clip_flight_params<double>&);
ANIMA_FLIGHT_INSTANCE clip<double> flight_clip(const flight_problem<double>&, const flight_keys<double>&, const skeleton<double>&, double, double);
// clang-format on
}  // namespace anima
#undef ANIMA_FLIGHT_INSTANCE
#endif
