// Whole-clip changes of frame and units that keep the motion: a change of
// basis (e.g. Y-up to Z-up), a uniform scale (e.g. centimetres to metres) and
// a new rotation-channel order for writing.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/constants.hpp>
#include <anima/core/error.hpp>
#include <anima/core/nondeduced.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/figure.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/euler.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace anima {

/// Applies the rotation r to the whole clip, as if the world were turned by r:
/// offsets, end sites and animated translations are rotated, and every local
/// rotation q becomes r q r^-1 so that each global orientation G becomes r G r^-1.
/// Global joint positions p become r p exactly. r is normalised here; a zero or
/// non-finite r throws anima::invalid_argument.
template <class T>
clip<T> rotate_clip(const clip<T>& c, const Eigen::Quaternion<T>& r_in) {
    const auto r = detail::store<Eigen::Quaternion<T>>(detail::normalized_or_throw(detail::load(r_in), "anima::rotate_clip"));
    skeleton<T> sk;
    for (std::size_t j = 0; j < c.joints(); ++j) {
        const auto& jt = c.skeleton()[j];
        sk.add_joint(jt.name, jt.parent, r * jt.offset, jt.channels);
        if (jt.end_site) sk.set_end_site(j, r * *jt.end_site);
    }
    clip<T> out(sk, c.frames(), c.frame_time());
    for (std::size_t f = 0; f < c.frames(); ++f)
        for (std::size_t j = 0; j < c.joints(); ++j) {
            out.set_rotation(f, j, r * c.rotation(f, j) * r.conjugate());
            if (sk.translation_slot(j) >= 0) out.set_translation(f, j, r * c.translation(f, j));
        }
    return out;
}

/// The proper rotation taking direction `from` to direction `to`: the
/// identity, a quarter turn about their cross product, or a half turn about
/// an axis orthogonal to both.
template <class T>
Eigen::Quaternion<T> axis_change(signed_axis from, signed_axis to) {
    const Eigen::Matrix<T, 3, 1> a = axis_vector<T>(from), b = axis_vector<T>(to);
    const T d = a.dot(b);
    if (d > T(0.5)) return Eigen::Quaternion<T>::Identity();
    if (d < T(-0.5)) {
        Eigen::Matrix<T, 3, 1> o = Eigen::Matrix<T, 3, 1>::Zero();
        o[(static_cast<int>(from.axis) + 1) % 3] = T(1);
        return Eigen::Quaternion<T>(Eigen::AngleAxis<T>(pi<T>, o));
    }
    return Eigen::Quaternion<T>(Eigen::AngleAxis<T>(pi<T> / T(2), a.cross(b)));
}

/// The clip with its up axis changed from `from` to `to` (e.g. +Y to +Z).
template <class T>
clip<T> change_up_axis(const clip<T>& c, signed_axis from, signed_axis to) {
    return rotate_clip(c, axis_change<T>(from, to));
}

/// The clip with every length multiplied by s > 0: offsets, end sites and
/// translations. Rotations are unchanged.
template <class T>
clip<T> scale_clip(const clip<T>& c, nondeduced_t<T> s) {
    check_positive("anima::scale_clip", "scale", s);
    T largest = 0;  // refuse up front a scale that overflows a position
    for (std::size_t j = 0; j < c.joints(); ++j) {
        const auto& jt = c.skeleton()[j];
        largest = std::max(largest, jt.offset.cwiseAbs().maxCoeff());
        if (jt.end_site) largest = std::max(largest, jt.end_site->cwiseAbs().maxCoeff());
    }
    for (const auto& t : c.translations()) largest = std::max(largest, t.cwiseAbs().maxCoeff());
    if (!std::isfinite(largest * s))
        throw invalid_argument("anima::scale_clip: scale " + detail::argument_text(s) +
                               " makes a position overflow the scalar type (largest component " +
                               detail::argument_text(largest) + ")");
    skeleton<T> sk;
    for (std::size_t j = 0; j < c.joints(); ++j) {
        const auto& jt = c.skeleton()[j];
        sk.add_joint(jt.name, jt.parent, s * jt.offset, jt.channels);
        if (jt.end_site) sk.set_end_site(j, s * *jt.end_site);
    }
    clip<T> out(sk, c.frames(), c.frame_time());
    for (std::size_t f = 0; f < c.frames(); ++f)
        for (std::size_t j = 0; j < c.joints(); ++j) {
            out.set_rotation(f, j, c.rotation(f, j));
            if (sk.translation_slot(j) >= 0) out.set_translation(f, j, s * c.translation(f, j));
        }
    return out;
}

/// The clip with every joint that has rotation channels given three rotation
/// channels in `order` (position channels keep their place, first). The motion
/// is unchanged; only how a BVH writer spells it differs.
template <class T>
clip<T> with_rotation_order(const clip<T>& c, euler_order order) {
    skeleton<T> sk = c.skeleton();
    const auto ax = axes_of(order);
    for (std::size_t j = 0; j < sk.size(); ++j) {
        if (!sk.has_rotation_channels(j)) continue;
        std::vector<channel> ch;
        for (channel x : sk[j].channels)
            if (is_position(x)) ch.push_back(x);
        for (axis a : ax) ch.push_back(static_cast<channel>(3 + static_cast<int>(a)));
        sk.set_channels(j, ch);
    }
    clip<T> out(sk, c.frames(), c.frame_time());
    for (std::size_t f = 0; f < c.frames(); ++f)
        for (std::size_t j = 0; j < c.joints(); ++j) {
            out.set_rotation(f, j, c.rotation(f, j));
            if (sk.translation_slot(j) >= 0) out.set_translation(f, j, c.translation(f, j));
        }
    return out;
}

}  // namespace anima
