// Multigrid and the sine/cosine-transform solver against Eigen's sparse
// Cholesky on the same assembled system, manufactured solutions (second-order
// convergence), multigrid's per-cycle residual reduction across grid sizes,
// masks, boundary mixes, float, the operator helpers and the errors.
#include "poisson_test_util.hpp"
#include "../test_support.hpp"

#include <anima/core/error.hpp>
#include <anima/poisson/cg_poisson.hpp>
#include <anima/poisson/dst_poisson.hpp>
#include <anima/poisson/gradient_field.hpp>
#include <anima/poisson/grid.hpp>
#include <anima/poisson/laplacian.hpp>
#include <anima/poisson/multigrid_poisson.hpp>
#include <anima/poisson/problem.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using namespace poisson_test;
using anima::boundary;
using anima_test::tolerance;
using grid = anima::poisson_grid<double>;
using mg_params = anima::multigrid_poisson<double>::params;

grid make(Eigen::Index rows, Eigen::Index cols, boundary tb = boundary::dirichlet, boundary lr = boundary::dirichlet,
          double hy = 1, double hx = 1) {
    grid g;
    g.rows = rows;
    g.cols = cols;
    g.top_bottom = tb;
    g.left_right = lr;
    g.hy = hy;
    g.hx = hx;
    return g;
}

mg_params tight() {
    mg_params prm;
    prm.tolerance = 1e-12;
    return prm;
}

// A mask with holes, a thin wall with a gap, isolated fixed cells and an
// isolated unknown cell.
anima::poisson_mask awkward_mask(Eigen::Index rows, Eigen::Index cols) {
    anima::poisson_mask m = anima::poisson_mask::Constant(rows, cols, true);
    for (Eigen::Index j = 0; j < cols; ++j)
        for (Eigen::Index i = 0; i < rows; ++i) {
            const double y = (i + 0.5) / rows - 0.4, x = (j + 0.5) / cols - 0.35;
            if (x * x + y * y < 0.04) m(i, j) = false;  // a disc
            if ((i * 7 + j * 3) % 13 == 0) m(i, j) = false;
        }
    const Eigen::Index wall = cols * 3 / 4;
    for (Eigen::Index i = 0; i < rows; ++i)
        if (i < rows / 2 - 1 || i > rows / 2 + 1) m(i, wall) = false;
    // One unknown cell surrounded by fixed ones.
    if (rows > 6 && cols > 6)
        for (Eigen::Index i = 3; i <= 5; ++i)
            for (Eigen::Index j = 3; j <= 5; ++j) m(i, j) = i == 4 && j == 4;
    return m;
}

}  // namespace

TEST_CASE("multigrid and DST agree with sparse Cholesky on any size and boundary mix") {
    struct shape {
        Eigen::Index rows, cols;
    };
    const shape shapes[] = {{1, 1}, {2, 2}, {3, 1}, {1, 7}, {33, 33}, {40, 23}, {17, 9}, {9, 64},
                            {64, 5}, {2, 300}, {200, 1}, {31, 127}, {101, 53}, {100, 100}};
    const boundary kinds[] = {boundary::dirichlet, boundary::neumann};
    for (const auto& s : shapes)
        for (boundary tb : kinds)
            for (boundary lr : kinds) {
                CAPTURE(s.rows);
                CAPTURE(s.cols);
                CAPTURE(anima::to_string(tb));
                CAPTURE(anima::to_string(lr));
                const grid g = make(s.rows, s.cols, tb, lr);
                const auto p = random_problem(g, static_cast<unsigned>(s.rows * 131 + s.cols));
                const matd ref = reference_solution(p);
                const auto mg = anima::solve_poisson_multigrid(p, tight());
                CHECK(mg.converged);
                CHECK(mg.relative_residual <= 1e-12);
                CHECK(relative_difference(mg.u, ref) < 1e-8);
                const auto fast = anima::solve_poisson_dst(p);
                CHECK(fast.converged);
                CHECK(fast.iterations == 0);
                CHECK(fast.relative_residual < 1e-12);
                CHECK(relative_difference(fast.u, ref) < 1e-10);
                if (g.singular()) {
                    CHECK(mg.removed_mean == doctest::Approx(p.rhs.mean()));
                    CHECK(std::abs(mg.u.mean()) < 1e-10);
                    CHECK(std::abs(fast.u.mean()) < 1e-10);
                }
            }
}

TEST_CASE("conjugate gradients, plain and with incomplete Cholesky, agree with sparse Cholesky") {
    using cg = anima::cg_poisson<double>;
    struct shape {
        Eigen::Index rows, cols;
    };
    const boundary kinds[] = {boundary::dirichlet, boundary::neumann};
    const Eigen::Index big = anima_test::sanitized_build ? 32 : 64;  // a quarter of the grid under the sanitizers
    for (const shape s : {shape{1, 1}, shape{3, 1}, shape{17, 9}, shape{40, 23}, shape{big, big}})
        for (boundary tb : kinds)
            for (boundary lr : kinds) {
                CAPTURE(s.rows);
                CAPTURE(s.cols);
                const grid g = make(s.rows, s.cols, tb, lr);
                const auto p = random_problem(g, static_cast<unsigned>(s.rows * 17 + s.cols));
                const matd ref = reference_solution(p);
                int iterations[2] = {0, 0};
                for (const auto pre : {anima::cg_preconditioner::diagonal, anima::cg_preconditioner::incomplete_cholesky}) {
                    cg::params prm;
                    prm.tolerance = 1e-11;
                    prm.preconditioner = pre;
                    const cg solver(p, prm);
                    const auto r = solver.solve();
                    CHECK(r.converged);
                    CHECK(r.relative_residual <= 1e-11);
                    CHECK(relative_difference(r.u, ref) < 1e-7);
                    if (g.singular()) CHECK(std::abs(r.u.mean()) < 1e-10);
                    iterations[pre == anima::cg_preconditioner::incomplete_cholesky] = r.iterations;
                }
                if (s.rows == big) CHECK(iterations[1] < iterations[0]);  // the factor pays
            }
    // A masked grid: fixed values outside the unknowns are kept.
    grid g = make(40, 50);
    g.mask = awkward_mask(40, 50);
    const auto p = random_problem(g, 5);
    const auto r = cg(p).solve();
    CHECK(r.converged);
    CHECK(relative_difference(r.u, reference_solution(p)) < 1e-5);
    // Float, against the double reference: the error is the residual times
    // the system's condition number (about 470 on a 33 x 33 Dirichlet grid).
    const auto pd = random_problem(make(33, 33), 9);
    anima::poisson_problem<float> pf;
    pf.grid = anima::make_poisson_grid<float>(33, 33, boundary::dirichlet);
    pf.rhs = pd.rhs.cast<float>();
    pf.boundary = {pd.boundary.top.cast<float>(), pd.boundary.bottom.cast<float>(), pd.boundary.left.cast<float>(),
                   pd.boundary.right.cast<float>()};
    const auto rf = anima::cg_poisson<float>(pf).solve();  // the float default tolerance, 1e-4
    CHECK(rf.converged);
    CHECK(rf.relative_residual <= 1e-4f);
    CHECK(relative_difference(rf.u.cast<double>().eval(), reference_solution(pd)) < 470 * 1e-4);
    // Bad parameters.
    cg::params bad;
    bad.tolerance = 0;
    CHECK_THROWS_AS(cg(random_problem(make(5, 5), 1), bad), anima::invalid_argument);
    bad.tolerance = 1e-8;
    bad.max_iterations = -1;
    CHECK_THROWS_AS(cg(random_problem(make(5, 5), 1), bad), anima::invalid_argument);
    // An iteration cap too small to converge is reported, not hidden.
    cg::params capped;
    capped.max_iterations = 2;
    capped.tolerance = 1e-12;
    const auto few = cg(random_problem(make(64, 64), 3), capped).solve();
    CHECK_FALSE(few.converged);
    CHECK(few.iterations <= 2);
    CHECK(few.relative_residual > 1e-12);
}

TEST_CASE("unequal spacings") {
    for (const auto& h : {std::pair{1.0, 0.5}, std::pair{0.25, 1.0}, std::pair{1.0, 1.3}}) {
        const double hy = h.first, hx = h.second;
        CAPTURE(hy);
        CAPTURE(hx);
        const grid g = make(45, 70, boundary::dirichlet, boundary::neumann, hy, hx);
        const auto p = random_problem(g, 3);
        const matd ref = reference_solution(p);
        const auto mg = anima::solve_poisson_multigrid(p, tight());
        CHECK(mg.converged);
        CHECK(relative_difference(mg.u, ref) < 1e-8);
        CHECK(relative_difference(anima::solve_poisson_dst(p).u, ref) < 1e-10);
    }
}

TEST_CASE("masks: unknowns inside, fixed values outside") {
    for (const auto& size : {std::pair<Eigen::Index, Eigen::Index>{48, 48}, {37, 61}, {10, 9}, {129, 65}}) {
        const Eigen::Index rows = size.first, cols = size.second;
        for (boundary sides : {boundary::dirichlet, boundary::neumann}) {
            CAPTURE(rows);
            CAPTURE(cols);
            CAPTURE(anima::to_string(sides));
            grid g = make(rows, cols, sides, sides);
            g.mask = awkward_mask(rows, cols);
            const auto p = random_problem(g, 11);
            const matd ref = reference_solution(p);
            const auto mg = anima::solve_poisson_multigrid(p, tight());
            CHECK(mg.converged);
            CHECK(relative_difference(mg.u, ref) < 1e-8);
            // Fixed cells keep exactly their values.
            for (Eigen::Index j = 0; j < cols; ++j)
                for (Eigen::Index i = 0; i < rows; ++i)
                    if (!g.mask(i, j)) REQUIRE(mg.u(i, j) == p.fixed(i, j));
            // The Galerkin hierarchy keeps convergence fast despite the holes.
            CHECK(mg.iterations <= 20);
        }
    }
}

TEST_CASE("a mask that keeps every cell gives the unmasked answer") {
    grid g = make(50, 37, boundary::neumann, boundary::dirichlet);
    const auto p = random_problem(g, 5);
    const auto plain = anima::solve_poisson_multigrid(p, tight());
    auto pm = p;
    pm.grid.mask = anima::poisson_mask::Constant(50, 37, true);
    const auto masked = anima::solve_poisson_multigrid(pm, tight());
    CHECK(relative_difference(masked.u, plain.u) < 1e-10);
    CHECK(relative_difference(masked.u, reference_solution(p)) < 1e-8);
}

TEST_CASE("a mask without unknowns returns the fixed values") {
    grid g = make(6, 5);
    g.mask = anima::poisson_mask::Constant(6, 5, false);
    const auto p = random_problem(g, 2);
    const auto r = anima::solve_poisson_multigrid(p);
    CHECK(r.converged);
    CHECK(r.u == p.fixed);
}

TEST_CASE("multigrid reduces the residual by a steady factor per cycle, whatever the grid size") {
    std::vector<double> factors;
    for (Eigen::Index n : {31, 63, 127, 255, 300}) {
        CAPTURE(n);
        const grid g = make(n, n);
        mg_params prm = tight();
        prm.full_multigrid = false;  // plain V-cycles from zero
        const auto r = anima::solve_poisson_multigrid(random_problem(g, 1), prm);
        CHECK(r.converged);
        const auto& h = r.residual_history;
        REQUIRE(h.size() >= 6);
        // Geometric mean reduction over the cycles after the first.
        const double factor = std::pow(h.back() / h.front(), 1.0 / static_cast<double>(h.size() - 1));
        for (std::size_t k = 1; k < h.size(); ++k) CHECK(h[k] / h[k - 1] < 0.2);
        factors.push_back(factor);
    }
    const double lo = *std::min_element(factors.begin(), factors.end());
    const double hi = *std::max_element(factors.begin(), factors.end());
    CHECK(hi < 0.15);
    CHECK(hi / lo < 1.6);
}

TEST_CASE("W cycles, sweep counts and the full-multigrid start") {
    const grid g = make(70, 90, boundary::dirichlet, boundary::neumann);
    const auto p = random_problem(g, 8);
    const matd ref = reference_solution(p);
    for (auto cycle : {anima::multigrid_cycle::v, anima::multigrid_cycle::w})
        for (const auto& sweeps : {std::pair{1, 1}, std::pair{2, 1}, std::pair{0, 2}, std::pair{3, 3}})
            for (bool fmg : {false, true}) {
                const int pre = sweeps.first, post = sweeps.second;
                CAPTURE(anima::to_string(cycle));
                CAPTURE(pre);
                CAPTURE(post);
                CAPTURE(fmg);
                mg_params prm = tight();
                prm.cycle = cycle;
                prm.pre_sweeps = pre;
                prm.post_sweeps = post;
                prm.full_multigrid = fmg;
                const auto r = anima::solve_poisson_multigrid(p, prm);
                CHECK(r.converged);
                CHECK(r.iterations == static_cast<int>(r.residual_history.size()));
                CHECK(relative_difference(r.u, ref) < 1e-8);
            }
    // The full-multigrid pass alone gets within a few per cent.
    mg_params one;
    one.max_cycles = 1;
    const auto first = anima::solve_poisson_multigrid(p, one);
    CHECK(first.iterations == 1);
    CHECK_FALSE(first.converged);
    CHECK(first.relative_residual < 0.05);
}

TEST_CASE("one multigrid solver serves many right-hand sides, and takes an initial guess") {
    const grid g = make(60, 45);
    anima::multigrid_poisson<double> mg(g, tight());
    CHECK(mg.levels() > 2);
    CHECK(mg.level_size(0) == std::pair<Eigen::Index, Eigen::Index>{60, 45});
    CHECK(mg.level_size(1) == std::pair<Eigen::Index, Eigen::Index>{30, 22});
    for (unsigned seed : {1u, 2u, 3u}) {
        const auto p = random_problem(g, seed);
        CHECK(relative_difference(mg.solve(p).u, reference_solution(p)) < 1e-8);
    }
    const auto p = random_problem(g, 4);
    const matd ref = reference_solution(p);
    const auto warm = mg.solve(p, ref);
    CHECK(warm.iterations <= 1);
    CHECK(relative_difference(warm.u, ref) < 1e-10);
    const anima::dst_poisson<double> fast(g);
    CHECK(relative_difference(fast.solve(p).u, ref) < 1e-10);
}

TEST_CASE("coarsening of very unequal axes") {
    // A long strip: only the long axis is coarsened once the short one is done.
    anima::multigrid_poisson<double> strip(make(4000, 3));
    CHECK(strip.level_size(1) == std::pair<Eigen::Index, Eigen::Index>{2000, 1});
    CHECK(strip.level_size(2) == std::pair<Eigen::Index, Eigen::Index>{1000, 1});
    // Rows four times closer than columns: rows are coarsened alone first.
    anima::multigrid_poisson<double> aniso(make(256, 64, boundary::dirichlet, boundary::dirichlet, 0.25, 1.0));
    CHECK(aniso.level_size(1) == std::pair<Eigen::Index, Eigen::Index>{128, 64});
    CHECK(aniso.level_size(2) == std::pair<Eigen::Index, Eigen::Index>{64, 64});
    CHECK(aniso.level_size(3) == std::pair<Eigen::Index, Eigen::Index>{32, 32});
    const auto p = random_problem(aniso.grid(), 9);
    const auto r = aniso.solve(p);
    CHECK(r.converged);
    CHECK(r.iterations <= 12);
}

namespace {

// Manufactured solution on [0, 1] x [0, 1.5] with Dirichlet values from u.
double u_exact(double x, double y) { return std::sin(2 * x + 1) * std::cos(3 * y) + x * x * y; }
double f_exact(double x, double y) { return -13 * std::sin(2 * x + 1) * std::cos(3 * y) + 2 * y; }

template <class Solve>
double dirichlet_error(Eigen::Index m, Solve solve) {
    const double h = 1.0 / static_cast<double>(m);  // m intervals across x
    const Eigen::Index nx = m - 1, ny = (3 * m) / 2 - 1;
    grid g = make(ny, nx, boundary::dirichlet, boundary::dirichlet, h, h);
    anima::poisson_problem<double> p;
    p.grid = g;
    p.rhs.resize(ny, nx);
    matd exact(ny, nx);
    for (Eigen::Index j = 0; j < nx; ++j)
        for (Eigen::Index i = 0; i < ny; ++i) {
            const double x = (j + 1) * h, y = (i + 1) * h;
            p.rhs(i, j) = f_exact(x, y);
            exact(i, j) = u_exact(x, y);
        }
    p.boundary.top.resize(nx);
    p.boundary.bottom.resize(nx);
    p.boundary.left.resize(ny);
    p.boundary.right.resize(ny);
    for (Eigen::Index j = 0; j < nx; ++j) {
        p.boundary.top[j] = u_exact((j + 1) * h, 0);
        p.boundary.bottom[j] = u_exact((j + 1) * h, 1.5);
    }
    for (Eigen::Index i = 0; i < ny; ++i) {
        p.boundary.left[i] = u_exact(0, (i + 1) * h);
        p.boundary.right[i] = u_exact(1, (i + 1) * h);
    }
    return (solve(p) - exact).cwiseAbs().maxCoeff();
}

// Cell-centred Neumann problem on [0, 1]^2: u = cos(pi x) cos(2 pi y) has zero
// normal derivative on the sides and zero mean.
template <class Solve>
double neumann_error(Eigen::Index n, Solve solve) {
    const double pi = 3.14159265358979323846, h = 1.0 / static_cast<double>(n);
    grid g = make(n, n, boundary::neumann, boundary::neumann, h, h);
    anima::poisson_problem<double> p;
    p.grid = g;
    p.rhs.resize(n, n);
    matd exact(n, n);
    for (Eigen::Index j = 0; j < n; ++j)
        for (Eigen::Index i = 0; i < n; ++i) {
            const double x = (j + 0.5) * h, y = (i + 0.5) * h;
            exact(i, j) = std::cos(pi * x) * std::cos(2 * pi * y);
            p.rhs(i, j) = -5 * pi * pi * exact(i, j);
        }
    return (solve(p) - exact).cwiseAbs().maxCoeff();
}

void check_second_order(const std::function<double(Eigen::Index)>& error, std::vector<Eigen::Index> sizes) {
    std::vector<double> e;
    for (Eigen::Index m : sizes) e.push_back(error(m));
    for (std::size_t k = 1; k < e.size(); ++k) {
        const double order = std::log2(e[k - 1] / e[k]);
        CAPTURE(k);
        CAPTURE(e[k - 1]);
        CAPTURE(e[k]);
        CHECK(order > 1.85);
        CHECK(order < 2.15);
    }
}

}  // namespace

TEST_CASE("manufactured solutions converge at second order") {
    const auto mg = [](const anima::poisson_problem<double>& p) { return anima::solve_poisson_multigrid(p, tight()).u; };
    const auto fast = [](const anima::poisson_problem<double>& p) { return anima::solve_poisson_dst(p).u; };
    check_second_order([&](Eigen::Index m) { return dirichlet_error(m, mg); }, {16, 32, 64, 128});
    check_second_order([&](Eigen::Index m) { return dirichlet_error(m, fast); }, {16, 32, 64, 128});
    check_second_order([&](Eigen::Index n) { return neumann_error(n, mg); }, {15, 30, 60, 120});
    check_second_order([&](Eigen::Index n) { return neumann_error(n, fast); }, {15, 30, 60, 120});
}

TEST_CASE("float solvers") {
    using gridf = anima::poisson_grid<float>;
    for (boundary sides : {boundary::dirichlet, boundary::neumann}) {
        CAPTURE(anima::to_string(sides));
        const grid gd = make(41, 30, sides, sides);
        const auto pd = random_problem(gd, 21);
        const matd ref = reference_solution(pd);
        gridf gf = anima::make_poisson_grid<float>(41, 30, sides);
        anima::poisson_problem<float> pf;
        pf.grid = gf;
        pf.rhs = pd.rhs.cast<float>();
        if (sides == boundary::dirichlet) {
            pf.boundary.top = pd.boundary.top.cast<float>();
            pf.boundary.bottom = pd.boundary.bottom.cast<float>();
            pf.boundary.left = pd.boundary.left.cast<float>();
            pf.boundary.right = pd.boundary.right.cast<float>();
        }
        const auto mg = anima::solve_poisson_multigrid(pf);
        CHECK(mg.converged);
        CHECK(mg.relative_residual <= anima::default_poisson_tolerance<float>());
        CHECK(relative_difference(mg.u.cast<double>(), ref) < 1e-3);
        const auto fast = anima::solve_poisson_dst(pf);
        CHECK(relative_difference(fast.u.cast<double>(), ref) < 1e-5);
        // A masked float problem.
        gridf gm = gf;
        gm.mask = awkward_mask(41, 30);
        anima::poisson_problem<float> pm = pf;
        pm.grid = gm;
        pm.fixed = Eigen::MatrixXf::Constant(41, 30, 2.5f);
        auto pmd = pd;
        pmd.grid.mask = gm.mask;
        pmd.fixed = Eigen::MatrixXd::Constant(41, 30, 2.5);
        const auto mm = anima::solve_poisson_multigrid(pm);
        CHECK(mm.converged);
        CHECK(relative_difference(mm.u.cast<double>(), reference_solution(pmd)) < 1e-3);
    }
}

TEST_CASE("float on a larger grid stays accurate at the lowest frequencies") {
    // lambda_0 ~ (pi / 258)^2 is far below the stencil's diagonal: adding the
    // two in float would lose most of its digits.
    const Eigen::Index n = 257;
    const matd f = random_matrix(n, n, 31);
    const auto pd = anima::make_poisson_problem(anima::make_poisson_grid<double>(n, n), f);
    const auto pf = anima::make_poisson_problem(anima::make_poisson_grid<float>(n, n), f.cast<float>());
    const matd ref = anima::solve_poisson_dst(pd).u;
    const matd fast = anima::solve_poisson_dst(pf).u.cast<double>();
    const matd mg = anima::solve_poisson_multigrid(pf).u.cast<double>();
    CHECK(relative_difference(fast, ref) < 1e-5);
    CHECK(relative_difference(mg, ref) < 1e-4);
    CHECK(anima::solve_poisson_dst(pd).relative_residual < 1e-12);
}

TEST_CASE("the Laplacian, gradient and divergence agree with each other") {
    for (boundary tb : {boundary::dirichlet, boundary::neumann})
        for (boundary lr : {boundary::dirichlet, boundary::neumann}) {
            const grid g = make(12, 17, tb, lr, 0.5, 0.25);
            const auto p = random_problem(g, 4);
            const matd u = random_matrix(12, 17, 99);
            const matd lap = anima::laplacian(g, u, p.boundary);
            const auto field = anima::gradient(g, u, p.boundary);
            CHECK(field.gx.rows() == 12);
            CHECK(field.gx.cols() == 18);
            CHECK(field.gy.rows() == 13);
            CHECK(field.gy.cols() == 17);
            CHECK((anima::divergence(g, field) - lap).cwiseAbs().maxCoeff() < 1e-10);
            // Solving with f = laplacian(u) and the same boundary data gives u back.
            auto q = p;
            q.rhs = lap;
            const matd back = anima::solve_poisson_dst(q).u;
            if (g.singular()) CHECK(relative_difference(back, (u.array() - u.mean()).matrix()) < 1e-9);
            else CHECK(relative_difference(back, u) < 1e-9);
        }
    // On a quadratic the 5-point stencil is exact: laplacian(x^2 + 3y^2) = 8.
    const double h = 0.1;
    const grid g = make(6, 8, boundary::dirichlet, boundary::dirichlet, h, h);
    const auto q = [&](double i, double j) { return (j * h) * (j * h) + 3 * (i * h) * (i * h); };
    matd u(6, 8);
    anima::boundary_values<double> b;
    b.top.resize(8);
    b.bottom.resize(8);
    b.left.resize(6);
    b.right.resize(6);
    for (Eigen::Index j = 0; j < 8; ++j) {
        for (Eigen::Index i = 0; i < 6; ++i) u(i, j) = q(i, j);
        b.top[j] = q(-1, j);
        b.bottom[j] = q(6, j);
    }
    for (Eigen::Index i = 0; i < 6; ++i) {
        b.left[i] = q(i, -1);
        b.right[i] = q(i, 8);
    }
    CHECK((anima::laplacian(g, u, b).array() - 8).abs().maxCoeff() < 1e-9);
}

TEST_CASE("relative_residual and the assembled system") {
    grid g = make(20, 14, boundary::dirichlet, boundary::neumann);
    g.mask = awkward_mask(20, 14);
    const auto p = random_problem(g, 6);
    const auto s = anima::assemble_poisson_system(p);
    CHECK(s.A.rows() == g.unknowns());
    CHECK((Eigen::MatrixXd(s.A) - Eigen::MatrixXd(s.A).transpose()).norm() == 0);
    const matd ref = reference_solution(p);
    CHECK(anima::relative_residual(p, ref) < 1e-13);
    CHECK(anima::relative_residual(p, matd::Zero(20, 14)) == doctest::Approx(1.0));
}

TEST_CASE("bad input raises anima::invalid_argument naming the problem") {
    const grid g = make(8, 6);
    const auto good = random_problem(g, 1);

    CHECK_THROWS_WITH_AS(anima::solve_poisson_multigrid(random_problem(make(0, 5), 1)),
                         doctest::Contains("the grid is empty"), anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::dst_poisson<double>(make(3, 0)), doctest::Contains("anima::dst_poisson"),
                         anima::invalid_argument);

    auto p = good;
    p.rhs.resize(8, 5);
    CHECK_THROWS_WITH_AS(anima::solve_poisson_multigrid(p), doctest::Contains("right-hand side is 8 x 5"),
                         anima::invalid_argument);
    CHECK_THROWS_AS(anima::solve_poisson_dst(p), anima::invalid_argument);

    p = good;
    p.rhs(3, 2) = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_WITH_AS(anima::solve_poisson_multigrid(p), doctest::Contains("rhs(3, 2) is not finite"),
                         anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::solve_poisson_dst(p), doctest::Contains("anima::solve_poisson_dst"),
                         anima::invalid_argument);

    p = good;
    p.boundary.left[4] = std::numeric_limits<double>::infinity();
    CHECK_THROWS_WITH_AS(anima::solve_poisson_multigrid(p), doctest::Contains("boundary.left[4]"),
                         anima::invalid_argument);
    p = good;
    p.boundary.top.resize(5);
    CHECK_THROWS_WITH_AS(anima::solve_poisson_dst(p), doctest::Contains("boundary.top has 5 values, expected 6"),
                         anima::invalid_argument);

    auto n = random_problem(make(8, 6, boundary::neumann, boundary::neumann), 1);
    n.boundary.right = Eigen::VectorXd::Zero(8);
    CHECK_THROWS_WITH_AS(anima::solve_poisson_multigrid(n), doctest::Contains("that side is Neumann"),
                         anima::invalid_argument);

    grid gm = g;
    gm.mask = anima::poisson_mask::Constant(8, 5, true);
    CHECK_THROWS_WITH_AS(anima::multigrid_poisson<double>{gm}, doctest::Contains("the mask is 8 x 5"),
                         anima::invalid_argument);
    gm.mask = anima::poisson_mask::Constant(8, 6, true);
    gm.mask(1, 1) = false;
    CHECK_THROWS_WITH_AS(anima::dst_poisson<double>{gm}, doctest::Contains("multigrid_poisson"), anima::invalid_argument);
    auto pm = random_problem(gm, 3);
    pm.fixed(1, 1) = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_WITH_AS(anima::solve_poisson_multigrid(pm), doctest::Contains("fixed(1, 1)"), anima::invalid_argument);
    pm.fixed(1, 1) = 0;
    pm.fixed(2, 2) = std::numeric_limits<double>::quiet_NaN();  // an unknown cell: never read
    CHECK(anima::solve_poisson_multigrid(pm).converged);

    grid bad_h = g;
    bad_h.hx = 0;
    CHECK_THROWS_WITH_AS(anima::multigrid_poisson<double>{bad_h}, doctest::Contains("spacings must be positive"),
                         anima::invalid_argument);

    mg_params prm;
    prm.pre_sweeps = prm.post_sweeps = 0;
    CHECK_THROWS_WITH_AS(anima::multigrid_poisson<double>(g, prm), doctest::Contains("smoothing sweep"),
                         anima::invalid_argument);
    prm = {};
    prm.max_cycles = 0;
    CHECK_THROWS_AS(anima::multigrid_poisson<double>(g, prm), anima::invalid_argument);
    prm = {};
    prm.tolerance = -1;
    CHECK_THROWS_AS(anima::multigrid_poisson<double>(g, prm), anima::invalid_argument);

    anima::multigrid_poisson<double> mg(g);
    CHECK_THROWS_WITH_AS(mg.solve(random_problem(make(8, 7), 1)), doctest::Contains("differs from the grid"),
                         anima::invalid_argument);
    CHECK_THROWS_WITH_AS(mg.solve(good, matd::Zero(8, 7)), doctest::Contains("initial guess is 8 x 7"),
                         anima::invalid_argument);
    const anima::dst_poisson<double> fast(g);
    CHECK_THROWS_AS(fast.solve(random_problem(make(8, 6, boundary::neumann), 1)), anima::invalid_argument);

    CHECK_THROWS_WITH_AS(anima::laplacian(g, matd::Zero(8, 5)), doctest::Contains("anima::laplacian: u is 8 x 5"),
                         anima::invalid_argument);
    anima::gradient_field<double> f;
    f.gx = matd::Zero(8, 6);
    f.gy = matd::Zero(9, 6);
    CHECK_THROWS_WITH_AS(anima::divergence(g, f), doctest::Contains("anima::divergence"), anima::invalid_argument);
    CHECK_THROWS_AS(anima::parse_boundary("periodic"), anima::invalid_argument);
    CHECK_THROWS_AS(anima::parse_multigrid_cycle("f"), anima::invalid_argument);
    CHECK(anima::parse_boundary("neumann") == boundary::neumann);
    CHECK(anima::parse_multigrid_cycle("W") == anima::multigrid_cycle::w);
}

TEST_CASE("zero right-hand side and data give zero") {
    const grid g = make(9, 9);
    anima::poisson_problem<double> p;
    p.grid = g;
    p.rhs = matd::Zero(9, 9);
    const auto r = anima::solve_poisson_multigrid(p);
    CHECK(r.converged);
    CHECK(r.iterations == 0);
    CHECK(r.relative_residual == 0);
    CHECK(r.u.isZero(0));
}

TEST_CASE_TEMPLATE("tiny and huge right-hand sides are solved and measured without their squares under- or overflowing",
                   T, float, double) {
    using mat = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const bool is_float = std::is_same_v<T, float>;
    // Squared, 1e-25 underflows float and 1e-170 double; 64 x (1e30)^2
    // overflows float and 64 x (1e300)^2 double.
    for (const double value : {is_float ? 1e-25 : 1e-170, is_float ? 1e30 : 1e300}) {
        CAPTURE(value);
        const auto g = anima::make_poisson_grid<T>(8, 8, boundary::dirichlet, T(1));
        const auto p = anima::make_poisson_problem(g, mat(mat::Constant(8, 8, static_cast<T>(value))));
        const auto dst = anima::solve_poisson_dst(p);
        const T peak = dst.u.cwiseAbs().maxCoeff();
        CHECK(peak == doctest::Approx(5.7869 * value).epsilon(1e-4));
        CHECK(std::isfinite(dst.relative_residual));
        CHECK(dst.relative_residual < tolerance<T>(1e-12, 1e-5));
        const T measured = anima::relative_residual(p, dst.u);
        CHECK(std::isfinite(measured));
        CHECK(measured < tolerance<T>(1e-12, 1e-5));
        anima::multigrid_poisson<T> mg(g);
        const auto r = mg.solve(p);
        CHECK(r.converged);
        CHECK(r.iterations > 0);
        CHECK(r.relative_residual <= tolerance<T>(1e-6, 1e-5));
        CHECK((r.u - dst.u).cwiseAbs().maxCoeff() <= tolerance<T>(1e-5, 1e-3) * peak);
    }
}

TEST_CASE_TEMPLATE("a spacing whose 1 / h^2 overflows or vanishes is refused, naming it", T, float, double) {
    using mat = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const bool is_float = std::is_same_v<T, float>;
    const mat ones = mat::Ones(8, 8);
    for (const double h : {is_float ? 1e-20 : 1e-160, is_float ? 1e25 : 1e160}) {
        CAPTURE(h);
        const auto g = anima::make_poisson_grid<T>(8, 8, boundary::dirichlet, static_cast<T>(h));
        const std::string named =
            "grid spacing hy = " + anima::detail::argument_text(static_cast<T>(h)) + " has 1 / hy^2 = ";
        CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)anima::laplacian(g, ones); }),
                                   "anima::laplacian: " + named));
        const auto dst = [&] { (void)anima::solve_poisson_dst(anima::make_poisson_problem(g, ones)); };
        CHECK(anima_test::contains(anima_test::invalid_argument_message(dst),
                                   "not finite and normal"));
        const auto mg = [&] { anima::multigrid_poisson<T>{g}; };
        CHECK(anima_test::contains(anima_test::invalid_argument_message(mg), named));
    }
    // The spacings either side of those still give a finite, non-zero Laplacian.
    const T fine = static_cast<T>(is_float ? 1e-15 : 1e-150);
    const auto lap = anima::laplacian(anima::make_poisson_grid<T>(8, 8, boundary::dirichlet, fine), ones);
    CHECK(lap.allFinite());
    CHECK(lap.cwiseAbs().maxCoeff() > T(0));
}

TEST_CASE_TEMPLATE("a spacing whose 1 / h^2 is subnormal is refused up front, naming the spacing", T, float, double) {
    // float h = 1e19: 1 / h^2 = 1e-38, below the smallest normal float. It
    // was accepted and the solvers failed later with "the right-hand side
    // is too large for the scalar type", for a right-hand side of 1e-20.
    using mat = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const bool is_float = std::is_same_v<T, float>;
    const T h = static_cast<T>(is_float ? 1e19 : 1e154);
    const mat small = mat::Constant(16, 16, static_cast<T>(is_float ? 1e-20 : 1e-300));
    const auto g = anima::make_poisson_grid<T>(16, 16, boundary::dirichlet, h);
    const std::string named = "grid spacing hy = " + anima::detail::argument_text(h) + " has 1 / hy^2 = ";
    const auto p = anima::make_poisson_problem(g, small);
    CHECK(anima_test::contains(
        anima_test::invalid_argument_message([&] { (void)anima::solve_poisson_multigrid(p); }), named));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)anima::solve_poisson_dst(p); }), named));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { anima::cg_poisson<T>{p}; }), named));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)anima::laplacian(g, small); }),
                               "not finite and normal"));
    // The largest spacing whose 1 / h^2 is normal is accepted, and the
    // transform solver (no coarse levels) solves with it.
    const T largest = T(1) / std::sqrt(std::numeric_limits<T>::min()) * T(0.99);
    const auto ok = anima::solve_poisson_dst(anima::make_poisson_problem(
        anima::make_poisson_grid<T>(16, 16, boundary::dirichlet, largest), small));
    CHECK(ok.u.allFinite());
    CHECK(ok.relative_residual <= tolerance<T>(1e-12, 1e-4));
    // Multigrid builds its hierarchy on the spacings divided by a power of
    // two: at float h = 4e18 (1 / h^2 normal) its scaled solution overflowed
    // and the solve failed with "the right-hand side is too large" for a
    // right-hand side of 1e-20; the transform solver's low eigenvalues were
    // subnormal, with the same message. The two now agree, and the
    // transform solver's residual is small.
    const T wide = static_cast<T>(is_float ? 4e18 : 5e153);
    mat rhs(64, 57);
    for (Eigen::Index j = 0; j < 57; ++j)
        for (Eigen::Index i = 0; i < 64; ++i)
            rhs(i, j) = static_cast<T>((is_float ? 1e-20 : 1e-300) * std::sin(0.21 * double(i * j) + double(i)));
    for (boundary sides : {boundary::dirichlet, boundary::neumann}) {
        CAPTURE(anima::to_string(sides));
        const auto pw = anima::make_poisson_problem(anima::make_poisson_grid<T>(64, 57, sides, wide), rhs);
        const auto mg = anima::solve_poisson_multigrid(pw);
        const auto fast = anima::solve_poisson_dst(pw);
        CHECK(mg.converged);
        CHECK(mg.u.allFinite());
        CHECK(fast.relative_residual <= tolerance<T>(1e-10, 1e-3));
        CHECK((mg.u - fast.u).cwiseAbs().maxCoeff() <= tolerance<T>(1e-6, 1e-2) * fast.u.cwiseAbs().maxCoeff());
    }
}

TEST_CASE_TEMPLATE("relative_residual of a homogeneous problem (b = 0) is the absolute residual, not infinity", T,
                   float, double) {
    // f = 0 with zero boundary data: the folded b is zero and the solution is
    // 0. The residual used to be ||A u|| / 0 = inf for any u but 0.
    for (boundary sides : {boundary::dirichlet, boundary::neumann}) {
        CAPTURE(anima::to_string(sides));
        anima::poisson_problem<T> p;
        p.grid = anima::make_poisson_grid<T>(12, 9, sides, T(0.5));
        p.rhs = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>::Zero(12, 9);
        using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
        CHECK(anima::relative_residual(p, matrix::Zero(12, 9)) == T(0));
        matrix u(12, 9);
        for (Eigen::Index j = 0; j < 9; ++j)
            for (Eigen::Index i = 0; i < 12; ++i) u(i, j) = T(std::sin(0.7 * double(i) + 0.3 * double(j * j)));
        const T r = anima::relative_residual(p, u);
        CHECK(std::isfinite(r));
        CHECK(r > T(0));
        // ||A u||: the Laplacian of u (zero data outside) on every cell.
        const auto lap = anima::laplacian(p.grid, u);
        CHECK(r == doctest::Approx(double(lap.template cast<double>().norm())).epsilon(1e-4));
        CHECK(anima::relative_residual(p, (T(4) * u).eval()) == doctest::Approx(double(T(4) * r)).epsilon(1e-4));
        // The solvers return u = 0 with a residual of 0: converged.
        const auto mg = anima::solve_poisson_multigrid(p);
        CHECK(mg.converged);
        CHECK(mg.relative_residual == T(0));
        CHECK(mg.u.isZero(0));
        const auto fast = anima::solve_poisson_dst(p);
        CHECK(fast.relative_residual == T(0));
        CHECK(fast.u.isZero(0));
        const auto cg = anima::cg_poisson<T>(p).solve();
        CHECK(cg.converged);
        CHECK(cg.relative_residual == T(0));
    }
}

TEST_CASE_TEMPLATE("cg_poisson is scale-invariant: b and b * 2^-k give the same iterations, proportional solutions", T,
                   float, double) {
    // Eigen's CG stops on ||r||^2 < tol^2 ||b||^2 floored at the smallest
    // normal number: for a float b of 1e-18 the floor ruled and CG stopped
    // at a relative residual of about 1e-2 (not converged), while b itself
    // converged. CG now runs on b scaled to a largest entry in [0.5, 1).
    using mat = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const bool is_float = std::is_same_v<T, float>;
    for (const int k : {is_float ? 60 : 100, is_float ? 100 : 500}) {
        for (boundary sides : {boundary::dirichlet, boundary::neumann}) {
            for (auto pre : {anima::cg_preconditioner::diagonal, anima::cg_preconditioner::incomplete_cholesky}) {
                CAPTURE(k);
                CAPTURE(anima::to_string(sides));
                CAPTURE(anima::to_string(pre));
                mat rhs(24, 19);
                for (Eigen::Index j = 0; j < 19; ++j)
                    for (Eigen::Index i = 0; i < 24; ++i)
                        rhs(i, j) = T(std::sin(0.37 * double(i * j) + 0.5 * double(i)) + 0.25);
                const auto g = anima::make_poisson_grid<T>(24, 19, sides, T(0.125));
                const auto big = anima::make_poisson_problem(g, rhs);
                const auto small = anima::make_poisson_problem(g, rhs.unaryExpr([k](T v) { return std::ldexp(v, -k); }));
                typename anima::cg_poisson<T>::params prm;
                prm.preconditioner = pre;
                const auto rb = anima::cg_poisson<T>(big, prm).solve();
                const auto rs = anima::cg_poisson<T>(small, prm).solve();
                REQUIRE(rb.converged);
                CHECK(rs.converged);
                CHECK(rs.iterations == rb.iterations);
                CHECK(rs.relative_residual <= anima::default_poisson_tolerance<T>());
                const mat scaled_back = rs.u.unaryExpr([k](T v) { return std::ldexp(v, k); });
                CHECK((scaled_back - rb.u).cwiseAbs().maxCoeff() <=
                      tolerance<T>(1e-12, 1e-5) * rb.u.cwiseAbs().maxCoeff());
            }
        }
    }
}
