// A played frame stream made into a clip, feet planted where the stream
// turns or jumps. Symmetric playback reverses the legs in mid-stride and a
// video-texture jump lands in another stride: a foot on the ground there
// slides unless it is held (ik/plant_feet.hpp), with the legs no faster
// than the source clip's own joints.
#pragma once

#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/ik/plant_feet.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/resequence.hpp>
#include <anima/motion/speed_limits.hpp>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace anima {

template <class T>
struct render_stream_params {
    /// The root's path and the up axis (guessed from the skeleton when empty).
    resequence_params resequence;
    /// Hold the feet that are on the ground through an event in place.
    bool plant_feet = true;
    /// How they are held. Its ranges are set from the events; empty joint
    /// speed limits become the source clip's (clip_speed_limits); an empty
    /// contacts up axis becomes resequence.up.
    plant_feet_params<T> planting;
};

template <class T>
struct rendered_stream {
    clip<T> motion;
    std::size_t planted_runs = 0;  ///< contact runs held (0 when nothing was planted)
};

/// The clip whose frame k is frame stream[k] of `source` (anima::resequence),
/// with the contact runs that reach an event frame (an output frame where
/// the stream turns or jumps: symmetric_playback::turns(),
/// video_texture_playback::jumps()) planted. Figures without feet to plant
/// are left as resequenced. Throws anima::invalid_argument for a stream
/// index outside the source or an event outside the stream (naming it).
template <class T>
rendered_stream<T> render_stream(const clip<T>& source, const std::vector<std::size_t>& stream,
                                 const std::vector<std::size_t>& events, const render_stream_params<T>& params = {}) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    for (std::size_t e = 0; e < events.size(); ++e)
        if (events[e] >= stream.size())
            throw invalid_argument("anima::render_stream: event " + std::to_string(e) + " is output frame " +
                                   std::to_string(events[e]) + ", outside the stream's " +
                                   std::to_string(stream.size()) + " frames");
    rendered_stream<T> out;
    out.motion = resequence(source, stream, params.resequence);
    if (!params.plant_feet || events.empty()) return out;
    plant_feet_params<T> pp = params.planting;
    if (!pp.contacts.up) pp.contacts.up = params.resequence.up;
    std::vector<frame_interval> ranges;
    for (const std::size_t f : events) ranges.push_back({f, f + 1 < stream.size() ? f + 1 : f});
    out.planted_runs = plant_feet_in_ranges(out.motion, std::move(ranges), pp, clip_speed_limits(source).joint);
    return out;
}

}  // namespace anima
