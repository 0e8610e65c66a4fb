// Argument checks at the API boundary, with one message shape everywhere:
//
//   anima::make_body_model: body_mass must be positive and finite, got -1
//
// naming the function, the argument, what it must be and the value it got
// (floating-point values in their shortest exact form, so 1e-12 does not
// print as 0.000000). The checks return nothing and throw anima::invalid_argument.
#pragma once

#include <anima/core/error.hpp>

#include <charconv>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>

namespace anima {
namespace detail {

/// A value for a message: integers exactly, floating point in the shortest
/// form that reads back to the same value (1e-12, 0.1f as 0.1).
template <class V>
std::string argument_text(const V& value) {
    if constexpr (std::is_floating_point_v<V>) {
        if (std::isnan(value)) return "nan";
        if (std::isinf(value)) return value < 0 ? "-inf" : "inf";
        char buffer[64];
        const auto r = std::to_chars(buffer, buffer + sizeof buffer, value);
        return std::string(buffer, r.ptr);
    } else if constexpr (std::is_integral_v<V>) {
        return std::to_string(value);
    } else if constexpr (std::is_convertible_v<const V&, std::string_view>) {
        return "'" + escape_for_message(std::string_view(value), 200) + "'";
    } else {
        // Scalars such as AutoDiff or long double wrappers convert to double.
        return argument_text(static_cast<double>(value));
    }
}

}  // namespace detail

/// Throws anima::invalid_argument "function: argument must be requirement,
/// got value". For a requirement whose text costs an allocation, so that it
/// is built only once the check has failed.
template <class V>
[[noreturn]] void fail_argument(std::string_view function, std::string_view argument, std::string_view requirement,
                                const V& value) {
    throw invalid_argument(std::string(function) + ": " + std::string(argument) + " must be " +
                           std::string(requirement) + ", got " + detail::argument_text(value));
}

/// fail_argument unless `ok`.
template <class V>
void check_argument(bool ok, std::string_view function, std::string_view argument, std::string_view requirement,
                    const V& value) {
    if (!ok) fail_argument(function, argument, requirement, value);
}

/// value > 0 and finite (NaN fails).
template <class T>
void check_positive(std::string_view function, std::string_view argument, const T& value) {
    using std::isfinite;
    check_argument(value > T(0) && isfinite(value), function, argument, "positive and finite", value);
}

/// value >= 0 and finite (NaN fails).
template <class T>
void check_non_negative(std::string_view function, std::string_view argument, const T& value) {
    using std::isfinite;
    check_argument(value >= T(0) && isfinite(value), function, argument, "non-negative and finite", value);
}

/// value finite.
template <class T>
void check_finite(std::string_view function, std::string_view argument, const T& value) {
    using std::isfinite;
    check_argument(static_cast<bool>(isfinite(value)), function, argument, "finite", value);
}

/// lo <= value <= hi (NaN fails).
template <class T>
void check_in_range(std::string_view function, std::string_view argument, const T& value, const T& lo, const T& hi) {
    check_argument(value >= lo && value <= hi, function, argument,
                   "in [" + detail::argument_text(lo) + ", " + detail::argument_text(hi) + "]", value);
}

/// value >= least (integers: counts, sizes, iterations).
template <class I>
void check_at_least(std::string_view function, std::string_view argument, const I& value, const I& least) {
    if (!(value >= least)) fail_argument(function, argument, "at least " + detail::argument_text(least), value);
}

/// A size that must match: "function: argument has 3 entries, expected 4".
inline void check_size(std::string_view function, std::string_view argument, std::size_t size, std::size_t expected,
                       std::string_view what = "entries") {
    if (size == expected) return;
    throw invalid_argument(std::string(function) + ": " + std::string(argument) + " has " + std::to_string(size) + " " +
                           std::string(what) + ", expected " + std::to_string(expected));
}

}  // namespace anima
