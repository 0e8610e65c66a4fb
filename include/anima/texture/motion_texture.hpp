// A long motion texture: textons patched end to end to any length (Eq 10),
// optionally mixed with symmetric playback, then Poisson-smoothed (Eq 14).
//
//   auto tex = anima::make_motion_texture(walk, 1700);   // 1700 frames
//   tex.motion;        // the clip
//   tex.texton.cut;    // per-row seams and costs
//   tex.timings;       // seconds per stage
//
// Patching: the texture shows the texton's frames in a loop (the texton's
// last frame leads into its first as recorded), each pass turned about the
// up axis by the texton's heading turn. With mixing on, at each turning
// candidate of the texton (symmetry_scores on the texton) a
// symmetric-playback passage starts with some probability: the motion
// plays on to a symmetric frame, backwards to another, and forwards again
// (anima::symmetric_playback), then the loop resumes. The frame stream is
// rendered with anima::resequence, so the root's ground path is
// accumulated from the texton's steps and the figure never snaps back.
//
// Smoothing (Eq 14): the fades of values become fades of velocities
// (motion_texton::fade_correction), each with one jump at its middle, and
// anima::smooth_seams removes the jumps, with a seam wherever the stream
// crosses the middle of a row's fade, spreading the mismatch they held
// over the whole texture. 1D per row by default; the paper's 2D form
// smooths the frames x DOF image once, at every row's seams. The root's
// ground position is not smoothed (it is already a sum of steps).
//
// Planting (optional): feet on the ground through a pass over the overlap
// or a turn are held where they are (anima::plant_feet, the legs solved by
// IK).
#pragma once

#include <anima/core/constants.hpp>
#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/core/stopwatch.hpp>
#include <anima/core/random.hpp>
#include <anima/ik/plant_feet.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/dof_view.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/resequence.hpp>
#include <anima/motion/speed_limits.hpp>
#include <anima/texture/motion_smoothing.hpp>
#include <anima/symmetry/symmetric_playback.hpp>
#include <anima/symmetry/symmetry_scores.hpp>
#include <anima/texture/texton.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <iterator>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace anima {

template <class T>
struct texture_mixing_params {
    /// Mix symmetric-playback passages into the loop.
    bool symmetric = false;
    /// Chance that a passage starts at a turning candidate the loop reaches.
    T probability = T(0.5);
    /// Turning candidates of the texton.
    symmetry_params<T> symmetry;
    /// The passages' turning rule; its seed seeds the whole mixing.
    playback_params<T> playback;
};

template <class T>
struct texture_smoothing_params {
    bool enabled = true;
    /// Form (1D per row by default, 2D image), solver, boundaries, and the
    /// differences replaced on each side of a seam's jump (radius).
    seam_smoothing_params<T> poisson;
};

/// Feet planted across seams and turns (ik/plant_feet.hpp): the contact
/// runs that reach a pass through the texton's overlap or a turn are held
/// in place, the legs within the source clip's joint speeds. Skipped for
/// figures without feet to plant. On by default: measured on every shared
/// CMU clip it takes the texture's foot skate to at most 1.07 times the
/// input's (0.25-0.81 on the walks, runs and jump; up to 1.43 without), and
/// it about doubles a texture's time (docs/texture.md).
template <class T>
struct texture_planting_params {
    bool enabled = true;
    /// Ranges are set from the texture's seams and turns; contacts are
    /// found along the texton's up axis when feet.contacts.up is empty.
    plant_feet_params<T> feet;
};

template <class T>
struct motion_texture_params {
    texton_params<T> texton;
    texture_mixing_params<T> mixing;
    texture_smoothing_params<T> smoothing;
    texture_planting_params<T> planting;
    /// The root's ground path (accumulated: the texton's steps added up).
    root_path root = root_path::accumulated;
    /// Texton frame the texture starts at (taken modulo its length).
    std::size_t start = 0;
    /// Bytes the texture's clip and frame stream may take (1 GiB; 0 lifts
    /// the limit): a texture of more frames is refused before any work. At
    /// about 1 KiB a frame (31 joints in double) that is a million frames.
    /// The seam smoothing's frames x DOFs matrices come on top.
    double max_memory = 1024.0 * 1024.0 * 1024.0;
    /// Called after each stage of make_motion_texture and patch_texton with
    /// the stage's name ("texton": features, search, cut and fades; "patch",
    /// "smoothing", "planting") and its seconds, so that a tool can report a
    /// long run while it goes. Empty: nothing is called.
    std::function<void(std::string_view stage, double seconds)> progress;
};

template <class T>
struct motion_texture {
    clip<T> motion;
    motion_texton<T> texton;
    /// Texton frame shown at each output frame.
    std::vector<std::size_t> stream;
    /// Per texton row: output frames where the stream crosses the middle of
    /// the row's fade (the frame after the crossing): its seams as
    /// anima::smooth_seams takes them.
    std::vector<std::vector<std::size_t>> row_seams;
    /// [first, last] output frames of each pass through an overlap of the
    /// texton (the one of its seam, or of every seam of several clips).
    std::vector<std::pair<std::size_t, std::size_t>> overlap_spans;
    /// Output frames where a symmetric passage reversed.
    std::vector<std::size_t> turns;
    /// Symmetric passages played.
    std::size_t passages = 0;
    seam_smoothing_stats<T> smoothing;
    std::size_t planted_runs = 0;  ///< contact runs planted (0 when planting is off)
    texture_timings timings;
};

/// The frame stream of a texture of `frames` frames over a texton, and
/// where symmetric passages turned. Exposed for tests and tools; see
/// make_motion_texture.
template <class T>
std::vector<std::size_t> texture_stream(const motion_texton<T>& texton, std::size_t frames,
                                        const motion_texture_params<T>& params = {},
                                        std::vector<std::size_t>* turns = nullptr, std::size_t* passages = nullptr) {
    const std::size_t L = texton.motion.frames();
    if (L == 0) throw invalid_argument("anima::texture_stream: the texton has no frames");
    std::vector<std::size_t> out;
    out.reserve(frames);
    std::vector<turning_candidate<T>> candidates;
    std::vector<bool> is_candidate(L, false);
    std::size_t last_candidate = 0;
    if (params.mixing.symmetric) {
        if (!(params.mixing.probability >= T(0)) || !(params.mixing.probability <= T(1)))
            throw invalid_argument("anima::texture_stream: the mixing probability must be in [0, 1], got " +
                                   detail::argument_text(params.mixing.probability));
        candidates = symmetry_scores(texton.motion, params.mixing.symmetry).candidates;
        for (const auto& c : candidates) {
            is_candidate[c.frame] = true;
            last_candidate = std::max(last_candidate, c.frame);
        }
        if (candidates.size() < 2) candidates.clear();  // nowhere to turn back to
    }
    random_source random(params.mixing.playback.seed);
    std::size_t pos = params.start % L;
    while (out.size() < frames) {
        out.push_back(pos);
        if (!candidates.empty() && is_candidate[pos] && pos < last_candidate && out.size() < frames &&
            random.uniform() < static_cast<double>(params.mixing.probability)) {
            playback_params<T> pp = params.mixing.playback;
            pp.start_frame = pos;
            pp.seed = random.raw();
            symmetric_playback<T> playback(L, candidates, pp);
            const std::size_t base = out.size() - 1;
            playback.next();  // the start frame, shown already
            while (out.size() < frames) {
                pos = playback.next();
                out.push_back(pos);
                // An even number of turns: moving forwards again.
                if (playback.turns().size() >= 2 && playback.turns().size() % 2 == 0) break;
            }
            if (turns)
                for (std::size_t t : playback.turns())
                    if (base + t < frames) turns->push_back(base + t);
            if (passages) ++*passages;
        }
        pos = (pos + 1) % L;
    }
    return out;
}

/// Which texton frame of a row stands for a seam: where the graph cut
/// switches clips (texton_join::seam_frame) or the middle of the fade
/// around it (blend_centre, what smooth_seams takes).
enum class seam_mark { cut, fade_centre };

/// Per texton row, the frames k of a stream over the texton (texture_stream,
/// motion_texture::stream) where it crosses that row's seams, either way:
/// stream[k - 1] and stream[k] are the seam's frame and the one before it.
template <class T>
std::vector<std::vector<std::size_t>> seam_crossings(const motion_texton<T>& texton,
                                                     const std::vector<std::size_t>& stream, seam_mark mark) {
    const std::size_t rows = texton.rows();
    const auto seams = texton.seams();
    // Each row's seam frames, once: the stream is long, the seams few.
    std::vector<std::vector<std::size_t>> at(rows);
    for (std::size_t r = 0; r < rows; ++r)
        for (const auto& seam : seams) at[r].push_back(mark == seam_mark::cut ? seam.seam_frame(r) : seam.blend_centre(r));
    std::vector<std::vector<std::size_t>> out(rows);
    for (std::size_t k = 1; k < stream.size(); ++k) {
        const std::size_t p = stream[k - 1], q = stream[k];
        for (std::size_t r = 0; r < rows; ++r)
            for (const std::size_t c : at[r])
                if ((p + 1 == c && q == c) || (p == c && q + 1 == c)) out[r].push_back(k);
    }
    return out;
}

/// The seams crossed in one pass through an overlap: the first and last
/// output frame where a row crosses its seam, and how many row crossings
/// (one per joint row that switches clips in the pass).
struct pass_seams {
    std::size_t first = 0, last = 0, crossings = 0;  ///< crossings = 0: none (first, last meaningless)
};

/// Per pass through an overlap (motion_texture::overlap_spans, in order),
/// the seams of seam_crossings(t.texton, t.stream, mark) that fall in it:
/// where a plot or a viewer marks the seams of each pass.
template <class T>
std::vector<pass_seams> seams_per_pass(const motion_texture<T>& t, seam_mark mark = seam_mark::cut) {
    const auto& spans = t.overlap_spans;
    std::vector<pass_seams> out(spans.size());
    for (const auto& row : seam_crossings(t.texton, t.stream, mark))
        for (const std::size_t k : row) {
            // The spans are in order and disjoint: the last one starting at or before k.
            const auto it = std::upper_bound(spans.begin(), spans.end(), k,
                                             [](std::size_t f, const auto& span) { return f < span.first; });
            if (it == spans.begin() || k > std::prev(it)->second) continue;
            pass_seams& p = out[static_cast<std::size_t>(std::prev(it) - spans.begin())];
            p.first = p.crossings ? std::min(p.first, k) : k;
            p.last = p.crossings ? std::max(p.last, k) : k;
            ++p.crossings;
        }
    return out;
}

namespace detail {

/// How fast the clips of `texton` move at most: its source_speeds, or its
/// own for a texton made without them.
template <class T>
speed_limits<T> source_speed_limits(const motion_texton<T>& texton) {
    return texton.source_speeds.joint.size() == texton.motion.joints() ? texton.source_speeds
                                                                         : clip_speed_limits(texton.motion);
}

/// Where the stream crosses each row's seams (out.row_seams) and the runs of
/// texture frames inside an overlap of the texton (out.overlap_spans).
template <class T>
void locate_texture_seams(motion_texture<T>& out, const motion_texton<T>& texton, std::size_t frames) {
    std::vector<bool> in_overlap(texton.motion.frames(), false);
    for (const auto& s : texton.seams())
        for (std::size_t t = 0; t < s.overlap; ++t) in_overlap[s.overlap_start + t] = true;
    out.row_seams = seam_crossings(texton, out.stream, seam_mark::fade_centre);
    for (std::size_t k = 0; k < frames; ++k) {
        if (!in_overlap[out.stream[k]]) continue;
        if (!out.overlap_spans.empty() && out.overlap_spans.back().second + 1 == k)
            out.overlap_spans.back().second = k;
        else
            out.overlap_spans.emplace_back(k, k);
    }
}

/// Turns each pass of the loop by the texton's heading turn: the root's
/// orientation, and its ground steps where the path is made of steps.
template <class T>
void turn_texture_passes(motion_texture<T>& out, const motion_texton<T>& texton, std::size_t frames,
                         const motion_texture_params<T>& params, const resequence_params& rp) {
    const auto& sk = texton.motion.skeleton();
    if (texton.heading_turn != T(0) && sk.has_rotation_channels(0)) {
        using vec3 = Eigen::Matrix<T, 3, 1>;
        const std::size_t L = texton.motion.frames();
        const vec3 up_vec = axis_vector<T>(*rp.up);
        const int up_k = static_cast<int>(rp.up->axis);
        const bool steps = sk.translation_slot(0) >= 0 &&
                           (params.root == root_path::accumulated || params.root == root_path::keep_direction);
        long pass = 0;
        vec3 previous = steps ? out.motion.root_position(0) : vec3::Zero();
        vec3 position = previous;
        for (std::size_t k = 0; k < frames; ++k) {
            if (k > 0 && out.stream[k - 1] + 1 == L && out.stream[k] == 0) ++pass;
            if (k > 0 && out.stream[k - 1] == 0 && out.stream[k] + 1 == L) --pass;
            const Eigen::Quaternion<T> turn(Eigen::AngleAxis<T>(static_cast<T>(pass) * texton.heading_turn, up_vec));
            out.motion.set_rotation(k, 0, turn * out.motion.rotation(k, 0));
            if (!steps) continue;
            const vec3 recorded = out.motion.root_position(k);
            if (k > 0) {
                vec3 step = recorded - previous;
                step[up_k] = T(0);
                position += turn * step;
            }
            previous = recorded;
            vec3 p = position;
            p[up_k] = recorded[up_k];
            out.motion.set_root_position(k, p);
        }
    }
}

/// Adds the texton's fade corrections to every texture frame: the fades of
/// values become fades of velocities, each with one jump at its middle.
template <class T>
void apply_fade_corrections(motion_texture<T>& out, const motion_texton<T>& texton, std::size_t frames) {
    const auto& layout = texton.layout;
    const auto& fix = texton.fade_correction;
    for (std::size_t k = 0; k < frames; ++k) {
        const auto f = static_cast<Eigen::Index>(out.stream[k]);
        for (std::size_t col = 0; col < layout.size(); col += 3) {
            const Eigen::Matrix<T, 3, 1> v = fix.row(f).segment(static_cast<Eigen::Index>(col), 3).transpose();
            if (v.isZero(T(0))) continue;
            const dof& d = layout.dofs[col];
            if (d.type == dof::kind::rotation)
                out.motion.set_rotation(k, d.joint, out.motion.rotation(k, d.joint) *
                                                        from_rotation_vector<Eigen::Quaternion<T>>(v));
            else
                out.motion.set_translation(k, d.joint, out.motion.translation(k, d.joint) + v);
        }
    }
}

/// Poisson smoothing of the texture's seams (Eq 14) in the DOF view: every
/// rotation DOF and the root's height; the ground path stays the
/// resequenced one.
template <class T>
void smooth_texture_seams(motion_texture<T>& out, const motion_texton<T>& texton, std::size_t frames,
                          const motion_texture_params<T>& params, int up_k) {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const std::size_t rows = texton.rows();
    const auto& layout = texton.layout;
    matrix y = to_dof_matrix(out.motion, layout);
    detail::unwrap_rotation_vectors(y, layout);
    // Columns smoothed per row: all three of a rotation, the height of
    // the root's translation (its ground path is a sum of steps).
    const auto columns = [&](std::size_t r) {
        std::vector<Eigen::Index> cols;
        for (int k = 0; k < 3; ++k) {
            const std::size_t c = 3 * r + static_cast<std::size_t>(k);
            const dof& d = layout.dofs[c];
            if (d.type == dof::kind::rotation || d.joint != 0 || d.component == up_k)
                cols.push_back(static_cast<Eigen::Index>(c));
        }
        return cols;
    };
    const auto record = [&](const seam_smoothing_stats<T>& s) {
        out.smoothing.solves += s.solves;
        out.smoothing.iterations = std::max(out.smoothing.iterations, s.iterations);
        out.smoothing.relative_residual = std::max(out.smoothing.relative_residual, s.relative_residual);
        out.smoothing.converged = out.smoothing.converged && s.converged;
    };
    const auto smooth = [&](const std::vector<Eigen::Index>& cols, const std::vector<std::size_t>& seams) {
        matrix part(y.rows(), static_cast<Eigen::Index>(cols.size()));
        for (std::size_t i = 0; i < cols.size(); ++i) part.col(static_cast<Eigen::Index>(i)) = y.col(cols[i]);
        const auto s = smooth_seams(part, seams, params.smoothing.poisson);
        for (std::size_t i = 0; i < cols.size(); ++i) y.col(cols[i]) = s.motion.col(static_cast<Eigen::Index>(i));
        record(s.stats);
    };
    if (params.smoothing.poisson.form == seam_smoothing_form::temporal) {
        // Rows with the same seams share one call (and one multigrid
        // hierarchy); the columns stay independent problems.
        std::vector<bool> done(rows, false);
        for (std::size_t r = 0; r < rows; ++r) {
            if (done[r] || out.row_seams[r].empty()) continue;
            std::vector<Eigen::Index> cols;
            for (std::size_t q = r; q < rows; ++q)
                if (!done[q] && out.row_seams[q] == out.row_seams[r]) {
                    const auto c = columns(q);
                    cols.insert(cols.end(), c.begin(), c.end());
                    done[q] = true;
                }
            smooth(cols, out.row_seams[r]);
        }
    } else {
        std::vector<Eigen::Index> cols;
        std::vector<std::size_t> seams;
        for (std::size_t r = 0; r < rows; ++r) {
            const auto c = columns(r);
            cols.insert(cols.end(), c.begin(), c.end());
            seams.insert(seams.end(), out.row_seams[r].begin(), out.row_seams[r].end());
        }
        smooth(cols, seams);
    }
    // The ground path stays the resequenced one.
    for (std::size_t c = 0; c < layout.size(); ++c) {
        const dof& d = layout.dofs[c];
        if (d.type == dof::kind::translation && d.joint == 0 && d.component != up_k)
            for (std::size_t k = 0; k < frames; ++k)
                y(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(c)) = out.motion.root_position(k)[d.component];
    }
    from_dof_matrix(y, layout, out.motion);
}

/// Throws anima::invalid_argument naming `function` unless a texture of
/// `frames` frames of skeleton `sk` fits max_memory (0: no limit) and the
/// address space.
template <class T>
void check_texture_memory(const skeleton<T>& sk, std::size_t frames, double max_memory, const char* function) {
    check_argument(max_memory >= 0, function, "max_memory", "non-negative", max_memory);
    const double frame_bytes = clip_frame_bytes(sk) + static_cast<double>(sizeof(std::size_t));  // clip + stream
    const double addressable = static_cast<double>(std::numeric_limits<std::ptrdiff_t>::max());
    const double limit = max_memory > 0 ? std::min(max_memory, addressable) : addressable;
    const double most = std::floor(limit / frame_bytes);
    if (static_cast<double>(frames) <= most) return;
    fail_argument(function, "frames",
                  "at most " + detail::argument_text(most) + " (" + detail::argument_text(frame_bytes) +
                      " bytes a frame, " +
                      (max_memory > 0 ? "max_memory " + detail::argument_text(max_memory / 1048576.0) + " MiB)"
                                      : std::string("the address space)")),
                  frames);
}

}  // namespace detail

/// Patches a texton into a texture of `frames` frames (Eq 10): the stream,
/// resequencing with the root policy, and the Poisson stage. Throws
/// anima::invalid_argument for frames = 0, a texture larger than
/// params.max_memory, or bad parameters.
template <class T>
motion_texture<T> patch_texton(const motion_texton<T>& texton, std::size_t frames,
                               const motion_texture_params<T>& params = {}) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    if (frames == 0) throw invalid_argument("anima::patch_texton: the texture needs at least one frame (N = 0)");
    detail::check_texture_memory(texton.motion.skeleton(), frames, params.max_memory, "anima::patch_texton");
    stopwatch clock;
    motion_texture<T> out;
    out.texton = texton;
    out.timings = texton.timings;
    out.stream = texture_stream(texton, frames, params, &out.turns, &out.passages);
    resequence_params rp;
    rp.root = params.root;
    rp.up = params.texton.up ? *params.texton.up : guess_up_axis(texton.motion.skeleton()).up;
    out.motion = resequence(texton.motion, out.stream, rp);

    detail::locate_texture_seams(out, texton, frames);
    detail::turn_texture_passes(out, texton, frames, params, rp);
    out.timings.patch = clock.lap();
    if (params.progress) params.progress("patch", out.timings.patch);

    // Poisson smoothing (Eq 14). The fades become fades of velocities, each
    // with one jump at its middle (texton.fade_correction); smooth_seams
    // removes the jumps and spreads what they held over the whole texture.
    const bool any_seam = std::any_of(out.row_seams.begin(), out.row_seams.end(), [](const auto& s) { return !s.empty(); });
    if (params.smoothing.enabled && frames >= 3) detail::apply_fade_corrections(out, texton, frames);
    if (params.smoothing.enabled && frames >= 3 && any_seam)
        detail::smooth_texture_seams(out, texton, frames, params, static_cast<int>(rp.up->axis));

    out.timings.smoothing = clock.lap();
    if (params.progress) params.progress("smoothing", out.timings.smoothing);

    // Feet planted across the seams and turns.
    if (params.planting.enabled) {
        std::vector<frame_interval> ranges;
        for (const auto& [first, last] : out.overlap_spans) ranges.push_back({first, last});
        for (const std::size_t f : out.turns) ranges.push_back({f, f});
        // Contacts along the texture's up axis unless told otherwise; the
        // legs stay within the speeds of the clip the texture is made of, as
        // the seams do.
        plant_feet_params<T> feet = params.planting.feet;
        if (!feet.contacts.up) feet.contacts.up = rp.up;
        out.planted_runs =
            plant_feet_in_ranges(out.motion, std::move(ranges), feet, detail::source_speed_limits(texton).joint);
    }
    out.timings.planting = clock.lap();
    if (params.progress) params.progress("planting", out.timings.planting);
    out.timings.total = texton.timings.total + out.timings.patch + out.timings.smoothing + out.timings.planting;
    return out;
}

/// A texture of `frames` frames from a clip: make_texton, then
/// patch_texton. Throws anima::invalid_argument for frames = 0, a texture
/// larger than params.max_memory (checked first), and everything make_texton
/// refuses.
template <class T>
motion_texture<T> make_motion_texture(const clip<T>& c, std::size_t frames, const motion_texture_params<T>& params = {}) {
    if (frames == 0) throw invalid_argument("anima::make_motion_texture: the texture needs at least one frame (N = 0)");
    detail::check_texture_memory(c.skeleton(), frames, params.max_memory, "anima::make_motion_texture");
    const motion_texton<T> texton = make_texton(c, params.texton);
    if (params.progress) params.progress("texton", texton.timings.total);
    return patch_texton(texton, frames, params);
}

/// A texture of `frames` frames that loops through several clips of one
/// skeleton (make_texton of the clips), with the seams between clips
/// smoothed and planted as the loop's own. Throws anima::invalid_argument
/// for frames = 0, a texture larger than params.max_memory, and everything
/// make_texton refuses.
template <class T>
motion_texture<T> make_motion_texture(const std::vector<clip<T>>& clips, std::size_t frames,
                                      const motion_texture_params<T>& params = {}) {
    if (frames == 0) throw invalid_argument("anima::make_motion_texture: the texture needs at least one frame (N = 0)");
    if (!clips.empty())
        detail::check_texture_memory(clips[0].skeleton(), frames, params.max_memory, "anima::make_motion_texture");
    const motion_texton<T> texton = make_texton(clips, params.texton);
    if (params.progress) params.progress("texton", texton.timings.total);
    return patch_texton(texton, frames, params);
}

}  // namespace anima
