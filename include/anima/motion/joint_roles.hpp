// What each joint does in a human figure, found from its name: the variable-
// timing transition times only the root, legs and feet, and interpolates
// fingers with the cheapest method. Users override the guess by editing the
// returned vector.
#pragma once

#include <anima/core/enum_names.hpp>
#include <anima/core/text.hpp>
#include <anima/motion/skeleton.hpp>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace anima {

enum class joint_role : unsigned char { root, leg, foot, finger, other };

template <>
struct enum_names<joint_role> {
    static constexpr const char* what = "joint role";
    static constexpr enum_entry<joint_role> entries[] = {{joint_role::root, "root"},
                                                         {joint_role::leg, "leg"},
                                                         {joint_role::foot, "foot"},
                                                         {joint_role::finger, "finger"},
                                                         {joint_role::other, "other"}};
};

/// Role of every joint. The roots are `root`; then by name (case-insensitive):
/// thumb/index/mid/ring/pinky/finger -> finger; foot/toe/ankle/heel -> foot;
/// thigh/shin/leg/knee/hip/buttock/calf -> leg; everything else -> other.
/// Works on the CMU, Daz/Poser and Mixamo-style names; check the result for
/// other rigs and edit it where it is wrong.
template <class T>
std::vector<joint_role> joint_roles(const skeleton<T>& sk) {
    static const char* const finger[] = {"thumb", "index", "mid", "ring", "pinky", "finger"};
    static const char* const foot[] = {"foot", "toe", "ankle", "heel"};
    static const char* const leg[] = {"thigh", "shin", "leg", "knee", "hip", "buttock", "calf"};
    const auto any = [](const std::string& n, const char* const* words, std::size_t count) {
        for (std::size_t i = 0; i < count; ++i)
            if (n.find(words[i]) != std::string::npos) return true;
        return false;
    };
    std::vector<joint_role> roles(sk.size(), joint_role::other);
    for (std::size_t j = 0; j < sk.size(); ++j) {
        const std::string n = ascii_lower(sk[j].name);
        if (sk[j].parent < 0) roles[j] = joint_role::root;
        else if (any(n, finger, 6)) roles[j] = joint_role::finger;
        else if (any(n, foot, 4)) roles[j] = joint_role::foot;
        else if (any(n, leg, 7)) roles[j] = joint_role::leg;
    }
    return roles;
}

}  // namespace anima
