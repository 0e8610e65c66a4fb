// anima::check_argument and its shorthands: the message names the function,
// the argument, the requirement and the value; NaN and infinities fail every
// finite check; values print with enough digits to be told apart.
#include <anima/core/check_argument.hpp>

#include <doctest/doctest.h>

#include <limits>
#include <string>

namespace {

template <class F>
std::string message_of(F&& f) {
    try {
        f();
    } catch (const anima::invalid_argument& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE_TEMPLATE("check_positive, check_non_negative and check_finite", T, float, double) {
    const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    CHECK(message_of([] { anima::check_positive("anima::f", "x", T(1e-30)); }).empty());
    CHECK(message_of([] { anima::check_positive("anima::f", "x", T(0)); }) == "anima::f: x must be positive and finite, got 0");
    CHECK(message_of([] { anima::check_positive("anima::f", "x", T(-2.5)); }) ==
          "anima::f: x must be positive and finite, got -2.5");
    CHECK(message_of([&] { anima::check_positive("anima::f", "x", nan); }) ==
          "anima::f: x must be positive and finite, got nan");
    CHECK(message_of([&] { anima::check_positive("anima::f", "x", inf); }) ==
          "anima::f: x must be positive and finite, got inf");
    CHECK(message_of([] { anima::check_non_negative("anima::g", "tolerance", T(0)); }).empty());
    CHECK(message_of([] { anima::check_non_negative("anima::g", "tolerance", T(-1e-12)); }) ==
          "anima::g: tolerance must be non-negative and finite, got -1e-12");
    CHECK(message_of([&] { anima::check_non_negative("anima::g", "tolerance", -inf); }) ==
          "anima::g: tolerance must be non-negative and finite, got -inf");
    CHECK(message_of([] { anima::check_finite("anima::h", "value", T(-3)); }).empty());
    CHECK(message_of([&] { anima::check_finite("anima::h", "value", nan); }) == "anima::h: value must be finite, got nan");
}

TEST_CASE("check_in_range, check_at_least, check_size and check_argument") {
    CHECK(message_of([] { anima::check_in_range("anima::f", "t", 0.5, 0.0, 1.0); }).empty());
    CHECK(message_of([] { anima::check_in_range("anima::f", "t", 1.0, 0.0, 1.0); }).empty());
    CHECK(message_of([] { anima::check_in_range("anima::f", "t", 1.25, 0.0, 1.0); }) ==
          "anima::f: t must be in [0, 1], got 1.25");
    CHECK(message_of([] { anima::check_in_range("anima::f", "t", std::nan(""), 0.0, 1.0); }) ==
          "anima::f: t must be in [0, 1], got nan");
    CHECK(message_of([] { anima::check_at_least("anima::f", "max_cycles", 0, 1); }) ==
          "anima::f: max_cycles must be at least 1, got 0");
    CHECK(message_of([] { anima::check_at_least("anima::f", "frames", std::size_t{2}, std::size_t{2}); }).empty());
    CHECK(message_of([] { anima::check_size("anima::f", "weights", 3, 4); }) ==
          "anima::f: weights has 3 entries, expected 4");
    CHECK(message_of([] { anima::check_size("anima::f", "q", 6, 7, "values"); }) == "anima::f: q has 6 values, expected 7");
    CHECK(message_of([] { anima::check_size("anima::f", "q", 7, 7); }).empty());
    // The shortest exact form: values that differ in the 8th digit read differently.
    CHECK(message_of([] { anima::check_argument(false, "anima::f", "a", "below 1", 1.0000001); }) ==
          "anima::f: a must be below 1, got 1.0000001");
    CHECK(message_of([] { anima::check_argument(false, "anima::f", "name", "a joint", "Nose\n"); }) ==
          "anima::f: name must be a joint, got 'Nose\\x0a'");
}
