// Max-flow on 4-connected grid graphs: anima's general flow_graph and its
// grid layout (grid_flow_graph) next to libmaxflow (Kolmogorov's BK code) and
// Boost.Graph's boykov_kolmogorov_max_flow, on the same graphs, int capacities.
//
//   BM_maxflow_solve<impl>/<family>/<rows>x<cols>   the max-flow computation alone
//   BM_maxflow_build<impl>/<family>/<rows>x<cols>   building the graph alone
//
//   impl:   anima_graph (flow_graph), anima_grid (grid_flow_graph),
//           libmaxflow (maxflow::Graph<int, int, int>), boost (adjacency_list
//           with vecS, terminals as two extra vertices)
//   family: segmentation  binary segmentation of a synthetic image (bright
//                         disks on a darker background, noise): terminal
//                         weights from the intensity, edge weights
//                         1 + 30 exp(-d^2 / 0.02) for an intensity step d
//           random        terminal and edge capacities uniform in 0..100
//
// A solve destroys the residual capacities, so each iteration of the solve
// benchmark builds a fresh graph with the timer paused. Before anything is
// timed, every implementation's flow on every graph used is compared once;
// the program aborts if they differ. The 1000 x 1000 grids run only when the
// environment variable ANIMA_BENCH_LARGE is set (they take seconds each).
//
// With glibc, freed memory is kept by the allocator (mallopt) for every
// implementation alike: otherwise whether an iteration pays page faults for
// fresh memory depends on how glibc's adaptive thresholds happen to react to
// each library's allocation sizes, not on the libraries.

#include <anima/core/random.hpp>
#include <anima/maxflow/graph.hpp>
#include <anima/maxflow/grid_graph.hpp>

#include <benchmark/benchmark.h>

#ifdef ANIMA_HAVE_MAXFLOW
#include <maxflow/graph.h>
#endif
#ifdef ANIMA_HAVE_BOOST_GRAPH
// GCC sees Boost's optional edge iterators as maybe uninitialised once inlined here.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#endif

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

namespace {

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "bench_maxflow: %s\n", what.c_str());
    std::abort();
}

enum class family { segmentation, random };

/// A 4-connected grid with symmetric edge weights (cap = rev_cap).
struct grid_data {
    std::size_t rows = 0, cols = 0;
    std::vector<int> right, down;    // rows x cols; unused in the last column / row
    std::vector<int> source, sink;  // rows x cols
};

grid_data make_segmentation(std::size_t rows, std::size_t cols) {
    anima::random_source rng(rows * 7919 + cols);
    grid_data d;
    d.rows = rows;
    d.cols = cols;
    const std::size_t n = rows * cols;
    std::vector<double> image(n, 0.3);
    const std::size_t disks = 3 + (rows * cols) / 20000;
    for (std::size_t k = 0; k < disks; ++k) {
        const double cr = rng.uniform() * double(rows), cc = rng.uniform() * double(cols);
        const double radius = (0.05 + 0.15 * rng.uniform()) * double(std::min(rows, cols));
        for (std::size_t r = 0; r < rows; ++r)
            for (std::size_t c = 0; c < cols; ++c)
                if ((double(r) - cr) * (double(r) - cr) + (double(c) - cc) * (double(c) - cc) <= radius * radius)
                    image[r * cols + c] = 0.7;
    }
    for (double& v : image) v = std::clamp(v + 0.3 * (rng.uniform() - 0.5), 0.0, 1.0);
    auto weight = [&](std::size_t a, std::size_t b) {
        const double step = image[a] - image[b];
        return 1 + static_cast<int>(std::lround(30 * std::exp(-step * step / 0.02)));
    };
    d.right.assign(n, 0);
    d.down.assign(n, 0);
    d.source.assign(n, 0);
    d.sink.assign(n, 0);
    for (std::size_t r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < cols; ++c) {
            const std::size_t i = r * cols + c;
            d.source[i] = static_cast<int>(std::lround(60 * image[i]));
            d.sink[i] = static_cast<int>(std::lround(60 * (1 - image[i])));
            if (c + 1 < cols) d.right[i] = weight(i, i + 1);
            if (r + 1 < rows) d.down[i] = weight(i, i + cols);
        }
    return d;
}

grid_data make_random(std::size_t rows, std::size_t cols) {
    anima::random_source rng(rows * 104729 + cols);
    grid_data d;
    d.rows = rows;
    d.cols = cols;
    const std::size_t n = rows * cols;
    auto cap = [&] { return static_cast<int>(rng.below(101)); };
    d.right.assign(n, 0);
    d.down.assign(n, 0);
    d.source.assign(n, 0);
    d.sink.assign(n, 0);
    for (std::size_t r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < cols; ++c) {
            const std::size_t i = r * cols + c;
            d.source[i] = cap();
            d.sink[i] = cap();
            if (c + 1 < cols) d.right[i] = cap();
            if (r + 1 < rows) d.down[i] = cap();
        }
    return d;
}

// ---------------------------------------------------------------------------
// The four implementations: build(data) constructs, solve() returns the flow.
// ---------------------------------------------------------------------------

struct anima_graph {
    anima::flow_graph<int> g;
    explicit anima_graph(const grid_data& d) : g(d.rows * d.cols, 2 * d.rows * d.cols) {
        for (std::size_t r = 0; r < d.rows; ++r)
            for (std::size_t c = 0; c < d.cols; ++c) {
                const std::size_t i = r * d.cols + c;
                if (c + 1 < d.cols) g.add_edge(i, i + 1, d.right[i], d.right[i]);
                if (r + 1 < d.rows) g.add_edge(i, i + d.cols, d.down[i], d.down[i]);
                g.add_tweights(i, d.source[i], d.sink[i]);
            }
    }
    long long solve() { return g.maxflow(); }
};

struct anima_grid {
    anima::grid_flow_graph<int> g;
    explicit anima_grid(const grid_data& d) : g(d.rows, d.cols) {
        for (std::size_t r = 0; r < d.rows; ++r)
            for (std::size_t c = 0; c < d.cols; ++c) {
                const std::size_t i = r * d.cols + c;
                if (c + 1 < d.cols) g.set_right(r, c, d.right[i], d.right[i]);
                if (r + 1 < d.rows) g.set_down(r, c, d.down[i], d.down[i]);
                g.set_tweights(r, c, d.source[i], d.sink[i]);
            }
    }
    long long solve() { return g.maxflow(); }
};

#ifdef ANIMA_HAVE_MAXFLOW
struct libmaxflow {
    maxflow::Graph<int, int, int> g;
    explicit libmaxflow(const grid_data& d)
        : g(static_cast<int>(d.rows * d.cols), static_cast<int>(2 * d.rows * d.cols)) {
        g.add_node(static_cast<int>(d.rows * d.cols));
        for (std::size_t r = 0; r < d.rows; ++r)
            for (std::size_t c = 0; c < d.cols; ++c) {
                const int i = static_cast<int>(r * d.cols + c);
                if (c + 1 < d.cols) g.add_edge(i, i + 1, d.right[i], d.right[i]);
                if (r + 1 < d.rows) g.add_edge(i, i + static_cast<int>(d.cols), d.down[i], d.down[i]);
                g.add_tweights(i, d.source[i], d.sink[i]);
            }
    }
    long long solve() { return g.maxflow(); }
};
#endif

#ifdef ANIMA_HAVE_BOOST_GRAPH
struct boost_graph {
    using traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
    struct arc {
        int cap = 0, residual = 0;
        traits::edge_descriptor reverse;
    };
    using graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::directedS, boost::no_property, arc>;
    graph g;
    std::size_t s, t;

    explicit boost_graph(const grid_data& d) : g(d.rows * d.cols + 2), s(d.rows * d.cols), t(d.rows * d.cols + 1) {
        for (std::size_t r = 0; r < d.rows; ++r)
            for (std::size_t c = 0; c < d.cols; ++c) {
                const std::size_t i = r * d.cols + c;
                if (c + 1 < d.cols) add(i, i + 1, d.right[i], d.right[i]);
                if (r + 1 < d.rows) add(i, i + d.cols, d.down[i], d.down[i]);
                if (d.source[i] > 0) add(s, i, d.source[i], 0);
                if (d.sink[i] > 0) add(i, t, d.sink[i], 0);
            }
    }
    void add(std::size_t u, std::size_t v, int cap, int rev) {
        const auto a = boost::add_edge(u, v, g).first, b = boost::add_edge(v, u, g).first;
        g[a].cap = cap;
        g[a].reverse = b;
        g[b].cap = rev;
        g[b].reverse = a;
    }
    long long solve() {
        return boost::boykov_kolmogorov_max_flow(g, boost::get(&arc::cap, g), boost::get(&arc::residual, g),
                                                 boost::get(&arc::reverse, g), boost::get(boost::vertex_index, g), s,
                                                 t);
    }
};
#endif

const char* family_name(family f) { return f == family::segmentation ? "segmentation" : "random"; }

/// The graph of a family and size, made once; on first use every
/// implementation's flow is compared.
const grid_data& data(family f, std::size_t rows, std::size_t cols) {
    static std::map<std::tuple<family, std::size_t, std::size_t>, std::unique_ptr<grid_data>> cache;
    auto& slot = cache[{f, rows, cols}];
    if (slot) return *slot;
    slot = std::make_unique<grid_data>(f == family::segmentation ? make_segmentation(rows, cols) : make_random(rows, cols));
    const grid_data& d = *slot;
    const long long expected = anima_graph(d).solve();
    auto check = [&](const char* who, long long flow) {
        if (flow != expected)
            fail(std::string(who) + " computes " + std::to_string(flow) + ", anima_graph " + std::to_string(expected) +
                 " on " + family_name(f) + " " + std::to_string(rows) + "x" + std::to_string(cols));
    };
    check("anima_grid", anima_grid(d).solve());
#ifdef ANIMA_HAVE_MAXFLOW
    check("libmaxflow", libmaxflow(d).solve());
#endif
#ifdef ANIMA_HAVE_BOOST_GRAPH
    check("boost", boost_graph(d).solve());
#endif
    return d;
}

template <class Impl>
void bm_solve(benchmark::State& state, family f, std::size_t rows, std::size_t cols) {
    const grid_data& d = data(f, rows, cols);
    for (auto _ : state) {
        state.PauseTiming();
        auto g = std::make_unique<Impl>(d);
        state.ResumeTiming();
        benchmark::DoNotOptimize(g->solve());
        state.PauseTiming();
        g.reset();
        state.ResumeTiming();
    }
    state.counters["nodes"] = double(rows * cols);
}

template <class Impl>
void bm_build(benchmark::State& state, family f, std::size_t rows, std::size_t cols) {
    const grid_data& d = data(f, rows, cols);
    for (auto _ : state) {
        auto g = std::make_unique<Impl>(d);
        benchmark::DoNotOptimize(g.get());
        state.PauseTiming();
        g.reset();
        state.ResumeTiming();
    }
    state.counters["nodes"] = double(rows * cols);
}

template <class Impl>
void register_impl(const char* name, family f, std::size_t rows, std::size_t cols) {
    const std::string suffix = std::string(name) + ">/" + family_name(f) + "/" + std::to_string(rows) + "x" +
                               std::to_string(cols);
    benchmark::RegisterBenchmark(("BM_maxflow_solve<" + suffix).c_str(), bm_solve<Impl>, f, rows, cols)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_maxflow_build<" + suffix).c_str(), bm_build<Impl>, f, rows, cols)
        ->Unit(benchmark::kMillisecond);
}

const bool registered = [] {
#if defined(__GLIBC__)
    mallopt(M_MMAP_THRESHOLD, 1 << 30);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
    struct size {
        std::size_t rows, cols;
    };
    std::vector<std::pair<family, size>> cases = {
        {family::segmentation, {50, 100}}, {family::segmentation, {200, 200}}, {family::segmentation, {500, 500}},
        {family::random, {50, 100}},       {family::random, {200, 200}},       {family::random, {500, 500}}};
    if (std::getenv("ANIMA_BENCH_LARGE") != nullptr) {
        cases.push_back({family::segmentation, {1000, 1000}});
        cases.push_back({family::random, {1000, 1000}});
    }
    for (const auto& [f, s] : cases) {
        register_impl<anima_graph>("anima_graph", f, s.rows, s.cols);
        register_impl<anima_grid>("anima_grid", f, s.rows, s.cols);
#ifdef ANIMA_HAVE_MAXFLOW
        register_impl<libmaxflow>("libmaxflow", f, s.rows, s.cols);
#endif
#ifdef ANIMA_HAVE_BOOST_GRAPH
        register_impl<boost_graph>("boost", f, s.rows, s.cols);
#endif
    }
    return true;
}();

}  // namespace
