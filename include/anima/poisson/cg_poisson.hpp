// Conjugate gradients on the assembled 5-point system: the Krylov reference
// the multigrid and sine-transform solvers are measured against (O(n^1.5)
// work on a square grid, against multigrid's O(n)). Eigen's sparse CG,
// optionally preconditioned by an incomplete Cholesky factor.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/poisson/grid.hpp>
#include <anima/poisson/laplacian.hpp>
#include <anima/poisson/problem.hpp>

#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include <cmath>
#include <string>

namespace anima {

enum class cg_preconditioner : unsigned char {
    diagonal,              ///< Jacobi (Eigen's default)
    incomplete_cholesky,   ///< IC(0)-like factor: fewer iterations, a costlier setup
};

template <>
struct enum_names<cg_preconditioner> {
    static constexpr const char* what = "preconditioner";
    static constexpr enum_entry<cg_preconditioner> entries[] = {
        {cg_preconditioner::diagonal, "diagonal"}, {cg_preconditioner::incomplete_cholesky, "incomplete_cholesky"}};
};

template <class T>
class cg_poisson {
public:
    struct params {
        T tolerance = default_poisson_tolerance<T>();  ///< on ||b - A x|| / ||b||
        int max_iterations = 0;                        ///< 0: Eigen's default (twice the unknowns)
        cg_preconditioner preconditioner = cg_preconditioner::diagonal;
    };

    /// Assembles and factors the problem's system (the setup). Throws
    /// anima::invalid_argument for a bad problem or parameters.
    explicit cg_poisson(const poisson_problem<T>& p, const params& prm = params())
        : problem_(p), prm_(prm), system_(assemble_poisson_system(p)) {
        const std::string who = "anima::cg_poisson";
        check_positive(who, "tolerance", prm_.tolerance);
        if (prm_.max_iterations < 0)
            throw invalid_argument(who + ": max_iterations must not be negative, got " +
                                   std::to_string(prm_.max_iterations));
        const auto setup = [&](auto& cg) {
            cg.setTolerance(prm_.tolerance);
            if (prm_.max_iterations > 0) cg.setMaxIterations(prm_.max_iterations);
            cg.compute(system_.A);
        };
        if (prm_.preconditioner == cg_preconditioner::incomplete_cholesky) setup(ic_);
        else setup(jacobi_);
    }

    /// Solves the system assembled at construction. The relative residual is
    /// measured on the grid (anima::relative_residual), not taken from CG's
    /// own estimate; converged means it is within the tolerance. CG runs on
    /// b scaled by a power of two to a largest entry in [0.5, 1) (exact):
    /// Eigen's squared norms underflowed for a tiny b (a float b of 1e-18
    /// stopped at a relative residual of 1e-2, its stopping threshold
    /// floored at the smallest normal number) and overflow for a huge one,
    /// so b and b * 2^-k now give the same iterations and proportional
    /// solutions.
    poisson_result<T> solve() const {
        Eigen::Matrix<T, Eigen::Dynamic, 1> x;
        Eigen::Index iterations = 0;
        int e = 0;
        if (system_.b.size()) std::frexp(system_.b.cwiseAbs().maxCoeff(), &e);
        const Eigen::Matrix<T, Eigen::Dynamic, 1> scaled = system_.b.unaryExpr([e](T v) { return std::ldexp(v, -e); });
        const auto run = [&](const auto& cg) {
            x = cg.solve(scaled).unaryExpr([e](T v) { return std::ldexp(v, e); });
            iterations = cg.iterations();
        };
        if (prm_.preconditioner == cg_preconditioner::incomplete_cholesky) run(ic_);
        else run(jacobi_);
        poisson_result<T> r;
        r.u = expand_solution(problem_, system_, x);
        // Pure Neumann: the solution is defined up to a constant; pick zero mean,
        // as the other solvers do.
        if (problem_.grid.singular()) r.u.array() -= r.u.mean();
        if (!r.u.allFinite())
            throw error("anima::cg_poisson::solve: the solution is not finite (the right-hand side is too large for "
                        "the scalar type)");
        r.iterations = static_cast<int>(iterations);
        r.removed_mean = system_.removed_mean;
        r.relative_residual = relative_residual(problem_, r.u);
        r.converged = r.relative_residual <= prm_.tolerance;
        return r;
    }

    const poisson_system<T>& system() const noexcept { return system_; }

    // The factorisations refer to system_.A: an object stays where it was built.
    cg_poisson(const cg_poisson&) = delete;
    cg_poisson& operator=(const cg_poisson&) = delete;

private:
    using sparse = Eigen::SparseMatrix<T>;
    poisson_problem<T> problem_;
    params prm_;
    poisson_system<T> system_;
    Eigen::ConjugateGradient<sparse, Eigen::Lower | Eigen::Upper> jacobi_;
    Eigen::ConjugateGradient<sparse, Eigen::Lower | Eigen::Upper, Eigen::IncompleteCholesky<T>> ic_;
};

}  // namespace anima
