// Where a motion can be played backwards without a visible seam (Eq 3-5).
//
// Frame i is a good turning point when the frames around it mirror each
// other: i-r looks like i+r for r = 1..n. Eq 3 sums those pair distances
// with binomial weights, Eq 4 maps the sums to [0, 1] (1 = most symmetric),
// and Eq 5 keeps the local maxima as turning candidates with probability
// score / 2. Only the pairs (i-r, i+r) are evaluated: O(frames * n * DOFs),
// never the full distance matrix.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/frame_distance.hpp>
#include <anima/motion/frame_features.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace anima {

template <class T>
struct symmetry_params {
    frame_distance_params<T> distance;
    /// n of Eq 3: the pairs (i-r, i+r) for r = 1..radius are compared.
    int radius = 10;
    /// s of Eq 3: the weights C(2(n-s), n-r) peak at r = s; 0 weighs the
    /// nearest pairs most. Valid for 0 <= s <= (n+1)/2, where every weight is
    /// positive.
    int smoothness = 0;
    /// Half-width of Eq 5's local-maximum window; 0 means `radius`.
    int candidate_radius = 0;
    /// Frames compared on fewer pairs than this are never candidates; 0
    /// means `radius`, capped at the most pairs any frame of the clip has
    /// (a clip shorter than 2 radius + 1 frames). Near the clip's ends a frame is judged on one or two
    /// short pairs and looks symmetric by accident (frame 1 of a walk scores
    /// 0.95); its score is still reported.
    int min_pairs = 0;
};

/// The fewest pairs a frame of a clip of `frames` frames must be compared on
/// to be a turning candidate: params.min_pairs, or when that is 0 the
/// radius capped at the most pairs any frame has ((frames - 1) / 2); at
/// least 1.
template <class T>
int candidate_min_pairs(const symmetry_params<T>& params, std::size_t frames) {
    const std::size_t most = frames > 0 ? (frames - 1) / 2 : 0;
    const int widest = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(std::max(params.radius, 0)), most));
    return std::max(1, params.min_pairs ? params.min_pairs : widest);
}

/// A frame where playback may reverse.
template <class T>
struct turning_candidate {
    std::size_t frame = 0;
    T score = T(0);        ///< Eq 4 value at the frame, in [0, 1]
    T probability = T(0);  ///< Eq 5: score / 2
};

template <class T>
struct symmetry_result {
    /// Eq 3 per frame, divided by the weights of the pairs that exist (fewer
    /// near the clip's ends). Frames without any pair (the first and last)
    /// get the largest value.
    Eigen::Matrix<T, Eigen::Dynamic, 1> weighted_distance;
    /// Eq 4: 1 - weighted_distance / max, 1 = most symmetric. All 1 when no
    /// pair differs at all (a frozen clip); 0 at frames without pairs.
    Eigen::Matrix<T, Eigen::Dynamic, 1> score;
    /// Pairs (i-r, i+r) inside the clip per frame: min(radius, i, frames-1-i).
    std::vector<int> pairs;
    /// Eq 5 local maxima, highest score first (ties: earlier frame first).
    std::vector<turning_candidate<T>> candidates;
};

/// The widest window binomial_weights computes: 10 million pairs, 80 MB of
/// weights in double (symmetry_scores needs at most half the clip's frames).
inline constexpr int max_binomial_radius = 10'000'000;

namespace detail {
inline void check_symmetry_params(int radius, int smoothness, int candidate_radius, int min_pairs, const char* function) {
    if (radius < 1)
        throw invalid_argument(std::string(function) + ": radius (n of Eq 3) must be at least 1, got " +
                               std::to_string(radius));
    // 64 bits: 2(n - s) overflows an int for a radius near INT_MAX.
    if (smoothness < 0 || 2 * (static_cast<long long>(radius) - smoothness) < static_cast<long long>(radius) - 1)
        throw invalid_argument(std::string(function) + ": smoothness (s of Eq 3) must be in [0, " +
                               std::to_string((static_cast<long long>(radius) + 1) / 2) + "] for radius " +
                               std::to_string(radius) + ", got " + std::to_string(smoothness));
    if (candidate_radius < 0)
        throw invalid_argument(std::string(function) + ": candidate radius must be >= 0, got " +
                               std::to_string(candidate_radius));
    if (min_pairs < 0 || min_pairs > radius)
        throw invalid_argument(std::string(function) + ": min_pairs must be in [0, radius = " + std::to_string(radius) +
                               "], got " + std::to_string(min_pairs));
}

// Eq 3's weights for r = 1..count (count <= radius), scaled to sum to 1.
// Logarithms relative to r = 1 by the ratio of neighbouring binomials,
// C(m, k-1) / C(m, k) = k / (m-k+1) with k = n-r. Not lgamma: POSIX lets
// it write the global signgam, a data race when threads score clips.
template <class T>
std::vector<T> binomial_weights(int radius, int smoothness, int count) {
    const double n = radius, m = 2.0 * (n - smoothness);
    std::vector<double> logs(static_cast<std::size_t>(count));
    if (logs.empty()) return {};
    logs[0] = 0;
    for (int r = 1; r < count; ++r) {
        const double k = n - r;
        logs[static_cast<std::size_t>(r)] = logs[static_cast<std::size_t>(r - 1)] + std::log(k) - std::log(m - k + 1);
    }
    const double top = *std::max_element(logs.begin(), logs.end());
    double sum = 0;
    for (double& l : logs) sum += (l = std::exp(l - top));
    std::vector<T> w(logs.size());
    // Tails of a wide binomial underflow in float: keep every weight positive
    // so the pairs that exist near the clip's ends always carry weight.
    for (std::size_t k = 0; k < w.size(); ++k) w[k] = std::max(static_cast<T>(logs[k] / sum), std::numeric_limits<T>::min());
    return w;
}
}  // namespace detail

/// Eq 3's weights C(2(n-s), n-r) for r = 1..n, scaled to sum to 1 (only
/// their ratios matter once the end frames are normalised by the weights
/// used). Computed in logarithms: C(2n, n) overflows a double near n = 515.
/// Throws anima::invalid_argument for a radius below 1 or above
/// max_binomial_radius, or a smoothness outside [0, (radius+1)/2].
template <class T>
std::vector<T> binomial_weights(int radius, int smoothness) {
    detail::check_symmetry_params(radius, smoothness, 0, 0, "anima::binomial_weights");
    check_argument(radius <= max_binomial_radius, "anima::binomial_weights", "radius (n of Eq 3)",
                   "at most " + std::to_string(max_binomial_radius), radius);
    return detail::binomial_weights<T>(radius, smoothness, radius);
}

/// Eq 5: frames whose score is the largest within +-window (the first
/// frame of a plateau) among the frames compared on at least min_pairs
/// pairs (>= 1) and not below either immediate neighbour, zero scores
/// excluded, sorted by score, highest first.
template <class T>
std::vector<turning_candidate<T>> turning_candidates(const Eigen::Matrix<T, Eigen::Dynamic, 1>& score,
                                                     const std::vector<int>& pairs, int window, int min_pairs = 1) {
    if (static_cast<std::size_t>(score.size()) != pairs.size())
        throw invalid_argument("anima::turning_candidates: " + std::to_string(score.size()) + " scores but " +
                               std::to_string(pairs.size()) + " pair counts");
    if (window < 1) throw invalid_argument("anima::turning_candidates: window must be at least 1, got " + std::to_string(window));
    if (min_pairs < 1)
        throw invalid_argument("anima::turning_candidates: min_pairs must be at least 1, got " + std::to_string(min_pairs));
    std::vector<turning_candidate<T>> out;
    const Eigen::Index n = score.size();
    for (Eigen::Index i = 0; i < n; ++i) {
        if (pairs[static_cast<std::size_t>(i)] < min_pairs || !(score[i] > T(0))) continue;
        // On a slope whatever the window says: a frame at the edge of the
        // eligible range must not win only because its neighbour is ineligible.
        if ((i > 0 && score[i - 1] > score[i]) || (i + 1 < n && score[i + 1] > score[i])) continue;
        bool best = true;
        // Frames with too few pairs neither turn nor suppress a candidate
        // further away: their scores are not comparable.
        for (Eigen::Index k = std::max<Eigen::Index>(0, i - window); best && k <= std::min(n - 1, i + window); ++k)
            if (pairs[static_cast<std::size_t>(k)] >= min_pairs) best = k < i ? score[k] < score[i] : score[k] <= score[i];
        if (best) out.push_back({static_cast<std::size_t>(i), score[i], score[i] / T(2)});
    }
    std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.score > b.score; });
    return out;
}

/// Symmetry of every frame of a frames x DOF matrix (see frame_features).
/// Throws anima::invalid_argument for bad parameters, a bad frame time,
/// non-finite values or distances that overflow the scalar type.
template <class Derived>
symmetry_result<typename Derived::Scalar> symmetry_scores(const Eigen::MatrixBase<Derived>& dofs,
                                                          typename Derived::Scalar frame_time,
                                                          const symmetry_params<typename Derived::Scalar>& params = {}) {
    using T = typename Derived::Scalar;
    const flush_denormals guard;  // squares of mocap's tiny angles are subnormal in float
    detail::check_symmetry_params(params.radius, params.smoothness, params.candidate_radius, params.min_pairs,
                                  "anima::symmetry_scores");
    const auto distance = make_frame_distance(dofs, frame_time, params.distance);
    // Only the pairs a frame of this clip can have: a radius far beyond the
    // clip's length costs nothing.
    const int widest = static_cast<int>(std::min<Eigen::Index>(params.radius, std::max<Eigen::Index>(0, (dofs.rows() - 1) / 2)));
    const auto weights = detail::binomial_weights<T>(params.radius, params.smoothness, widest);
    // Frames as contiguous columns: every pair reads two of them. For Eq 2
    // the columns are scaled by sqrt(C^-1), making each pair a squared norm.
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> frames = dofs.transpose();
    const bool mahalanobis = distance.metric == frame_metric::mahalanobis;
    if (mahalanobis) frames = distance.precision.cwiseSqrt().asDiagonal() * frames;
    const Eigen::Index n = frames.cols();

    symmetry_result<T> out;
    out.weighted_distance.setZero(n);
    out.pairs.assign(static_cast<std::size_t>(n), 0);
    T largest = T(0);
    for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::Index reach = std::min<Eigen::Index>({params.radius, i, n - 1 - i});
        T sum = T(0), used = T(0);
        for (Eigen::Index r = 1; r <= reach; ++r) {
            const T w = weights[static_cast<std::size_t>(r - 1)];
            sum += w * (mahalanobis ? (frames.col(i - r) - frames.col(i + r)).squaredNorm()
                                    : distance(frames.col(i - r), frames.col(i + r)));
            used += w;
        }
        out.pairs[static_cast<std::size_t>(i)] = static_cast<int>(reach);
        if (reach > 0) {
            out.weighted_distance[i] = sum / used;
            // Finite DOFs can still overflow T once squared and summed.
            if (!std::isfinite(out.weighted_distance[i]))
                throw invalid_argument("anima::symmetry_scores: the distances around frame " + std::to_string(i) +
                                       " overflow the scalar type; scale the DOFs down");
            largest = std::max(largest, out.weighted_distance[i]);
        }
    }
    out.score.setZero(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        if (out.pairs[static_cast<std::size_t>(i)] == 0) {
            out.weighted_distance[i] = largest;
            continue;
        }
        out.score[i] = largest > T(0) ? T(1) - out.weighted_distance[i] / largest : T(1);
    }
    out.candidates = turning_candidates(out.score, out.pairs, params.candidate_radius ? params.candidate_radius : params.radius,
                                        candidate_min_pairs(params, static_cast<std::size_t>(dofs.rows())));
    return out;
}

/// Symmetry of a clip's frames (features from anima::frame_features).
template <class T>
symmetry_result<T> symmetry_scores(const clip<T>& c, const symmetry_params<T>& params = {},
                                   const frame_feature_params& features = {}) {
    return symmetry_scores(frame_features(c, features), c.frame_time(), params);
}

}  // namespace anima
