// anima maxflow FILE.max [--json] [--real]: the maximum flow and minimum cut
// of a DIMACS max-flow problem, with anima's Boykov-Kolmogorov solver.
#include "commands.hpp"
#include "common.hpp"

#include <anima/core/stopwatch.hpp>
#include <anima/maxflow.hpp>

#include <CLI/CLI.hpp>

#include <cstddef>
#include <iostream>
#include <string>
#include <type_traits>

namespace anima_cli {
namespace {

struct maxflow_options {
    std::string input;
    bool json = false;
    bool real = false;
};

template <class Cap>
void solve(const maxflow_options& o, const std::string& text) {
    anima::stopwatch timer;
    const anima::dimacs_max_flow<Cap> problem = anima::parse_dimacs_max_flow<Cap>(text, o.input);
    const double read_seconds = timer.lap();

    // Timed: building the graph and solving, as a program embedding anima would.
    const auto result = [&] {
        try {
            return anima::solve_max_flow(problem);
        } catch (const anima::invalid_argument& e) {
            throw failure("'" + o.input + "': " + e.what());  // an arc whose capacity overflows a node's sum
        }
    }();
    const double seconds = timer.lap();
    const std::size_t source_side = result.source_count();

    if (o.json) {
        print_json({{"file", o.input},
                    {"nodes", problem.nodes},
                    {"arcs", problem.arcs.size()},
                    {"source", problem.source + 1},
                    {"sink", problem.sink + 1},
                    {"capacity_type", o.real ? "double" : "integer"},
                    {"flow", result.flow},
                    {"source_side", source_side},
                    {"sink_side", problem.nodes - source_side},
                    {"seconds", seconds},
                    {"read_seconds", read_seconds}});
        return;
    }
    std::cout << o.input << '\n';
    std::cout << "nodes         " << problem.nodes << " (source " << problem.source + 1 << ", sink "
              << problem.sink + 1 << ")\n";
    std::cout << "arcs          " << problem.arcs.size() << '\n';
    if constexpr (std::is_floating_point_v<Cap>)
        std::cout << "flow          " << format_number(result.flow, 15) << '\n';
    else
        std::cout << "flow          " << result.flow << '\n';
    std::cout << "source side   " << source_side << " nodes (the source and what it reaches in the residual graph), "
              << problem.nodes - source_side << " on the sink side\n";
    std::cout << "seconds       " << format_number(seconds, 3) << " (building the graph and solving; reading took "
              << format_number(read_seconds, 3) << ")\n";
}

void run_maxflow(const maxflow_options& o) {
    const std::string text = read_text_file(o.input);
    if (o.real)
        solve<double>(o, text);
    else
        solve<long long>(o, text);
}

}  // namespace
}  // namespace anima_cli

void register_maxflow(CLI::App& app) {
    const auto [sub, opts] = anima_cli::add_command<anima_cli::maxflow_options>(
        app, "maxflow", "Solve a DIMACS max-flow problem: the flow value, the minimum cut's sides, the time taken",
        anima_cli::run_maxflow);
    sub->add_option("FILE", opts->input, "DIMACS max-flow file (p max NODES ARCS, n ID s|t, a U V CAP)")
        ->required()
        ->type_name("PATH");
    sub->add_flag("--real", opts->real, "Read capacities as real numbers (default: whole numbers, 64-bit)");
    sub->add_flag("--json", opts->json, "Print one JSON object instead of text");
}
