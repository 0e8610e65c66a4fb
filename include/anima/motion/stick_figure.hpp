// A clip's pose as a stick figure seen from the front, the side or above:
// each bone (joint to parent, joint to End Site) projected onto the view's
// plane, with its depth toward the viewer for drawing order and its body
// side for colour. What `anima render` draws; a user can draw it with any
// 2D library.
#pragma once

#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/body_sides.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/skeleton.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <string_view>
#include <vector>

namespace anima {

/// Where the figure is seen from: front (its left on the viewer's right),
/// side (seen from its right, facing right) or top (from above, facing up).
enum class stick_view : unsigned char { front, side, top };

template <>
struct enum_names<stick_view> {
    static constexpr const char* what = "stick figure view";
    static constexpr enum_entry<stick_view> entries[] = {
        {stick_view::front, "front"}, {stick_view::side, "side"}, {stick_view::top, "top"}};
};

inline stick_view parse_stick_view(std::string_view name) {
    return parse_enum<stick_view>(name, "anima::parse_stick_view");
}

/// The view's plane: world directions drawn to the right and upwards, and
/// the one toward the viewer.
template <class T>
struct stick_view_basis {
    Eigen::Matrix<T, 3, 1> right, up, toward;
    bool vertical = true;  ///< `up` is the figure's up axis (front and side views)
};

/// The basis of `view` for a figure with up axis `up` and left axis `left`
/// (anima::left_axis); a figure facing +Z with +Y up has its left at +X.
/// Throws anima::invalid_argument when `left` is along `up`.
template <class T>
stick_view_basis<T> make_stick_view(stick_view view, signed_axis up, signed_axis left) {
    if (up.axis == left.axis)
        throw invalid_argument("anima::make_stick_view: left axis " + to_string(left) + " is along up axis " +
                               to_string(up));
    const Eigen::Matrix<T, 3, 1> u = axis_vector<T>(up), l = axis_vector<T>(left);
    const Eigen::Matrix<T, 3, 1> forward = l.cross(u);
    switch (view) {
        case stick_view::side: return {forward, u, -l, true};
        case stick_view::top: return {-l, forward, u, false};
        default: return {l, u, forward, true};
    }
}

/// A line from joint `from` to joint `to`, or to `to`'s End Site.
struct stick_bone {
    std::size_t from = 0, to = 0;
    bool end_site = false;
    body_side side = body_side::centre;  ///< anima::side_of the joint `to`
};

/// Each joint's bone from its parent, then the one to its End Site, in
/// joint order.
template <class T>
std::vector<stick_bone> stick_bones(const skeleton<T>& sk) {
    std::vector<stick_bone> out;
    for (std::size_t j = 0; j < sk.size(); ++j) {
        const body_side side = side_of(sk[j].name);
        if (sk[j].parent >= 0) out.push_back({static_cast<std::size_t>(sk[j].parent), j, false, side});
        if (sk[j].end_site) out.push_back({j, j, true, side});
    }
    return out;
}

/// A bone in view coordinates: its ends, its mean depth toward the viewer
/// and its length in 3D.
template <class T>
struct stick_segment {
    T x1 = 0, y1 = 0, x2 = 0, y2 = 0, depth = 0, length = 0;
    body_side side = body_side::centre;
};

/// The bones of frame `f` in view coordinates, one segment per bone in the
/// bones' order, relative to the root's position along `basis.right` (and
/// along `basis.up` in the top view) so that the figure stays centred.
/// Throws anima::invalid_argument for a frame outside the clip or a bone
/// naming a joint the skeleton does not have.
template <class T>
std::vector<stick_segment<T>> project_stick_figure(const clip<T>& c, std::size_t f, const std::vector<stick_bone>& bones,
                                                   const stick_view_basis<T>& basis) {
    const std::size_t joints = c.skeleton().size();
    for (const stick_bone& b : bones)
        if (b.from >= joints || b.to >= joints)
            throw invalid_argument("anima::project_stick_figure: bone " + std::to_string(b.from) + " -> " +
                                   std::to_string(b.to) + " is outside the skeleton's " + std::to_string(joints) +
                                   " joints");
    const global_pose<T> pose = forward_kinematics(c, f);
    const std::vector<Eigen::Matrix<T, 3, 1>> sites = end_site_positions(c.skeleton(), pose);
    const Eigen::Matrix<T, 3, 1>& root = pose.positions[0];
    const T rx = root.dot(basis.right), ry = basis.vertical ? T(0) : root.dot(basis.up);
    std::vector<stick_segment<T>> out;
    out.reserve(bones.size());
    for (const stick_bone& b : bones) {
        const Eigen::Matrix<T, 3, 1>& p = pose.positions[b.from];
        const Eigen::Matrix<T, 3, 1>& q = b.end_site ? sites[b.to] : pose.positions[b.to];
        out.push_back({p.dot(basis.right) - rx, p.dot(basis.up) - ry, q.dot(basis.right) - rx, q.dot(basis.up) - ry,
                       (p + q).dot(basis.toward) / 2, (p - q).norm(), b.side});
    }
    return out;
}

}  // namespace anima
