// Which side of the body a joint is on, and which way the figure's left
// points: what a renderer needs to colour and frame a figure, and what foot
// and hand pairs are matched by. Both come from joint names and the rest
// pose, as BVH files record neither.
#pragma once

#include <anima/core/enum_names.hpp>
#include <anima/core/text.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/skeleton.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <string_view>

namespace anima {

enum class body_side : unsigned char { centre, left, right };

template <>
struct enum_names<body_side> {
    static constexpr const char* what = "body side";
    static constexpr enum_entry<body_side> entries[] = {
        {body_side::centre, "centre"}, {body_side::left, "left"}, {body_side::right, "right"}};
};

/// The side a joint name says: "left"/"right" anywhere in any case
/// (LeftUpLeg, RightHand), or a leading l/L or r/R followed by an upper-case
/// letter, a digit or a separator (lShldr, rThigh, L_Foot, r.hand, LHipJoint).
/// CMU ASF names such as lhumerus and rfemur are all lower case and are read
/// as l/r + bone as well when the rest is a known bone of that skeleton.
/// Anything else is the centre.
inline body_side side_of(std::string_view name) {
    const std::string lower = ascii_lower(name);
    if (lower.find("left") != std::string::npos) return body_side::left;
    if (lower.find("right") != std::string::npos) return body_side::right;
    if (name.size() < 2 || (lower[0] != 'l' && lower[0] != 'r')) return body_side::centre;
    const body_side side = lower[0] == 'l' ? body_side::left : body_side::right;
    const char second = name[1];
    if (std::isupper(static_cast<unsigned char>(second)) || std::isdigit(static_cast<unsigned char>(second)) ||
        second == '_' || second == '-' || second == '.' || second == ':')
        return side;
    // CMU ASF bone names (lhumerus, rfemur, ltibia, ...).
    static constexpr std::string_view asf[] = {"clavicle", "humerus", "radius", "wrist", "hand", "fingers", "thumb",
                                               "hipjoint", "femur", "tibia", "foot", "toes"};
    const std::string_view rest = std::string_view(lower).substr(1);
    for (const std::string_view bone : asf)
        if (rest == bone) return side;
    return body_side::centre;
}

/// The figure's left direction in its rest pose, as a signed horizontal axis
/// (perpendicular to `up`): from the mean of its right-side joints to the
/// mean of its left-side joints, snapped to the nearer horizontal axis.
/// Without left and right joints, the horizontal axis along which the rest
/// pose is widest, positive. The figure faces left x up.
template <class T>
signed_axis left_axis(const skeleton<T>& sk, signed_axis up) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    const auto [joints, ends] = rest_positions(sk);
    vec3 left = vec3::Zero(), right = vec3::Zero();
    int nl = 0, nr = 0;
    for (std::size_t j = 0; j < sk.size(); ++j) {
        const body_side s = side_of(sk[j].name);
        if (s == body_side::left) left += joints[j], ++nl;
        if (s == body_side::right) right += joints[j], ++nr;
    }
    const int u = static_cast<int>(up.axis);
    const int h0 = (u + 1) % 3, h1 = (u + 2) % 3;
    if (nl > 0 && nr > 0) {
        const vec3 d = left / T(nl) - right / T(nr);
        const int k = std::abs(d[h0]) >= std::abs(d[h1]) ? h0 : h1;
        if (std::abs(d[k]) > T(0)) return {static_cast<axis>(k), d[k] < T(0) ? -1 : 1};
    }
    vec3 lo = vec3::Zero(), hi = vec3::Zero();
    bool first = true;
    const auto extend = [&](const vec3& p) {
        lo = first ? p : vec3(lo.cwiseMin(p));
        hi = first ? p : vec3(hi.cwiseMax(p));
        first = false;
    };
    for (const auto& p : joints) extend(p);
    for (const auto& p : ends) extend(p);
    return {static_cast<axis>(hi[h0] - lo[h0] >= hi[h1] - lo[h1] ? h0 : h1), 1};
}

}  // namespace anima
