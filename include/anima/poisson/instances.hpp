// The Poisson module's heavy instantiations for double, for builds that
// compile them once: ANIMA_EXTERN_TEMPLATES makes them explicit
// instantiation declarations, ANIMA_INSTANTIATE_POISSON (in one unit) their
// definitions; neither, and nothing changes. See flight/instances.hpp and
// docs/building.md.
#pragma once

#include <anima/poisson/multigrid_poisson.hpp>

#if defined(ANIMA_INSTANTIATE_POISSON)
#define ANIMA_POISSON_INSTANCE template
#elif defined(ANIMA_EXTERN_TEMPLATES)
#define ANIMA_POISSON_INSTANCE extern template
#endif

#ifdef ANIMA_POISSON_INSTANCE
namespace anima {
// The solver's members defined out of its class body: building the levels,
// the cycles and the solve.
ANIMA_POISSON_INSTANCE class multigrid_poisson<double>;
}  // namespace anima
#undef ANIMA_POISSON_INSTANCE
#endif
