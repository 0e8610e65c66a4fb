// Classification of a clip as on the spot, plane motion or space flight
// (section 3 of the variable-timing paper), from foot and hip trajectories.
//
// Feet are in contact where they move slower than contact_speed (speed rather
// than height, because retargeted mocap drifts in height: the Daz-layout CMU
// walk's planted toe rises 9 cm over 3 s). A clip is
//   space flight  when both feet leave contact for flight_min_time or longer
//                 and the hip rises flight_hip_rise above its median height;
//   on the spot   otherwise, when the feet's horizontal range stays below
//                 on_spot_distance;
//   plane motion  otherwise.
// Thresholds are in metres and seconds; the clip's unit is converted with
// metres_per_unit, guessed from the figure's height unless given.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/contacts.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/finite_difference.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/joint_roles.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

namespace anima {

enum class motion_class : unsigned char { on_the_spot, plane_motion, space_flight };

template <>
struct enum_names<motion_class> {
    static constexpr const char* what = "motion class";
    static constexpr enum_entry<motion_class> entries[] = {{motion_class::on_the_spot, "on_the_spot"},
                                                           {motion_class::plane_motion, "plane_motion"},
                                                           {motion_class::space_flight, "space_flight"}};
};

struct classify_params {
    std::optional<signed_axis> up;           ///< guessed from the skeleton when empty
    std::optional<double> metres_per_unit;   ///< guessed from the figure's height when empty
    double on_spot_distance = 0.5;           ///< m
    double contact_speed = 0.6;              ///< m/s
    double flight_min_time = 0.15;           ///< s
    double flight_hip_rise = 0.15;           ///< m
};

/// The class and the measurements that decided it.
struct motion_classification {
    motion_class type = motion_class::on_the_spot;
    double foot_range = 0;        ///< m, largest horizontal extent of any foot joint
    double longest_airborne = 0;  ///< s, longest run of frames with both feet out of contact
    double hip_rise = 0;          ///< m, highest root height above its median
    signed_axis up;
    double metres_per_unit = 1;
    /// Space flight only: the airborne phases (no foot in contact, by
    /// find_contacts), so a transition applies gravity only where the body
    /// is in the air.
    std::vector<frame_interval> airborne;
};

namespace detail {
/// The checks of classify_params; the errors name `who`.
inline void check_classify_params(const classify_params& p, const char* who) {
    check_positive(who, "classify_params::on_spot_distance", p.on_spot_distance);
    check_positive(who, "classify_params::contact_speed", p.contact_speed);
    check_non_negative(who, "classify_params::flight_min_time", p.flight_min_time);
    check_non_negative(who, "classify_params::flight_hip_rise", p.flight_hip_rise);
    if (p.metres_per_unit) check_positive(who, "classify_params::metres_per_unit", *p.metres_per_unit);
}
}  // namespace detail

/// Classifies a clip. `roles` (from joint_roles) tells which joints are feet. A clip without foot
/// joints is classified from the root alone (its horizontal range, and its
/// rise for flight). Empty clips are on the spot; a clip with frames but no
/// joints throws anima::invalid_argument.
template <class T>
motion_classification classify_motion(const clip<T>& c, const std::vector<joint_role>& roles,
                                       const classify_params& params = {}) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    detail::check_classify_params(params, "anima::classify_motion");
    if (roles.size() != c.joints())
        throw invalid_argument("anima::classify_motion: " + std::to_string(roles.size()) + " roles for " +
                               std::to_string(c.joints()) + " joints");
    motion_classification out;
    out.up = params.up ? *params.up : guess_up_axis(c.skeleton()).up;
    out.metres_per_unit = params.metres_per_unit ? *params.metres_per_unit : guess_units(c.skeleton(), out.up).metres_per_unit;
    if (c.frames() == 0) return out;
    if (c.joints() == 0) throw invalid_argument("anima::classify_motion: the clip has frames but no joints");
    const double m = out.metres_per_unit;
    const int k = static_cast<int>(out.up.axis);

    std::vector<std::size_t> feet;
    for (std::size_t j = 0; j < roles.size(); ++j)
        if (roles[j] == joint_role::foot) feet.push_back(j);
    const auto P = global_positions(c);
    const auto V = time_derivative(P, c.frame_time());
    const auto n = static_cast<Eigen::Index>(c.frames());

    // Horizontal range of the feet (or of the root when there are none).
    const std::vector<std::size_t> tracked = feet.empty() ? std::vector<std::size_t>{0} : feet;
    for (std::size_t j : tracked)
        for (int d = 0; d < 3; ++d) {
            if (d == k) continue;
            const auto col = P.col(static_cast<Eigen::Index>(3 * j) + d);
            out.foot_range = std::max(out.foot_range, static_cast<double>(col.maxCoeff() - col.minCoeff()) * m);
        }

    // Root height above its median.
    std::vector<double> h(static_cast<std::size_t>(n));
    for (Eigen::Index f = 0; f < n; ++f)
        h[static_cast<std::size_t>(f)] = out.up.sign * static_cast<double>(P(f, k)) * m;
    std::vector<double> sorted = h;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    out.hip_rise = *std::max_element(h.begin(), h.end()) - sorted[sorted.size() / 2];

    // Longest run of frames in which no foot joint is in contact.
    if (!feet.empty()) {
        std::size_t run = 0, longest = 0;
        for (Eigen::Index f = 0; f < n; ++f) {
            bool contact = false;
            for (std::size_t j : feet)
                contact = contact || static_cast<double>(V.row(f).template segment<3>(static_cast<Eigen::Index>(3 * j)).norm()) * m <
                                         params.contact_speed;
            run = contact ? 0 : run + 1;
            longest = std::max(longest, run);
        }
        out.longest_airborne = static_cast<double>(longest) * static_cast<double>(c.frame_time());
    }

    if (out.longest_airborne >= params.flight_min_time && out.hip_rise >= params.flight_hip_rise && !feet.empty()) {
        out.type = motion_class::space_flight;
        contact_params<T> cp;
        cp.up = out.up;
        for (std::size_t j : feet) cp.feet.push_back(c.skeleton()[j].name);
        out.airborne = find_contacts(c, cp).airborne_phases;
    }
    else if (out.foot_range < params.on_spot_distance)
        out.type = motion_class::on_the_spot;
    else
        out.type = motion_class::plane_motion;
    return out;
}

}  // namespace anima
