// Mathematical constants and unit conversions, generic over the scalar.
#pragma once

namespace anima {

template <class T>
inline constexpr T pi = T(3.141592653589793238462643383279502884L);

template <class T>
constexpr T radians(T degrees) {
    return degrees * (pi<T> / T(180));
}
template <class T>
constexpr T degrees(T radians) {
    return radians * (T(180) / pi<T>);
}

}  // namespace anima
