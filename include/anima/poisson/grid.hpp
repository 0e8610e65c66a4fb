// The regular grid a Poisson problem lives on: its size, the spacing of its
// rows and columns, the boundary condition on each pair of opposite sides and
// an optional mask of the cells to solve for.
//
// The unknowns are the cells of a rows x cols matrix (row i, column j). The
// discrete operator is the standard 5-point Laplacian
//   (u(i-1,j) - 2u(i,j) + u(i+1,j)) / hy^2 + (u(i,j-1) - 2u(i,j) + u(i,j+1)) / hx^2
// where a neighbour outside the grid is
//   - for a Dirichlet side, a given value one spacing beyond the last row or
//     column (vertex-centred: the unknowns are the interior points of a grid
//     whose outermost points carry the boundary values);
//   - for a Neumann side, the cell itself (zero flux across the side:
//     cell-centred, the side lies half a spacing beyond the last cell).
// Cells outside the mask keep given values and act as Dirichlet data for
// their neighbours.
#pragma once

#include <anima/core/enum_names.hpp>
#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <string>
#include <string_view>

namespace anima {

/// The condition on a pair of opposite sides of a grid.
enum class boundary : unsigned char {
    dirichlet,  ///< u is given just outside the grid (zero unless values are supplied)
    neumann     ///< zero flux across the side; a flux enters through the right-hand side
};

template <>
struct enum_names<boundary> {
    static constexpr const char* what = "boundary condition";
    static constexpr enum_entry<boundary> entries[] = {{boundary::dirichlet, "dirichlet"},
                                                       {boundary::neumann, "neumann"}};
};

/// "dirichlet" or "neumann" (any case); throws anima::invalid_argument otherwise.
inline boundary parse_boundary(std::string_view name) {
    return parse_enum<boundary>(name, "anima::parse_boundary");
}

/// Which cells are unknown (true) and which keep fixed values (false).
using poisson_mask = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic>;

/// A rows x cols grid of unknowns with spacings, boundary conditions and an
/// optional mask. Everything a solver can precompute depends on this alone.
template <class T>
struct poisson_grid {
    Eigen::Index rows = 0;
    Eigen::Index cols = 0;
    T hy = T(1);  ///< distance between consecutive rows
    T hx = T(1);  ///< distance between consecutive columns
    boundary top_bottom = boundary::dirichlet;  ///< the sides before row 0 and after the last row
    boundary left_right = boundary::dirichlet;  ///< the sides before column 0 and after the last column
    poisson_mask mask;  ///< empty (every cell unknown) or rows x cols

    Eigen::Index cells() const noexcept { return rows * cols; }
    bool masked() const noexcept { return mask.size() != 0; }
    bool unknown(Eigen::Index i, Eigen::Index j) const { return !masked() || mask(i, j); }
    Eigen::Index unknowns() const { return masked() ? static_cast<Eigen::Index>(mask.count()) : cells(); }
    /// Pure Neumann with no fixed cell: the operator has the constants as its
    /// null space; solvers then remove the mean of the right-hand side and
    /// return the zero-mean solution.
    bool singular() const {
        return top_bottom == boundary::neumann && left_right == boundary::neumann && unknowns() == cells();
    }
};

/// A grid of rows x cols unknowns with the same boundary condition on every side.
template <class T = double>
poisson_grid<T> make_poisson_grid(Eigen::Index rows, Eigen::Index cols, boundary sides = boundary::dirichlet,
                                  T spacing = T(1)) {
    poisson_grid<T> g;
    g.rows = rows;
    g.cols = cols;
    g.hy = g.hx = spacing;
    g.top_bottom = g.left_right = sides;
    return g;
}

namespace detail {

inline std::string index_string(Eigen::Index i, Eigen::Index j) {
    return "(" + std::to_string(i) + ", " + std::to_string(j) + ")";
}

/// Throws anima::invalid_argument naming `who` unless the grid is usable.
template <class T>
void check_poisson_grid(const poisson_grid<T>& g, const std::string& who) {
    if (g.rows <= 0 || g.cols <= 0)
        throw invalid_argument(who + ": the grid is empty (" + std::to_string(g.rows) + " x " + std::to_string(g.cols) +
                               "); it needs at least one row and one column");
    if (!(g.hx > T(0)) || !(g.hy > T(0)) || !std::isfinite(g.hx) || !std::isfinite(g.hy))
        throw invalid_argument(who + ": grid spacings must be positive and finite, got hy = " +
                               detail::argument_text(g.hy) + ", hx = " +
                               detail::argument_text(g.hx));
    // The operator's coefficients are 1 / h^2: h = 1e-20 in float overflows
    // them (the Laplacian came back NaN), h = 1e25 underflows them to 0, and
    // h = 1e19 makes them subnormal (1e-38): accepted, the solvers failed
    // later with "the right-hand side is too large". A normal number only.
    const auto check_inverse_square = [&](const char* name, T h) {
        const T c = T(1) / (h * h);
        if (!(c >= std::numeric_limits<T>::min()) || !std::isfinite(c))
            throw invalid_argument(who + ": grid spacing " + name + " = " + detail::argument_text(h) +
                                   " has 1 / " + name + "^2 = " + detail::argument_text(c) +
                                   ", not finite and normal (at least " +
                                   detail::argument_text(std::numeric_limits<T>::min()) +
                                   ") in this precision: measure the grid in a larger or smaller unit");
    };
    check_inverse_square("hy", g.hy);
    check_inverse_square("hx", g.hx);
    if (g.masked() && (g.mask.rows() != g.rows || g.mask.cols() != g.cols))
        throw invalid_argument(who + ": the mask is " + std::to_string(g.mask.rows()) + " x " +
                               std::to_string(g.mask.cols()) + ", the grid " + std::to_string(g.rows) + " x " +
                               std::to_string(g.cols));
}

/// Whether two grids describe the same discrete operator.
template <class T>
bool same_operator(const poisson_grid<T>& a, const poisson_grid<T>& b) {
    if (a.rows != b.rows || a.cols != b.cols || a.hx != b.hx || a.hy != b.hy || a.top_bottom != b.top_bottom ||
        a.left_right != b.left_right || a.masked() != b.masked())
        return false;
    return !a.masked() || (a.mask == b.mask).all();
}

}  // namespace detail
}  // namespace anima
