// Poisson solvers on N x N grids of unknowns (unit spacing, zero Dirichlet
// values around, the standard 5-point Laplacian, a uniform random right-hand
// side in [-1, 1]), every solver on the same input, in the same run:
//
//   multigrid/N          anima::multigrid_poisson, hierarchy built and solved
//   multigrid_reused/N   the same hierarchy solving again (precompute/solve split)
//   dst/N                anima::dst_poisson (transforms planned beforehand)
//   fftw_dst/N           FFTW's RODFT00 in 2D (planned beforehand), when FFTW is installed
//   cg_poisson/N         anima::cg_poisson (diagonal preconditioner), built and solved: the
//                        assembly, Eigen's CG on b scaled by a power of two, the grid's residual
//   cg_poisson_ic/N      the same with cg_preconditioner::incomplete_cholesky
//   cg_poisson_reused/N  a cg_poisson (diagonal) built beforehand solving again: solve() alone
//   eigen_cg/N           Eigen::ConjugateGradient (diagonal preconditioner) on the system
//                        assembled beforehand, b as it is: cg_poisson's CG without anima's work
//   eigen_cg_ic/N        Eigen::ConjugateGradient with IncompleteCholesky (factorisation timed too)
//   seam_smoothing/...   anima::smooth_seams on the bundled CMU walk stitched to itself
//
// Iterative solvers stop at the same relative residual ||b - A x|| / ||b||
// of 1e-8 (multigrid and Eigen use this very definition); before timing, each
// solver's result is checked against that tolerance (the direct solvers
// against 1e-10) with anima::relative_residual, and the program aborts if
// one fails. Counters: per_unknown (CPU time / N^2), iterations, residual.
//
// Sizes: N = 65 to 513 by default, the CG rows (anima's and Eigen's) up to
// 257 (a brief run stays well under half a minute);
// ANIMA_BENCH_POISSON_MAX=2049 runs every solver on every size up to 2049
// (CG then takes minutes).
#include <anima/bvh/reader.hpp>
#include <anima/core/random.hpp>
#include <anima/poisson.hpp>
#include <anima/texture/motion_smoothing.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#ifdef ANIMA_HAVE_FFTW
#include <fftw3.h>
#endif

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

#ifndef ANIMA_BENCH_DATA_DIR
#error "ANIMA_BENCH_DATA_DIR must name the examples/data directory"
#endif

namespace {

using matrix = Eigen::MatrixXd;
constexpr double tolerance = 1e-8;

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "bench_poisson: %s\n", what.c_str());
    std::abort();
}

const anima::poisson_problem<double>& problem(Eigen::Index n) {
    static std::map<Eigen::Index, anima::poisson_problem<double>> cache;
    auto it = cache.find(n);
    if (it != cache.end()) return it->second;
    anima::random_source rng(42);
    matrix f(n, n);
    for (Eigen::Index j = 0; j < n; ++j)
        for (Eigen::Index i = 0; i < n; ++i) f(i, j) = 2 * rng.uniform() - 1;
    return cache.emplace(n, anima::make_poisson_problem(anima::make_poisson_grid<double>(n, n), f)).first->second;
}

void check(const anima::poisson_problem<double>& p, const matrix& u, double limit, const char* who) {
    const double r = anima::relative_residual(p, u);
    if (!(r <= limit))
        fail(std::string(who) + " on " + std::to_string(p.grid.rows) + "^2: relative residual " + std::to_string(r) +
             " above " + std::to_string(limit));
}

void report(benchmark::State& state, Eigen::Index n, double iterations, double residual) {
    // Seconds per unknown, printed with an SI prefix ("85.2ns").
    state.counters["per_unknown"] = benchmark::Counter(
        static_cast<double>(n * n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
    state.counters["iterations"] = iterations;
    state.counters["residual"] = residual;
}

anima::multigrid_poisson<double>::params mg_params() {
    anima::multigrid_poisson<double>::params prm;
    prm.tolerance = tolerance;
    return prm;
}

void multigrid(benchmark::State& state, Eigen::Index n) {
    const auto& p = problem(n);
    anima::poisson_result<double> r = anima::solve_poisson_multigrid(p, mg_params());
    check(p, r.u, tolerance, "multigrid");
    for (auto _ : state) {
        r = anima::solve_poisson_multigrid(p, mg_params());
        benchmark::DoNotOptimize(r.u.data());
    }
    report(state, n, r.iterations, r.relative_residual);
}

void multigrid_reused(benchmark::State& state, Eigen::Index n) {
    const auto& p = problem(n);
    anima::multigrid_poisson<double> mg(p.grid, mg_params());
    anima::poisson_result<double> r = mg.solve(p);
    check(p, r.u, tolerance, "multigrid_reused");
    for (auto _ : state) {
        r = mg.solve(p);
        benchmark::DoNotOptimize(r.u.data());
    }
    report(state, n, r.iterations, r.relative_residual);
}

void dst(benchmark::State& state, Eigen::Index n) {
    const auto& p = problem(n);
    anima::dst_poisson<double>::params prm;
    prm.compute_residual = false;  // as for FFTW: the solve alone
    const anima::dst_poisson<double> solver(p.grid, prm);
    anima::poisson_result<double> r = solver.solve(p);
    check(p, r.u, 1e-10, "dst");
    for (auto _ : state) {
        r = solver.solve(p);
        benchmark::DoNotOptimize(r.u.data());
    }
    report(state, n, 0, anima::relative_residual(p, r.u));
}

#ifdef ANIMA_HAVE_FFTW
// The same solve with FFTW: RODFT00 both ways (its own inverse up to
// 4 (n+1)^2), division by the eigenvalues in between.
void fftw_dst(benchmark::State& state, Eigen::Index n) {
    const auto& p = problem(n);
    const int ni = static_cast<int>(n);
    double* data = fftw_alloc_real(static_cast<std::size_t>(n * n));
    // Column-major n x n matrix = row-major array [col][row].
    fftw_plan plan = fftw_plan_r2r_2d(ni, ni, data, data, FFTW_RODFT00, FFTW_RODFT00, FFTW_MEASURE);
    std::vector<double> lam(static_cast<std::size_t>(n));
    const double pi = 3.14159265358979323846;
    for (Eigen::Index k = 0; k < n; ++k) {
        const double s = std::sin(pi * static_cast<double>(k + 1) / (2.0 * static_cast<double>(n + 1)));
        lam[static_cast<std::size_t>(k)] = 4 * s * s;
    }
    const double scale = 1.0 / (4.0 * static_cast<double>(n + 1) * static_cast<double>(n + 1));
    matrix u(n, n);
    const auto solve = [&] {
        // A x = b with A = -L and b = -f.
        for (Eigen::Index k = 0; k < n * n; ++k) data[k] = -p.rhs.data()[k];
        fftw_execute(plan);
        for (Eigen::Index j = 0; j < n; ++j)
            for (Eigen::Index i = 0; i < n; ++i)
                data[j * n + i] /= lam[static_cast<std::size_t>(i)] + lam[static_cast<std::size_t>(j)];
        fftw_execute(plan);
        for (Eigen::Index k = 0; k < n * n; ++k) u.data()[k] = data[k] * scale;
    };
    solve();
    check(p, u, 1e-10, "fftw_dst");
    for (auto _ : state) {
        solve();
        benchmark::DoNotOptimize(u.data());
    }
    report(state, n, 0, anima::relative_residual(p, u));
    fftw_destroy_plan(plan);
    fftw_free(data);
}
#endif

// One use of anima's CG: the system assembled and the preconditioner set up
// (the constructor), then solve(). Against eigen_cg, which times Eigen's
// compute() and solve(), it adds the assembly, the scaling of b by a power
// of two and back, the expansion to the grid and the residual on the grid.
void cg(benchmark::State& state, Eigen::Index n, anima::cg_preconditioner preconditioner) {
    const auto& p = problem(n);
    anima::cg_poisson<double>::params prm;
    prm.tolerance = tolerance;
    prm.preconditioner = preconditioner;
    const auto solve = [&] { return anima::cg_poisson<double>(p, prm).solve(); };
    anima::poisson_result<double> r = solve();
    check(p, r.u, tolerance * 1.01, "cg_poisson");
    for (auto _ : state) {
        r = solve();
        benchmark::DoNotOptimize(r.u.data());
    }
    report(state, n, r.iterations, r.relative_residual);
}

// solve() alone on a cg_poisson built beforehand: Eigen's CG, the scaling of
// b, the expansion and the residual (eigen_cg's compute() with the diagonal
// preconditioner only reads the diagonal).
void cg_reused(benchmark::State& state, Eigen::Index n) {
    const auto& p = problem(n);
    anima::cg_poisson<double>::params prm;
    prm.tolerance = tolerance;
    const anima::cg_poisson<double> solver(p, prm);
    anima::poisson_result<double> r = solver.solve();
    check(p, r.u, tolerance * 1.01, "cg_poisson_reused");
    for (auto _ : state) {
        r = solver.solve();
        benchmark::DoNotOptimize(r.u.data());
    }
    report(state, n, r.iterations, r.relative_residual);
}

template <class Preconditioner>
void eigen_cg(benchmark::State& state, Eigen::Index n) {
    const auto& p = problem(n);
    const auto sys = anima::assemble_poisson_system(p);
    using cg_t = Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper, Preconditioner>;
    Eigen::VectorXd x;
    double iterations = 0;
    const auto solve = [&] {
        cg_t cg;
        cg.setTolerance(tolerance);
        cg.setMaxIterations(100 * static_cast<Eigen::Index>(n));
        cg.compute(sys.A);
        x = cg.solve(sys.b);
        iterations = static_cast<double>(cg.iterations());
    };
    solve();
    check(p, anima::expand_solution(p, sys, x), tolerance * 1.01, "eigen_cg");
    for (auto _ : state) {
        solve();
        benchmark::DoNotOptimize(x.data());
    }
    report(state, n, iterations, anima::relative_residual(p, anima::expand_solution(p, sys, x)));
}

// Seam smoothing of a stitched clip: the walk, then the walk again from
// frame 40, then from frame 80 (two seams, about 900 frames, 96 DOFs).
struct stitched {
    anima::clip<double> clip;
    std::vector<std::size_t> seams;
};

const stitched& stitched_walk() {
    static const stitched s = [] {
        const auto walk = anima::read_bvh<double>(ANIMA_BENCH_DATA_DIR "/walk_cmu31_02_01.bvh");
        stitched out{walk, {}};
        for (std::size_t from : {40, 80}) {
            out.seams.push_back(out.clip.frames());
            out.clip.append(walk.slice(from, walk.frames()));
        }
        return out;
    }();
    return s;
}

void seam_smoothing(benchmark::State& state, anima::seam_smoothing_form form, anima::poisson_method method) {
    const auto& c = stitched_walk().clip;
    const auto& seams = stitched_walk().seams;
    anima::seam_smoothing_params<double> prm;
    prm.form = form;
    prm.solver = method;
    auto out = anima::smooth_seams(c, seams, prm);
    if (!out.stats.converged) fail("seam smoothing did not converge");
    for (auto _ : state) {
        out = anima::smooth_seams(c, seams, prm);
        benchmark::DoNotOptimize(out.motion.rotations().data());
    }
    state.counters["frames"] = static_cast<double>(c.frames());
    state.counters["solves"] = out.stats.solves;
    state.counters["iterations"] = out.stats.iterations;
}

int register_all() {
    long max_n = 513, max_cg = 257;
    if (const char* env = std::getenv("ANIMA_BENCH_POISSON_MAX")) max_n = max_cg = std::atol(env);
    for (Eigen::Index n : {65, 129, 257, 513, 1025, 2049}) {
        if (n > max_n) break;
        const std::string s = "/" + std::to_string(n);
        const auto unit = n >= 513 ? benchmark::kMillisecond : benchmark::kMicrosecond;
        benchmark::RegisterBenchmark(("multigrid" + s).c_str(), multigrid, n)->Unit(unit);
        benchmark::RegisterBenchmark(("multigrid_reused" + s).c_str(), multigrid_reused, n)->Unit(unit);
        benchmark::RegisterBenchmark(("dst" + s).c_str(), dst, n)->Unit(unit);
#ifdef ANIMA_HAVE_FFTW
        benchmark::RegisterBenchmark(("fftw_dst" + s).c_str(), fftw_dst, n)->Unit(unit);
#endif
        if (n > max_cg) continue;
        benchmark::RegisterBenchmark(("cg_poisson" + s).c_str(), cg, n, anima::cg_preconditioner::diagonal)->Unit(unit);
        benchmark::RegisterBenchmark(("cg_poisson_ic" + s).c_str(), cg, n,
                                     anima::cg_preconditioner::incomplete_cholesky)
            ->Unit(unit);
        benchmark::RegisterBenchmark(("cg_poisson_reused" + s).c_str(), cg_reused, n)->Unit(unit);
        benchmark::RegisterBenchmark(("eigen_cg" + s).c_str(), eigen_cg<Eigen::DiagonalPreconditioner<double>>, n)
            ->Unit(unit);
        benchmark::RegisterBenchmark(("eigen_cg_ic" + s).c_str(), eigen_cg<Eigen::IncompleteCholesky<double>>, n)
            ->Unit(unit);
    }
    using anima::poisson_method;
    using anima::seam_smoothing_form;
    benchmark::RegisterBenchmark("seam_smoothing/1d/multigrid", seam_smoothing, seam_smoothing_form::temporal,
                                 poisson_method::multigrid)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("seam_smoothing/1d/dst", seam_smoothing, seam_smoothing_form::temporal,
                                 poisson_method::dst)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("seam_smoothing/2d/multigrid", seam_smoothing, seam_smoothing_form::image,
                                 poisson_method::multigrid)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("seam_smoothing/2d/dst", seam_smoothing, seam_smoothing_form::image,
                                 poisson_method::dst)
        ->Unit(benchmark::kMillisecond);
    return 0;
}

[[maybe_unused]] const int registered = register_all();

}  // namespace
