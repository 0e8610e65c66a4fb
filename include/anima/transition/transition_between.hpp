// One call from two clips to the joined clip a tool writes: the transition by
// the chosen method (the variable-timing one or a baseline), the feet planted
// through its window, and both versions measured. This is the whole of
// `anima transition`; a caller that wants only one step calls make_transition,
// direct_cut, crossfade, inertialize, plant_transition_feet or
// measure_transition itself.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/joint_roles.hpp>
#include <anima/transition/baselines.hpp>
#include <anima/transition/metrics.hpp>
#include <anima/transition/plant_transition_feet.hpp>
#include <anima/transition/variable_timing_transition.hpp>

#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

namespace anima {

/// How the frames between the two clips are made.
enum class transition_method : unsigned char {
    variable,    ///< make_transition: the variable-timing hierarchical transition
    cut,         ///< direct_cut: B placed right after the trigger
    crossfade,   ///< crossfade over crossfade_time
    inertialize  ///< inertialize with a spring of the given half-life
};

template <>
struct enum_names<transition_method> {
    static constexpr const char* what = "transition method";
    static constexpr enum_entry<transition_method> entries[] = {{transition_method::variable, "variable"},
                                                                {transition_method::cut, "cut"},
                                                                {transition_method::crossfade, "crossfade"},
                                                                {transition_method::inertialize, "inertialize"}};
};

template <class T>
struct transition_between_params {
    transition_method method = transition_method::variable;
    /// The variable method's parameters. Its classification's up axis and
    /// units (guessed from A's skeleton when empty) are those of every
    /// method and of the measures; its roles (joint_roles of A when empty)
    /// are the measures' too.
    transition_params variable;
    double crossfade_time = 0.3;  ///< s, the crossfade's length
    double halflife = 0.1;        ///< s, the inertialization spring's half-life
    bool plant_feet = true;       ///< plant_transition_feet on the joined clip
    /// The planting; its contacts are found along the up axis above when
    /// feet.planting.contacts.up is empty.
    transition_feet_params<T> feet;
    std::size_t measure_margin = 12;  ///< frames either side of the window that measure_transition counts
};

/// What transition_between made, and how it measures.
template <class T>
struct transition_between_result {
    joined_clip<T> joined;     ///< A[..trigger] + transition + placed B, feet planted when asked
    joined_clip<T> unplanted;  ///< the same as the method left it (equal to `joined` without planting)
    /// The variable method's timing, per-joint methods, classes and root
    /// path (empty for the baselines).
    std::optional<transition_frames<T>> variable;
    transition_quality<T> quality;            ///< measure_transition of `joined`
    transition_quality<T> unplanted_quality;  ///< measure_transition of `unplanted`
    std::vector<joint_role> roles;            ///< what the measures took for each joint
    signed_axis up;                           ///< the up axis of the methods and measures
    double metres_per_unit = 1;
};

/// The transition from frame `trigger` of a to frame `b_start` of b by
/// params.method, with the feet planted through its window unless
/// params.plant_feet is false, and measured before and after planting.
/// Its results are those of the single steps called one after another on
/// the same arguments: make_transition + join (or the baseline),
/// plant_transition_feet, measure_transition. Throws anima::invalid_argument
/// as those do, naming the parameter (crossfade_time, halflife).
template <class T>
transition_between_result<T> transition_between(const clip<T>& a, std::size_t trigger, const clip<T>& b,
                                                std::size_t b_start, const transition_between_params<T>& params = {}) {
    constexpr const char* who = "anima::transition_between";
    check_non_negative(who, "transition_between_params::crossfade_time", params.crossfade_time);
    check_positive(who, "transition_between_params::halflife", params.halflife);
    transition_between_result<T> out;
    const classify_params& world = params.variable.classification;
    // Each method checks the clips and frames itself.
    switch (params.method) {
        case transition_method::variable: {
            transition<T> t = make_transition(a, trigger, b, b_start, params.variable);
            out.unplanted = join(a, trigger, t);
            out.variable = std::move(static_cast<transition_frames<T>&>(t));
            break;
        }
        case transition_method::cut: out.unplanted = direct_cut(a, trigger, b, b_start, world.up); break;
        case transition_method::crossfade:
            out.unplanted = crossfade(a, trigger, b, b_start, static_cast<T>(params.crossfade_time), world.up);
            break;
        case transition_method::inertialize:
            out.unplanted = inertialize(a, trigger, b, b_start, static_cast<T>(params.halflife), world.up);
            break;
    }
    out.up = world.up ? *world.up : guess_up_axis(a.skeleton()).up;
    out.metres_per_unit = world.metres_per_unit ? *world.metres_per_unit
                                                : guess_units(a.skeleton(), out.up).metres_per_unit;
    out.roles = params.variable.roles.empty() ? joint_roles(a.skeleton()) : params.variable.roles;
    out.unplanted_quality =
        measure_transition(out.unplanted, out.roles, out.up, out.metres_per_unit, params.measure_margin);
    if (!params.plant_feet) {
        out.joined = out.unplanted;
        out.quality = out.unplanted_quality;
        return out;
    }
    // The feet's contacts along the same up axis, unless told otherwise.
    transition_feet_params<T> feet = params.feet;
    if (!feet.planting.contacts.up) feet.planting.contacts.up = out.up;
    out.joined = plant_transition_feet(out.unplanted, feet);
    out.quality = measure_transition(out.joined, out.roles, out.up, out.metres_per_unit, params.measure_margin);
    return out;
}

}  // namespace anima
