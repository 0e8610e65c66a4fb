// Video-texture jumps (Schodl et al. 2000), the alternative the paper
// contrasts with symmetric playback: from frame i the stream may continue
// at any frame j whose predecessor j-1 looks like i, with probability
// proportional to Eq 1's similarity exp(-D(i, j-1) / sigma). The natural
// continuation j = i+1 has D = 0 and weight 1. Finding the jumps needs all
// frame pairs: O(frames^2 * DOFs) once, O(frames * max_targets) memory.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/random.hpp>
#include <anima/motion/frame_distance.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace anima {

template <class T>
struct video_texture_params {
    frame_distance_params<T> distance{frame_metric::l2, T(1e-3), 3};
    /// sigma of Eq 1 as a fraction of the mean distance over all jump pairs.
    T sigma_scale = T(0.05);
    /// Jumps that land fewer than this many frames from i+1 are ignored:
    /// they are the continuation with a stutter, not a transition.
    int min_jump = 10;
    /// The most similar jumps kept per frame.
    std::size_t max_targets = 4;
    /// Jumps less likely than this are dropped (the last frame keeps its
    /// best one regardless, or the stream would end there).
    T min_probability = T(1e-3);
};

template <class T>
struct jump {
    std::size_t to = 0;
    T probability = T(0);
};

/// Where the stream may go from each frame, continuation included.
template <class T>
struct jump_table {
    std::vector<std::vector<jump<T>>> from;
    T sigma = T(0);  ///< the sigma of Eq 1 used
};

/// The jumps of a frames x DOF matrix. Throws anima::invalid_argument for
/// bad parameters, non-finite values, a clip too short to jump in
/// (frames <= min_jump + 1), or DOFs so large that their distances
/// overflow the scalar type.
template <class Derived>
jump_table<typename Derived::Scalar> video_texture_jumps(const Eigen::MatrixBase<Derived>& dofs,
                                                         typename Derived::Scalar frame_time,
                                                         const video_texture_params<typename Derived::Scalar>& params = {}) {
    using T = typename Derived::Scalar;
    const char* who = "anima::video_texture_jumps";
    const auto fail = [who](const std::string& what) { throw invalid_argument(std::string(who) + ": " + what); };
    check_positive(who, "sigma_scale", params.sigma_scale);
    check_at_least(who, "min_jump", params.min_jump, 1);
    check_at_least(who, "max_targets", params.max_targets, std::size_t(1));
    check_argument(params.min_probability >= T(0) && params.min_probability < T(1), who, "min_probability", "in [0, 1)",
                   params.min_probability);
    const Eigen::Index n = dofs.rows();
    // In Eigen::Index: min_jump + 1 overflows an int at INT_MAX.
    const Eigen::Index least = static_cast<Eigen::Index>(params.min_jump) + 1;
    if (n <= least)
        fail("the clip has " + std::to_string(n) + " frames; jumps of at least " + std::to_string(params.min_jump) +
             " frames need more than " + std::to_string(least));
    const auto distance = make_frame_distance(dofs, frame_time, params.distance);
    const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> frames = dofs.transpose();

    // Pass 1: the best targets of every frame, and the mean distance.
    std::vector<std::vector<std::pair<T, std::size_t>>> best(static_cast<std::size_t>(n));
    double total = 0;
    std::size_t count = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
        auto& b = best[static_cast<std::size_t>(i)];
        for (Eigen::Index j = 1; j < n; ++j) {
            const Eigen::Index gap = j > i + 1 ? j - (i + 1) : (i + 1) - j;
            if (gap < params.min_jump) continue;
            const T d = distance(frames.col(i), frames.col(j - 1));
            total += static_cast<double>(d);
            ++count;
            if (b.size() < params.max_targets) {
                b.emplace_back(d, static_cast<std::size_t>(j));
                std::push_heap(b.begin(), b.end());
            } else if (d < b.front().first) {
                std::pop_heap(b.begin(), b.end());
                b.back() = {d, static_cast<std::size_t>(j)};
                std::push_heap(b.begin(), b.end());
            }
        }
        std::sort_heap(b.begin(), b.end());
    }
    jump_table<T> table;
    const double mean = count ? total / static_cast<double>(count) : 0.0;
    // A frozen clip has only zero distances: any positive sigma will do.
    table.sigma = mean > 0 ? static_cast<T>(static_cast<double>(params.sigma_scale) * mean) : T(1);
    // Finite DOFs can still give distances, or a sigma, beyond T's range.
    if (!std::isfinite(total) || !std::isfinite(table.sigma))
        fail("the distances between frames overflow the scalar type; scale the DOFs down");

    // Pass 2: probabilities, continuation first.
    table.from.resize(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i) {
        auto& out = table.from[static_cast<std::size_t>(i)];
        const bool last = i == n - 1;
        if (!last) out.push_back({static_cast<std::size_t>(i + 1), T(1)});
        for (const auto& [d, j] : best[static_cast<std::size_t>(i)]) out.push_back({j, l2_similarity(d, table.sigma)});
        const auto normalise = [&out] {
            T sum = T(0);
            for (const auto& e : out) sum += e.probability;
            for (auto& e : out) e.probability /= sum;
        };
        if (last) {
            // Keep the best jump alive even if its similarity underflowed.
            for (auto& e : out) e.probability = std::max(e.probability, std::numeric_limits<T>::min());
        }
        normalise();
        const auto keep = std::max<std::ptrdiff_t>(1, std::count_if(out.begin(), out.end(), [&](const jump<T>& e) {
                                                         return e.probability >= params.min_probability;
                                                     }));
        std::stable_sort(out.begin(), out.end(), [](const jump<T>& a, const jump<T>& b) { return a.probability > b.probability; });
        out.resize(static_cast<std::size_t>(keep));
        normalise();
    }
    return table;
}

/// Generator of a video-texture frame stream.
template <class T>
class video_texture_playback {
public:
    video_texture_playback(jump_table<T> table, std::uint64_t seed = 1, std::size_t start_frame = 0)
        : table_(std::move(table)), random_(seed), frame_(start_frame) {
        if (table_.from.empty()) throw invalid_argument("anima::video_texture_playback: empty jump table");
        if (start_frame >= table_.from.size())
            throw invalid_argument("anima::video_texture_playback: start frame " + std::to_string(start_frame) +
                                   " is outside the clip's " + std::to_string(table_.from.size()) + " frames");
        for (std::size_t i = 0; i < table_.from.size(); ++i) {
            if (table_.from[i].empty())
                throw invalid_argument("anima::video_texture_playback: frame " + std::to_string(i) + " has no successor");
            for (const auto& e : table_.from[i])
                if (e.to >= table_.from.size() || !(e.probability >= T(0)))
                    throw invalid_argument("anima::video_texture_playback: bad jump from frame " + std::to_string(i));
        }
    }

    /// The frame to show now; advances the stream.
    std::size_t next() {
        const std::size_t shown = frame_;
        const auto& out = table_.from[shown];
        double u = random_.uniform();
        std::size_t pick = out.size() - 1;
        for (std::size_t k = 0; k < out.size(); ++k) {
            u -= static_cast<double>(out[k].probability);
            if (u < 0) {
                pick = k;
                break;
            }
        }
        frame_ = out[pick].to;
        if (frame_ != shown + 1) jumps_.push_back(emitted_);
        ++emitted_;
        return shown;
    }

    std::vector<std::size_t> take(std::size_t n) {
        std::vector<std::size_t> out(n);
        for (auto& f : out) f = next();
        return out;
    }

    /// Positions in the stream after which it jumped.
    const std::vector<std::size_t>& jumps() const noexcept { return jumps_; }

private:
    jump_table<T> table_;
    random_source random_;
    std::size_t frame_ = 0, emitted_ = 0;
    std::vector<std::size_t> jumps_;
};

}  // namespace anima
