// A clip played into a new motion of any length, in one call: its frame
// features, then either symmetric playback (Eq 3-5 scores, turns at the
// candidates, adaptive (Eq 6) or fixed probabilities) or, for comparison,
// video-texture jumps between similar frames; the stream rendered with the
// feet held where it turns or jumps. This is the whole of `anima playback`;
// the steps are symmetry_scores, symmetric_playback or video_texture_jumps
// with video_texture_playback, coverage and render_stream.
#pragma once

#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/frame_features.hpp>
#include <anima/symmetry/render_stream.hpp>
#include <anima/symmetry/symmetric_playback.hpp>
#include <anima/symmetry/symmetry_scores.hpp>
#include <anima/symmetry/video_texture.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace anima {

/// How play_clip chooses the frames.
enum class playback_method : unsigned char {
    adaptive,      ///< symmetric playback, turn probabilities adapted as they are passed (Eq 6)
    fixed,         ///< symmetric playback, every candidate keeps its Eq 5 probability
    video_texture  ///< jumps to similar frames (L2 distance), the baseline
};

template <>
struct enum_names<playback_method> {
    static constexpr const char* what = "playback method";
    static constexpr enum_entry<playback_method> entries[] = {{playback_method::adaptive, "adaptive"},
                                                              {playback_method::fixed, "fixed"},
                                                              {playback_method::video_texture, "video_texture"}};
};

template <class T>
struct play_clip_params {
    playback_method method = playback_method::adaptive;
    /// The features compared (their up axis, guessed from the skeleton when
    /// empty, is also the rendering's unless render.resequence.up is set).
    frame_feature_params features;
    symmetry_params<T> symmetry;    ///< the symmetric methods' scores and candidates
    /// Seed, start frame and probabilities of the symmetric methods
    /// (playback.adaptive is set by `method`); the video texture takes
    /// its seed and start frame.
    playback_params<T> playback;
    video_texture_params<T> video_texture;
    /// The root's path and the planting (the up axis, when empty, is the
    /// features'). Not used without make_clip.
    render_stream_params<T> render;
    /// false: only the stream and its report, no clip (rendering and
    /// planting are most of the cost).
    bool make_clip = true;
};

template <class T>
struct played_clip {
    clip<T> motion;                     ///< frame k is source frame stream[k] (empty without make_clip)
    std::vector<std::size_t> stream;    ///< the source frame shown at each output frame
    std::vector<std::size_t> events;    ///< output frames where the stream turns (symmetric) or after which it jumps
    frame_coverage<T> coverage;         ///< of the source frames by the stream
    std::size_t planted_runs = 0;       ///< contact runs held at the events
    /// The symmetric methods: the candidates (Eq 5 probabilities), each
    /// one's probability when playback ended, and the span playback stays in.
    std::vector<turning_candidate<T>> candidates;
    std::vector<T> final_probabilities;
    std::size_t first_turning_frame = 0, last_turning_frame = 0;
    T sigma = T(0);  ///< the video texture's sigma of Eq 1
};

/// `frames` frames played from clip c by params.method. Throws
/// anima::invalid_argument for an empty clip, frames = 0, a clip with fewer
/// than two turning candidates for the symmetric methods (naming the
/// candidate radius), and everything the steps refuse.
template <class T>
played_clip<T> play_clip(const clip<T>& c, std::size_t frames, const play_clip_params<T>& params = {}) {
    constexpr const char* who = "anima::play_clip";
    if (c.frames() == 0) throw invalid_argument(std::string(who) + ": the clip has no frames");
    if (frames == 0) throw invalid_argument(std::string(who) + ": frames is 0: a played clip needs at least one");
    frame_feature_params fp = params.features;
    if (!fp.up) fp.up = guess_up_axis(c.skeleton()).up;
    const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> features = frame_features(c, fp);
    const T dt = c.frame_time();
    played_clip<T> out;
    if (params.method == playback_method::video_texture) {
        const jump_table<T> table = video_texture_jumps(features, dt, params.video_texture);
        out.sigma = table.sigma;
        video_texture_playback<T> playback(table, params.playback.seed, params.playback.start_frame);
        out.stream = playback.take(frames);
        out.events = playback.jumps();
    } else {
        const symmetry_result<T> scores = symmetry_scores(features, dt, params.symmetry);
        out.candidates = scores.candidates;
        if (out.candidates.size() < 2) {
            const std::size_t n = out.candidates.size();
            throw invalid_argument(std::string(who) + ": the clip (" + std::to_string(c.frames()) + " frames) has " +
                                   std::to_string(n) + " turning candidate" + (n == 1 ? "" : "s") +
                                   " with symmetry_params::radius " + std::to_string(params.symmetry.radius) +
                                   "; symmetric playback needs two: a smaller radius, candidate_radius or "
                                   "min_pairs, or more frames");
        }
        playback_params<T> pp = params.playback;
        pp.adaptive = params.method == playback_method::adaptive;
        symmetric_playback<T> playback(c.frames(), out.candidates, pp);
        out.stream = playback.take(frames);
        out.events = playback.turns();
        for (const auto& candidate : out.candidates) out.final_probabilities.push_back(playback.probability(candidate.frame));
        out.first_turning_frame = playback.first_turning_frame();
        out.last_turning_frame = playback.last_turning_frame();
    }
    out.coverage = coverage<T>(out.stream, c.frames());
    if (!params.make_clip) return out;
    render_stream_params<T> rp = params.render;
    if (!rp.resequence.up) rp.resequence.up = fp.up;
    rendered_stream<T> rendered = render_stream(c, out.stream, out.events, rp);
    out.motion = std::move(rendered.motion);
    out.planted_runs = rendered.planted_runs;
    return out;
}

}  // namespace anima
