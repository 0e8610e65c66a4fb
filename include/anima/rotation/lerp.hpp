// Linear blends of quaternions. lerp is the raw component-wise blend (Eq 6 of
// the variable-timing paper, used there for fingers); nlerp takes the short
// way round and renormalises, which is what a blend of rotations usually wants.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/quat_traits.hpp>

#include <type_traits>

namespace anima {

/// (1 - t) a + t b, component-wise. Not normalised, no hemisphere flip: the
/// result is a rotation only after normalisation, and it takes the long way
/// round when a.b < 0. Kept because some published methods specify it.
/// Throws anima::invalid_argument for a non-finite t.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q lerp(const Q& a, const Q& b, quat_scalar_t<Q> t) {
    using T = quat_scalar_t<Q>;
    check_finite("anima::lerp", "t", t);
    return detail::store<Q>(detail::load(a) * (T(1) - t) + detail::load(b) * t);
}

/// Normalised lerp along the shorter arc: cheap, exact at t = 0 and 1, with a
/// non-constant angular speed (worst for large angles). Throws
/// anima::invalid_argument for a non-finite t, or when the blend is zero, which needs a == -b with
/// no flip, i.e. never for unit inputs.
template <class Q, std::enable_if_t<is_quaternion_v<Q>, int> = 0>
Q nlerp(const Q& a, const Q& b, quat_scalar_t<Q> t) {
    using T = quat_scalar_t<Q>;
    check_finite("anima::nlerp", "t", t);
    const auto p = detail::load(a);
    auto r = detail::load(b);
    if (detail::dot4(p, r) < T(0)) r = -r;
    return detail::store<Q>(detail::normalized_or_throw(p * (T(1) - t) + r * t, "anima::nlerp"));
}

}  // namespace anima
