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
#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
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
#include <limits>
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
    /// 46 frames, 42 of them blended). At most F - overlap. A loop through
    /// several clips is at least one overlap per clip long; a min_frames
    /// it does not reach is an error.
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

/// The lengths when m and the overlap may each be given (kept as they are:
/// make_texton refuses ones that do not fit) or left to params' defaults
/// (std::nullopt), for clips of at least `frames` frames: without m,
/// fit_texton_lengths shrinks params' m and its overlap (unless given) to
/// fit; a given m without an overlap gets m / 2, at least 2 and at most
/// params.overlap (50 for m = 100, as in the paper). Defaults fitted to a
/// short clip, values a user asked for left alone. Throws
/// anima::invalid_argument for a given m or overlap under 2.
template <class T>
texton_params<T> choose_texton_lengths(texton_params<T> params, std::size_t frames, std::optional<std::size_t> m,
                                       std::optional<std::size_t> overlap) {
    if (m && *m < 2)
        throw invalid_argument("anima::choose_texton_lengths: m = " + std::to_string(*m) + " is under 2 frames");
    if (overlap && *overlap < 2)
        throw invalid_argument("anima::choose_texton_lengths: overlap = " + std::to_string(*overlap) +
                               " is under 2 frames");
    if (m) {
        params.overlap = overlap ? *overlap : std::min(params.overlap, std::max<std::size_t>(*m / 2, 2));
        params.m = *m;
        return params;
    }
    if (overlap) params.overlap = *overlap;
    params = fit_texton_lengths(params, frames);
    if (overlap) params.overlap = *overlap;
    return params;
}

/// Seconds spent in each stage.
struct texture_timings {
    double features = 0, search = 0, cut = 0, blend = 0, patch = 0, smoothing = 0, planting = 0, total = 0;
};

namespace detail {
// Texton frame at the middle of a row's fade (the seam itself without one).
inline std::size_t fade_centre(std::size_t overlap_start, std::size_t seam, std::size_t blend_frames,
                               std::size_t overlap) {
    if (blend_frames == 0) return overlap_start + seam;
    return overlap_start + blend_window_start(seam, blend_frames, overlap) + blend_frames / 2;
}
}  // namespace detail

/// One seam of a texton of several clips: the last m frames of clip `from`
/// laid over the first m frames of clip `to`, found and cut as the
/// texton's own seam is.
template <class T>
struct texton_join {
    std::size_t from = 0, to = 0;  ///< clip indices in the order given (to = from + 1, or 0 for the last)
    std::size_t offset_a = 0;      ///< first overlap frame in from's last m (clip frame F - m + offset_a)
    std::size_t offset_b = 0;      ///< first overlap frame in to's first m (clip frame offset_b)
    std::size_t overlap_start = 0; ///< the texton frame where the overlap begins
    std::size_t overlap = 0, blend_frames = 0;
    /// Turn about the up axis (radians) that `to` was given, beyond what
    /// `from` was, to meet from's heading.
    T heading_turn = T(0);
    T search_cost = T(0);          ///< summed frame distance over the chosen overlap
    seam_cut_result<T> cut;        ///< per-row seams and costs, as motion_texton::cut

    std::size_t seam_frame(std::size_t r) const { return overlap_start + cut.seam.at(r); }
    std::size_t blend_centre(std::size_t r) const {
        return detail::fade_centre(overlap_start, cut.seam.at(r), blend_frames, overlap);
    }
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
    /// The DOF view the texton was cut in (anima::make_dof_layout of the
    /// clip; of several clips, their common mean rotations).
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

    /// A texton of several clips: the seams between them (clip i's M2 over
    /// clip i+1's M1), in loop order. The fields above then describe the
    /// seam that closes the loop (the last clip's M2 over the first clip's
    /// M1), and heading_turn is the turn of the whole loop. Empty for one clip.
    std::vector<texton_join<T>> joins;
    std::size_t clips = 1;  ///< clips the loop passes through

    std::size_t rows() const noexcept { return row_joint.size(); }
    /// Texton frame where row r switches to M1 (the first frame after its seam).
    std::size_t seam_frame(std::size_t r) const { return overlap_start + cut.seam.at(r); }
    /// Texton frame at the middle of row r's fade (the seam itself without one).
    std::size_t blend_centre(std::size_t r) const {
        return detail::fade_centre(overlap_start, cut.seam.at(r), blend_frames, overlap);
    }
    /// Every seam of the loop in texton order: the joins, then the closing
    /// seam. Their heading turns add up to heading_turn.
    std::vector<texton_join<T>> seams() const {
        std::vector<texton_join<T>> out = joins;
        texton_join<T> closing;
        closing.from = clips - 1;
        closing.offset_a = offset_m2;
        closing.offset_b = offset_m1;
        closing.overlap_start = overlap_start;
        closing.overlap = overlap;
        closing.blend_frames = blend_frames;
        closing.heading_turn = heading_turn;
        for (const auto& j : joins) closing.heading_turn -= j.heading_turn;
        closing.search_cost = search_cost;
        closing.cut = cut;
        out.push_back(std::move(closing));
        return out;
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


/// Throws anima::invalid_argument unless the texton lengths fit the clip;
/// `who` starts each message. min_frames is checked here for a loop of
/// one clip only (a loop through several is checked once it is made).
template <class T>
void check_texton_params(const clip<T>& c, const texton_params<T>& params, const std::string& who, bool one_clip) {
    const std::size_t F = c.frames(), m = params.m, n = params.overlap;
    if (c.joints() == 0) throw invalid_argument(who + "the clip has no joints");
    if (n < 2)
        throw invalid_argument(who + "the overlap must be at least 2 frames (its first frame is M2's, its last M1's), got " +
                               std::to_string(n));
    if (n > m)
        throw invalid_argument(who + "the overlap (" + std::to_string(n) + " frames) is longer than m (" +
                               std::to_string(m) + "): it must lie inside M1 and M2");
    if (m > F / 2)  // 2 * m > F, without 2 * m wrapping to a small number
        throw invalid_argument(who + "m = " + std::to_string(m) + " is too large for a clip of " + std::to_string(F) +
                               " frames: M1 and M2 (m frames each) must not share frames, so m <= " +
                               std::to_string(F / 2));
    if (params.blend.frames > n)
        throw invalid_argument(who + "a blend of " + std::to_string(params.blend.frames) +
                               " frames does not fit the overlap of " + std::to_string(n));
    if (one_clip && params.min_frames > F - n)
        throw invalid_argument(who + "min_frames = " + std::to_string(params.min_frames) +
                               " is longer than the longest loop a clip of " + std::to_string(F) +
                               " frames allows with an overlap of " + std::to_string(n) + " (" +
                               std::to_string(F - n) + ")");
}

/// Throws anima::invalid_argument, naming the function and the clip, for no
/// clips, a clip the texton lengths do not fit, or a clip whose hierarchy
/// or frame time is not the first clip's.
template <class T>
void check_texton_clips(const std::vector<const clip<T>*>& clips, const texton_params<T>& params,
                        const char* function = "anima::make_texton") {
    const std::string who = std::string(function) + ": ";
    if (clips.empty()) throw invalid_argument(who + "no clips to make a texton of");
    const bool one = clips.size() == 1;
    for (std::size_t i = 0; i < clips.size(); ++i) {
        const std::string where = one ? who : who + "clip " + std::to_string(i) + ": ";
        check_texton_params(*clips[i], params, where, one);
        if (i == 0) continue;
        try {
            check_same_hierarchy(clips[0]->skeleton(), clips[i]->skeleton());
        } catch (const invalid_argument& e) {
            throw invalid_argument(where + "its skeleton is not clip 0's (" + e.what() + ")");
        }
        const T dt0 = clips[0]->frame_time(), dt = clips[i]->frame_time();
        if (std::abs(dt - dt0) > T(1e-4) * dt0)
            throw invalid_argument(where + "its frame time (" + detail::argument_text(dt) +
                                   " s) is not clip 0's (" + detail::argument_text(dt0) +
                                   " s); resample it first");
    }
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
/// of `layout` (rotations from its references): frame_features (ground
/// position zeroed) with the root's
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
    matrix x = frame_features(c, layout, fp);
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

/// The turn about `up_vec` that takes M1's heading (clip b's) to M2's (clip
/// a's): the circular mean of the root's heading differences over the n
/// overlap frames.
template <class T>
T overlap_heading_turn(const clip<T>& a, std::size_t a_first, const clip<T>& b, std::size_t b_first, std::size_t n,
                       const Eigen::Matrix<T, 3, 1>& up_vec) {
    T sin_sum = T(0), cos_sum = T(0);
    for (std::size_t t = 0; t < n; ++t) {
        const T d = twist_angle(a.rotation(a_first + t, 0), up_vec) - twist_angle(b.rotation(b_first + t, 0), up_vec);
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

/// A stretch of the texton: frames a_first.. of clip `a`, or, where `alpha`
/// is set (rows x length, 1 = side a), an overlap faded from a's frames
/// a_first.. to b's frames b_first..
template <class T>
struct texton_piece {
    const clip<T>* a = nullptr;
    std::size_t a_first = 0;
    const clip<T>* b = nullptr;
    std::size_t b_first = 0;
    const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>* alpha = nullptr;
    std::size_t length = 0;
};

/// Writes the pieces end to end into out.motion; the root's ground path is
/// the sum of the steps each piece's frames took in their clips.
template <class T>
void assemble_texton(motion_texton<T>& out, const std::vector<texton_piece<T>>& pieces, int up_k) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    const clip<T>& first = *pieces.front().a;
    const auto& sk = first.skeleton();
    const bool root_moves = sk.translation_slot(0) >= 0;
    std::vector<long> rot_row(sk.size(), -1), tra_row(sk.size(), -1);
    for (std::size_t r = 0; r < out.rows(); ++r)
        (out.row_rotation[r] ? rot_row : tra_row)[out.row_joint[r]] = static_cast<long>(r);
    std::size_t length = 0;
    for (const auto& p : pieces) length += p.length;
    out.motion = clip<T>(sk, length, first.frame_time());
    const auto ground = [up_k](vec3 v) {
        v[up_k] = T(0);
        return v;
    };
    // The step a clip's root made into frame f (frame 0: out of it).
    const auto step = [&](const clip<T>& from, std::size_t f) -> vec3 {
        return f > 0 ? ground(from.root_position(f) - from.root_position(f - 1))
                     : ground(from.root_position(1) - from.root_position(0));
    };
    vec3 position = root_moves ? ground(first.root_position(pieces.front().a_first)) : vec3::Zero();
    std::size_t k = 0;
    for (const auto& p : pieces)
        for (std::size_t t = 0; t < p.length; ++t, ++k) {
            const clip<T>& a = *p.a;
            const std::size_t fa = p.a_first + t;
            vec3 root_step = vec3::Zero();
            if (!p.alpha) {
                for (std::size_t j = 0; j < sk.size(); ++j) {
                    out.motion.set_rotation(k, j, a.rotation(fa, j));
                    if (sk.translation_slot(j) >= 0) out.motion.set_translation(k, j, a.translation(fa, j));
                }
                if (root_moves) root_step = step(a, fa);
            } else {
                const clip<T>& b = *p.b;
                const std::size_t fb = p.b_first + t;
                const auto col = static_cast<Eigen::Index>(t);
                for (std::size_t j = 0; j < sk.size(); ++j) {
                    const auto& qa = a.rotation(fa, j);
                    if (rot_row[j] >= 0)
                        out.motion.set_rotation(k, j, slerp(b.rotation(fb, j), qa, (*p.alpha)(rot_row[j], col)));
                    else
                        out.motion.set_rotation(k, j, qa);
                    if (sk.translation_slot(j) < 0) continue;
                    const T w = tra_row[j] >= 0 ? (*p.alpha)(tra_row[j], col) : T(1);
                    out.motion.set_translation(k, j, w * a.translation(fa, j) + (T(1) - w) * b.translation(fb, j));
                    if (j == 0) root_step = w * step(a, fa) + (T(1) - w) * step(b, fb);
                }
            }
            if (!root_moves) continue;
            if (k > 0) position += root_step;
            vec3 pos = position;
            pos[up_k] = out.motion.root_position(k)[up_k];
            out.motion.set_root_position(k, pos);
        }
}

/// One seam as the fade corrections see it: the DOF matrices of its two
/// sides (side b turned as it is shown), where its overlap starts in them
/// and in the texton, its per-row seams and fade weights.
template <class T>
struct fade_seam {
    const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>* raw_a = nullptr;
    const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>* raw_b = nullptr;
    std::size_t a_first = 0, b_first = 0, overlap_start = 0;
    const std::vector<std::size_t>* seam = nullptr;
    const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>* alpha = nullptr;
};

/// out.fade_correction (see there), built in the DOF view from the two
/// sides of every seam.
template <class T>
void fade_corrections(motion_texton<T>& out, const std::vector<fade_seam<T>>& seams, int up_k) {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    using vec3 = Eigen::Matrix<T, 3, 1>;
    using quat = Eigen::Quaternion<T>;
    const std::size_t n = out.overlap;
    matrix y = to_dof_matrix(out.motion, out.layout);
    unwrap_rotation_vectors(y, out.layout);
    matrix z = y;
    out.fade_correction = matrix::Zero(y.rows(), y.cols());
    const auto step_of = [&](const matrix& raw, Eigen::Index f, Eigen::Index col, bool rotation) -> vec3 {
        const vec3 v0 = raw.row(f - 1).segment(col, 3).transpose(), v1 = raw.row(f).segment(col, 3).transpose();
        return rotation ? vec3(nearest_equivalent(v1, v0) - v0) : vec3(v1 - v0);
    };
    const std::size_t k_len = out.blend_frames;
    for (const fade_seam<T>& s : seams)
        for (std::size_t r = 0; r < out.rows() && k_len > 0; ++r) {
            const auto col = static_cast<Eigen::Index>(3 * r);
            const bool rotation = out.row_rotation[r];
            const auto a_first = static_cast<Eigen::Index>(s.a_first), b_first = static_cast<Eigen::Index>(s.b_first);
            const matrix& alpha = *s.alpha;
            const std::size_t w = blend_window_start((*s.seam)[r], k_len, n);  // overlap frame
            const std::size_t centre = w + k_len / 2;
            // Velocity of the fade into overlap frame t (from t - 1).
            const auto fade_step = [&](std::size_t t) -> vec3 {
                // Into the overlap's first frame: from a frame of side a (alpha = 1).
                if (t == 0) return step_of(*s.raw_a, a_first, col, rotation);
                const T w_a = (alpha(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(t)) +
                               alpha(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(t - 1))) / T(2);
                return w_a * step_of(*s.raw_a, a_first + static_cast<Eigen::Index>(t), col, rotation) +
                       (T(1) - w_a) * step_of(*s.raw_b, b_first + static_cast<Eigen::Index>(t), col, rotation);
            };
            const auto at = [&](std::size_t t) { return static_cast<Eigen::Index>(s.overlap_start + t); };
            // Forward from the last frame before the fade (its first frame when
            // the texton starts there), backwards from the fade's last frame.
            const bool before = w > 0 || s.overlap_start > 0;
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

namespace detail {

/// Where seam i of the loop lies before it is cut: clip i's frames
/// a_first.. over the next clip's frames b_first.., and the turn the next
/// clip needs to meet clip i's heading there.
template <class T>
struct texton_seam_place {
    overlap_search_result<T> search;
    std::size_t a_first = 0, b_first = 0;
    T turn = T(0);
};

/// Searches every junction of the loop (clip i's M2 over clip i+1's M1)
/// for its overlap of least summed distance, and its heading turn.
template <class T, class Distance>
std::vector<texton_seam_place<T>> place_texton_seams(
    const std::vector<const clip<T>*>& clips, const std::vector<Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>>& x,
    const Distance& distance, const texton_params<T>& params, bool align, const Eigen::Matrix<T, 3, 1>& up_vec) {
    const std::size_t K = clips.size(), m = params.m, n = params.overlap;
    const auto M = static_cast<Eigen::Index>(m);
    std::vector<texton_seam_place<T>> place(K);
    for (std::size_t i = 0; i < K; ++i) {
        const std::size_t next = (i + 1) % K, F = clips[i]->frames();
        // One clip: a loop at least min_frames long; several: every loop is.
        const std::ptrdiff_t min_shift =
            K == 1 ? texton_min_shift(F, params) : std::numeric_limits<std::ptrdiff_t>::min();
        place[i].search = search_overlap(frame_pair_costs(x[i].bottomRows(M), x[next].topRows(M), distance), n, min_shift);
        place[i].a_first = F - m + place[i].search.first_a;
        place[i].b_first = place[i].search.first_b;
        if (align)
            place[i].turn = overlap_heading_turn(*clips[i], place[i].a_first, *clips[next], place[i].b_first, n, up_vec);
    }
    return place;
}

/// What the search and the cut compare, for clips that passed
/// check_texton_clips: one DOF layout for every clip (rotations from their
/// common mean, so that the features of different clips compare), each
/// clip's texton_features, and the frame distance with Eq 2's variances
/// pooled over the clips.
template <class T>
struct texton_inputs {
    signed_axis up;
    bool align = false;
    dof_layout<T> layout;
    std::vector<Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>> x;
    frame_distance<T> distance;
};

template <class T>
texton_inputs<T> texton_inputs_of(const std::vector<const clip<T>*>& clips, const texton_params<T>& params) {
    texton_inputs<T> in;
    const auto& sk = clips.front()->skeleton();
    in.up = params.up ? *params.up : guess_up_axis(sk).up;
    in.align = params.align_heading && sk.has_rotation_channels(0);
    in.layout = dof_layout_of(clips, dof_reference::mean);
    for (const clip<T>* c : clips) in.x.push_back(texton_features(*c, in.layout, in.up, in.align));
    in.distance = make_frame_distance(in.x, clips.front()->frame_time(), params.distance);
    return in;
}

/// The seams into `out`: the last (the one that closes the loop) in its
/// own fields, the others as joins.
template <class T>
void record_texton_seams(motion_texton<T>& out, const std::vector<texton_seam_place<T>>& place,
                         std::vector<seam_cut_result<T>> cuts, const std::vector<std::size_t>& starts) {
    const std::size_t K = place.size();
    for (std::size_t i = 0; i + 1 < K; ++i) {
        texton_join<T> join;
        join.from = i;
        join.to = i + 1;
        join.offset_a = place[i].search.first_a;
        join.offset_b = place[i].search.first_b;
        join.overlap_start = starts[i];
        join.overlap = out.overlap;
        join.blend_frames = out.blend_frames;
        join.heading_turn = place[i].turn;
        join.search_cost = place[i].search.cost;
        join.cut = std::move(cuts[i]);
        out.joins.push_back(std::move(join));
    }
    const auto& last = place.back();
    out.offset_m2 = last.search.first_a;
    out.offset_m1 = last.search.first_b;
    out.search_cost = last.search.cost;
    out.search_costs = last.search.costs;
    out.overlap_start = starts.back();
    out.cut = std::move(cuts.back());
}

/// The texton of a loop through `clips` (one clip: the paper's texton).
template <class T>
motion_texton<T> make_texton_of(const std::vector<const clip<T>*>& clips, const texton_params<T>& params) {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    check_texton_clips(clips, params);
    const std::size_t K = clips.size(), m = params.m, n = params.overlap;
    stopwatch clock;
    motion_texton<T> out;
    out.m = m;
    out.overlap = n;
    out.clips = K;
    const clip<T>& c0 = *clips[0];
    const auto& sk = c0.skeleton();
    // Features, and the rows of the cut: one per 3-column block of the layout.
    texton_inputs<T> in = texton_inputs_of(clips, params);
    const Eigen::Matrix<T, 3, 1> up_vec = axis_vector<T>(in.up);
    const int up_k = static_cast<int>(in.up.axis);
    const bool align = in.align;
    const std::vector<matrix>& x = in.x;
    const auto& distance = in.distance;
    out.layout = std::move(in.layout);
    for (std::size_t col = 0; col < out.layout.size(); col += 3) {
        out.row_joint.push_back(out.layout.dofs[col].joint);
        out.row_rotation.push_back(out.layout.dofs[col].type == dof::kind::rotation);
    }
    const Eigen::Matrix<T, Eigen::Dynamic, 1> weights =
        distance.metric == frame_metric::mahalanobis ? distance.precision
                                                     : Eigen::Matrix<T, Eigen::Dynamic, 1>::Ones(x[0].cols());
    out.timings.features = clock.lap();

    // The seams' offsets; side[i] is clip i as shown, turned by the seams
    // before it, and side[K] clip 0 again after the last seam.
    const auto place = place_texton_seams(clips, x, distance, params, align, up_vec);
    std::vector<std::optional<clip<T>>> turned(K + 1);
    std::vector<const clip<T>*> side(K + 1);
    for (std::size_t i = 0; i <= K; ++i) {
        if (i > 0) out.heading_turn += place[i - 1].turn;
        if (out.heading_turn != T(0)) turned[i] = turned_about_up(*clips[i % K], out.heading_turn, up_vec);
        side[i] = turned[i] ? &*turned[i] : clips[i % K];
    }
    out.timings.search = clock.lap();

    // The per-row seams.
    const auto neighbours = texton_neighbours(sk, out.row_joint, out.row_rotation);
    const auto N = static_cast<Eigen::Index>(n);
    std::vector<seam_cut_result<T>> cuts;
    for (std::size_t i = 0; i < K; ++i) {
        const seam_cost<T> cost(x[i].middleRows(static_cast<Eigen::Index>(place[i].a_first), N),
                                x[(i + 1) % K].middleRows(static_cast<Eigen::Index>(place[i].b_first), N), 3, weights,
                                params.cut.cost);
        cuts.push_back(cut_seams(cost, neighbours, params.cut.neighbour_weight));
    }
    out.timings.cut = clock.lap();

    // Assembly with the fades of values, then of velocities.
    out.blend_frames = blend_frames(params.blend, n);
    std::vector<matrix> alpha;
    for (const auto& cut : cuts) alpha.push_back(blend_weights<T>(cut.seam, n, out.blend_frames));
    std::vector<texton_piece<T>> pieces{{side[0], m, nullptr, 0, nullptr, place[0].a_first - m}};
    std::vector<std::size_t> starts(K);
    std::size_t length = pieces[0].length;
    for (std::size_t i = 0; i < K; ++i) {
        starts[i] = length;
        pieces.push_back({side[i], place[i].a_first, side[i + 1], place[i].b_first, &alpha[i], n});
        const std::size_t from = place[i].b_first + n, to = i + 1 < K ? place[i + 1].a_first : m;
        pieces.push_back({side[i + 1], from, nullptr, 0, nullptr, to - from});
        length += n + to - from;
    }
    if (length < params.min_frames)
        throw invalid_argument("anima::make_texton: the loop through the " + std::to_string(K) + " clips is " +
                               std::to_string(length) + " frames, shorter than min_frames = " +
                               std::to_string(params.min_frames));
    assemble_texton(out, pieces, up_k);
    std::vector<matrix> raws;
    raws.reserve(K + 1);
    std::vector<const matrix*> raw(K + 1);
    for (std::size_t i = 0; i <= K; ++i) {
        if (i == K && side[K] == side[0]) {
            raw[K] = raw[0];
            continue;
        }
        raws.push_back(to_dof_matrix(*side[i], out.layout));
        raw[i] = &raws.back();
    }
    std::vector<fade_seam<T>> fades;
    for (std::size_t i = 0; i < K; ++i)
        fades.push_back({raw[i], raw[i + 1], place[i].a_first, place[i].b_first, starts[i], &cuts[i].seam, &alpha[i]});
    fade_corrections(out, fades, up_k);
    record_texton_seams(out, place, std::move(cuts), starts);
    out.source_speeds = clip_speed_limits(c0);
    for (std::size_t i = 1; i < K; ++i) {
        const auto s = clip_speed_limits(*clips[i]);
        for (std::size_t j = 0; j < s.joint.size(); ++j) out.source_speeds.joint[j] = std::max(out.source_speeds.joint[j], s.joint[j]);
        out.source_speeds.root = std::max(out.source_speeds.root, s.root);
    }
    out.timings.blend = clock.lap();
    out.timings.total = out.timings.features + out.timings.search + out.timings.cut + out.timings.blend;
    return out;
}

}  // namespace detail

/// Builds the texton of a clip. Throws anima::invalid_argument for a clip
/// without joints, an overlap below 2 or above m, or m above half the
/// clip's frames (M1 and M2 must not share frames; fit_texton_lengths
/// shrinks m for short clips), or bad distance or cut parameters.
template <class T>
motion_texton<T> make_texton(const clip<T>& c, const texton_params<T>& params = {}) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    return detail::make_texton_of(std::vector<const clip<T>*>{&c}, params);
}

/// Builds a texton that loops through several clips of one skeleton, in
/// the order given: clip i's M2 laid over clip i+1's M1 and the last
/// clip's over the first's, every seam found, cut and faded as the one of a
/// single clip (see the top of this file); m and the overlap are the same
/// for every clip. Throws anima::invalid_argument, naming the clip, for no
/// clips, clips whose hierarchies (joint names, parents, position
/// channels) or frame times differ from the first's, and everything the
/// texton of each clip alone would refuse. The texton has the first clip's
/// skeleton: its bone lengths, whatever the other clips' are.
template <class T>
motion_texton<T> make_texton(const std::vector<clip<T>>& clips, const texton_params<T>& params = {}) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    std::vector<const clip<T>*> pointers;
    for (const clip<T>& c : clips) pointers.push_back(&c);
    return detail::make_texton_of(pointers, params);
}

}  // namespace anima
