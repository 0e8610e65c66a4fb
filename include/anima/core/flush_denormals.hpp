// A scope in which the processor treats subnormal numbers as zero.
//
// Why: real motion capture holds angles such as 1e-19 degrees (the CMU
// conversions do). In float the quaternion components and products made from
// them fall below the smallest normal number (1.2e-38), and x86 processors
// take a microcode path for every operation that reads or makes such a
// number: on the bundled run a float transition takes twice as long. A
// rotation loses nothing when they are zero, as they are 1e-38 of a unit
// quaternion. The mode belongs to the calling thread; the guard saves it and
// puts it back, also when an exception leaves the scope, so code around it
// keeps IEEE gradual underflow.
#pragma once

#if defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2)
#include <xmmintrin.h>
#define ANIMA_DENORMALS_MXCSR 1
#elif defined(__aarch64__) && (defined(__GNUC__) || defined(__clang__))
#define ANIMA_DENORMALS_FPCR 1
#endif

namespace anima {

/// While an object lives, the calling thread's floating-point unit flushes
/// subnormal results to zero and reads subnormal operands as zero (x86 SSE:
/// MXCSR's FTZ and DAZ bits; AArch64: FPCR's FZ bit). The previous mode is
/// restored when it goes. Elsewhere it does nothing (`supported` is false).
/// The whole-clip functions (docs/rotation.md lists them: resampling,
/// positions, features, transitions, contacts, planting, symmetry scores,
/// textures) hold one; per-frame and per-rotation functions do not, so put
/// one around a loop of your own that runs float rotations of real motion
/// capture. Callbacks called inside the scope run in its mode.
class flush_denormals {
public:
#if defined(ANIMA_DENORMALS_MXCSR)
    static constexpr bool supported = true;
    /// MXCSR bits: flush to zero (15) and denormals are zero (6).
    static constexpr unsigned int bits = 0x8000u | 0x0040u;
    flush_denormals() noexcept : saved_(_mm_getcsr()) { set(saved_ | bits); }
    ~flush_denormals() { set(saved_); }
#elif defined(ANIMA_DENORMALS_FPCR)
    static constexpr bool supported = true;
    /// FPCR bit 24: flush to zero, for operands and results.
    static constexpr unsigned long long bits = 1ull << 24;
    flush_denormals() noexcept {
        __asm__ __volatile__("mrs %0, fpcr" : "=r"(saved_) : : "memory");
        set(saved_ | bits);
    }
    ~flush_denormals() { set(saved_); }
#else
    static constexpr bool supported = false;
    flush_denormals() noexcept {}
    ~flush_denormals() {}
#endif
    flush_denormals(const flush_denormals&) = delete;
    flush_denormals& operator=(const flush_denormals&) = delete;

private:
    // The switch is an asm statement with a memory clobber, so that loads
    // and stores (and the arithmetic on what they load) stay on their side
    // of it; the compiler may still move arithmetic on values it already
    // holds in registers, which the functions holding a guard do not have.
#if defined(ANIMA_DENORMALS_MXCSR)
    static void set(unsigned int mode) noexcept {
#if defined(__GNUC__) || defined(__clang__)
        __asm__ __volatile__("ldmxcsr %0" : : "m"(mode) : "memory");
#else
        _mm_setcsr(mode);
#endif
    }
    unsigned int saved_;
#elif defined(ANIMA_DENORMALS_FPCR)
    static void set(unsigned long long mode) noexcept { __asm__ __volatile__("msr fpcr, %0" : : "r"(mode) : "memory"); }
    unsigned long long saved_;
#endif
};

}  // namespace anima

#undef ANIMA_DENORMALS_MXCSR
#undef ANIMA_DENORMALS_FPCR
