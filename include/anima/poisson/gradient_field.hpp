// Gradient fields on the faces of a grid and their divergence: the
// right-hand side of gradient-domain problems (Eq 14: nabla^2 u = div G).
//
// gx lives on the faces between horizontally adjacent cells, gy on those
// between vertically adjacent cells, including the faces on the grid's
// sides. With forward differences and the same boundary rules as the
// Laplacian, divergence(gradient(u)) is exactly laplacian(u), so solving
// nabla^2 u = divergence(G) with the same boundary data gives back u when
// G = gradient(u), and the least-squares fit to G otherwise.
#pragma once

#include <anima/core/error.hpp>
#include <anima/poisson/grid.hpp>
#include <anima/poisson/problem.hpp>

#include <Eigen/Core>

#include <string>

namespace anima {

/// A vector field on the faces of a rows x cols grid.
template <class T>
struct gradient_field {
    /// rows x (cols + 1): gx(i, j) lies between cells (i, j - 1) and (i, j);
    /// columns 0 and cols are the faces on the left and right sides.
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> gx;
    /// (rows + 1) x cols: gy(i, j) lies between cells (i - 1, j) and (i, j);
    /// rows 0 and rows are the faces on the top and bottom sides.
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> gy;
};

/// Forward differences of u divided by the spacing: gx(i, j) = (u(i, j) -
/// u(i, j - 1)) / hx. Beyond a Dirichlet side u is the boundary value (zero
/// where `values` is empty); the faces on a Neumann side are zero (no flux).
/// The mask is ignored.
template <class T, class Derived>
gradient_field<T> gradient(const poisson_grid<T>& g, const Eigen::MatrixBase<Derived>& u,
                           const boundary_values<T>& values = {}) {
    const std::string who = "anima::gradient";
    detail::check_grid_function(g, u, values, who, "u", "u");
    const Eigen::Index ny = g.rows, nx = g.cols;
    const T ix = T(1) / g.hx, iy = T(1) / g.hy;
    gradient_field<T> out;
    out.gx.setZero(ny, nx + 1);
    out.gy.setZero(ny + 1, nx);
    const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> v = u.template cast<T>();
    if (nx > 1) out.gx.middleCols(1, nx - 1) = (v.rightCols(nx - 1) - v.leftCols(nx - 1)) * ix;
    if (ny > 1) out.gy.middleRows(1, ny - 1) = (v.bottomRows(ny - 1) - v.topRows(ny - 1)) * iy;
    if (g.left_right == boundary::dirichlet) {
        out.gx.col(0) = v.col(0) * ix;
        out.gx.col(nx) = -v.col(nx - 1) * ix;
        if (values.left.size()) out.gx.col(0) -= values.left * ix;
        if (values.right.size()) out.gx.col(nx) += values.right * ix;
    }
    if (g.top_bottom == boundary::dirichlet) {
        out.gy.row(0) = v.row(0) * iy;
        out.gy.row(ny) = -v.row(ny - 1) * iy;
        if (values.top.size()) out.gy.row(0) -= values.top.transpose() * iy;
        if (values.bottom.size()) out.gy.row(ny) += values.bottom.transpose() * iy;
    }
    return out;
}

/// (gx(i, j + 1) - gx(i, j)) / hx + (gy(i + 1, j) - gy(i, j)) / hy on every
/// cell: the right-hand side f of nabla^2 u = div G. On a Neumann side the
/// side faces of G act as the prescribed flux (zero for the natural
/// condition).
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> divergence(const poisson_grid<T>& g, const gradient_field<T>& field) {
    const std::string who = "anima::divergence";
    detail::check_poisson_grid(g, who);
    const Eigen::Index ny = g.rows, nx = g.cols;
    if (field.gx.rows() != ny || field.gx.cols() != nx + 1 || field.gy.rows() != ny + 1 || field.gy.cols() != nx)
        throw invalid_argument(who + ": the field has gx " + std::to_string(field.gx.rows()) + " x " +
                               std::to_string(field.gx.cols()) + " and gy " + std::to_string(field.gy.rows()) + " x " +
                               std::to_string(field.gy.cols()) + "; a " + std::to_string(ny) + " x " +
                               std::to_string(nx) + " grid needs " + std::to_string(ny) + " x " +
                               std::to_string(nx + 1) + " and " + std::to_string(ny + 1) + " x " + std::to_string(nx));
    detail::check_finite_matrix(field.gx, who, "gx");
    detail::check_finite_matrix(field.gy, who, "gy");
    return (field.gx.rightCols(nx) - field.gx.leftCols(nx)) / g.hx +
           (field.gy.bottomRows(ny) - field.gy.topRows(ny)) / g.hy;
}

}  // namespace anima
