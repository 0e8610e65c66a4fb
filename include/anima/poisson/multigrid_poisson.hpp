// Multigrid for nabla^2 u = f on a grid of any size: red-black Gauss-Seidel
// smoothing, linear interpolation, Galerkin coarse operators, V or W cycles,
// a full-multigrid start, and cycles until the relative residual reaches a
// tolerance. O(n) work per cycle and a residual reduction per cycle that does
// not depend on the grid size.
//
// The hierarchy (every coarse operator and the coarsest factorisation)
// depends only on the grid, so build one solver and call solve() for each
// right-hand side: the columns of a motion, the channels of an image.
// Levels and coarsening are described in detail/multigrid_levels.hpp; a mask
// of any shape is handled exactly (Galerkin products with interpolation
// restricted to the unknown cells).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/poisson/detail/multigrid_levels.hpp>
#include <anima/poisson/grid.hpp>
#include <anima/poisson/laplacian.hpp>
#include <anima/poisson/problem.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace anima {

/// How often a cycle visits the coarser levels: once (V) or twice (W).
enum class multigrid_cycle : unsigned char { v, w };

template <>
struct enum_names<multigrid_cycle> {
    static constexpr const char* what = "cycle";
    static constexpr enum_entry<multigrid_cycle> entries[] = {{multigrid_cycle::v, "v"}, {multigrid_cycle::w, "w"}};
};

/// "v" or "w" (any case); throws anima::invalid_argument otherwise.
inline multigrid_cycle parse_multigrid_cycle(std::string_view name) {
    return parse_enum<multigrid_cycle>(name, "anima::parse_multigrid_cycle");
}

template <class T>
class multigrid_poisson {
public:
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

    struct params {
        multigrid_cycle cycle = multigrid_cycle::v;
        int pre_sweeps = 2;   ///< red-black Gauss-Seidel sweeps before the coarse correction
        int post_sweeps = 2;  ///< and after it
        int max_cycles = 100;
        T tolerance = default_poisson_tolerance<T>();  ///< on ||b - A x|| / ||b||
        /// Start with a full-multigrid pass (coarsest solve, then one cycle on
        /// each finer level, each started from the interpolated coarser
        /// solution); it counts as one cycle.
        bool full_multigrid = true;
        /// Coarsening stops once a level has at most this many cells (or no
        /// axis of length 3 or more is left); that level is solved directly.
        Eigen::Index coarsest_cells = 64;
    };

    /// Builds the hierarchy for a grid. Throws anima::invalid_argument for an
    /// unusable grid or parameters.
    explicit multigrid_poisson(poisson_grid<T> grid, const params& prm = params())
        : grid_(std::move(grid)), prm_(prm) {
        const std::string who = "anima::multigrid_poisson";
        detail::check_poisson_grid(grid_, who);
        if (prm_.pre_sweeps < 0 || prm_.post_sweeps < 0 || prm_.pre_sweeps + prm_.post_sweeps < 1)
            throw invalid_argument(who + ": needs at least one smoothing sweep per cycle, got pre_sweeps = " +
                                   std::to_string(prm_.pre_sweeps) + ", post_sweeps = " + std::to_string(prm_.post_sweeps));
        if (prm_.max_cycles < 1)
            throw invalid_argument(who + ": max_cycles must be at least 1, got " + std::to_string(prm_.max_cycles));
        check_non_negative(who, "tolerance", prm_.tolerance);
        if (prm_.coarsest_cells < 1)
            throw invalid_argument(who + ": coarsest_cells must be at least 1, got " + std::to_string(prm_.coarsest_cells));
        build();
    }

    const poisson_grid<T>& grid() const noexcept { return grid_; }
    const params& parameters() const noexcept { return prm_; }
    /// Number of levels, the finest first.
    std::size_t levels() const noexcept { return levels_.size(); }
    /// Rows and columns of level l.
    std::pair<Eigen::Index, Eigen::Index> level_size(std::size_t l) const {
        const auto& L = levels_.at(l);
        return {L.ny, L.nx};
    }

    /// Solves the problem from a zero start. The problem's grid must be the
    /// one the solver was built for. Not thread-safe on one object (it reuses
    /// its work arrays): use one solver per thread.
    poisson_result<T> solve(const poisson_problem<T>& p) { return run(p, nullptr); }

    /// Solves starting from `initial_guess` (read on the unknown cells).
    template <class Derived>
    poisson_result<T> solve(const poisson_problem<T>& p, const Eigen::MatrixBase<Derived>& initial_guess) {
        const std::string who = "anima::multigrid_poisson::solve";
        if (initial_guess.rows() != grid_.rows || initial_guess.cols() != grid_.cols)
            throw invalid_argument(who + ": the initial guess is " + std::to_string(initial_guess.rows()) + " x " +
                                   std::to_string(initial_guess.cols()) + ", the grid " + std::to_string(grid_.rows) +
                                   " x " + std::to_string(grid_.cols));
        detail::check_finite_matrix(initial_guess, who, "initial_guess");
        const matrix guess = initial_guess.template cast<T>();
        return run(p, &guess);
    }

private:
    using level = detail::mg::level<T>;
    using index = Eigen::Index;

    void build();

    // One cycle on level l; returns ||b - A u||^2 afterwards when `norm`.
    T cycle(std::size_t l, bool norm);

    poisson_result<T> run(const poisson_problem<T>& p, const matrix* guess);

    // Restricts the residual of the start down the hierarchy, solves the
    // coarsest level, and works back up with one cycle per level, each
    // started from the interpolated coarser solution. Returns the squared
    // residual norm on level 0 afterwards.
    T full_multigrid_pass();

    poisson_grid<T> grid_;
    params prm_;
    std::vector<level> levels_;
    // The hierarchy is built for the spacings divided by 2^spacing_exponent_
    // (the smaller one in [0.5, 1)): exact, the same arithmetic scaled, and
    // no coarse level's 1 / h^2 near underflow (float h = 4e18 made the
    // scaled solution overflow, reported as "the right-hand side is too
    // large" for a right-hand side of 1e-20). run() scales u to match.
    int spacing_exponent_ = 0;
    detail::mg::coarse_solver<T> coarse_;
    std::vector<T> ring_;
};

// The heavy members are defined out of the class body so that builds
// compiling anima's instantiations once (poisson/instances.hpp) can declare
// them extern: clang instantiates members defined in the class wherever
// they are used.
template <class T>
void multigrid_poisson<T>::build() {
    using detail::mg::at;
    const bool masked = grid_.masked();
    const bool y_neu = grid_.top_bottom == boundary::neumann, x_neu = grid_.left_right == boundary::neumann;
    levels_.clear();
    levels_.emplace_back();
    level& f = levels_.back();
    f.first = true;
    f.ny = grid_.rows;
    f.nx = grid_.cols;
    f.ld = f.ny + 2;
    std::frexp(std::min(grid_.hy, grid_.hx), &spacing_exponent_);
    f.hy = std::ldexp(grid_.hy, -spacing_exponent_);
    f.hx = std::ldexp(grid_.hx, -spacing_exponent_);
    for (index i = 0; i < f.ny; ++i) f.ypos.push_back(static_cast<double>(i));
    for (index j = 0; j < f.nx; ++j) f.xpos.push_back(static_cast<double>(j));
    f.cy = T(1) / (f.hy * f.hy);
    f.cx = T(1) / (f.hx * f.hx);
    const auto diagonal_1d = [](index n, T c, bool neumann) {
        std::vector<T> d(at(n + 2), T(0));
        for (index i = 0; i < n; ++i) {
            // Two neighbours, less the ones beyond a Neumann side.
            int k = 2;
            if (neumann && i == 0) --k;
            if (neumann && i == n - 1) --k;
            d[at(i + 1)] = c * T(k);
        }
        return d;
    };
    f.dy = diagonal_1d(f.ny, f.cy, y_neu);
    f.dx = diagonal_1d(f.nx, f.cx, x_neu);
    if (masked) {
        f.active.assign(at(f.size()), 0);
        for (index j = 0; j < f.nx; ++j)
            for (index i = 0; i < f.ny; ++i) f.active[at(f.at2(i, j))] = grid_.mask(i, j) ? 1 : 0;
    } else {
        const auto factors = [](const std::vector<T>& d, index n, T c, detail::mg::tridiagonal<T>& k,
                                detail::mg::tridiagonal<T>& m) {
            k.d.assign(d.begin() + 1, d.begin() + 1 + n);
            k.l.assign(at(n), -c);
            k.l[0] = T(0);
            m.d.assign(at(n), T(1));
            m.l.assign(at(n), T(0));
        };
        factors(f.dy, f.ny, f.cy, f.ky, f.my);
        factors(f.dx, f.nx, f.cx, f.kx, f.mx);
    }
    detail::mg::first_level_classes(f);
    if (grid_.unknowns() > 0) {
        for (;;) {
            level& L = levels_.back();
            const bool can_y = L.ny >= 3, can_x = L.nx >= 3;
            if ((!can_y && !can_x) || L.ny * L.nx <= prm_.coarsest_cells) break;
            const T hmin = can_y && can_x ? std::min(L.hy, L.hx) : can_y ? L.hy : L.hx;
            const T limit = hmin * T(1.4142135623730951);
            const bool cy = can_y && L.hy <= limit, cx = can_x && L.hx <= limit;
            const auto hi_y = static_cast<double>(grid_.rows), hi_x = static_cast<double>(grid_.cols);
            L.ymap = detail::mg::make_axis_map<T>(L.ypos, -1.0, hi_y, cy, y_neu);
            L.xmap = detail::mg::make_axis_map<T>(L.xpos, -1.0, hi_x, cx, x_neu);
            level c;
            c.ny = L.ymap.coarse;
            c.nx = L.xmap.coarse;
            c.ld = c.ny + 2;
            c.hy = cy ? 2 * L.hy : L.hy;
            c.hx = cx ? 2 * L.hx : L.hx;
            // Coarse point k sits on fine point 2k + 1.
            for (index k = 0; k < c.ny; ++k) c.ypos.push_back(cy ? L.ypos[at(2 * k + 1)] : L.ypos[at(k)]);
            for (index k = 0; k < c.nx; ++k) c.xpos.push_back(cx ? L.xpos[at(2 * k + 1)] : L.xpos[at(k)]);
            if (masked) {
                detail::mg::galerkin_2d(L, c);
                detail::mg::finish_stored_level(c, true);
            } else {
                c.ky = detail::mg::galerkin_1d(L.ky, L.ymap);
                c.my = detail::mg::galerkin_1d(L.my, L.ymap);
                c.kx = detail::mg::galerkin_1d(L.kx, L.xmap);
                c.mx = detail::mg::galerkin_1d(L.mx, L.xmap);
                // The stencil as a few column vectors; stored in full
                // only if the factors vary along the columns.
                if (!detail::mg::tensor_classes(c, 16)) {
                    detail::mg::stencil_from_factors(c);
                    detail::mg::finish_stored_level(c, false);
                }
            }
            levels_.push_back(std::move(c));
        }
    }
    for (auto& L : levels_) {
        L.u.assign(at(L.size()), T(0));
        L.b = L.u;
    }
    coarse_.factor(levels_.back(), grid_.singular());
}

template <class T>
T multigrid_poisson<T>::cycle(std::size_t l, bool norm) {
    using namespace detail::mg;
    level& L = levels_[l];
    if (l + 1 == levels_.size()) {
        coarse_.solve(L);
        return norm ? residual_norm2(L) : T(0);
    }
    level& c = levels_[l + 1];
    presmooth_restrict(L, c, prm_.pre_sweeps, ring_);
    std::fill(c.u.begin(), c.u.end(), T(0));
    const int visits = prm_.cycle == multigrid_cycle::w && l + 2 < levels_.size() ? 2 : 1;
    for (int k = 0; k < visits; ++k) cycle(l + 1, false);
    return prolong_postsmooth(c, L, prm_.post_sweeps, norm, ring_);
}

template <class T>
poisson_result<T> multigrid_poisson<T>::run(const poisson_problem<T>& p, const matrix* guess) {
    using detail::mg::at;
    const std::string who = "anima::multigrid_poisson::solve";
    const auto folded = detail::checked_fold_rhs(p, grid_, who);
    poisson_result<T> res;
    res.removed_mean = folded.removed_mean;
    level& f = levels_.front();
    std::fill(f.u.begin(), f.u.end(), T(0));
    std::fill(f.b.begin(), f.b.end(), T(0));
    // The cycles run on b and u scaled by 2^-e, b's largest entry in
    // [0.5, 1): the system is linear and the scaling exact, and the squared
    // norms neither underflow (a float b of 1e-25 read as zero) nor overflow.
    // With the hierarchy's spacings divided by 2^s its operator is 2^2s A,
    // so its solution for b 2^-e is u 2^-(e + 2s).
    int e = 0;
    if (folded.b.size()) std::frexp(folded.b.cwiseAbs().maxCoeff(), &e);
    const int ue = e + 2 * spacing_exponent_;
    for (index j = 0; j < f.nx; ++j)
        for (index i = 0; i < f.ny; ++i) {
            const auto k = at(f.at2(i, j));
            if (!grid_.unknown(i, j)) continue;
            f.b[k] = std::ldexp(folded.b(i, j), -e);
            if (guess) f.u[k] = std::ldexp((*guess)(i, j), -ue);
        }
    using column = Eigen::Matrix<T, Eigen::Dynamic, 1>;
    const T bnorm = Eigen::Map<const column>(f.b.data(), static_cast<index>(f.b.size())).norm();
    if (bnorm > T(0) && grid_.unknowns() > 0) {
        T r = T(0);
        if (levels_.size() == 1) {
            coarse_.solve(f);
            res.iterations = 1;
            r = std::sqrt(detail::mg::residual_norm2(f)) / bnorm;
            res.residual_history.push_back(r);
        } else {
            if (prm_.full_multigrid) {
                r = std::sqrt(full_multigrid_pass()) / bnorm;
                res.iterations = 1;
                res.residual_history.push_back(r);
            } else {
                r = std::sqrt(detail::mg::residual_norm2(f)) / bnorm;
            }
            int slow = 0;
            while (r > prm_.tolerance && res.iterations < prm_.max_cycles && std::isfinite(r)) {
                const T next = std::sqrt(cycle(0, true)) / bnorm;
                ++res.iterations;
                res.residual_history.push_back(next);
                // Rounding floor (e.g. float on a large grid): stop when
                // three cycles in a row gain less than 5% each.
                slow = next >= T(0.95) * r ? slow + 1 : 0;
                r = next;
                if (slow >= 3) break;
            }
        }
        if (!std::isfinite(r))
            throw error(who + ": the residual became non-finite (the right-hand side is too large for the scalar type)");
        res.relative_residual = r;
    } else {
        std::fill(f.u.begin(), f.u.end(), T(0));
    }
    res.converged = res.relative_residual <= prm_.tolerance;
    res.u = p.fixed.size() ? p.fixed : matrix::Zero(grid_.rows, grid_.cols);
    T sum = T(0);  // of the scaled values, which cannot overflow
    for (index j = 0; j < f.nx; ++j)
        for (index i = 0; i < f.ny; ++i)
            if (grid_.unknown(i, j)) {
                res.u(i, j) = std::ldexp(f.u[at(f.at2(i, j))], ue);
                sum += f.u[at(f.at2(i, j))];
            }
    if (grid_.singular()) res.u.array() -= std::ldexp(sum / static_cast<T>(grid_.cells()), ue);
    if (!res.u.allFinite())
        throw error(who + ": the solution is not finite (the right-hand side is too large for the scalar type)");
    return res;
}

template <class T>
T multigrid_poisson<T>::full_multigrid_pass() {
    using namespace detail::mg;
    const std::size_t last = levels_.size() - 1;
    // With u = 0 on the coarse levels, "residual and restrict" restricts b.
    presmooth_restrict(levels_[0], levels_[1], 0, ring_);
    for (std::size_t l = 1; l < last; ++l) {
        std::fill(levels_[l].u.begin(), levels_[l].u.end(), T(0));
        presmooth_restrict(levels_[l], levels_[l + 1], 0, ring_);
    }
    coarse_.solve(levels_[last]);
    for (std::size_t l = last; l-- > 0;) {
        if (l > 0) std::fill(levels_[l].u.begin(), levels_[l].u.end(), T(0));
        for (index j = 0; j < levels_[l].nx; ++j) prolong_column(levels_[l + 1], levels_[l], j, ring_);
        if (l > 0) cycle(l, false);
    }
    return cycle(0, true);
}

/// Builds a multigrid solver for the problem's grid and solves it once.
template <class T>
poisson_result<T> solve_poisson_multigrid(const poisson_problem<T>& p,
                                          const typename multigrid_poisson<T>::params& prm = {}) {
    detail::check_poisson_problem(p, "anima::solve_poisson_multigrid");
    multigrid_poisson<T> mg(p.grid, prm);
    return mg.solve(p);
}

}  // namespace anima
