// A flight problem from a recorded jump (paper 001, 3.2): the airborne phase
// of the clip (no foot in contact, anima::find_contacts), keys placed on
// evenly spaced frames of it with the recorded root positions and joint
// rotations, and the body model of the clip's skeleton. optimize_flight then
// retimes those keys; the first and last keep the phase's start and length.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/flight/body_model.hpp>
#include <anima/flight/key_set.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/contacts.hpp>
#include <anima/motion/figure.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace anima {

template <class T>
struct clip_flight_params {
    std::size_t keys = 8;                 ///< keys over the airborne phase, at least 2
    std::optional<frame_interval> phase;  ///< default: the longest airborne phase of the clip
    contact_params<T> contacts;           ///< how the phase is found
    /// The body; metres_per_unit 0 takes the CMU layouts' unit, or the unit
    /// guess_units is confident of.
    body_model_params<T> body;
};

/// The key set and where it came from.
template <class T>
struct clip_flight_keys {
    flight_key_set<T> key_set;            ///< times from 0 (the phase's first frame), in seconds
    frame_interval phase;                 ///< the airborne frames
    std::vector<std::size_t> key_frames;  ///< the clip frame of each key
};

/// Keys on the airborne phase of `c`. Throws anima::invalid_argument when the
/// clip has no airborne phase (naming the clip's frames), the phase is
/// outside the clip or has fewer frames than keys, fewer than 2 keys are
/// asked for, or the unit cannot be told.
template <class T>
clip_flight_keys<T> flight_keys_from_clip(const clip<T>& c, const clip_flight_params<T>& params = {}) {
    const char* who = "anima::flight_keys_from_clip";
    check_at_least(who, "keys", params.keys, std::size_t{2});
    const auto& sk = c.skeleton();
    const contact_set<T> contacts = find_contacts(c, params.contacts);
    clip_flight_keys<T> out;
    if (params.phase) {
        out.phase = *params.phase;
        if (out.phase.first > out.phase.last || out.phase.last >= c.frames())
            throw invalid_argument(std::string(who) + ": the phase " + std::to_string(out.phase.first) + "-" +
                                   std::to_string(out.phase.last) + " is not within the clip's " +
                                   std::to_string(c.frames()) + " frames");
    } else {
        if (contacts.airborne_phases.empty())
            throw invalid_argument(std::string(who) + ": the clip (" + std::to_string(c.frames()) +
                                   " frames) has no airborne phase: some foot is planted in every frame");
        out.phase = contacts.airborne_phases.front();
        for (const auto& p : contacts.airborne_phases)
            if (p.frames() > out.phase.frames()) out.phase = p;
    }
    if (out.phase.frames() < params.keys)
        throw invalid_argument(std::string(who) + ": the phase " + std::to_string(out.phase.first) + "-" +
                               std::to_string(out.phase.last) + " has " + std::to_string(out.phase.frames()) +
                               " frames, fewer than the " + std::to_string(params.keys) + " keys asked for");

    body_model_params<T> body = params.body;
    if (!(body.metres_per_unit > T(0))) {
        if (const auto unit = layout_metres_per_unit(sk)) {
            body.metres_per_unit = *unit;
        } else {
            const unit_guess g = guess_units(sk, contacts.up);
            if (!g.confident)
                throw invalid_argument(std::string(who) + ": the skeleton's unit cannot be told (a " +
                                       std::to_string(g.height) + " unit tall figure): give body.metres_per_unit");
            body.metres_per_unit = T(g.metres_per_unit);
        }
    }
    flight_key_set<T> set;
    set.name = "airborne frames " + std::to_string(out.phase.first) + "-" + std::to_string(out.phase.last);
    set.skeleton = sk;
    set.model = make_body_model(sk, body);
    set.metres_per_unit = body.metres_per_unit;
    set.settings.gravity = -T(9.81) * axis_vector<T>(contacts.up);
    const T span = static_cast<T>(out.phase.last - out.phase.first);
    for (std::size_t k = 0; k < params.keys; ++k) {
        const auto f = out.phase.first +
                       static_cast<std::size_t>(std::lround(static_cast<double>(span) * static_cast<double>(k) /
                                                            static_cast<double>(params.keys - 1)));
        out.key_frames.push_back(f);
        set.keys.times.push_back(static_cast<T>(f - out.phase.first) * c.frame_time());
        set.keys.root_positions.push_back(c.root_position(f) * body.metres_per_unit);
        std::vector<Eigen::Quaternion<T>> rotations(sk.size());
        for (std::size_t j = 0; j < sk.size(); ++j) rotations[j] = c.rotation(f, j);
        set.keys.rotations.push_back(std::move(rotations));
    }
    out.key_set = std::move(set);
    return out;
}

}  // namespace anima
