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

#include <anima/core/check_argument.hpp>
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
    /// Bytes the turning table (8 a frame up to the last candidate) and a
    /// take() may each allocate (1 GiB; 0 lifts the limit): candidate frames
    /// below 134,217,728 and takes of at most as many frames.
    double max_memory = 1024.0 * 1024.0 * 1024.0;
};

namespace detail {

/// The most entries of `bytes_each` bytes that fit max_memory (0: no limit)
/// and a std::vector of them; throws anima::invalid_argument naming
/// `function` for a negative or NaN max_memory.
inline std::size_t playback_entry_limit(std::size_t bytes_each, std::size_t vector_max, double max_memory,
                                        const char* function) {
    check_argument(max_memory >= 0, function, "max_memory", "non-negative", max_memory);
    const double fit = std::floor(max_memory / static_cast<double>(bytes_each));
    if (max_memory > 0 && fit < static_cast<double>(vector_max)) return static_cast<std::size_t>(fit);
    return vector_max;
}

/// " (N bytes each, max_memory M MiB)" for a limit's message.
inline std::string playback_limit_text(std::size_t bytes_each, double max_memory) {
    return " (" + std::to_string(bytes_each) + " bytes each, " +
           (max_memory > 0 ? "max_memory " + detail::argument_text(max_memory / 1048576.0) + " MiB)"
                           : std::string("the largest vector)"));
}

}  // namespace detail

/// Generator of a symmetric-playback frame stream.
template <class T>
class symmetric_playback {
public:
    /// Needs at least two candidates, all inside [0, frames). Throws
    /// anima::invalid_argument otherwise, for bad parameters, or for a last
    /// candidate frame whose turning table exceeds params.max_memory.
    symmetric_playback(std::size_t frames, const std::vector<turning_candidate<T>>& candidates,
                       const playback_params<T>& params = {})
        : params_(params), random_(params.seed) {
        const char* who = "anima::symmetric_playback";
        const auto fail = [who](const std::string& what) { throw invalid_argument(std::string(who) + ": " + what); };
        // The probability bounds: 0 <= min <= max <= 1.
        check_in_range(who, "min_probability", params.min_probability, T(0), T(1));
        check_in_range(who, "max_probability", params.max_probability, params.min_probability, T(1));
        check_non_negative(who, "turn penalty", params.turn_penalty);
        check_argument(params.gain >= T(1) && std::isfinite(params.gain), who, "gain k", "finite and at least 1",
                       params.gain);
        if (candidates.size() < 2)
            fail("needs at least two turning candidates, got " + std::to_string(candidates.size()) +
                 " (a clip this short or this regular has nowhere to reverse)");
        for (const auto& c : candidates) {
            if (c.frame >= frames)
                fail("candidate frame " + std::to_string(c.frame) + " is outside the clip's " + std::to_string(frames) +
                     " frames");
            if (!std::isfinite(c.probability)) fail("candidate frame " + std::to_string(c.frame) + " has a non-finite probability");
            last_ = std::max(last_, c.frame);
        }
        // The table covers frames 0 .. last candidate, not the whole clip.
        const std::size_t most = detail::playback_entry_limit(sizeof(long), is_candidate_.max_size(), params.max_memory, who);
        if (last_ >= most)
            fail_argument(who, "the last candidate frame",
                          "below " + std::to_string(most) + detail::playback_limit_text(sizeof(long), params.max_memory),
                          last_);
        is_candidate_.assign(last_ + 1, -1);
        for (const auto& c : candidates) {
            if (is_candidate_[c.frame] >= 0) fail("frame " + std::to_string(c.frame) + " is listed twice");
            is_candidate_[c.frame] = static_cast<long>(probability_.size());
            probability_.push_back(std::clamp(c.probability, params.min_probability, params.max_probability));
            if (probability_.size() == 1 || c.frame < first_) first_ = c.frame;
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

    /// The next n frames of the stream. Throws anima::invalid_argument for
    /// an n whose frames exceed the params' max_memory.
    std::vector<std::size_t> take(std::size_t n) {
        std::vector<std::size_t> out;
        const char* who = "anima::symmetric_playback::take";
        const std::size_t most = detail::playback_entry_limit(sizeof(std::size_t), out.max_size(), params_.max_memory, who);
        if (n > most)
            fail_argument(who, "n",
                          "at most " + std::to_string(most) +
                              detail::playback_limit_text(sizeof(std::size_t), params_.max_memory),
                          n);
        out.resize(n);
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
/// Takes memory in proportion to the stream, whatever `frames` is.
template <class T = double>
frame_coverage<T> coverage(const std::vector<std::size_t>& stream, std::size_t frames) {
    frame_coverage<T> out;
    if (frames == 0 || stream.empty()) return out;
    std::size_t last = 0;
    for (std::size_t f : stream) {
        if (f >= frames)
            throw invalid_argument("anima::coverage: frame " + std::to_string(f) + " is outside the clip's " +
                                   std::to_string(frames) + " frames");
        last = std::max(last, f);
    }
    // Visits per frame shown, in frame order: a histogram up to the last
    // frame shown when that is not much longer than the stream, else runs of
    // the sorted stream.
    std::vector<std::size_t> visits;
    if (last / 4 < stream.size() + 1024) {
        std::vector<std::size_t> count(last + 1, 0);
        for (std::size_t f : stream) ++count[f];
        for (std::size_t n : count)
            if (n) visits.push_back(n);
    } else {
        std::vector<std::size_t> sorted = stream;
        std::sort(sorted.begin(), sorted.end());
        for (std::size_t i = 0; i < sorted.size();) {
            std::size_t j = i + 1;
            while (j < sorted.size() && sorted[j] == sorted[i]) ++j;
            visits.push_back(j - i);
            i = j;
        }
    }
    std::size_t seen = 0;
    double entropy = 0;
    const double total = static_cast<double>(stream.size());
    for (std::size_t n : visits) {
        ++seen;
        const double p = static_cast<double>(n) / total;
        entropy -= p * std::log(p);
    }
    out.visited = static_cast<T>(static_cast<double>(seen) / static_cast<double>(frames));
    out.evenness = frames > 1 ? static_cast<T>(entropy / std::log(static_cast<double>(frames))) : T(1);
    return out;
}

}  // namespace anima
