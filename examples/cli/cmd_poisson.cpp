// anima poisson --grid WxH --rhs random|FILE.csv: solves the 5-point Poisson
// equation nabla^2 u = f on a W x H grid of unknowns (unit spacing, zero
// Dirichlet values around, or zero flux with --neumann) with multigrid, the
// sine-transform solver or Eigen's conjugate gradient, and reports time,
// iterations and the relative residual: a quick look at the solvers.
#include "commands.hpp"
#include "common.hpp"

#include <anima/core/stopwatch.hpp>
#include <anima/poisson.hpp>

#include <CLI/CLI.hpp>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include <cerrno>
#include <cstdlib>
#include <iostream>
#include <string>

namespace anima_cli {
namespace {

struct poisson_options {
    std::string grid, rhs = "random", solver = "multigrid", output, cycle = "v";
    std::uint64_t seed = 1;
    double tolerance = 1e-8;
    int pre = 2, post = 2, max_cycles = 100;
    bool neumann = false, json = false;
};

struct grid_size {
    Eigen::Index width = 0, height = 0;
};

grid_size parse_grid(const std::string& text) {
    const auto x = text.find_first_of("xX");
    const auto number = [&](const std::string& s) -> Eigen::Index {
        if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos) return -1;
        errno = 0;
        const long long v = std::strtoll(s.c_str(), nullptr, 10);
        return errno ? -1 : static_cast<Eigen::Index>(v);
    };
    grid_size g;
    if (x != std::string::npos) {
        g.width = number(text.substr(0, x));
        g.height = number(text.substr(x + 1));
    }
    if (g.width <= 0 || g.height <= 0 || g.width > 100000 || g.height > 100000)
        throw CLI::ValidationError("--grid", "'" + text + "' is not a grid size: use WxH with W, H from 1 to 100000");
    return g;
}

void run_poisson(const poisson_options& o) {
    check_outputs({{"--out", &o.output}});
    const grid_size size = parse_grid(o.grid);
    // u, f, the residual and the coarser levels (multigrid, dst), or a sparse
    // matrix and its incomplete factor (cg-ic): about 12 or 40 doubles per unknown.
    check_request_memory(static_cast<double>(size.width) * static_cast<double>(size.height),
                         (o.solver == "cg" || o.solver == "cg-ic" ? 40.0 : 12.0) * 8,
                         "a " + std::to_string(size.width) + " x " + std::to_string(size.height) + " grid with " +
                             o.solver,
                         "--grid");
    const anima::boundary sides = o.neumann ? anima::boundary::neumann : anima::boundary::dirichlet;
    Eigen::MatrixXd f;
    if (o.rhs == "random") {
        anima::random_source rng(o.seed);
        f.resize(size.height, size.width);
        for (Eigen::Index j = 0; j < size.width; ++j)
            for (Eigen::Index i = 0; i < size.height; ++i) f(i, j) = 2 * rng.uniform() - 1;
    } else {
        f = anima::parse_grid_csv<double>(read_text_file(o.rhs), o.rhs, size.height, size.width);
    }
    const auto problem = anima::make_poisson_problem(anima::make_poisson_grid<double>(size.height, size.width, sides), f);

    json out = {{"grid", {{"width", size.width}, {"height", size.height}}},
                {"unknowns", size.width * size.height},
                {"boundary", anima::to_string(sides)},
                {"rhs", o.rhs},
                {"solver", o.solver},
                {"tolerance", o.tolerance}};
    anima::poisson_result<double> r;
    double setup = 0, solve = 0;
    anima::stopwatch timer;
    if (o.solver == "multigrid") {
        anima::multigrid_poisson<double>::params prm;
        prm.tolerance = o.tolerance;
        prm.cycle = anima::parse_multigrid_cycle(o.cycle);
        prm.pre_sweeps = o.pre;
        prm.post_sweeps = o.post;
        prm.max_cycles = o.max_cycles;
        anima::multigrid_poisson<double> mg(problem.grid, prm);
        setup = timer.lap();
        r = mg.solve(problem);
        solve = timer.lap();
        json levels = json::array();
        for (std::size_t l = 0; l < mg.levels(); ++l)
            levels.push_back({{"width", mg.level_size(l).second}, {"height", mg.level_size(l).first}});
        out["cycle"] = o.cycle;
        out["pre_sweeps"] = o.pre;
        out["post_sweeps"] = o.post;
        out["levels"] = levels;
    } else if (o.solver == "dst") {
        const anima::dst_poisson<double> fast(problem.grid);
        setup = timer.lap();
        r = fast.solve(problem);
        solve = timer.lap();
    } else {
        // Conjugate gradients on the assembled system, as a reference.
        anima::cg_poisson<double>::params prm;
        prm.tolerance = o.tolerance;
        if (o.solver == "cg-ic") prm.preconditioner = anima::cg_preconditioner::incomplete_cholesky;
        const anima::cg_poisson<double> cg(problem, prm);
        setup = timer.lap();
        r = cg.solve();
        solve = timer.lap();
    }
    const double seconds = setup + solve;
    out["seconds"] = seconds;
    out["setup_seconds"] = setup;
    out["solve_seconds"] = solve;
    out["ns_per_unknown"] = seconds * 1e9 / static_cast<double>(size.width * size.height);
    out["iterations"] = r.iterations;
    out["relative_residual"] = r.relative_residual;
    out["converged"] = r.converged;
    if (o.neumann) out["removed_mean"] = r.removed_mean;
    if (!r.residual_history.empty()) out["residual_history"] = r.residual_history;
    if (!o.output.empty()) {
        write_text_file(o.output, anima::format_grid_csv(r.u));
        out["output"] = o.output;
    }
    if (!r.converged)
        std::cerr << "anima: warning: " << o.solver << " stopped at relative residual "
                  << format_number(r.relative_residual, 3) << ", above the tolerance " << format_number(o.tolerance)
                  << "\n";
    if (o.json) return print_json(out);
    std::cout << o.solver << " on a " << size.width << " x " << size.height << " grid ("
              << size.width * size.height << " unknowns, " << anima::to_string(sides) << "): ";
    if (o.solver == "dst") std::cout << "direct";
    else std::cout << r.iterations << (o.solver == "multigrid" ? " cycle" : " iteration") << (r.iterations == 1 ? "" : "s");
    std::cout << ", relative residual " << format_number(r.relative_residual, 3) << ", " << format_fixed(seconds, 4)
              << " s (setup " << format_fixed(setup, 4) << " s, " << format_number(out["ns_per_unknown"].get<double>(), 3)
              << " ns per unknown)\n";
    if (o.neumann && r.removed_mean != 0)
        std::cout << "pure Neumann: removed the mean " << format_number(r.removed_mean) << " of f; u has zero mean\n";
    if (!o.output.empty())
        report_written(o.output + " (" + std::to_string(size.height) + " rows of " + std::to_string(size.width) + ")");
}

}  // namespace
}  // namespace anima_cli

void register_poisson(CLI::App& app) {
    using namespace anima_cli;
    const auto [sub, opts] = add_command<poisson_options>(
        app, "poisson",
        "Solve the 5-point Poisson equation on a grid with multigrid, the sine transform or CG, and time it",
        run_poisson);
    sub->add_option("--grid", opts->grid, "W x H unknowns (unit spacing), e.g. 513x257")->required()->type_name("WxH");
    sub->add_option("--rhs", opts->rhs, "Right-hand side f: 'random' (uniform in [-1, 1]) or a CSV file of H rows of W numbers")
        ->type_name("random|FILE.csv")
        ->capture_default_str();
    add_setting(*sub, "--seed", opts->seed, "Seed of the random right-hand side", count_up_to(~0ULL));
    add_setting(*sub, "--solver", opts->solver,
                "multigrid, dst (sine/cosine transform), cg or cg-ic (Eigen's CG, with IncompleteCholesky)",
                CLI::IsMember({"multigrid", "dst", "cg", "cg-ic"}));
    sub->add_flag("--neumann", opts->neumann, "Zero flux on every side instead of zero Dirichlet values");
    add_setting(*sub, "--tolerance", opts->tolerance,
                "Stop at this relative residual ||b - Ax|| / ||b|| (multigrid, cg)", number_in(0, 1, true, true));
    add_setting(*sub, "--cycle", opts->cycle, "Multigrid cycle: v or w",
                CLI::IsMember(anima::enum_name_list<anima::multigrid_cycle>()));
    add_setting(*sub, "--pre", opts->pre, "Multigrid smoothing sweeps before the coarse correction",
                integer_in(0, 1000));
    add_setting(*sub, "--post", opts->post, "Multigrid smoothing sweeps after it", integer_in(0, 1000));
    add_setting(*sub, "--max-cycles", opts->max_cycles, "Most multigrid cycles", integer_in(1, 100000));
    sub->add_option("--out", opts->output, "Write u as CSV, H rows of W numbers")->type_name("U.csv");
    sub->add_flag("--json", opts->json, "Print a JSON object instead of text");
}
