// Poisson smoothing of the seams of a stitched motion (Eq 14): the motion's
// frame-to-frame differences are kept everywhere except across the seams,
// where the jump is replaced by the trend of the neighbouring differences,
// and the motion is rebuilt from that target by solving nabla^2 u = div G
// with the first and last frames fixed (Dirichlet, the paper's choice: no
// shift ambiguity). The jump is thus spread over the whole clip as a slow
// drift, while every other difference (the motion's detail) is kept.
//
// Two forms:
//  - temporal (default): each DOF on its own along time, a 1D problem per
//    DOF column; the jump of each DOF disappears exactly and DOFs never mix.
//  - image: the paper's form, the frames x DOF matrix as one 2D grid with the
//    differences between neighbouring DOF columns kept as well. The DOF axis
//    has no natural order, and DOFs of different units (radians and
//    lengths) are compared directly, so a DOF's jump is shared with its
//    neighbours in the matrix rather than removed; use it to reproduce the
//    paper.
// The motion is a frames x DOF matrix (anima::to_dof_matrix) or a clip.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/dof_view.hpp>
#include <anima/poisson/dst_poisson.hpp>
#include <anima/poisson/gradient_field.hpp>
#include <anima/poisson/grid.hpp>
#include <anima/poisson/multigrid_poisson.hpp>
#include <anima/poisson/problem.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace anima {

enum class seam_smoothing_form : unsigned char {
    temporal,  ///< each DOF along time (1D)
    image      ///< the frames x DOF matrix as one 2D grid (the paper)
};

template <>
struct enum_names<seam_smoothing_form> {
    static constexpr const char* what = "smoothing form";
    static constexpr enum_entry<seam_smoothing_form> entries[] = {{seam_smoothing_form::temporal, "1d"},
                                                                  {seam_smoothing_form::image, "2d"},
                                                                  {seam_smoothing_form::temporal, "temporal"},
                                                                  {seam_smoothing_form::image, "image"}};
};

/// "1d" (or "temporal") or "2d" (or "image") (any case); throws anima::invalid_argument otherwise.
inline seam_smoothing_form parse_seam_smoothing_form(std::string_view name) {
    return parse_enum<seam_smoothing_form>(name, "anima::parse_seam_smoothing_form");
}

/// Which Poisson solver does the work.
enum class poisson_method : unsigned char { multigrid, dst };

template <>
struct enum_names<poisson_method> {
    static constexpr const char* what = "Poisson solver";
    static constexpr enum_entry<poisson_method> entries[] = {{poisson_method::multigrid, "multigrid"},
                                                             {poisson_method::dst, "dst"}};
};

/// "multigrid" or "dst" (any case); throws anima::invalid_argument otherwise.
inline poisson_method parse_poisson_method(std::string_view name) {
    return parse_enum<poisson_method>(name, "anima::parse_poisson_method");
}

template <class T>
struct seam_smoothing_params {
    seam_smoothing_form form = seam_smoothing_form::temporal;
    poisson_method solver = poisson_method::multigrid;
    /// Differences on each side of a seam's own jump that are replaced too
    /// (0: only the jump). Replaced differences are interpolated linearly
    /// between the nearest kept ones (their mean, for a single jump).
    std::size_t radius = 0;
    /// Image form: the sides beyond the first and last DOF column. Neumann
    /// (free) by default; Dirichlet with zero values is the paper's zero
    /// padding.
    boundary dof_sides = boundary::neumann;
    /// Image form: spacing of the DOF columns relative to the frame spacing
    /// (larger: weaker coupling between DOFs).
    T dof_spacing = T(1);
    typename multigrid_poisson<T>::params multigrid;
};

/// How the solves went.
template <class T>
struct seam_smoothing_stats {
    int solves = 0;              ///< Poisson solves (one per DOF, or one)
    int iterations = 0;          ///< the most multigrid cycles of any solve (0 for DST)
    T relative_residual = 0;     ///< the largest final relative residual
    bool converged = true;       ///< every solve reached its tolerance
};

template <class T>
struct smoothed_motion {
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> motion;  ///< frames x DOF
    seam_smoothing_stats<T> stats;
};

template <class T>
struct smoothed_clip {
    clip<T> motion;
    seam_smoothing_stats<T> stats;
};

namespace detail {

inline std::vector<std::size_t> checked_seams(std::vector<std::size_t> seams, std::size_t frames, const std::string& who) {
    if (frames < 3)
        throw invalid_argument(who + ": the motion has " + std::to_string(frames) +
                               " frames; smoothing needs at least 3 (the first and last stay fixed)");
    for (std::size_t s : seams)
        if (s < 1 || s >= frames)
            throw invalid_argument(who + ": seam at frame " + std::to_string(s) + " is outside 1.." +
                                   std::to_string(frames - 1) + " (a seam is the first frame after a jump)");
    std::sort(seams.begin(), seams.end());
    seams.erase(std::unique(seams.begin(), seams.end()), seams.end());
    return seams;
}

}  // namespace detail

namespace detail {

/// seam_target_differences below; `who` (the public function called) starts
/// each message.
template <class Derived>
Eigen::Matrix<typename Derived::Scalar, Eigen::Dynamic, Eigen::Dynamic> seam_target_differences(
    const Eigen::MatrixBase<Derived>& m, const std::vector<std::size_t>& seams, std::size_t radius,
    const std::string& who) {
    using T = typename Derived::Scalar;
    const auto frames = static_cast<std::size_t>(m.rows());
    const auto list = detail::checked_seams(seams, frames, who);
    detail::check_finite_matrix(m, who, "motion");
    const Eigen::Index faces = m.rows() - 1;
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> d = m.bottomRows(faces) - m.topRows(faces);
    std::vector<bool> replaced(static_cast<std::size_t>(faces), false);
    for (std::size_t s : list) {
        const std::size_t face = s - 1;
        const std::size_t lo = face >= radius ? face - radius : 0;
        const std::size_t last = static_cast<std::size_t>(faces) - 1;  // no overflow for any radius
        const std::size_t hi = radius >= last - face ? last : face + radius;
        for (std::size_t k = lo; k <= hi; ++k) replaced[k] = true;
    }
    for (Eigen::Index a = 0; a < faces;) {
        if (!replaced[static_cast<std::size_t>(a)]) {
            ++a;
            continue;
        }
        Eigen::Index b = a;
        while (b + 1 < faces && replaced[static_cast<std::size_t>(b + 1)]) ++b;
        const bool left = a > 0, right = b + 1 < faces;
        for (Eigen::Index k = a; k <= b; ++k) {
            if (left && right) {
                const T t = T(k - (a - 1)) / T(b + 1 - (a - 1));
                d.row(k) = (T(1) - t) * d.row(a - 1) + t * d.row(b + 1);
            } else if (left) {
                d.row(k) = d.row(a - 1);
            } else if (right) {
                d.row(k) = d.row(b + 1);
            } else {
                d.row(k).setZero();
            }
        }
        a = b + 1;
    }
    return d;
}

}  // namespace detail

/// The target frame-to-frame differences of a frames x DOF motion: row k is
/// m(k + 1) - m(k), with the rows across each seam (row s - 1 for a seam at
/// frame s, and `radius` rows on each side) replaced by a linear
/// interpolation of the nearest kept rows.
template <class Derived>
Eigen::Matrix<typename Derived::Scalar, Eigen::Dynamic, Eigen::Dynamic> seam_target_differences(
    const Eigen::MatrixBase<Derived>& m, const std::vector<std::size_t>& seams, std::size_t radius = 0) {
    return detail::seam_target_differences(m, seams, radius, "anima::seam_target_differences");
}

/// How far a frames x DOF motion (in `layout`) jumps across the seam at
/// frame s beyond the trend of its neighbouring frame differences
/// (seam_target_differences): the largest excess over its rotation DOFs
/// (radians) and which DOF it is, and the largest over its translation DOFs
/// (file units). What smooth_seams takes away; zero for a motion without
/// a jump there.
template <class T>
struct seam_jump {
    T rotation = T(0);
    std::size_t worst_rotation_dof = 0;  ///< column of the largest rotation excess
    T translation = T(0);
};

template <class Derived>
seam_jump<typename Derived::Scalar> measure_seam_jump(const Eigen::MatrixBase<Derived>& m, std::size_t seam,
                                                      const dof_layout<typename Derived::Scalar>& layout) {
    using T = typename Derived::Scalar;
    if (static_cast<std::size_t>(m.cols()) != layout.size())
        throw invalid_argument("anima::measure_seam_jump: " + std::to_string(m.cols()) + " DOF columns for a layout of " +
                               std::to_string(layout.size()));
    // Checks the seam and the values.
    const auto target = detail::seam_target_differences(m, {seam}, 0, "anima::measure_seam_jump");
    const auto face = static_cast<Eigen::Index>(seam - 1);
    seam_jump<T> out;
    for (Eigen::Index d = 0; d < m.cols(); ++d) {
        const T excess = std::abs(m(face + 1, d) - m(face, d) - target(face, d));
        if (layout.dofs[static_cast<std::size_t>(d)].type == dof::kind::rotation) {
            if (excess > out.rotation) {
                out.rotation = excess;
                out.worst_rotation_dof = static_cast<std::size_t>(d);
            }
        } else {
            out.translation = std::max(out.translation, excess);
        }
    }
    return out;
}

/// Smooths the seams of a frames x DOF motion; the first and last frames
/// are kept. Throws anima::invalid_argument for fewer than 3 frames, a seam
/// outside 1..frames-1, a non-finite value or bad parameters.
template <class Derived>
smoothed_motion<typename Derived::Scalar> smooth_seams(const Eigen::MatrixBase<Derived>& motion,
                                                       const std::vector<std::size_t>& seams,
                                                       const seam_smoothing_params<typename Derived::Scalar>& prm = {}) {
    using T = typename Derived::Scalar;
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const std::string who = "anima::smooth_seams";
    if (motion.cols() < 1) throw invalid_argument(who + ": the motion has no DOF columns");
    check_positive(who, "dof_spacing", prm.dof_spacing);
    const matrix m = motion;
    const matrix d = detail::seam_target_differences(m, seams, prm.radius, who);
    const Eigen::Index frames = m.rows(), dofs = m.cols(), inner = frames - 2;

    smoothed_motion<T> out;
    out.motion = m;
    const auto record = [&](const poisson_result<T>& r) {
        ++out.stats.solves;
        out.stats.iterations = std::max(out.stats.iterations, r.iterations);
        out.stats.relative_residual = std::max(out.stats.relative_residual, r.relative_residual);
        out.stats.converged = out.stats.converged && r.converged;
    };

    poisson_grid<T> g;
    g.rows = inner;
    g.top_bottom = boundary::dirichlet;  // the first and last frames stay
    if (prm.form == seam_smoothing_form::temporal) {
        g.cols = 1;
        g.left_right = boundary::neumann;  // one Neumann column: no coupling, a 1D problem
        std::optional<multigrid_poisson<T>> mg;
        std::optional<dst_poisson<T>> fast;
        if (prm.solver == poisson_method::multigrid) mg.emplace(g, prm.multigrid);
        else fast.emplace(g);
        poisson_problem<T> p;
        p.grid = g;
        p.rhs.resize(inner, 1);
        p.boundary.top.resize(1);
        p.boundary.bottom.resize(1);
        for (Eigen::Index c = 0; c < dofs; ++c) {
            // div of the target differences on frames 1..frames-2.
            p.rhs.col(0) = d.col(c).tail(inner) - d.col(c).head(inner);
            p.boundary.top[0] = m(0, c);
            p.boundary.bottom[0] = m(frames - 1, c);
            const poisson_result<T> r = mg ? mg->solve(p) : fast->solve(p);
            record(r);
            out.motion.col(c).segment(1, inner) = r.u.col(0);
        }
        return out;
    }

    g.cols = dofs;
    g.hx = prm.dof_spacing;
    g.left_right = prm.dof_sides;
    boundary_values<T> values;
    values.top = m.row(0).transpose();
    values.bottom = m.row(frames - 1).transpose();
    gradient_field<T> field = gradient(g, m.middleRows(1, inner), values);
    field.gy = d;  // hy = 1: differences are the gradient
    poisson_problem<T> p;
    p.grid = g;
    p.rhs = divergence(g, field);
    p.boundary = values;
    const poisson_result<T> r =
        prm.solver == poisson_method::multigrid ? solve_poisson_multigrid(p, prm.multigrid) : solve_poisson_dst(p);
    record(r);
    out.motion.middleRows(1, inner) = r.u;
    return out;
}

/// Smooths the seams of a clip through its DOF view (rotation vectors about
/// each joint's mean rotation, and translations); see smooth_seams above.
template <class T>
smoothed_clip<T> smooth_seams(const clip<T>& c, const std::vector<std::size_t>& seams,
                              const seam_smoothing_params<T>& prm = {}) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    const auto layout = make_dof_layout(c);
    const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> m = to_dof_matrix(c, layout);
    smoothed_motion<T> s = smooth_seams(m, seams, prm);
    smoothed_clip<T> out{c, s.stats};
    from_dof_matrix(s.motion, layout, out.motion);
    return out;
}

/// The seams of a clip before and after smoothing, in its DOF view: per
/// seam (sorted, each once) its jump in each, and the largest change of
/// any frame. What `anima smooth` reports.
template <class T>
struct seam_smoothing_measures {
    dof_layout<T> layout;                ///< make_dof_layout(before), the view measured in
    std::vector<std::size_t> seams;      ///< sorted, duplicates removed
    std::vector<seam_jump<T>> before, after;  ///< measure_seam_jump of each seam
    dof_change<T> largest_change;        ///< largest_dof_change(before, after)
};

/// Measures `after` (smooth_seams of `before`, or any clip of its skeleton
/// and length) against `before` at `seams`. Throws anima::invalid_argument
/// for clips of different skeletons or lengths, fewer than 3 frames or a
/// seam outside 1..frames-1.
template <class T>
seam_smoothing_measures<T> measure_smoothing(const clip<T>& before, const clip<T>& after,
                                             const std::vector<std::size_t>& seams) {
    if (before.skeleton() != after.skeleton() || before.frames() != after.frames())
        throw invalid_argument("anima::measure_smoothing: the clips differ in skeleton or length (" +
                               std::to_string(before.frames()) + " and " + std::to_string(after.frames()) +
                               " frames)");
    seam_smoothing_measures<T> out;
    out.seams = detail::checked_seams(seams, before.frames(), "anima::measure_smoothing");
    out.layout = make_dof_layout(before);
    const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> b = to_dof_matrix(before, out.layout),
                                                           a = to_dof_matrix(after, out.layout);
    for (const std::size_t s : out.seams) {
        out.before.push_back(measure_seam_jump(b, s, out.layout));
        out.after.push_back(measure_seam_jump(a, s, out.layout));
    }
    out.largest_change = largest_dof_change(b, a, out.layout);
    return out;
}

}  // namespace anima
