// Heap allocations counted around a call, for the tests of the per-call
// (game-loop) forms: operator new is replaced (heap_count.cpp, linked into
// the test), and Eigen, which allocates with malloc, reports each allocation
// through eigen_assert while EIGEN_RUNTIME_NO_MALLOC forbids them. So this
// header comes before any header that includes Eigen, in every file of the
// test executable (Eigen must be configured alike throughout), and the
// executable is declared OWN_EIGEN_CONFIG.
#pragma once

#include <cstdio>
#include <cstdlib>

namespace heap_count {
inline bool counting = false;
inline long allocations = 0;
// Whether an eigen_assert passes: a refused Eigen allocation while counting is counted instead.
inline bool eigen_check(bool ok) {
    if (!ok && counting) ++allocations;
    return ok || counting;
}
// Any other failed eigen_assert stops the test, as Eigen's own would (not under NDEBUG).
inline void eigen_failed([[maybe_unused]] const char* what, [[maybe_unused]] const char* file,
                         [[maybe_unused]] int line) {
#ifndef NDEBUG
    std::fprintf(stderr, "%s:%d: Eigen assertion failed: %s\n", file, line, what);
    std::abort();
#endif
}
}  // namespace heap_count
#define EIGEN_RUNTIME_NO_MALLOC
#define eigen_assert(x)                                                     \
    (heap_count::eigen_check(static_cast<bool>(x)) ? static_cast<void>(0) \
                                                   : heap_count::eigen_failed(#x, __FILE__, __LINE__))

#include <Eigen/Core>

namespace heap_count {

/// Heap allocations (operator new and Eigen's) made by f.
template <class F>
long allocations_in(F&& f) {
    allocations = 0;
    counting = true;
    Eigen::internal::set_is_malloc_allowed(false);
    f();
    Eigen::internal::set_is_malloc_allowed(true);
    counting = false;
    return allocations;
}

}  // namespace heap_count
