// Anthropometric segment parameters: de Leva (1996), "Adjustments to
// Zatsiorsky-Seluyanov's segment inertia parameters", J. Biomechanics 29(9),
// Table 4. Mass as a fraction of body mass, centre of mass and radii of
// gyration as fractions of the segment length, and the mean segment length
// of the measured population (used only when a skeleton does not give one).
//
// de Leva measures the centre of mass from the segment's proximal landmark:
// the shoulder, elbow, wrist, hip, knee and heel for the limbs, but the
// vertex of the head and the cervicale / xiphoid / omphalion for the head and
// the three trunk parts, i.e. from the end away from the pelvis. Skeleton
// trees grow away from the pelvis, so `measured_from_far_end` says which.
#pragma once

#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>

#include <string>
#include <string_view>

namespace anima {

enum class sex { male, female };

/// The fourteen segments of de Leva's model, sides merged (a left and a right
/// thigh have the same parameters).
enum class segment_kind { head, upper_trunk, middle_trunk, lower_trunk, upper_arm, forearm, hand, thigh, shank, foot };

template <>
struct enum_names<segment_kind> {
    static constexpr const char* what = "segment";
    static constexpr enum_entry<segment_kind> entries[] = {
        {segment_kind::head, "head"},           {segment_kind::upper_trunk, "upper_trunk"},
        {segment_kind::middle_trunk, "middle_trunk"}, {segment_kind::lower_trunk, "lower_trunk"},
        {segment_kind::upper_arm, "upper_arm"}, {segment_kind::forearm, "forearm"},
        {segment_kind::hand, "hand"},           {segment_kind::thigh, "thigh"},
        {segment_kind::shank, "shank"},         {segment_kind::foot, "foot"}};
};

inline segment_kind parse_segment_kind(std::string_view s) {
    return parse_enum<segment_kind>(s, "anima::parse_segment_kind");
}

/// One row of de Leva's Table 4 (fractions, not percent).
struct segment_parameters {
    double mass_fraction;         ///< of the whole body's mass
    double com_fraction;          ///< distance of the centre of mass from de Leva's proximal landmark / length
    double radius_sagittal;       ///< radius of gyration about the medio-lateral axis / length
    double radius_transverse;     ///< about the antero-posterior axis / length
    double radius_longitudinal;   ///< about the segment's long axis / length
    double mean_length;           ///< segment length of the sample, metres
    bool measured_from_far_end;   ///< com_fraction counts from the end away from the pelvis
};

/// de Leva (1996) Table 4, adjusted Zatsiorsky-Seluyanov parameters. The mass
/// fractions sum to 1 over head, three trunk parts and two of each limb segment.
inline const segment_parameters& de_leva_parameters(segment_kind k, sex s) {
    // mass, com, r_sag, r_trans, r_long, length (m), far end
    static const segment_parameters male[] = {
        {0.0694, 0.5976, 0.362, 0.376, 0.312, 0.2429, true},   // head: vertex - cervicale
        {0.1596, 0.2999, 0.716, 0.454, 0.659, 0.2421, true},   // upper trunk: cervicale - xiphoid
        {0.1633, 0.4502, 0.482, 0.383, 0.468, 0.2155, true},   // middle trunk: xiphoid - omphalion
        {0.1117, 0.6115, 0.615, 0.551, 0.587, 0.1457, true},   // lower trunk: omphalion - hip centres
        {0.0271, 0.5772, 0.285, 0.269, 0.158, 0.2817, false},  // upper arm: shoulder - elbow
        {0.0162, 0.4574, 0.276, 0.265, 0.121, 0.2689, false},  // forearm: elbow - wrist
        {0.0061, 0.7900, 0.628, 0.513, 0.401, 0.0862, false},  // hand: wrist - 3rd metacarpale
        {0.1416, 0.4095, 0.329, 0.329, 0.149, 0.4222, false},  // thigh: hip - knee
        {0.0433, 0.4459, 0.255, 0.249, 0.103, 0.4340, false},  // shank: knee - lateral malleolus
        {0.0137, 0.4415, 0.257, 0.245, 0.124, 0.2581, false},  // foot: heel - toe tip
    };
    static const segment_parameters female[] = {
        {0.0668, 0.5894, 0.330, 0.359, 0.318, 0.2437, true},
        {0.1545, 0.2077, 0.746, 0.502, 0.718, 0.2280, true},
        {0.1465, 0.4512, 0.433, 0.354, 0.415, 0.2053, true},
        {0.1247, 0.4920, 0.433, 0.402, 0.444, 0.1815, true},
        {0.0255, 0.5754, 0.278, 0.260, 0.148, 0.2751, false},
        {0.0138, 0.4559, 0.261, 0.257, 0.094, 0.2643, false},
        {0.0056, 0.7474, 0.531, 0.454, 0.335, 0.0780, false},
        {0.1478, 0.3612, 0.369, 0.364, 0.162, 0.3685, false},
        {0.0481, 0.4416, 0.271, 0.267, 0.093, 0.4323, false},
        {0.0129, 0.4014, 0.299, 0.279, 0.139, 0.2283, false},
    };
    return (s == sex::male ? male : female)[static_cast<int>(k)];
}

}  // namespace anima
