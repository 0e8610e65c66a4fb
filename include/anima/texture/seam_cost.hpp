// The cost of a seam between two overlapping motions A (M2, being left) and
// B (M1, switched to), sampled on a (row x frame) lattice: a row is a block
// of DOF columns that switches together (a joint's rotation vector, the
// root's translation), a frame is a frame of the overlap.
//
// Eq 8 (Kwatra et al. 2003): cutting between nodes s and t costs the
// mismatch on both sides, M(s, t) = |A(s) - B(s)| + |A(t) - B(t)|.
// Eq 9: the gradient normaliser grad(s, t) = |G_A(s)| + |G_A(t)| +
// |G_B(s)| + |G_B(t)|, with G the temporal gradient of each motion.
// Eq 7 as printed, exp(-M / grad), falls as the mismatch grows, so a
// min-cut would seek the worst seam. The capacities offered all grow with
// the mismatch:
//   normalized   M / (grad + eps)      Kwatra's, the default: a seam through
//                                      fast motion is less visible
//   exponential  1 - exp(-M / (grad + eps))  the paper's exponential, turned
//                                      so that it grows; saturates at 1
//   plain        M                     no normaliser
// Edges between rows (neighbouring joints) use the same formula; their
// gradient is the temporal one of both nodes, since the difference between
// two joints' DOFs is not a gradient of anything.
#pragma once

#include <anima/core/enum_names.hpp>
#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/finite_difference.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>

namespace anima {

/// How an edge's capacity follows from Eq 8 and Eq 9.
enum class seam_capacity : unsigned char { normalized, exponential, plain };

template <>
struct enum_names<seam_capacity> {
    static constexpr const char* what = "seam capacity";
    static constexpr enum_entry<seam_capacity> entries[] = {{seam_capacity::normalized, "normalized"},
                                                            {seam_capacity::exponential, "exponential"},
                                                            {seam_capacity::plain, "plain"}};
};

/// "normalized", "exponential" or "plain" (any case); throws anima::invalid_argument otherwise.
inline seam_capacity parse_seam_capacity(std::string_view name) {
    return parse_enum<seam_capacity>(name, "anima::parse_seam_capacity");
}

template <class T>
struct seam_cost_params {
    seam_capacity capacity = seam_capacity::normalized;
    /// eps of the normaliser, as a fraction of the mean node gradient: a row
    /// that does not move gets a finite capacity.
    T epsilon = T(0.05);
};

/// Eq 8-9 on the lattice of two overlapping motions.
template <class T>
class seam_cost;

namespace detail {
template <class T>
T seam_edge(const seam_cost<T>& cost, std::size_t r1, std::size_t t1, std::size_t r2, std::size_t t2);
}  // namespace detail

template <class T>
class seam_cost {
public:
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    using vector = Eigen::Matrix<T, Eigen::Dynamic, 1>;

    /// a, b: overlap frames x columns, the two motions at the same times.
    /// Columns are grouped into rows of `block` consecutive columns, each
    /// column weighted by weights[c] (squared-norm weights, e.g. Eq 2's
    /// inverse velocity variances; empty: all 1). Throws
    /// anima::invalid_argument for mismatched sizes, fewer than 2 frames, a
    /// block that does not divide the columns, a negative or non-finite
    /// weight, a non-finite value or bad parameters.
    template <class DA, class DB>
    seam_cost(const Eigen::MatrixBase<DA>& a, const Eigen::MatrixBase<DB>& b, std::size_t block,
              const vector& weights = vector(), const seam_cost_params<T>& params = {})
        : params_(params) {
        const std::string who = "anima::seam_cost: ";
        if (a.rows() != b.rows() || a.cols() != b.cols())
            throw invalid_argument(who + "the motions are " + std::to_string(a.rows()) + " x " + std::to_string(a.cols()) +
                                   " and " + std::to_string(b.rows()) + " x " + std::to_string(b.cols()));
        if (a.rows() < 2) throw invalid_argument(who + "the overlap needs at least 2 frames, got " + std::to_string(a.rows()));
        if (block == 0 || a.cols() == 0 || static_cast<std::size_t>(a.cols()) % block != 0)
            throw invalid_argument(who + "a block of " + std::to_string(block) + " columns does not divide " +
                                   std::to_string(a.cols()) + " columns");
        if (weights.size() != 0 && weights.size() != a.cols())
            throw invalid_argument(who + std::to_string(weights.size()) + " weights for " + std::to_string(a.cols()) +
                                   " columns");
        for (Eigen::Index c = 0; c < weights.size(); ++c)
            if (!(weights[c] >= T(0)) || !std::isfinite(weights[c]))
                throw invalid_argument(who + "weight " + std::to_string(c) + " is negative or not finite");
        if (!(params.epsilon > T(0)) || !std::isfinite(params.epsilon))
            throw invalid_argument(who + "epsilon must be positive and finite, got " +
                                   detail::argument_text(params.epsilon));
        const matrix ma = a, mb = b;
        if (!ma.allFinite() || !mb.allFinite()) throw invalid_argument(who + "the motions have a non-finite value");
        const vector w = weights.size() ? weights : vector::Ones(a.cols());
        const Eigen::Index frames = a.rows(), rows = a.cols() / static_cast<Eigen::Index>(block);
        const auto bk = static_cast<Eigen::Index>(block);
        mismatch_.resize(rows, frames);
        gradient_.resize(rows, frames);
        // Weighted norm of a block of one row of a matrix (frame t).
        const auto norm = [&](const auto& m, Eigen::Index t, Eigen::Index r) {
            return std::sqrt((m.row(t).segment(r * bk, bk).transpose().array().square() * w.segment(r * bk, bk).array()).sum());
        };
        const matrix diff = ma - mb;
        // Per frame: central differences inside, one-sided at the ends.
        const matrix ga = time_derivative(ma, T(1)), gb = time_derivative(mb, T(1));
        for (Eigen::Index r = 0; r < rows; ++r)
            for (Eigen::Index t = 0; t < frames; ++t) {
                mismatch_(r, t) = norm(diff, t, r);
                gradient_(r, t) = norm(ga, t, r) + norm(gb, t, r);
            }
        if (!mismatch_.allFinite() || !gradient_.allFinite())
            throw invalid_argument(who + "the weighted differences overflow the scalar type; scale the motions down");
        // Finite even when nothing moves: capacities stay below max-flow's infinity.
        eps_ = std::max(params.epsilon * gradient_.mean(), std::sqrt(std::numeric_limits<T>::min()));
    }

    std::size_t rows() const noexcept { return static_cast<std::size_t>(mismatch_.rows()); }
    std::size_t frames() const noexcept { return static_cast<std::size_t>(mismatch_.cols()); }

    /// |A - B| of row r at frame t (the weighted norm over the row's block).
    /// Throws anima::invalid_argument for a row or frame out of range, as do
    /// gradient and edge.
    T mismatch(std::size_t r, std::size_t t) const {
        check_node("anima::seam_cost::mismatch", r, t);
        return mismatch_(index(r), index(t));
    }
    /// |G_A| + |G_B| of row r at frame t.
    T gradient(std::size_t r, std::size_t t) const {
        check_node("anima::seam_cost::gradient", r, t);
        return gradient_(index(r), index(t));
    }
    /// Per-node mismatch and gradient: rows x frames.
    const matrix& mismatches() const noexcept { return mismatch_; }
    const matrix& gradients() const noexcept { return gradient_; }
    /// The absolute eps added to the normaliser.
    T epsilon() const noexcept { return eps_; }
    const seam_cost_params<T>& params() const noexcept { return params_; }

    /// Capacity of the edge between nodes (r1, t1) and (r2, t2) (Eq 8-9 and
    /// the capacity policy); symmetric.
    T edge(std::size_t r1, std::size_t t1, std::size_t r2, std::size_t t2) const {
        check_node("anima::seam_cost::edge", r1, t1);
        check_node("anima::seam_cost::edge", r2, t2);
        return detail::seam_edge(*this, r1, t1, r2, t2);
    }

    /// The capacity policy for a mismatch sum M (Eq 8) and gradient sum (Eq 9).
    T capacity(T m, T grad) const {
        switch (params_.capacity) {
            case seam_capacity::plain: return m;
            case seam_capacity::exponential: return -std::expm1(-m / (grad + eps_));
            case seam_capacity::normalized: break;
        }
        return m / (grad + eps_);
    }

private:
    static Eigen::Index index(std::size_t i) { return static_cast<Eigen::Index>(i); }

    void check_node(const char* function, std::size_t r, std::size_t t) const {
        if (r < rows() && t < frames()) return;
        check_argument(r < rows(), function, "row", "less than the " + std::to_string(rows()) + " rows", r);
        check_argument(t < frames(), function, "frame", "less than the " + std::to_string(frames()) + " frames", t);
    }

    seam_cost_params<T> params_;
    matrix mismatch_, gradient_;
    T eps_ = T(0);
};

namespace detail {

/// seam_cost::edge without the range checks, for the min-cut's loops over
/// nodes that are in range by construction.
template <class T>
T seam_edge(const seam_cost<T>& cost, std::size_t r1, std::size_t t1, std::size_t r2, std::size_t t2) {
    const auto i = [](std::size_t k) { return static_cast<Eigen::Index>(k); };
    const auto& m = cost.mismatches();
    const auto& g = cost.gradients();
    return cost.capacity(m(i(r1), i(t1)) + m(i(r2), i(t2)), g(i(r1), i(t1)) + g(i(r2), i(t2)));
}

}  // namespace detail

}  // namespace anima
