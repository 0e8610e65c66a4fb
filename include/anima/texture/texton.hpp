// A motion texton: a clip rearranged into a seamless loop (Section 4).
//
// M1 is the clip's first m frames and M2 its last m; the paper plays
// M(m+1 .. end-m), then M2, then M1. The middle part runs into M2 as
// recorded, and M1 runs into the middle part as recorded (M1's last frame
// is frame m-1, the middle starts at frame m). The only junction that was
// never recorded is M2 -> M1, and that is where the seam goes; played end
// to end, textons then join as recorded too (Eq 10 needs no extra seam).
//
// The seam: M2's frames a .. a+n-1 are laid over M1's frames b .. b+n-1
// (n = the overlap), with (a, b) the offsets of least summed frame
// distance (overlap_search.hpp) among those that leave a loop at least
// twice the overlap long (texton_params::min_frames). The frames after
// M2's overlap and before M1's are dropped. Inside the overlap each row (a
// joint's rotation, the root's translation) switches from M2 to M1 at its
// own frame, chosen by a min-cut (seam_cut.hpp), and fades over k frames
// around it (seam_blend.hpp). The texton is then
//
//   frames m .. F-m-1 | M2 frames 0 .. a-1 | overlap (n) | M1 frames b+n .. m-1
//
// (F = clip frames), F - m + a - b frames long, and its last frame leads
// into its first as recorded.
//
// The DOFs compared are anima::frame_features (rotation vectors about each
// joint's mean rotation, the root's height) with the root's ground-plane
// velocity in place of its ground position: where the figure stands does
// not matter, how fast it goes does. The texton's ground path is rebuilt
// from the blended velocities, so it does not jump where M1 begins. With
// heading alignment (the default) the root is compared without its heading
// and M1 is turned to M2's heading, so a clip that turns keeps turning
// from loop to loop rather than turning back inside the overlap.
#pragma once

#include <anima/core/constants.hpp>
#include <anima/core/error.hpp>
#include <anima/core/stopwatch.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/dof_view.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/finite_difference.hpp>
#include <anima/rotation/exp_log.hpp>
#include <anima/rotation/slerp.hpp>
#include <anima/rotation/swing_twist.hpp>
#include <anima/motion/frame_distance.hpp>
#include <anima/motion/frame_features.hpp>
#include <anima/motion/speed_limits.hpp>
#include <anima/texture/overlap_search.hpp>
#include <anima/texture/seam_blend.hpp>
#include <anima/texture/seam_cost.hpp>
#include <anima/texture/seam_cut.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace anima {

template <class T>
struct texton_params {
    /// Frames of M1 (the clip's first) and M2 (its last); 2m <= clip frames.
    std::size_t m = 100;
    /// n_overlap: frames where M2 and M1 are both shown; 2 <= overlap <= m.
    std::size_t overlap = 50;
    /// Shortest loop the offset search may choose, in frames (the texton
    /// is F - m + a - b frames long). 0: twice the overlap, or the longest
    /// loop the clip allows (F - overlap) when that is shorter, so that at
    /// most about half of every pass is blended. Without it a short clip
    /// can loop on a part of one stride that is almost all overlap, and the
    /// legs fade between steps the whole time (a 169-frame run looped on
    /// 46 frames, 42 of them blended). At most F - overlap.
    std::size_t min_frames = 0;
    /// The frame distance of the offset search (Eq 2 by default); its
    /// per-DOF weights also weigh the seam costs.
    frame_distance_params<T> distance;
    seam_cut_params<T> cut;
    seam_blend_params blend;
    /// Compare poses whatever way the figure faces, and turn M1 about the
    /// up axis to M2's heading in the overlap: the texton then turns by
    /// heading_turn per loop (a clip that turns keeps turning) instead of
    /// turning back inside the overlap. false: headings are compared and
    /// blended like any rotation.
    bool align_heading = true;
    /// Up axis of the clip; guessed from the skeleton when empty.
    std::optional<signed_axis> up;
};

/// params with m and the overlap shrunk in proportion, when needed, so that
/// they fit a clip of `frames` frames (2m <= frames, overlap >= 2). A clip
/// of fewer than 4 frames is left to make_texton to refuse.
template <class T>
texton_params<T> fit_texton_lengths(texton_params<T> params, std::size_t frames) {
    if (frames < 4 || 2 * params.m <= frames) return params;
    const std::size_t m = frames / 2;
    const double scale = params.m ? static_cast<double>(m) / static_cast<double>(params.m) : 1.0;
    params.overlap = std::clamp<std::size_t>(static_cast<std::size_t>(static_cast<double>(params.overlap) * scale + 0.5), 2, m);
    params.m = m;
    if (params.blend.frames > params.overlap) params.blend.frames = params.overlap;
    return params;
}

/// Seconds spent in each stage.
struct texture_timings {
    double features = 0, search = 0, cut = 0, blend = 0, patch = 0, smoothing = 0, planting = 0, total = 0;
};

template <class T>
struct motion_texton {
    /// The loop: its last frame leads into its first turned by heading_turn.
    clip<T> motion;
    std::size_t m = 0, overlap = 0;
    std::size_t blend_frames = 0;  ///< k of Eq 12 (0: hard cut)
    std::size_t offset_m2 = 0;     ///< a: M2's first overlap frame (clip frame F - m + a)
    std::size_t offset_m1 = 0;     ///< b: M1's first overlap frame (clip frame b)
    std::size_t overlap_start = 0; ///< the texton frame where the overlap begins
    /// Turn about the up axis (radians) that M1 was given to meet M2's
    /// heading: each pass of the loop starts turned by this much from the
    /// last (anima::patch_texton applies it).
    T heading_turn = T(0);
    T search_cost = T(0);          ///< summed frame distance over the chosen overlap
    /// Every window's summed distance: (m - n + 1) x (m - n + 1), indexed (a, b).
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> search_costs;
    /// Rows of the cut: one per 3-column block of `layout` (row r = DOFs
    /// 3r .. 3r+2), with its joint and whether it is a rotation.
    std::vector<std::size_t> row_joint;
    std::vector<bool> row_rotation;
    /// Per row seams (overlap frames, first frame from M1) and costs.
    seam_cut_result<T> cut;
    /// The DOF view the texton was cut in (anima::make_dof_layout of the clip).
    dof_layout<T> layout;
    /// What turns each row's fade of values (Eq 11, 13) into a fade of
    /// velocities, frames x DOFs in the columns of `layout`: inside a fade
    /// the velocity is the alpha-mix of both motions' velocities,
    /// integrated from the fade's ends towards its middle, where one jump is
    /// left (the mismatch that the fade of values spreads over k frames,
    /// and the Poisson stage spreads over the whole texture). For a
    /// rotation the entry is the rotation vector c with q' = q exp(c) (on
    /// the right, so a turn of the whole figure leaves it valid), for a
    /// translation the difference. Zero outside the fades and everywhere
    /// without them.
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> fade_correction;
    /// How fast the clip the texton was cut from moves at most: the legs of
    /// planted feet are kept within it (empty: the texton's own).
    speed_limits<T> source_speeds;
    texture_timings timings;

    std::size_t rows() const noexcept { return row_joint.size(); }
    /// Texton frame where row r switches to M1 (the first frame after its seam).
    std::size_t seam_frame(std::size_t r) const { return overlap_start + cut.seam.at(r); }
    /// Texton frame at the middle of row r's fade (the seam itself without one).
    std::size_t blend_centre(std::size_t r) const {
        if (blend_frames == 0) return seam_frame(r);
        return overlap_start + blend_window_start(cut.seam.at(r), blend_frames, overlap) + blend_frames / 2;
    }
};

namespace detail {

// The 2 pi-equivalent of rotation vector v (same rotation) closest to ref:
// rotation vectors are unique only up to |v| = pi.
template <class T>
Eigen::Matrix<T, 3, 1> nearest_equivalent(const Eigen::Matrix<T, 3, 1>& v, const Eigen::Matrix<T, 3, 1>& ref) {
    const T len = v.norm();
    if (!(len > T(0))) return v;
    const T two_pi = T(2) * pi<T>;
    const Eigen::Matrix<T, 3, 1> axis = v / len;
    const T turns = std::round((axis.dot(ref) - len) / two_pi);
    return turns != T(0) ? Eigen::Matrix<T, 3, 1>(v + turns * two_pi * axis) : v;
}

// Makes each rotation's vectors continuous along the rows (frames) of m.
template <class T>
void unwrap_rotation_vectors(Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& m, const dof_layout<T>& layout) {
    for (std::size_t col = 0; col < layout.size(); col += 3) {
        if (layout.dofs[col].type != dof::kind::rotation) continue;
        const auto c = static_cast<Eigen::Index>(col);
        for (Eigen::Index f = 1; f < m.rows(); ++f)
            m.row(f).segment(c, 3) = nearest_equivalent<T>(m.row(f).segment(c, 3).transpose(),
                                                           m.row(f - 1).segment(c, 3).transpose())
                                         .transpose();
    }
}

/// Pairs of rows to tie: a joint's translation and rotation rows, and the
/// rotation rows of a joint and its nearest ancestor that has one.
template <class T>
std::vector<std::pair<std::size_t, std::size_t>> texton_neighbours(const skeleton<T>& sk,
                                                                   const std::vector<std::size_t>& row_joint,
                                                                   const std::vector<bool>& row_rotation) {
    std::vector<long> rot(sk.size(), -1), tra(sk.size(), -1);
    for (std::size_t r = 0; r < row_joint.size(); ++r) (row_rotation[r] ? rot : tra)[row_joint[r]] = static_cast<long>(r);
    std::vector<std::pair<std::size_t, std::size_t>> out;
    for (std::size_t j = 0; j < sk.size(); ++j) {
        if (rot[j] >= 0 && tra[j] >= 0) out.emplace_back(static_cast<std::size_t>(tra[j]), static_cast<std::size_t>(rot[j]));
        if (rot[j] < 0) continue;
        int p = sk[j].parent;
        while (p >= 0 && rot[static_cast<std::size_t>(p)] < 0) p = sk[static_cast<std::size_t>(p)].parent;
        if (p >= 0) out.emplace_back(static_cast<std::size_t>(rot[static_cast<std::size_t>(p)]), static_cast<std::size_t>(rot[j]));
    }
    return out;
}


/// Throws anima::invalid_argument unless the texton lengths fit the clip.
template <class T>
void check_texton_params(const clip<T>& c, const texton_params<T>& params) {
    const std::string who = "anima::make_texton: ";
    const std::size_t F = c.frames(), m = params.m, n = params.overlap;
    if (c.joints() == 0) throw invalid_argument(who + "the clip has no joints");
    if (n < 2)
        throw invalid_argument(who + "the overlap must be at least 2 frames (its first frame is M2's, its last M1's), got " +
                               std::to_string(n));
    if (n > m)
        throw invalid_argument(who + "the overlap (" + std::to_string(n) + " frames) is longer than m (" +
                               std::to_string(m) + "): it must lie inside M1 and M2");
    if (2 * m > F)
        throw invalid_argument(who + "m = " + std::to_string(m) + " is too large for a clip of " + std::to_string(F) +
                               " frames: M1 and M2 (m frames each) must not share frames, so m <= " +
                               std::to_string(F / 2));
    if (params.blend.frames > n)
        throw invalid_argument(who + "a blend of " + std::to_string(params.blend.frames) +
                               " frames does not fit the overlap of " + std::to_string(n));
    if (params.min_frames > F - n)
        throw invalid_argument(who + "min_frames = " + std::to_string(params.min_frames) +
                               " is longer than the longest loop a clip of " + std::to_string(F) +
                               " frames allows with an overlap of " + std::to_string(n) + " (" +
                               std::to_string(F - n) + ")");
}

/// The least a - b (M2's overlap offset minus M1's) that gives a loop of at
/// least params.min_frames (or its default) frames: the loop is F - m + a - b.
template <class T>
std::ptrdiff_t texton_min_shift(std::size_t F, const texton_params<T>& params) {
    const std::size_t n = params.overlap;
    const std::size_t shortest = params.min_frames ? params.min_frames : std::min(2 * n, F - n);
    return static_cast<std::ptrdiff_t>(shortest) - static_cast<std::ptrdiff_t>(F - params.m);
}

/// The features the overlap search and the seam costs compare, frames x DOFs
/// of `layout`: frame_features (ground position zeroed) with the root's
/// ground velocity added; when `align`, the root's rotation without its
/// heading and the velocity in the heading's frame.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> texton_features(const clip<T>& c, const dof_layout<T>& layout,
                                                                 signed_axis up, bool align) {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    using vec3 = Eigen::Matrix<T, 3, 1>;
    using quat = Eigen::Quaternion<T>;
    const std::size_t F = c.frames();
    const int up_k = static_cast<int>(up.axis);
    frame_feature_params fp;
    fp.up = up;
    matrix x = frame_features(c, fp);
    const bool root_moves = c.skeleton().translation_slot(0) >= 0;
    const vec3 up_vec = axis_vector<T>(up);
    std::vector<quat> heading(align ? F : 0);
    for (std::size_t f = 0; f < heading.size(); ++f) heading[f] = swing_twist(c.rotation(f, 0), up_vec).second;
    for (std::size_t col = 0; col < layout.size(); ++col) {
        const dof& d = layout.dofs[col];
        if (d.joint != 0 || d.component != 0) continue;
        const auto cl = static_cast<Eigen::Index>(col);
        if (d.type == dof::kind::rotation && align)
            for (std::size_t f = 0; f < F; ++f)
                x.row(static_cast<Eigen::Index>(f)).segment(cl, 3) =
                    to_rotation_vector(quat(heading[f].conjugate() * c.rotation(f, 0))).transpose();
        if (d.type != dof::kind::translation || !root_moves) continue;
        matrix root(static_cast<Eigen::Index>(F), 3);
        for (std::size_t f = 0; f < F; ++f) root.row(static_cast<Eigen::Index>(f)) = c.root_position(f).transpose();
        const matrix velocity = time_derivative(root, c.frame_time());
        for (std::size_t f = 0; f < F; ++f) {
            const auto fi = static_cast<Eigen::Index>(f);
            vec3 v = velocity.row(fi).transpose();
            if (align) v = heading[f].conjugate() * v;
            for (int k = 0; k < 3; ++k)
                if (k != up_k) x(fi, cl + k) = v[k];
        }
    }
    return x;
}

/// The turn about `up_vec` that takes M1's heading to M2's: the circular
/// mean of the root's heading differences over the n overlap frames.
template <class T>
T overlap_heading_turn(const clip<T>& c, std::size_t a_first, std::size_t b_first, std::size_t n,
                       const Eigen::Matrix<T, 3, 1>& up_vec) {
    T sin_sum = T(0), cos_sum = T(0);
    for (std::size_t t = 0; t < n; ++t) {
        const T d = twist_angle(c.rotation(a_first + t, 0), up_vec) - twist_angle(c.rotation(b_first + t, 0), up_vec);
        sin_sum += std::sin(d);
        cos_sum += std::cos(d);
    }
    return std::atan2(sin_sum, cos_sum);
}

/// The clip turned by `angle` about `up_vec` (root rotation and position).
template <class T>
clip<T> turned_about_up(const clip<T>& c, T angle, const Eigen::Matrix<T, 3, 1>& up_vec) {
    clip<T> out = c;
    const Eigen::Quaternion<T> turn(Eigen::AngleAxis<T>(angle, up_vec));
    const bool root_moves = c.skeleton().translation_slot(0) >= 0;
    for (std::size_t f = 0; f < c.frames(); ++f) {
        out.set_rotation(f, 0, turn * c.rotation(f, 0));
        if (root_moves) out.set_root_position(f, turn * c.root_position(f));
    }
    return out;
}

/// Writes the texton's frames into out.motion: M2 up to the overlap, the
/// faded overlap (alpha: rows x overlap frames, 1 = M2's side a, 0 = M1's
/// side b of `cb`), then M1; the root's ground path is the sum of the steps.
template <class T>
void assemble_texton(motion_texton<T>& out, const clip<T>& c, const clip<T>& cb,
                     const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& alpha, std::size_t a_first,
                     std::size_t b_first, int up_k) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    const auto& sk = c.skeleton();
    const std::size_t F = c.frames(), m = out.m, n = out.overlap;
    const bool root_moves = sk.translation_slot(0) >= 0;
    std::vector<long> rot_row(sk.size(), -1), tra_row(sk.size(), -1);
    for (std::size_t r = 0; r < out.rows(); ++r)
        (out.row_rotation[r] ? rot_row : tra_row)[out.row_joint[r]] = static_cast<long>(r);
    const std::size_t length = F - m + out.offset_m2 - out.offset_m1;
    out.motion = clip<T>(sk, length, c.frame_time());
    // Source clip and frame of a texton frame outside the overlap.
    const auto source = [&](std::size_t k) -> std::pair<const clip<T>*, std::size_t> {
        if (k < out.overlap_start) return {&c, m + k};
        return {&cb, out.offset_m1 + n + (k - out.overlap_start - n)};
    };
    const auto ground = [up_k](vec3 v) {
        v[up_k] = T(0);
        return v;
    };
    // The step a clip's root made into frame f (frame 0: out of it).
    const auto step = [&](const clip<T>& from, std::size_t f) -> vec3 {
        return f > 0 ? ground(from.root_position(f) - from.root_position(f - 1))
                     : ground(from.root_position(1) - from.root_position(0));
    };
    vec3 position = root_moves ? ground(c.root_position(m)) : vec3::Zero();
    for (std::size_t k = 0; k < length; ++k) {
        const bool in_overlap = k >= out.overlap_start && k < out.overlap_start + n;
        vec3 root_step = vec3::Zero();
        if (!in_overlap) {
            const auto [from, f] = source(k);
            for (std::size_t j = 0; j < sk.size(); ++j) {
                out.motion.set_rotation(k, j, from->rotation(f, j));
                if (sk.translation_slot(j) >= 0) out.motion.set_translation(k, j, from->translation(f, j));
            }
            if (root_moves) root_step = step(*from, f);
        } else {
            const std::size_t t = k - out.overlap_start;
            const std::size_t fa = a_first + t, fb = b_first + t;
            for (std::size_t j = 0; j < sk.size(); ++j) {
                const auto& qa = c.rotation(fa, j);
                const auto& qb = cb.rotation(fb, j);
                if (rot_row[j] >= 0)
                    out.motion.set_rotation(k, j, slerp(qb, qa, alpha(rot_row[j], static_cast<Eigen::Index>(t))));
                else
                    out.motion.set_rotation(k, j, qa);
                if (sk.translation_slot(j) < 0) continue;
                const T w = tra_row[j] >= 0 ? alpha(tra_row[j], static_cast<Eigen::Index>(t)) : T(1);
                out.motion.set_translation(k, j, w * c.translation(fa, j) + (T(1) - w) * cb.translation(fb, j));
                if (j == 0) root_step = w * step(c, fa) + (T(1) - w) * step(cb, fb);
            }
        }
        if (!root_moves) continue;
        if (k > 0) position += root_step;
        vec3 p = position;
        p[up_k] = out.motion.root_position(k)[up_k];
        out.motion.set_root_position(k, p);
    }
}

/// out.fade_correction (see there), built in the DOF view from the two
/// sources of the overlap: `c` (side a) and `cb` (side b, c turned or c).
template <class T>
void fade_corrections(motion_texton<T>& out, const clip<T>& c, const clip<T>* turned,
                      const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& alpha, std::size_t a_first_frame,
                      std::size_t b_first_frame, int up_k) {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    using vec3 = Eigen::Matrix<T, 3, 1>;
    using quat = Eigen::Quaternion<T>;
    const std::size_t n = out.overlap;
    const auto a_first = static_cast<Eigen::Index>(a_first_frame), b_first = static_cast<Eigen::Index>(b_first_frame);
    const matrix raw_a = to_dof_matrix(c, out.layout);
    const matrix raw_b = turned ? to_dof_matrix(*turned, out.layout) : raw_a;
    matrix y = to_dof_matrix(out.motion, out.layout);
    unwrap_rotation_vectors(y, out.layout);
    matrix z = y;
    out.fade_correction = matrix::Zero(y.rows(), y.cols());
    const auto step_of = [&](const matrix& raw, Eigen::Index f, Eigen::Index col, bool rotation) -> vec3 {
        const vec3 v0 = raw.row(f - 1).segment(col, 3).transpose(), v1 = raw.row(f).segment(col, 3).transpose();
        return rotation ? vec3(nearest_equivalent(v1, v0) - v0) : vec3(v1 - v0);
    };
    const std::size_t k_len = out.blend_frames;
    for (std::size_t r = 0; r < out.rows() && k_len > 0; ++r) {
        const auto col = static_cast<Eigen::Index>(3 * r);
        const bool rotation = out.row_rotation[r];
        const std::size_t w = blend_window_start(out.cut.seam[r], k_len, n);  // overlap frame
        const std::size_t centre = w + k_len / 2;
        // Velocity of the fade into overlap frame t (from t - 1).
        const auto fade_step = [&](std::size_t t) -> vec3 {
            // Into the overlap's first frame: from a frame of A (alpha = 1).
            if (t == 0) return step_of(raw_a, a_first, col, rotation);
            const T w_a = (alpha(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(t)) +
                           alpha(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(t - 1))) / T(2);
            return w_a * step_of(raw_a, a_first + static_cast<Eigen::Index>(t), col, rotation) +
                   (T(1) - w_a) * step_of(raw_b, b_first + static_cast<Eigen::Index>(t), col, rotation);
        };
        const auto at = [&](std::size_t t) { return static_cast<Eigen::Index>(out.overlap_start + t); };
        // Forward from the last frame before the fade (its first frame when
        // the texton starts there), backwards from the fade's last frame.
        const bool before = w > 0 || out.overlap_start > 0;
        for (std::size_t t = before ? w : w + 1; t < centre; ++t)
            z.row(at(t)).segment(col, 3) = z.row(at(t) - 1).segment(col, 3) + fade_step(t).transpose();
        for (std::size_t t = w + k_len - 1; t-- > centre;)
            z.row(at(t)).segment(col, 3) = z.row(at(t) + 1).segment(col, 3) - fade_step(t + 1).transpose();
        for (std::size_t t = w; t + 1 < w + k_len; ++t) {
            const vec3 from = y.row(at(t)).segment(col, 3).transpose(), to = z.row(at(t)).segment(col, 3).transpose();
            out.fade_correction.row(at(t)).segment(col, 3) =
                (rotation ? vec3(to_rotation_vector(quat(from_rotation_vector<quat>(from).conjugate() *
                                                         from_rotation_vector<quat>(to))))
                          : vec3(to - from))
                    .transpose();
        }
    }
    // The root's ground path is a sum of steps, not a DOF to correct.
    for (std::size_t col = 0; col < out.layout.size(); ++col) {
        const dof& d = out.layout.dofs[col];
        if (d.joint == 0 && d.type == dof::kind::translation && d.component != up_k)
            out.fade_correction.col(static_cast<Eigen::Index>(col)).setZero();
    }
}

}  // namespace detail

/// Builds the texton of a clip. Throws anima::invalid_argument for a clip
/// without joints, an overlap below 2 or above m, or m above half the
/// clip's frames (M1 and M2 must not share frames; fit_texton_lengths
/// shrinks m for short clips), or bad distance or cut parameters.
template <class T>
motion_texton<T> make_texton(const clip<T>& c, const texton_params<T>& params = {}) {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    detail::check_texton_params(c, params);
    const std::size_t F = c.frames(), m = params.m, n = params.overlap;
    stopwatch clock;
    motion_texton<T> out;
    out.m = m;
    out.overlap = n;
    const auto& sk = c.skeleton();
    const signed_axis up = params.up ? *params.up : guess_up_axis(sk).up;
    const Eigen::Matrix<T, 3, 1> up_vec = axis_vector<T>(up);
    const bool align = params.align_heading && sk.has_rotation_channels(0);

    // Features, and the rows of the cut: one per 3-column block of the layout.
    out.layout = make_dof_layout(c);
    const matrix x = detail::texton_features(c, out.layout, up, align);
    for (std::size_t col = 0; col < out.layout.size(); col += 3) {
        out.row_joint.push_back(out.layout.dofs[col].joint);
        out.row_rotation.push_back(out.layout.dofs[col].type == dof::kind::rotation);
    }
    const auto distance = make_frame_distance(x, c.frame_time(), params.distance);
    const Eigen::Matrix<T, Eigen::Dynamic, 1> weights =
        distance.metric == frame_metric::mahalanobis ? distance.precision
                                                     : Eigen::Matrix<T, Eigen::Dynamic, 1>::Ones(x.cols());
    const auto M = static_cast<Eigen::Index>(m), N = static_cast<Eigen::Index>(n);
    const Eigen::Index m2_first = static_cast<Eigen::Index>(F) - M;
    out.timings.features = clock.lap();

    // The (i, j) loop: where M2 and M1 overlap best; M1's side turned to M2's heading.
    const auto search = search_overlap(frame_pair_costs(x.middleRows(m2_first, M), x.topRows(M), distance), n,
                                       detail::texton_min_shift(F, params));
    out.offset_m2 = search.first_a;
    out.offset_m1 = search.first_b;
    out.search_cost = search.cost;
    out.search_costs = search.costs;
    const std::size_t a_first = static_cast<std::size_t>(m2_first) + out.offset_m2, b_first = out.offset_m1;
    if (align) out.heading_turn = detail::overlap_heading_turn(c, a_first, b_first, n, up_vec);
    std::optional<clip<T>> turned;
    if (out.heading_turn != T(0)) turned = detail::turned_about_up(c, out.heading_turn, up_vec);
    const clip<T>& cb = turned ? *turned : c;
    out.timings.search = clock.lap();

    // The per-row seams.
    const seam_cost<T> cost(x.middleRows(static_cast<Eigen::Index>(a_first), N),
                            x.middleRows(static_cast<Eigen::Index>(b_first), N), 3, weights, params.cut.cost);
    out.cut = cut_seams(cost, detail::texton_neighbours(sk, out.row_joint, out.row_rotation), params.cut.neighbour_weight);
    out.timings.cut = clock.lap();

    // Assembly with the fades of values, then of velocities.
    out.blend_frames = blend_frames(params.blend, n);
    const matrix alpha = blend_weights<T>(out.cut.seam, n, out.blend_frames);
    out.overlap_start = F - 2 * m + out.offset_m2;
    const int up_k = static_cast<int>(up.axis);
    detail::assemble_texton(out, c, cb, alpha, a_first, b_first, up_k);
    detail::fade_corrections(out, c, turned ? &*turned : nullptr, alpha, a_first, b_first, up_k);
    out.source_speeds = clip_speed_limits(c);
    out.timings.blend = clock.lap();
    out.timings.total = out.timings.features + out.timings.search + out.timings.cut + out.timings.blend;
    return out;
}

}  // namespace anima
