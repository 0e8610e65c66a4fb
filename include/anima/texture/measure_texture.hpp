// How good a motion texture is, against the clips it was made from: each
// pass through an overlap (where the seams are) held to the fastest the
// inputs themselves move, and the feet's skate before and after. What
// `anima texture` reports; a test or a tuning loop asks the same.
//
//   auto t = anima::make_motion_texture(walk, 1700);
//   auto q = anima::measure_texture(walk, t);
//   bool seamless = q.worst.within(0.02);
#pragma once

#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/contacts.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/skeleton.hpp>
#include <anima/texture/motion_texture.hpp>
#include <anima/texture/seam_speed.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace anima {

template <class T>
struct texture_measures {
    /// seam_speeds of each pass through an overlap (motion_texture::
    /// overlap_spans, in order) against the texton's source speeds.
    std::vector<seam_speed<T>> seams;
    seam_speed<T> worst;  ///< worst_seam_speed(seams)
    /// clip_foot_skate: the inputs' median (all of them together) and the
    /// texture's, in body heights per second; 0 without feet or contacts.
    skate_summary<T> input_skate, skate;
};

namespace detail {
template <class T>
texture_measures<T> measure_texture(const std::vector<const clip<T>*>& inputs, const motion_texture<T>& t,
                                    std::optional<signed_axis> up) {
    if (inputs.empty()) throw invalid_argument("anima::measure_texture: no input clip to measure the texture against");
    for (std::size_t i = 0; i < inputs.size(); ++i) try {
            check_same_hierarchy(inputs[i]->skeleton(), t.motion.skeleton());
        } catch (const invalid_argument& e) {
            throw invalid_argument("anima::measure_texture: input " + std::to_string(i) +
                                   " is not of the texture's skeleton: " + e.what());
        }
    texture_measures<T> out;
    out.seams = seam_speeds(t.motion, t.overlap_spans, source_speed_limits(t.texton));
    out.worst = worst_seam_speed(out.seams);
    out.input_skate = detail::clip_foot_skate(inputs, up);
    out.skate = anima::clip_foot_skate(t.motion, up);
    return out;
}
}  // namespace detail

/// Measures texture `t` against `inputs`, the clips it was made from (one,
/// or the loop's several, in any order). `up` is the axis the contacts are
/// found along (unset: guessed from the skeleton). Throws
/// anima::invalid_argument for no input, or an input of another hierarchy
/// than the texture.
template <class T>
texture_measures<T> measure_texture(const std::vector<clip<T>>& inputs, const motion_texture<T>& t,
                                    std::optional<signed_axis> up = std::nullopt) {
    std::vector<const clip<T>*> pointers;
    for (const clip<T>& c : inputs) pointers.push_back(&c);
    return detail::measure_texture(pointers, t, up);
}

/// measure_texture of a texture made from one clip.
template <class T>
texture_measures<T> measure_texture(const clip<T>& input, const motion_texture<T>& t,
                                    std::optional<signed_axis> up = std::nullopt) {
    return detail::measure_texture(std::vector<const clip<T>*>{&input}, t, up);
}

}  // namespace anima
