// The discrete operator itself: the 5-point Laplacian of a grid function,
// the residual of a candidate solution, and the assembled sparse system for
// general-purpose solvers (Eigen's direct and iterative solvers, used by the
// tests and benchmarks as independent references).
#pragma once

#include <anima/core/error.hpp>
#include <anima/poisson/grid.hpp>
#include <anima/poisson/problem.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cmath>
#include <string>
#include <vector>

namespace anima {

namespace detail {

/// y = A x for A = -(5-point Laplacian) with homogeneous boundary data,
/// restricted to the unknown cells: x is read, and y written, on unknown
/// cells only (zero elsewhere).
template <class T, class Derived>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> apply_operator(const poisson_grid<T>& g,
                                                                const Eigen::MatrixBase<Derived>& x) {
    const Eigen::Index ny = g.rows, nx = g.cols;
    const T cy = T(1) / (g.hy * g.hy), cx = T(1) / (g.hx * g.hx);
    const bool ny_neu = g.top_bottom == boundary::neumann, nx_neu = g.left_right == boundary::neumann;
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> y(ny, nx);
    const auto in = [&](Eigen::Index i, Eigen::Index j) { return g.unknown(i, j); };
    for (Eigen::Index j = 0; j < nx; ++j)
        for (Eigen::Index i = 0; i < ny; ++i) {
            if (!in(i, j)) {
                y(i, j) = T(0);
                continue;
            }
            const T c = x(i, j);
            T s = T(0);
            // Each neighbour inside the grid couples; one outside does so only
            // on a Dirichlet side (its value is data, zero here).
            if (i > 0) s += cy * (c - (in(i - 1, j) ? T(x(i - 1, j)) : T(0)));
            else if (!ny_neu) s += cy * c;
            if (i + 1 < ny) s += cy * (c - (in(i + 1, j) ? T(x(i + 1, j)) : T(0)));
            else if (!ny_neu) s += cy * c;
            if (j > 0) s += cx * (c - (in(i, j - 1) ? T(x(i, j - 1)) : T(0)));
            else if (!nx_neu) s += cx * c;
            if (j + 1 < nx) s += cx * (c - (in(i, j + 1) ? T(x(i, j + 1)) : T(0)));
            else if (!nx_neu) s += cx * c;
            y(i, j) = s;
        }
    return y;
}

/// ||b - A x|| / ||b|| with b folded from the problem; when b = 0 (a
/// homogeneous problem, whose solution is 0) the absolute residual ||A x||:
/// 0 for x = 0, never the infinity of a division by zero.
/// stableNorm: the plain sum of squares overflows for a float b of 1e18 on
/// a 100 x 100 grid (NaN) and underflows to 0 for one of 1e-25.
template <class T, class Derived>
T relative_residual_of(const poisson_problem<T>& p, const folded_rhs<T>& f, const Eigen::MatrixBase<Derived>& u) {
    const T bn = f.b.stableNorm();
    const T rn = (f.b - apply_operator(p.grid, u)).stableNorm();
    return bn == T(0) ? rn : rn / bn;
}

}  // namespace detail

/// nabla^2 u on every cell of the grid (the mask is ignored: every cell is a
/// value), with the neighbours outside the grid taken from `values` on
/// Dirichlet sides (zero where empty) and equal to the cell on Neumann sides.
template <class T, class Derived>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> laplacian(const poisson_grid<T>& g, const Eigen::MatrixBase<Derived>& u,
                                                           const boundary_values<T>& values = {}) {
    const std::string who = "anima::laplacian";
    detail::check_grid_function(g, u, values, who, "u", "u");
    poisson_grid<T> plain = g;
    plain.mask.resize(0, 0);
    // L u = b_boundary - A u, A = -L with homogeneous data.
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> out = -detail::apply_operator(plain, u.template cast<T>());
    detail::add_boundary_terms(out, plain, values);
    return out;
}

/// The relative residual ||b - A x|| / ||b|| of u (its unknown cells) for the
/// problem's discrete system, the measure every solver stops on. When the
/// folded right-hand side b is zero it is the absolute residual ||A x||
/// (0 when u is zero on the unknowns too): the solvers return u = 0 there,
/// with a residual of 0.
template <class T, class Derived>
T relative_residual(const poisson_problem<T>& p, const Eigen::MatrixBase<Derived>& u) {
    detail::check_poisson_problem(p, "anima::relative_residual");
    if (u.rows() != p.grid.rows || u.cols() != p.grid.cols)
        throw invalid_argument("anima::relative_residual: u is " + std::to_string(u.rows()) + " x " +
                               std::to_string(u.cols()) + ", the grid " + std::to_string(p.grid.rows) + " x " +
                               std::to_string(p.grid.cols));
    detail::check_finite_matrix(u, "anima::relative_residual", "u");
    return detail::relative_residual_of(p, detail::fold_rhs(p), u.template cast<T>());
}

/// The discrete system A x = b over the unknown cells, assembled.
template <class T>
struct poisson_system {
    Eigen::SparseMatrix<T> A;                   ///< -(5-point Laplacian), symmetric positive (semi-)definite
    Eigen::Matrix<T, Eigen::Dynamic, 1> b;      ///< folded right-hand side
    std::vector<Eigen::Index> cells;            ///< unknown k is cell cells[k] = i + j * rows (column-major)
    T removed_mean = 0;                         ///< see poisson_result::removed_mean
};

/// Assembles the problem's discrete system (for direct or Krylov solvers).
template <class T>
poisson_system<T> assemble_poisson_system(const poisson_problem<T>& p) {
    detail::check_poisson_problem(p, "anima::assemble_poisson_system");
    const auto& g = p.grid;
    const Eigen::Index ny = g.rows, nx = g.cols;
    const T cy = T(1) / (g.hy * g.hy), cx = T(1) / (g.hx * g.hx);
    const bool ny_neu = g.top_bottom == boundary::neumann, nx_neu = g.left_right == boundary::neumann;
    std::vector<Eigen::Index> index(static_cast<std::size_t>(ny * nx), -1);
    poisson_system<T> s;
    for (Eigen::Index j = 0; j < nx; ++j)
        for (Eigen::Index i = 0; i < ny; ++i)
            if (g.unknown(i, j)) {
                index[static_cast<std::size_t>(i + j * ny)] = static_cast<Eigen::Index>(s.cells.size());
                s.cells.push_back(i + j * ny);
            }
    const auto n = static_cast<Eigen::Index>(s.cells.size());
    std::vector<Eigen::Triplet<T>> entries;
    entries.reserve(static_cast<std::size_t>(5 * n));
    for (Eigen::Index k = 0; k < n; ++k) {
        const Eigen::Index cell = s.cells[static_cast<std::size_t>(k)];
        const Eigen::Index i = cell % ny, j = cell / ny;
        T diag = T(0);
        const auto couple = [&](Eigen::Index ii, Eigen::Index jj, T c, bool outside_couples) {
            if (ii < 0 || ii >= ny || jj < 0 || jj >= nx) {
                if (outside_couples) diag += c;
                return;
            }
            diag += c;
            const Eigen::Index other = index[static_cast<std::size_t>(ii + jj * ny)];
            if (other >= 0) entries.emplace_back(k, other, -c);
        };
        couple(i - 1, j, cy, !ny_neu);
        couple(i + 1, j, cy, !ny_neu);
        couple(i, j - 1, cx, !nx_neu);
        couple(i, j + 1, cx, !nx_neu);
        entries.emplace_back(k, k, diag);
    }
    s.A.resize(n, n);
    s.A.setFromTriplets(entries.begin(), entries.end());
    const auto folded = detail::fold_rhs(p);
    s.b.resize(n);
    for (Eigen::Index k = 0; k < n; ++k) s.b[k] = folded.b(s.cells[static_cast<std::size_t>(k)] % ny, s.cells[static_cast<std::size_t>(k)] / ny);
    s.removed_mean = folded.removed_mean;
    return s;
}

/// The grid function with x on the unknown cells and the problem's fixed
/// values elsewhere.
template <class T, class Derived>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> expand_solution(const poisson_problem<T>& p,
                                                                 const poisson_system<T>& s,
                                                                 const Eigen::MatrixBase<Derived>& x) {
    if (x.size() != static_cast<Eigen::Index>(s.cells.size()))
        throw invalid_argument("anima::expand_solution: x has " + std::to_string(x.size()) + " entries, the system " +
                               std::to_string(s.cells.size()) + " unknowns");
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> u =
        p.fixed.size() ? p.fixed : Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>::Zero(p.grid.rows, p.grid.cols);
    for (std::size_t k = 0; k < s.cells.size(); ++k) u.data()[s.cells[k]] = x[static_cast<Eigen::Index>(k)];
    return u;
}

}  // namespace anima
