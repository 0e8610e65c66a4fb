// Symmetric playback: an endless stream of frame indices that plays a clip
// forwards and backwards, reversing only at turning candidates (Eq 5).
//
// With fixed probabilities the most symmetric points win every time and the
// same stretch of the clip repeats while the rest is never shown. The
// adaptive rule of the paper (after Van Haevre and Van Reeth) lowers a
// point's probability by a fixed amount when a turn is taken there and
// raises it by the factor k of Eq 6 when it is passed, which spreads the
// playback over the clip. Render a stream with anima::resequence.
#pragma once

#include <anima/core/error.hpp>
#include <anima/core/random.hpp>
#include <anima/symmetry/symmetry_scores.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace anima {

template <class T>
struct playback_params {
    /// false: every candidate keeps its Eq 5 probability (the baseline).
    bool adaptive = true;
    /// Subtracted from a point's probability when a turn is taken there.
    T turn_penalty = T(0.2);
    /// k of Eq 6: a point's probability is multiplied by it when passed.
    T gain = T(1.25);
    /// Bounds of the adapted probabilities; the start values (Eq 5) are
    /// clamped into them too.
    T min_probability = T(0.02);
    T max_probability = T(0.9);
    std::uint64_t seed = 1;
    /// First frame shown, clamped to the span between the first and last
    /// candidate (playback never leaves that span).
    std::size_t start_frame = 0;
};

/// Generator of a symmetric-playback frame stream.
template <class T>
class symmetric_playback {
public:
    /// Needs at least two candidates, all inside [0, frames). Throws
    /// anima::invalid_argument otherwise or for bad parameters.
    symmetric_playback(std::size_t frames, const std::vector<turning_candidate<T>>& candidates,
                       const playback_params<T>& params = {})
        : params_(params), random_(params.seed), is_candidate_(frames, -1) {
        const auto fail = [](const std::string& what) { throw invalid_argument("anima::symmetric_playback: " + what); };
        if (!(params.min_probability >= T(0)) || !(params.min_probability <= params.max_probability) ||
            !(params.max_probability <= T(1)))
            fail("probability bounds must satisfy 0 <= min <= max <= 1");
        if (!(params.turn_penalty >= T(0)) || !std::isfinite(params.turn_penalty))
            fail("turn penalty must be finite and >= 0");
        if (!(params.gain >= T(1)) || !std::isfinite(params.gain)) fail("gain k must be finite and >= 1");
        if (candidates.size() < 2)
            fail("needs at least two turning candidates, got " + std::to_string(candidates.size()) +
                 " (a clip this short or this regular has nowhere to reverse)");
        for (const auto& c : candidates) {
            if (c.frame >= frames)
                fail("candidate frame " + std::to_string(c.frame) + " is outside the clip's " + std::to_string(frames) +
                     " frames");
            if (!std::isfinite(c.probability)) fail("candidate frame " + std::to_string(c.frame) + " has a non-finite probability");
            if (is_candidate_[c.frame] >= 0) fail("frame " + std::to_string(c.frame) + " is listed twice");
            is_candidate_[c.frame] = static_cast<long>(probability_.size());
            probability_.push_back(std::clamp(c.probability, params.min_probability, params.max_probability));
            if (probability_.size() == 1 || c.frame < first_) first_ = c.frame;
            if (probability_.size() == 1 || c.frame > last_) last_ = c.frame;
        }
        frame_ = std::clamp(params.start_frame, first_, last_);
        direction_ = frame_ == last_ ? -1 : 1;
    }

    /// The frame to show now; advances the stream.
    std::size_t next() {
        const std::size_t shown = frame_;
        const long c = is_candidate_[shown];
        // The start frame was not arrived at: nothing to turn back from.
        if (c >= 0 && emitted_ > 0) {
            const bool forced = (direction_ > 0 && shown == last_) || (direction_ < 0 && shown == first_);
            T& p = probability_[static_cast<std::size_t>(c)];
            const bool turn = forced || random_.uniform() < static_cast<double>(p);
            if (!forced && params_.adaptive)
                p = turn ? std::max(params_.min_probability, p - params_.turn_penalty)
                         : std::min(params_.max_probability, p * params_.gain);
            if (turn) {
                direction_ = -direction_;
                turns_.push_back(emitted_);
            }
        }
        frame_ = direction_ > 0 ? frame_ + 1 : frame_ - 1;
        ++emitted_;
        return shown;
    }

    /// The next n frames of the stream.
    std::vector<std::size_t> take(std::size_t n) {
        std::vector<std::size_t> out(n);
        for (auto& f : out) f = next();
        return out;
    }

    /// Positions in the stream (0 = first frame shown) where it reversed.
    const std::vector<std::size_t>& turns() const noexcept { return turns_; }
    /// Current turning probability of a candidate frame (0 for other frames).
    T probability(std::size_t frame) const {
        return frame < is_candidate_.size() && is_candidate_[frame] >= 0 ? probability_[static_cast<std::size_t>(is_candidate_[frame])] : T(0);
    }
    std::size_t first_turning_frame() const noexcept { return first_; }
    std::size_t last_turning_frame() const noexcept { return last_; }

private:
    playback_params<T> params_;
    random_source random_;
    std::vector<long> is_candidate_;  // index into probability_, or -1
    std::vector<T> probability_;
    std::vector<std::size_t> turns_;
    std::size_t first_ = 0, last_ = 0, frame_ = 0, emitted_ = 0;
    int direction_ = 1;
};

/// How much of a clip a frame stream shows.
template <class T>
struct frame_coverage {
    T visited = T(0);  ///< fraction of the clip's frames shown at least once
    T evenness = T(0); ///< entropy of the visit histogram / log(frames): 1 = every frame equally often
};

/// Coverage of `frames` clip frames by a stream. Throws for indices outside.
template <class T = double>
frame_coverage<T> coverage(const std::vector<std::size_t>& stream, std::size_t frames) {
    frame_coverage<T> out;
    if (frames == 0 || stream.empty()) return out;
    std::vector<std::size_t> count(frames, 0);
    for (std::size_t f : stream) {
        if (f >= frames)
            throw invalid_argument("anima::coverage: frame " + std::to_string(f) + " is outside the clip's " +
                                   std::to_string(frames) + " frames");
        ++count[f];
    }
    std::size_t seen = 0;
    double entropy = 0;
    const double total = static_cast<double>(stream.size());
    for (std::size_t n : count)
        if (n) {
            ++seen;
            const double p = static_cast<double>(n) / total;
            entropy -= p * std::log(p);
        }
    out.visited = static_cast<T>(static_cast<double>(seen) / static_cast<double>(frames));
    out.evenness = frames > 1 ? static_cast<T>(entropy / std::log(static_cast<double>(frames))) : T(1);
    return out;
}

}  // namespace anima
