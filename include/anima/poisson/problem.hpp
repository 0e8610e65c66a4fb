// A Poisson problem on a grid, nabla^2 u = f: the right-hand side, the
// Dirichlet values beyond the sides, the values of the fixed (masked-out)
// cells, and what a solver reports back.
//
// Every solver works on the same discrete system A x = b over the unknown
// cells, with A = -(5-point Laplacian) (symmetric positive definite, or
// semi-definite for pure Neumann) and b = -f plus the contributions of the
// Dirichlet values and fixed cells next to each unknown. The relative
// residual ||b - A x|| / ||b|| (2-norms) is the common stopping measure.
#pragma once

#include <anima/core/error.hpp>
#include <anima/poisson/grid.hpp>

#include <Eigen/Core>

#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

namespace anima {

/// Values of u just outside the grid on its Dirichlet sides. An empty vector
/// means zero. Neumann sides take no values: their flux is zero, and a
/// non-zero outward derivative g enters the right-hand side instead, as
/// f -= g / h on the cells next to the side.
template <class T>
struct boundary_values {
    Eigen::Matrix<T, Eigen::Dynamic, 1> top;     ///< before row 0, one per column
    Eigen::Matrix<T, Eigen::Dynamic, 1> bottom;  ///< after the last row, one per column
    Eigen::Matrix<T, Eigen::Dynamic, 1> left;    ///< before column 0, one per row
    Eigen::Matrix<T, Eigen::Dynamic, 1> right;   ///< after the last column, one per row
};

/// nabla^2 u = rhs on grid, with boundary values and fixed cells.
template <class T>
struct poisson_problem {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    poisson_grid<T> grid;
    matrix rhs;                   ///< f, rows x cols (read on unknown cells only)
    boundary_values<T> boundary;  ///< Dirichlet data
    matrix fixed;                 ///< empty (zero) or rows x cols: u on the cells outside grid.mask
};

/// A problem with the given grid and right-hand side, zero boundary values.
template <class T, class Derived>
poisson_problem<T> make_poisson_problem(poisson_grid<T> grid, const Eigen::MatrixBase<Derived>& rhs) {
    poisson_problem<T> p;
    p.grid = std::move(grid);
    p.rhs = rhs.template cast<T>();
    return p;
}

/// What a solver returns.
template <class T>
struct poisson_result {
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> u;  ///< the whole grid; fixed cells keep their values
    int iterations = 0;        ///< multigrid cycles on the finest grid (0 for a direct solve)
    T relative_residual = 0;   ///< ||b - A x|| / ||b|| of the discrete system (||A x|| when b = 0)
    bool converged = false;    ///< relative_residual reached the tolerance
    T removed_mean = 0;        ///< pure Neumann only: the mean of f that was subtracted to make it solvable
    std::vector<T> residual_history;  ///< relative residual after each cycle (multigrid)
};

/// The default stopping tolerance on the relative residual: 1e-8 in double,
/// 1e-4 in float (where rounding stops multigrid at about 2e-5 on grids from
/// 65^2 to 1025^2).
template <class T>
constexpr T default_poisson_tolerance() {
    return std::is_same<T, float>::value ? T(1e-4) : T(1e-8);
}

namespace detail {

template <class Derived>
void check_finite_matrix(const Eigen::MatrixBase<Derived>& m, const std::string& who, const char* what) {
    for (Eigen::Index j = 0; j < m.cols(); ++j)
        for (Eigen::Index i = 0; i < m.rows(); ++i)
            if (!std::isfinite(static_cast<double>(m(i, j))))
                throw invalid_argument(who + ": " + what + index_string(i, j) + " is not finite");
}

template <class T>
void check_side(const Eigen::Matrix<T, Eigen::Dynamic, 1>& v, Eigen::Index expected, boundary kind,
                const std::string& who, const char* side) {
    if (v.size() == 0) return;
    if (kind == boundary::neumann)
        throw invalid_argument(who + ": boundary." + side +
                               " has values but that side is Neumann (zero flux); put a flux into the right-hand side");
    if (v.size() != expected)
        throw invalid_argument(who + ": boundary." + side + " has " + std::to_string(v.size()) + " values, expected " +
                               std::to_string(expected));
    for (Eigen::Index k = 0; k < v.size(); ++k)
        if (!std::isfinite(static_cast<double>(v[k])))
            throw invalid_argument(who + ": boundary." + side + "[" + std::to_string(k) + "] is not finite");
}

/// A usable grid, a finite grid function `u` of its size (`described` in
/// the size message, `name` in the finite one) and boundary values that fit.
template <class T, class Derived>
void check_grid_function(const poisson_grid<T>& g, const Eigen::MatrixBase<Derived>& u, const boundary_values<T>& values,
                         const std::string& who, const char* described, const char* name) {
    check_poisson_grid(g, who);
    if (u.rows() != g.rows || u.cols() != g.cols)
        throw invalid_argument(who + ": " + described + " is " + std::to_string(u.rows()) + " x " +
                               std::to_string(u.cols()) + ", the grid " + std::to_string(g.rows) + " x " +
                               std::to_string(g.cols));
    check_finite_matrix(u, who, name);
    check_side(values.top, g.cols, g.top_bottom, who, "top");
    check_side(values.bottom, g.cols, g.top_bottom, who, "bottom");
    check_side(values.left, g.rows, g.left_right, who, "left");
    check_side(values.right, g.rows, g.left_right, who, "right");
}

/// Throws anima::invalid_argument naming `who` and the bad value unless the
/// problem is well formed: a usable grid, sizes that match it, finite data.
template <class T>
void check_poisson_problem(const poisson_problem<T>& p, const std::string& who) {
    check_grid_function(p.grid, p.rhs, p.boundary, who, "the right-hand side", "rhs");
    const auto& g = p.grid;
    if (p.fixed.size() != 0) {
        if (p.fixed.rows() != g.rows || p.fixed.cols() != g.cols)
            throw invalid_argument(who + ": the fixed values are " + std::to_string(p.fixed.rows()) + " x " +
                                   std::to_string(p.fixed.cols()) + ", the grid " + std::to_string(g.rows) + " x " +
                                   std::to_string(g.cols));
        for (Eigen::Index j = 0; j < g.cols; ++j)
            for (Eigen::Index i = 0; i < g.rows; ++i)
                if (!g.unknown(i, j) && !std::isfinite(static_cast<double>(p.fixed(i, j))))
                    throw invalid_argument(who + ": fixed" + index_string(i, j) + " is not finite");
    }
}

/// The right-hand side b of A x = b on the grid (zero on fixed cells), after
/// folding in Dirichlet values and fixed neighbours and, for a singular
/// (pure Neumann) grid, removing the mean.
template <class T>
struct folded_rhs {
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> b;
    T removed_mean = 0;
};

/// Adds the Dirichlet values' share of the 5-point stencil, value / h^2, to
/// the cells next to each Dirichlet side.
template <class T>
void add_boundary_terms(Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& b, const poisson_grid<T>& g,
                        const boundary_values<T>& bv) {
    const T cy = T(1) / (g.hy * g.hy), cx = T(1) / (g.hx * g.hx);
    if (g.top_bottom == boundary::dirichlet) {
        if (bv.top.size()) b.row(0) += cy * bv.top.transpose();
        if (bv.bottom.size()) b.row(g.rows - 1) += cy * bv.bottom.transpose();
    }
    if (g.left_right == boundary::dirichlet) {
        if (bv.left.size()) b.col(0) += cx * bv.left;
        if (bv.right.size()) b.col(g.cols - 1) += cx * bv.right;
    }
}

template <class T>
folded_rhs<T> fold_rhs(const poisson_problem<T>& p) {
    const auto& g = p.grid;
    const Eigen::Index ny = g.rows, nx = g.cols;
    const T cy = T(1) / (g.hy * g.hy), cx = T(1) / (g.hx * g.hx);
    folded_rhs<T> out;
    out.b = -p.rhs;
    auto& b = out.b;
    add_boundary_terms(b, g, p.boundary);
    if (g.masked()) {
        const bool has_fixed = p.fixed.size() != 0;
        for (Eigen::Index j = 0; j < nx; ++j)
            for (Eigen::Index i = 0; i < ny; ++i) {
                if (!g.mask(i, j)) {
                    b(i, j) = T(0);
                    continue;
                }
                if (!has_fixed) continue;
                T add = T(0);
                if (i > 0 && !g.mask(i - 1, j)) add += cy * p.fixed(i - 1, j);
                if (i + 1 < ny && !g.mask(i + 1, j)) add += cy * p.fixed(i + 1, j);
                if (j > 0 && !g.mask(i, j - 1)) add += cx * p.fixed(i, j - 1);
                if (j + 1 < nx && !g.mask(i, j + 1)) add += cx * p.fixed(i, j + 1);
                b(i, j) += add;
            }
    }
    if (g.singular()) {
        const T mean = b.mean();
        b.array() -= mean;
        out.removed_mean = -mean;  // b = -f, so f lost -mean
    }
    return out;
}

/// The checks every grid solver starts a solve with (a valid problem on the
/// grid it was built for), then the folded right-hand side.
template <class T>
folded_rhs<T> checked_fold_rhs(const poisson_problem<T>& p, const poisson_grid<T>& built_for, const std::string& who) {
    check_poisson_problem(p, who);
    if (!same_operator(p.grid, built_for))
        throw invalid_argument(who + ": the problem's grid (size, spacing, boundaries or mask) differs from the "
                                     "grid the solver was built for");
    return fold_rhs(p);
}

}  // namespace detail
}  // namespace anima
