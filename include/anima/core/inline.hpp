// ANIMA_FORCE_INLINE marks the small helpers on the rotation toolkit's hot
// paths (quaternion products, lane arithmetic, series): the compiler inlines
// them even where its size heuristics would stop, which in a translation unit
// with many instantiations otherwise leaves them as calls returning
// quaternions through memory. A plain `inline` with other compilers.
// ANIMA_COLD marks the rare general paths next to them: kept out of line, so
// the hot caller neither inlines them nor prepares their arguments in memory
// on every call.
#pragma once

#if defined(__GNUC__) || defined(__clang__)
#define ANIMA_FORCE_INLINE inline __attribute__((always_inline))
#define ANIMA_COLD __attribute__((noinline, cold))
#elif defined(_MSC_VER)
#define ANIMA_FORCE_INLINE __forceinline
#define ANIMA_COLD __declspec(noinline)
#else
#define ANIMA_FORCE_INLINE inline
#define ANIMA_COLD
#endif
