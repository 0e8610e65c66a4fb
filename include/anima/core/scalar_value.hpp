// The plain value of a scalar that may be an automatic-derivative type
// (Eigen::AutoDiffScalar keeps it in .value()), for messages and for the
// branches of scalar-generic maths, which go through select_less: a series
// near a singular point is chosen by the value, and the derivatives follow
// the branch taken.
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

/// How scalar-generic maths chooses between a series near a singular point
/// and the closed form away from it: one customisation point, so that no
/// formula hard-codes an `if` on its scalar. For plain and
/// automatic-derivative scalars the comparison is on the values and only the
/// branch taken is evaluated: the other may be singular there (a square root
/// or a division at 0), and the derivatives follow the branch taken. A scalar
/// that cannot branch on a value (a symbolic one) specialises this to
/// evaluate both branches and build its own conditional.
template <class S, class = void>
struct scalar_select {
    template <class Then, class Else>
    static auto less(const S& lhs, const S& rhs, Then&& then, Else&& otherwise) -> decltype(then()) {
        if (scalar_value(lhs) < scalar_value(rhs)) return then();
        return otherwise();
    }
};

/// then() where lhs < rhs, otherwise() elsewhere, through scalar_select<S>.
template <class S, class Then, class Else>
auto select_less(const S& lhs, const S& rhs, Then&& then, Else&& otherwise) -> decltype(then()) {
    return scalar_select<S>::less(lhs, rhs, std::forward<Then>(then), std::forward<Else>(otherwise));
}

}  // namespace anima::detail
