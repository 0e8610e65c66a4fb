// operator new counted while heap_count::counting (heap_count.hpp).
#include "heap_count.hpp"

#include <cstddef>
#include <cstdlib>
#include <new>

// Not inlined: GCC would otherwise see free() on the result of operator new and warn.
#if defined(__GNUC__)
#define HEAP_COUNT_NOINLINE __attribute__((noinline))
#else
#define HEAP_COUNT_NOINLINE
#endif
HEAP_COUNT_NOINLINE void* operator new(std::size_t size) {
    if (heap_count::counting) ++heap_count::allocations;
    if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
    throw std::bad_alloc();
}
HEAP_COUNT_NOINLINE void* operator new[](std::size_t size) { return operator new(size); }
HEAP_COUNT_NOINLINE void operator delete(void* p) noexcept { std::free(p); }
HEAP_COUNT_NOINLINE void operator delete[](void* p) noexcept { std::free(p); }
HEAP_COUNT_NOINLINE void operator delete(void* p, std::size_t) noexcept { std::free(p); }
HEAP_COUNT_NOINLINE void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
