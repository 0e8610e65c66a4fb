// Small helpers every module's tests use: paths of the bundled clips,
// per-precision tolerances and the message of an expected anima error.
#pragma once

#include <anima/core/error.hpp>

#include <limits>
#include <string>
#include <type_traits>

#if defined(__SANITIZE_ADDRESS__)
#define ANIMA_TEST_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ANIMA_TEST_SANITIZED 1
#endif
#endif

namespace anima_test {

/// True in a build under AddressSanitizer. There, the few tests whose point
/// is convergence of a long optimisation run every code path in a few
/// iterations and leave the convergence checks to the optimised build: the
/// sanitizers look at memory and undefined behaviour, which the later
/// iterations do not add to, at 50-100x the run time.
#ifdef ANIMA_TEST_SANITIZED
inline constexpr bool sanitized_build = true;
#else
inline constexpr bool sanitized_build = false;
#endif

/// A file of examples/data.
inline std::string bundled(const std::string& name) { return std::string(ANIMA_TEST_DATA_DIR) + "/" + name; }

/// The tolerance for the scalar type under test.
template <class T>
T tolerance(double for_double, double for_float) {
    return static_cast<T>(std::is_same_v<T, double> ? for_double : for_float);
}

/// The calling thread has IEEE gradual underflow, as a test process starts:
/// no anima::flush_denormals scope was left switched on.
inline bool gradual_underflow() {
    volatile float smallest = std::numeric_limits<float>::min();
    volatile float half = smallest * 0.5f;
    return half > 0.0f;
}

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/// The message of the anima::invalid_argument thrown by f ("" if none).
template <class F>
std::string invalid_argument_message(F&& f) {
    try {
        f();
    } catch (const anima::invalid_argument& e) {
        return e.what();
    }
    return "";
}

}  // namespace anima_test
