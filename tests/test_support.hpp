// Small helpers every module's tests use: paths of the bundled clips,
// per-precision tolerances and the message of an expected anima error.
#pragma once

#include <anima/core/error.hpp>

#include <string>
#include <type_traits>

namespace anima_test {

/// A file of examples/data.
inline std::string bundled(const std::string& name) { return std::string(ANIMA_TEST_DATA_DIR) + "/" + name; }

/// The tolerance for the scalar type under test.
template <class T>
T tolerance(double for_double, double for_float) {
    return static_cast<T>(std::is_same_v<T, double> ? for_double : for_float);
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
