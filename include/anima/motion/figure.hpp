// Guesses about a skeleton that BVH files do not record: which axis is up and
// what the length unit is. Both are heuristics on the rest pose of a human
// figure; the result says how sure it is, and every module that depends on
// them takes the values as parameters so a user can override the guess.
#pragma once

#include <anima/core/text.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/skeleton.hpp>
#include <anima/rotation/euler.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace anima {

/// A signed axis: +Y, -Z...
struct signed_axis {
    anima::axis axis = anima::axis::y;
    int sign = 1;
    friend bool operator==(signed_axis a, signed_axis b) { return a.axis == b.axis && a.sign == b.sign; }
    friend bool operator!=(signed_axis a, signed_axis b) { return !(a == b); }
};

inline std::string to_string(signed_axis a) {
    return std::string(a.sign < 0 ? "-" : "+") + static_cast<char>('X' + static_cast<int>(a.axis));
}

/// The signed axis `text` names, the inverse of to_string: "+Y", "-z" or
/// "Z" (the sign optional, + by default; any case); empty for anything else.
inline std::optional<signed_axis> try_parse_signed_axis(std::string_view text) {
    int sign = 1;
    if (!text.empty() && (text[0] == '+' || text[0] == '-')) {
        sign = text[0] == '-' ? -1 : 1;
        text.remove_prefix(1);
    }
    if (text.size() != 1) return std::nullopt;
    const char c = ascii_lower(text)[0];
    if (c < 'x' || c > 'z') return std::nullopt;
    return signed_axis{static_cast<anima::axis>(c - 'x'), sign};
}

/// As try_parse_signed_axis, and throws anima::invalid_argument naming the
/// text for anything that is not a signed axis.
inline signed_axis parse_signed_axis(std::string_view text) {
    if (const auto a = try_parse_signed_axis(text)) return *a;
    throw invalid_argument("anima::parse_signed_axis: '" + escape_for_message(text, 200) +
                           "' is not a signed axis: use +X, -X, +Y, -Y, +Z or -Z (the sign optional, any case)");
}

/// Unit vector of a signed axis.
template <class T>
Eigen::Matrix<T, 3, 1> axis_vector(signed_axis a) {
    Eigen::Matrix<T, 3, 1> v = Eigen::Matrix<T, 3, 1>::Zero();
    v[static_cast<int>(a.axis)] = a.sign < 0 ? T(-1) : T(1);
    return v;
}

/// The up direction of a figure and whether it was found from named joints.
struct up_axis_guess {
    signed_axis up;
    bool confident = false;  ///< false: no head or foot joint was found, +Y assumed
};

namespace detail {
template <class T>
signed_axis dominant_axis(const Eigen::Matrix<T, 3, 1>& v) {
    Eigen::Index k;
    v.cwiseAbs().maxCoeff(&k);
    return {static_cast<axis>(k), v[k] < T(0) ? -1 : 1};
}
}  // namespace detail

/// Up axis of a human figure: the dominant direction from the root to the
/// head in the rest pose, or else the opposite of the direction to the feet.
template <class T>
up_axis_guess guess_up_axis(const skeleton<T>& sk) {
    if (sk.empty()) return {};
    const auto rest = rest_positions(sk).first;
    const auto root = rest[0];
    const auto direction_to = [&](const char* const* words, std::size_t count) -> Eigen::Matrix<T, 3, 1> {
        Eigen::Matrix<T, 3, 1> sum = Eigen::Matrix<T, 3, 1>::Zero();
        for (std::size_t j = 1; j < sk.size(); ++j) {
            const std::string name = ascii_lower(sk[j].name);
            for (std::size_t w = 0; w < count; ++w)
                if (name.find(words[w]) != std::string::npos) {
                    sum += rest[j] - root;
                    break;
                }
        }
        return sum;
    };
    static const char* const head[] = {"head", "neck"};
    static const char* const feet[] = {"foot", "toe", "ankle"};
    const auto up = direction_to(head, 2);
    if (up.norm() > T(0)) return {detail::dominant_axis(up), true};
    const auto down = direction_to(feet, 3);
    if (down.norm() > T(0)) return {detail::dominant_axis(Eigen::Matrix<T, 3, 1>(-down)), true};
    return {};
}

/// A length unit guessed from a figure's height.
struct unit_guess {
    std::string name;          ///< "metres", "centimetres", "millimetres", "inches", "cmu-asf" or "unknown"
    double metres_per_unit = 1;  ///< 1 for "unknown" too
    double height = 0;         ///< rest-pose height along the up axis, in file units
    bool confident = false;    ///< the figure is 1.2-2.3 m tall in the chosen unit
};

/// Rest-pose height of a figure along `up` (joints and End Sites), in its units.
template <class T>
T figure_height(const skeleton<T>& sk, signed_axis up) {
    if (sk.empty()) return T(0);
    auto [joints, ends] = rest_positions(sk);
    joints.insert(joints.end(), ends.begin(), ends.end());
    const auto k = static_cast<Eigen::Index>(up.axis);
    T lo = joints[0][k], hi = joints[0][k];
    for (const auto& p : joints) {
        lo = std::min(lo, p[k]);
        hi = std::max(hi, p[k]);
    }
    return hi - lo;
}

/// The unit under which the figure's height is closest to a typical adult's
/// 1.7 m (on a log scale). CMU ASF units are 0.056444 m (the CMU FAQ's
/// conversion), which makes CMU skeletons about 1.5 m tall.
template <class T>
unit_guess guess_units(const skeleton<T>& sk, signed_axis up) {
    unit_guess g;
    g.height = static_cast<double>(figure_height(sk, up));
    g.name = "unknown";
    if (!(g.height > 0)) return g;
    struct unit {
        const char* name;
        double metres;
    };
    static const unit units[] = {{"metres", 1.0},
                                 {"centimetres", 0.01},
                                 {"millimetres", 0.001},
                                 {"inches", 0.0254},
                                 {"cmu-asf", 0.056444}};
    double best = 1e300;
    for (const auto& u : units) {
        const double err = std::abs(std::log(g.height * u.metres / 1.7));
        if (err < best) {
            best = err;
            g.name = u.name;
            g.metres_per_unit = u.metres;
        }
    }
    const double metres = g.height * g.metres_per_unit;
    g.confident = metres >= 1.2 && metres <= 2.3;
    return g;
}

}  // namespace anima
