// The plain value of a scalar that may be an automatic-derivative type
// (Eigen::AutoDiffScalar keeps it in .value()), for messages and for the
// branches of scalar-generic maths: a series near a singular point is chosen
// by the value, and the derivatives follow the branch taken.
#pragma once

#include <type_traits>
#include <utility>

namespace anima::detail {

template <class S>
double scalar_value(const S& x) {
    if constexpr (std::is_arithmetic_v<S>)
        return static_cast<double>(x);
    else
        return scalar_value(x.value());
}

/// The floating-point type underneath S: S itself for float or double, the
/// value type (recursively) for an automatic-derivative scalar.
template <class S, class = void>
struct real_scalar {
    using type = S;
};
template <class S>
struct real_scalar<S, std::enable_if_t<!std::is_arithmetic_v<S>>> {
    using type = typename real_scalar<std::decay_t<decltype(std::declval<const S&>().value())>>::type;
};
template <class S>
using real_scalar_t = typename real_scalar<S>::type;

}  // namespace anima::detail
