// Shared by the Poisson tests: random problems and the independent reference
// (Eigen's sparse direct solver on the assembled system).
#pragma once

#include <anima/poisson/grid.hpp>
#include <anima/poisson/laplacian.hpp>
#include <anima/poisson/problem.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <random>
#include <stdexcept>

namespace poisson_test {

using matd = Eigen::MatrixXd;
using vecd = Eigen::VectorXd;

inline matd random_matrix(Eigen::Index rows, Eigen::Index cols, unsigned seed, double lo = -1, double hi = 1) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(lo, hi);
    matd m(rows, cols);
    for (Eigen::Index j = 0; j < cols; ++j)
        for (Eigen::Index i = 0; i < rows; ++i) m(i, j) = u(rng);
    return m;
}

/// A problem with random right-hand side, random Dirichlet values on the
/// Dirichlet sides and random fixed values when the grid has a mask.
inline anima::poisson_problem<double> random_problem(const anima::poisson_grid<double>& g, unsigned seed) {
    anima::poisson_problem<double> p;
    p.grid = g;
    p.rhs = random_matrix(g.rows, g.cols, seed);
    if (g.top_bottom == anima::boundary::dirichlet) {
        p.boundary.top = random_matrix(g.cols, 1, seed + 1);
        p.boundary.bottom = random_matrix(g.cols, 1, seed + 2);
    }
    if (g.left_right == anima::boundary::dirichlet) {
        p.boundary.left = random_matrix(g.rows, 1, seed + 3);
        p.boundary.right = random_matrix(g.rows, 1, seed + 4);
    }
    if (g.masked()) p.fixed = random_matrix(g.rows, g.cols, seed + 5, 2, 3);
    return p;
}

/// The solution of the assembled system by sparse Cholesky (LDL^T). For a
/// singular (pure Neumann) grid one unknown is pinned, which gives a
/// solution of the compatible system, then the mean is removed.
inline matd reference_solution(const anima::poisson_problem<double>& p) {
    const auto s = anima::assemble_poisson_system(p);
    const Eigen::Index n = s.A.rows();
    vecd x = vecd::Zero(n);
    if (n == 0) return anima::expand_solution(p, s, x);
    if (p.grid.singular()) {
        if (n > 1) {
            const Eigen::SparseMatrix<double> a = s.A.bottomRightCorner(n - 1, n - 1);
            Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(a);
            if (ldlt.info() != Eigen::Success) throw std::runtime_error("reference factorisation failed");
            x.tail(n - 1) = ldlt.solve(s.b.tail(n - 1));
        }
        x.array() -= x.mean();
    } else {
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(s.A);
        if (ldlt.info() != Eigen::Success) throw std::runtime_error("reference factorisation failed");
        x = ldlt.solve(s.b);
    }
    return anima::expand_solution(p, s, x);
}

inline double relative_difference(const matd& a, const matd& b) {
    const double scale = b.norm();
    return (a - b).norm() / (scale > 0 ? scale : 1);
}

}  // namespace poisson_test
