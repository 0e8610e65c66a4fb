// The fast Poisson solver for a rectangular grid without a mask. The sine
// transform (DST-I) diagonalises the 5-point Laplacian along a Dirichlet axis
// and the cosine transform (DCT-II, inverse DCT-III) along a Neumann axis.
// Transforming the columns (along y) splits the problem into one tridiagonal
// system along x per y-frequency k,
//   (lambda_k + Kx) v_k = (transformed b)_k,
// solved by elimination for all k at once (Hockney's method: half the
// transforms of a 2D transform, no transposes). O(n log n) for any size,
// exact up to rounding, no iterations.
//
// The low frequencies are the delicate part: lambda_0 ~ (pi / n)^2 is tiny
// next to the diagonal 2 / hx^2, and a plain elimination that adds the two
// loses lambda's digits (1e-3 relative error in float on a 1025^2 grid). The
// elimination here carries e_j = 1 - (the eliminated upper coefficient),
// which satisfies e_j = (lambda + e_{j-1} / hx^2) / (pivot), so lambda is
// only ever added to quantities of its own size.
//
// Eigenvalues of -(second difference) / h^2 on n points:
//   Dirichlet: 4 sin^2(pi (k+1) / (2(n+1))) / h^2,  k = 0..n-1
//   Neumann:   4 sin^2(pi k / (2n)) / h^2  (k = 0 is the constant mode; with
//              Neumann on both axes its system is singular and is solved for
//              the zero-mean solution)
#pragma once

#include <anima/core/error.hpp>
#include <anima/poisson/grid.hpp>
#include <anima/poisson/laplacian.hpp>
#include <anima/poisson/problem.hpp>
#include <anima/poisson/real_transforms.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>

namespace anima {

namespace detail {

/// Eigenvalues of -(second difference) / h^2 in the transform's basis.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, 1> laplacian_eigenvalues(Eigen::Index n, T h, boundary b) {
    const double pi = 3.14159265358979323846264338327950288;
    Eigen::Matrix<T, Eigen::Dynamic, 1> lam(n);
    const double c = 4.0 / (static_cast<double>(h) * static_cast<double>(h));
    for (Eigen::Index k = 0; k < n; ++k) {
        const double s = b == boundary::dirichlet ? std::sin(pi * static_cast<double>(k + 1) / (2.0 * static_cast<double>(n + 1)))
                                                  : std::sin(pi * static_cast<double>(k) / (2.0 * static_cast<double>(n)));
        lam[k] = static_cast<T>(c * s * s);
    }
    return lam;
}

}  // namespace detail

template <class T>
class dst_poisson {
public:
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

    struct params {
        /// Evaluate the relative residual of the result (one operator
        /// application, about a tenth of the solve).
        bool compute_residual = true;
    };

    /// Plans the transforms for a grid. Throws anima::invalid_argument for an
    /// unusable grid or one with a mask (use multigrid_poisson for masks).
    explicit dst_poisson(poisson_grid<T> grid, const params& prm = params()) : grid_(std::move(grid)), prm_(prm) {
        const std::string who = "anima::dst_poisson";
        detail::check_poisson_grid(grid_, who);
        if (grid_.masked())
            throw invalid_argument(who + ": the transforms need the whole rectangle; a grid with a mask needs "
                                         "multigrid_poisson");
        if (grid_.rows > 1) {  // a length-1 transform and its inverse cancel
            const bool d = grid_.top_bottom == boundary::dirichlet;
            fy_.emplace(d ? real_transform_kind::dst1 : real_transform_kind::dct2, grid_.rows);
            iy_.emplace(d ? real_transform_kind::dst1 : real_transform_kind::dct3, grid_.rows);
            scale_ = T(1) / static_cast<T>(d ? 2 * (grid_.rows + 1) : 2 * grid_.rows);
        }
        // The solve runs on the spacings divided by 2^spacing_exponent_ (the
        // smaller one in [0.5, 1)): exact, and the low eigenvalues
        // (pi / n)^2 / h^2 stay normal (float h = 4e18 on a 64-row grid made
        // them subnormal: "the solution is not finite").
        std::frexp(std::min(grid_.hy, grid_.hx), &spacing_exponent_);
        hx_ = std::ldexp(grid_.hx, -spacing_exponent_);
        lam_y_ = detail::laplacian_eigenvalues(grid_.rows, std::ldexp(grid_.hy, -spacing_exponent_), grid_.top_bottom);
    }

    const poisson_grid<T>& grid() const noexcept { return grid_; }

    /// Solves the problem (its grid must be the one the solver was planned
    /// for). Safe to call from several threads on one object.
    poisson_result<T> solve(const poisson_problem<T>& p) const {
        const std::string who = "anima::dst_poisson::solve";
        const auto folded = detail::checked_fold_rhs(p, grid_, who);
        poisson_result<T> res;
        res.removed_mean = folded.removed_mean;
        matrix b = folded.b;
        if (fy_) fy_->apply_columns(b);
        solve_rows(b);
        if (iy_) iy_->apply_columns(b);
        // The scaled operator is 2^2s A: its solution is u 2^-2s. One
        // multiplication by scale_ 2^2s when that factor is a normal number
        // (exact, and the same result as two: a pass of ldexp per cell made
        // the solve 15-20 % slower); two steps only for spacings so small
        // that the factor would lose bits as a subnormal.
        const T factor = std::ldexp(scale_, 2 * spacing_exponent_);
        if (factor >= std::numeric_limits<T>::min() && factor <= std::numeric_limits<T>::max()) {
            b *= factor;
        } else {
            b *= scale_;
            b = b.unaryExpr([s = 2 * spacing_exponent_](T v) { return std::ldexp(v, s); });
        }
        if (!b.allFinite())
            throw error(who + ": the solution is not finite (the right-hand side is too large for the scalar type)");
        if (prm_.compute_residual) res.relative_residual = detail::relative_residual_of(p, folded, b);
        res.converged = true;
        res.u = std::move(b);
        return res;
    }

private:
    // (lambda_k + Kx) v = row k of b for every k, in place: elimination along
    // x, a column at a time for all k (contiguous, vectorisable).
    void solve_rows(matrix& b) const {
        const Eigen::Index ny = b.rows(), nx = b.cols();
        const T cx = T(1) / (hx_ * hx_);
        const bool x_neu = grid_.left_right == boundary::neumann;
        // Neighbours of column j inside the grid or on a Dirichlet side.
        const auto couplings = [&](Eigen::Index j) {
            int k = 2;
            if (x_neu && j == 0) --k;
            if (x_neu && j == nx - 1) --k;
            return T(k);
        };
        // Pure Neumann: the k = 0 system is singular (its right-hand side sums
        // to zero); solved separately below.
        const bool singular = grid_.singular();
        const Eigen::Matrix<T, 1, Eigen::Dynamic> row0 = b.row(0);
        // Pivot_j = lambda + (couplings_j - 1) cx + cx e_{j-1} (e_{-1} = 1),
        // upper coefficient cx / pivot_j = 1 - e_j.
        matrix e(ny, nx);
        for (Eigen::Index j = 0; j < nx; ++j) {
            const T kj = couplings(j);
            T* bj = &b(0, j);
            T* ej = &e(0, j);
            const T* bp = j > 0 ? &b(0, j - 1) : nullptr;
            const T* ep = j > 0 ? &e(0, j - 1) : nullptr;
            for (Eigen::Index k = 0; k < ny; ++k) {
                const T lam = lam_y_[k];
                const T prev_e = ep ? ep[k] : T(1);
                const T num = lam + (kj - T(2)) * cx + cx * prev_e;  // pivot - cx
                const T pivot = num + cx;
                const T m = pivot != T(0) ? T(1) / pivot : T(0);
                ej[k] = num * m;
                bj[k] = (bj[k] + (bp ? cx * bp[k] : T(0))) * m;
            }
        }
        // v_j = d_j + (1 - e_j) v_{j+1}
        for (Eigen::Index j = nx - 1; j-- > 0;) {
            T* bj = &b(0, j);
            const T* bn = &b(0, j + 1);
            const T* ej = &e(0, j);
            for (Eigen::Index k = 0; k < ny; ++k) bj[k] += bn[k] - ej[k] * bn[k];
        }
        if (singular) {
            // Zero-flux 1D problem: the flux out of cells 0..j balances their
            // sources, cx (v_j - v_j+1) = sum_{m <= j} r_m; then zero mean.
            T flux = T(0), v = T(0), sum = T(0);
            for (Eigen::Index j = 0; j < nx; ++j) {
                b(0, j) = v;
                sum += v;
                flux += row0[j];
                v -= flux / cx;
            }
            b.row(0).array() -= sum / static_cast<T>(nx);
        }
    }

    poisson_grid<T> grid_;
    params prm_;
    std::optional<real_transform<T>> fy_, iy_;
    Eigen::Matrix<T, Eigen::Dynamic, 1> lam_y_;
    T scale_ = 1;
    int spacing_exponent_ = 0;
    T hx_ = 1;  ///< grid_.hx / 2^spacing_exponent_
};

/// Plans a DST solver for the problem's grid and solves it once.
template <class T>
poisson_result<T> solve_poisson_dst(const poisson_problem<T>& p, const typename dst_poisson<T>::params& prm = {}) {
    detail::check_poisson_problem(p, "anima::solve_poisson_dst");
    return dst_poisson<T>(p.grid, prm).solve(p);
}

}  // namespace anima
