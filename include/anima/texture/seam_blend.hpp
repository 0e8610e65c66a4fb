// Graph-cut-guided blending (Eq 11-13): around each row's seam the motion
// does not switch from one source to the other in a single frame but fades
// over k frames with the C1 weight of motion graphs (Kovar et al. 2002),
//
//   alpha(p) = 1                                     p <= -1
//   alpha(p) = 2((p+1)/k)^3 - 3((p+1)/k)^2 + 1      -1 <= p <= k-1
//   alpha(p) = 0                                     p >= k-1
//
// the weight of the motion being left (M2) at frame p of the blend window;
// M1 gets 1 - alpha. The printed Eq 12 is garbled; this is the reading of
// the spec it cites. alpha is 1 with zero slope at p = -1 and 0 with zero
// slope at p = k-1, so the blend joins both motions with continuous
// velocity. Root positions mix linearly with alpha (Eq 11), rotations by
// slerp (Eq 13); the texton does the mixing, this header the weights.
#pragma once

#include <anima/core/error.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace anima {

struct seam_blend_params {
    /// false: switch at the seam frame (a hard cut per row).
    bool enabled = true;
    /// k, the frames of the fade; 0: half the overlap (at least 2). Capped
    /// at the overlap: both motions exist only there.
    std::size_t frames = 0;
};

/// alpha(p) for a blend of k >= 1 frames (the weight of the motion being
/// left). Defined for every real p; equal to the spec's values at integers.
/// Throws anima::invalid_argument for k = 0.
template <class T>
T blend_weight(T p, std::size_t k) {
    if (k == 0) throw invalid_argument("anima::blend_weight: the blend needs at least one frame (k = 0)");
    if (!(p > T(-1))) return p <= T(-1) ? T(1) : T(0);  // NaN reads as "past the blend"
    const T x = (p + T(1)) / static_cast<T>(k);
    if (x >= T(1)) return T(0);
    return (T(2) * x - T(3)) * x * x + T(1);
}

/// The blend length used for an overlap of `overlap` frames.
inline std::size_t blend_frames(const seam_blend_params& p, std::size_t overlap) {
    if (!p.enabled || overlap == 0) return 0;
    const std::size_t k = p.frames ? p.frames : std::max<std::size_t>(2, overlap / 2);
    return std::min(k, overlap);
}

/// First overlap frame of the blend window of a row whose seam (first frame
/// of the motion switched to) is `seam`: the window is centred on the seam
/// and moved inside the overlap when it would stick out.
inline std::size_t blend_window_start(std::size_t seam, std::size_t k, std::size_t overlap) {
    if (k == 0 || k > overlap)
        throw invalid_argument("anima::blend_window_start: a blend of " + std::to_string(k) +
                               " frames does not fit an overlap of " + std::to_string(overlap));
    const std::size_t half = k / 2;
    const std::size_t start = seam > half ? seam - half : 0;
    return std::min(start, overlap - k);
}

/// Weight of the motion being left at every (row, overlap frame): rows x
/// overlap, from the per-row seams (each in 1..overlap-1). With k = 0 the
/// weight is 1 before the seam and 0 from it on (a hard cut). Throws
/// anima::invalid_argument for a seam outside the overlap or k > overlap.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> blend_weights(const std::vector<std::size_t>& seams,
                                                               std::size_t overlap, std::size_t k) {
    if (k > overlap)
        throw invalid_argument("anima::blend_weights: a blend of " + std::to_string(k) +
                               " frames does not fit an overlap of " + std::to_string(overlap));
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> w(static_cast<Eigen::Index>(seams.size()),
                                                      static_cast<Eigen::Index>(overlap));
    for (std::size_t r = 0; r < seams.size(); ++r) {
        const std::size_t s = seams[r];
        if (s < 1 || s >= overlap)
            throw invalid_argument("anima::blend_weights: row " + std::to_string(r) + " has its seam at overlap frame " +
                                   std::to_string(s) + ", outside 1.." + std::to_string(overlap ? overlap - 1 : 0));
        const std::size_t start = k ? blend_window_start(s, k, overlap) : 0;
        for (std::size_t t = 0; t < overlap; ++t)
            w(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(t)) =
                k ? blend_weight(static_cast<T>(t) - static_cast<T>(start), k) : (t < s ? T(1) : T(0));
    }
    return w;
}

}  // namespace anima
