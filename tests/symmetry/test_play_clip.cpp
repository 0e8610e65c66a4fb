// play_clip: the whole of `anima playback` in one call. Checked against the
// single steps called one after another (frame_features, symmetry_scores +
// symmetric_playback or video_texture_jumps + video_texture_playback,
// coverage, render_stream) on the bundled walk, in float and double, for
// each method; without a clip; bad input and clips too short to play.
#include "symmetry_test_support.hpp"

#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/frame_features.hpp>
#include <anima/symmetry/play_clip.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using namespace symmetry_test;
using anima::playback_method;

template <class T>
bool same_clip(const anima::clip<T>& x, const anima::clip<T>& y) {
    if (x.frames() != y.frames() || x.joints() != y.joints()) return false;
    for (std::size_t i = 0; i < x.rotations().size(); ++i)
        if (x.rotations()[i].coeffs() != y.rotations()[i].coeffs()) return false;
    return x.translations() == y.translations();
}

/// What play_clip does, step by step.
template <class T>
anima::played_clip<T> by_steps(const anima::clip<T>& c, std::size_t frames, const anima::play_clip_params<T>& p) {
    anima::frame_feature_params fp;
    fp.up = anima::guess_up_axis(c.skeleton()).up;
    const matrix<T> features = anima::frame_features(c, fp);
    anima::played_clip<T> out;
    if (p.method == playback_method::video_texture) {
        const auto table = anima::video_texture_jumps(features, c.frame_time());
        out.sigma = table.sigma;
        anima::video_texture_playback<T> playback(table, p.playback.seed, p.playback.start_frame);
        out.stream = playback.take(frames);
        out.events = playback.jumps();
    } else {
        out.candidates = anima::symmetry_scores(features, c.frame_time(), p.symmetry).candidates;
        anima::playback_params<T> pp = p.playback;
        pp.adaptive = p.method == playback_method::adaptive;
        anima::symmetric_playback<T> playback(c.frames(), out.candidates, pp);
        out.stream = playback.take(frames);
        out.events = playback.turns();
        for (const auto& k : out.candidates) out.final_probabilities.push_back(playback.probability(k.frame));
        out.first_turning_frame = playback.first_turning_frame();
        out.last_turning_frame = playback.last_turning_frame();
    }
    out.coverage = anima::coverage<T>(out.stream, c.frames());
    anima::render_stream_params<T> rp;
    rp.resequence.up = fp.up;
    auto rendered = anima::render_stream(c, out.stream, out.events, rp);
    out.motion = std::move(rendered.motion);
    out.planted_runs = rendered.planted_runs;
    return out;
}

}  // namespace

TEST_CASE_TEMPLATE("play_clip: the single steps' results bit for bit, every method", T, float, double) {
    const anima::clip<T>& w = walk<T>();
    // Fewer frames in float, whose planting IK runs unoptimised in this unit.
    const std::size_t frames = std::is_same_v<T, float> ? 250 : 600;
    for (const playback_method method :
         {playback_method::adaptive, playback_method::fixed, playback_method::video_texture}) {
        CAPTURE(anima::to_string(method));
        anima::play_clip_params<T> p;
        p.method = method;
        p.playback.seed = 7;
        p.playback.start_frame = 50;
        const auto r = anima::play_clip(w, frames, p);
        const auto s = by_steps(w, frames, p);
        CHECK(r.stream == s.stream);
        CHECK(r.events == s.events);
        CHECK(r.coverage.visited == s.coverage.visited);
        CHECK(r.coverage.evenness == s.coverage.evenness);
        CHECK(r.planted_runs == s.planted_runs);
        CHECK(same_clip(r.motion, s.motion));
        CHECK(r.motion.frames() == frames);
        CHECK(r.sigma == s.sigma);
        CHECK(r.candidates.size() == s.candidates.size());
        CHECK(r.final_probabilities == s.final_probabilities);
        CHECK(r.first_turning_frame == s.first_turning_frame);
        CHECK(r.last_turning_frame == s.last_turning_frame);
        // The walk turns (or jumps) and the feet are held there.
        CHECK(!r.events.empty());
        CHECK(r.planted_runs > 0);
        if (method == playback_method::fixed)
            for (std::size_t i = 0; i < r.candidates.size(); ++i)
                CHECK(r.final_probabilities[i] ==
                      std::clamp(r.candidates[i].probability, p.playback.min_probability, p.playback.max_probability));

        // Without a clip: the same stream, nothing rendered.
        p.make_clip = false;
        const auto bare = anima::play_clip(w, frames, p);
        CHECK(bare.stream == r.stream);
        CHECK(bare.motion.frames() == 0);
        CHECK(bare.planted_runs == 0);
    }
}

TEST_CASE_TEMPLATE("play_clip: empty and short clips, no frames, too few candidates", T, float, double) {
    const anima::clip<T>& w = walk<T>();
    anima::play_clip_params<T> p;
    CHECK(contains(invalid_argument_message([&] { anima::play_clip(w, 0, p); }), "frames is 0"));
    CHECK(contains(invalid_argument_message([&] { anima::play_clip(w.slice(0, 0), 10, p); }), "no frames"));
    // One frame, and a few frames with a wide window: no two candidates.
    for (const std::size_t n : {std::size_t(1), std::size_t(12)}) {
        CAPTURE(n);
        p.symmetry.radius = 40;
        const std::string m = invalid_argument_message([&] { anima::play_clip(w.slice(100, 100 + n), 50, p); });
        CHECK(contains(m, "anima::play_clip"));
        CHECK(contains(m, "turning candidate"));
        CHECK(contains(m, "radius 40"));
    }
    // The video texture refuses a clip too short to jump in.
    p.method = playback_method::video_texture;
    CHECK_THROWS_AS(anima::play_clip(w.slice(100, 105), 50, p), anima::invalid_argument);
}
