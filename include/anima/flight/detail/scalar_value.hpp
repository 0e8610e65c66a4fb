// The plain value of a scalar that may be an automatic-derivative type
// (Eigen::AutoDiffScalar keeps it in .value()), for messages and branches.
#pragma once

#include <type_traits>

namespace anima::detail {

template <class S>
double scalar_value(const S& x) {
    if constexpr (std::is_arithmetic_v<S>)
        return static_cast<double>(x);
    else
        return scalar_value(x.value());
}

}  // namespace anima::detail
