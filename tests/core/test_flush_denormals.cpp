// anima::flush_denormals: inside the scope subnormal operands read as zero
// and subnormal results become zero, in float and double; outside, and
// after an exception, IEEE gradual underflow is back.
#include <anima/core/flush_denormals.hpp>

#include <doctest/doctest.h>

#include <limits>
#include <stdexcept>

namespace {

/// Half the smallest normal number, read and made through volatiles so that
/// the compiler computes them at run time, under the mode of the moment.
template <class T>
T half_of_smallest() {
    volatile T smallest = std::numeric_limits<T>::min();
    volatile T half = smallest * T(0.5);
    return half;
}

template <class T>
T times_one(T x) {
    volatile T v = x, one = T(1);
    volatile T r = v * one;
    return r;
}

template <class T>
void check_modes() {
    const T gradual = half_of_smallest<T>();
    REQUIRE(gradual > T(0));  // the test process starts in IEEE mode
    {
        const anima::flush_denormals guard;
        CHECK(half_of_smallest<T>() == T(0));  // a result flushed
        CHECK(times_one(gradual) == T(0));      // an operand read as zero
        CHECK(times_one(std::numeric_limits<T>::min()) == std::numeric_limits<T>::min());  // normal numbers untouched
        {
            const anima::flush_denormals nested;
            CHECK(half_of_smallest<T>() == T(0));
        }
        CHECK(half_of_smallest<T>() == T(0));  // the inner guard gave back the outer one's mode
    }
    CHECK(half_of_smallest<T>() == gradual);
    CHECK(times_one(gradual) == gradual);
    try {
        const anima::flush_denormals guard;
        throw std::runtime_error("leaves the scope");
    } catch (const std::runtime_error&) {
    }
    CHECK(half_of_smallest<T>() == gradual);
}

}  // namespace

TEST_CASE("flush_denormals treats subnormals as zero inside its scope only, in float and double") {
    if (!anima::flush_denormals::supported) {
        // Nothing is switched: the scope changes nothing.
        const anima::flush_denormals guard;
        CHECK(half_of_smallest<float>() > 0.0f);
        return;
    }
    check_modes<float>();
    check_modes<double>();
}
