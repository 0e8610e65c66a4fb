// Capacity types for max-flow: what they may be, the "infinity" to use for
// hard constraints, and the wider type the flow is summed in.
//
// Capacities are any signed arithmetic type (int, long long, float,
// double...). They must be finite and non-negative; the graphs check this
// when a capacity is given, together with the sums that must stay
// representable while flow is pushed:
//
//   - an edge's two capacities (cap + rev_cap): the residual capacity of one
//     direction grows up to that sum;
//   - a node's accumulated source and sink capacities (add_tweights).
//
// The flow value is summed in flow_type: long long for integers narrower than
// long long (so many int-capacity terminal edges cannot overflow the total),
// double for float, the capacity type itself otherwise. Every addition is
// checked: a flow that would overflow throws anima::invalid_argument instead
// of wrapping around (integers) or becoming inf (double).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

namespace anima {

template <class Cap>
struct capacity_traits {
    static_assert(std::is_arithmetic_v<Cap> && std::is_signed_v<Cap> && !std::is_same_v<Cap, bool>,
                  "max-flow capacities must be a signed arithmetic type (int, long long, float, double...)");

    using capacity_type = Cap;
    using flow_type = std::conditional_t<
        std::is_floating_point_v<Cap>, std::conditional_t<(sizeof(Cap) < sizeof(double)), double, Cap>,
        std::conditional_t<(sizeof(Cap) < sizeof(long long)), long long, Cap>>;

    /// The capacity for hard constraints ("this edge must not be cut", "this
    /// node is a source seed"): a quarter of the largest value, so that an
    /// edge may have it in both directions and a node may get it from several
    /// add_tweights calls without overflow. It is only "infinite" if every
    /// finite cut of the graph is cheaper: with int (about 5.4e8) keep the
    /// sum of the finite capacities of any cut below it, or use long long
    /// (about 2.3e18) or double. Do not pass std::numeric_limits::infinity():
    /// capacities must be finite. A maximum flow of at least infinity() means
    /// the hard constraints contradict each other.
    static constexpr Cap infinity() noexcept { return std::numeric_limits<Cap>::max() / 4; }

    /// Finite and >= 0 (NaN is neither).
    static bool valid(Cap c) noexcept {
        if constexpr (std::is_floating_point_v<Cap>)
            return c >= Cap(0) && c <= std::numeric_limits<Cap>::max();
        else
            return c >= Cap(0);
    }

    /// Whether a + b is representable (and finite), for valid a and b.
    static bool sum_fits(Cap a, Cap b) noexcept {
        if constexpr (std::is_floating_point_v<Cap>)
            return std::isfinite(a + b);
        else
            return a <= std::numeric_limits<Cap>::max() - b;
    }

    /// flow + amount for amount >= 0; throws instead of overflowing (an
    /// integer wrapping around, a floating-point sum becoming inf).
    static flow_type add_flow(flow_type flow, Cap amount) {
        bool fits;
        if constexpr (std::is_integral_v<flow_type>)
            fits = flow <= std::numeric_limits<flow_type>::max() - static_cast<flow_type>(amount);
        else
            fits = std::isfinite(flow + static_cast<flow_type>(amount));
        if (!fits) flow_overflow(flow, amount);
        return flow + static_cast<flow_type>(amount);
    }

private:
    [[noreturn]] static void flow_overflow(flow_type flow, Cap amount) {
        const bool integral = std::is_integral_v<flow_type>;
        throw invalid_argument(
            "max-flow: the flow value " + detail::argument_text(flow) + " plus " +
            detail::argument_text(amount) + " overflows the flow type (" +
            (integral ? std::to_string(std::numeric_limits<flow_type>::digits + 1) + "-bit integers"
                      : "largest " + detail::argument_text(std::numeric_limits<flow_type>::max())) +
            "); the hard constraints may contradict each other, or " +
            (integral ? "use a wider capacity type" : "scale the capacities down"));
    }
};

/// capacity_traits<Cap>::infinity(): the capacity to use for hard constraints.
template <class Cap>
constexpr Cap max_flow_infinity() noexcept {
    return capacity_traits<Cap>::infinity();
}

}  // namespace anima
