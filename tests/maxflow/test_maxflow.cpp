// Max-flow / min-cut: flow_graph and grid_flow_graph against an independent
// Edmonds-Karp on a dense matrix (always) and against libmaxflow and
// Boost.Graph's boykov_kolmogorov_max_flow (when the build found them), on
// thousands of random graphs and grids in int, long long, float and double. Every solution is also checked on its own: capacities
// respected, flow conserved at every node, the cut's capacity equal to the
// flow, and the source side exactly the nodes reachable from the source in
// the residual graph. Then corner cases (disconnected graphs, zero and huge
// capacities, overflow), argument errors, re-solving, and the DIMACS reader.
#include <anima/core/error.hpp>
#include <anima/core/random.hpp>
#include <anima/maxflow.hpp>

#include <doctest/doctest.h>

#include "../test_support.hpp"

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

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace {

template <class Cap>
using flow_t = typename anima::capacity_traits<Cap>::flow_type;

template <class Cap>
struct test_edge {
    std::size_t u, v;
    Cap cap, rev;
};

/// A graph with terminal weights, as given to the solvers.
template <class Cap>
struct problem {
    std::size_t n = 0;
    std::vector<test_edge<Cap>> edges;
    std::vector<Cap> source, sink;
};

// ---------------------------------------------------------------------------
// Independent reference: Edmonds-Karp (shortest augmenting paths by BFS) on a
// dense residual matrix with the source at n and the sink at n + 1.
// ---------------------------------------------------------------------------
template <class Cap>
flow_t<Cap> reference_max_flow(const problem<Cap>& p) {
    using F = flow_t<Cap>;
    const std::size_t n = p.n + 2, s = p.n, t = p.n + 1;
    std::vector<F> r(n * n, F(0));
    for (const auto& e : p.edges) {
        if (e.u == e.v) continue;
        r[e.u * n + e.v] += F(e.cap);
        r[e.v * n + e.u] += F(e.rev);
    }
    for (std::size_t i = 0; i < p.n; ++i) {
        r[s * n + i] += F(p.source[i]);
        r[i * n + t] += F(p.sink[i]);
    }
    F flow = 0;
    std::vector<std::size_t> prev(n);
    for (;;) {
        std::fill(prev.begin(), prev.end(), n);
        prev[s] = s;
        std::deque<std::size_t> q{s};
        while (!q.empty() && prev[t] == n) {
            const std::size_t u = q.front();
            q.pop_front();
            for (std::size_t v = 0; v < n; ++v)
                if (prev[v] == n && r[u * n + v] > F(0)) {
                    prev[v] = u;
                    q.push_back(v);
                }
        }
        if (prev[t] == n) return flow;
        F b = std::numeric_limits<F>::max();
        for (std::size_t v = t; v != s; v = prev[v]) b = std::min(b, r[prev[v] * n + v]);
        for (std::size_t v = t; v != s; v = prev[v]) {
            r[prev[v] * n + v] -= b;
            r[v * n + prev[v]] += b;
        }
        flow += b;
    }
}

// ---------------------------------------------------------------------------
// Random problems. Capacities are multiples of 1/8 for floating types, so
// every sum the solvers and the reference form is exact and the results can
// be compared with ==.
// ---------------------------------------------------------------------------
template <class Cap>
Cap random_capacity(anima::random_source& rng, int max_units, double zero_chance) {
    if (rng.uniform() < zero_chance) return Cap(0);
    const auto units = static_cast<long long>(1 + rng.below(static_cast<std::uint64_t>(max_units)));
    if constexpr (std::is_floating_point_v<Cap>)
        return static_cast<Cap>(units) / Cap(8);
    else
        return static_cast<Cap>(units);
}

template <class Cap>
problem<Cap> random_problem(anima::random_source& rng, std::size_t n, std::size_t m, int max_units,
                            double terminal_chance) {
    problem<Cap> p;
    p.n = n;
    p.source.assign(n, Cap(0));
    p.sink.assign(n, Cap(0));
    for (std::size_t i = 0; i < n; ++i) {
        if (rng.uniform() < terminal_chance) p.source[i] = random_capacity<Cap>(rng, max_units, 0.1);
        if (rng.uniform() < terminal_chance) p.sink[i] = random_capacity<Cap>(rng, max_units, 0.1);
    }
    if (n == 0) return p;
    for (std::size_t k = 0; k < m; ++k) {
        // Self-loops and parallel edges happen: v may equal u, pairs repeat.
        const std::size_t u = rng.below(n), v = rng.below(n);
        const Cap cap = random_capacity<Cap>(rng, max_units, 0.25);
        const Cap rev = rng.uniform() < 0.5 ? Cap(0) : random_capacity<Cap>(rng, max_units, 0.25);
        p.edges.push_back({u, v, cap, rev});
        if (rng.uniform() < 0.05) p.edges.push_back({u, v, rev, cap});
    }
    return p;
}

/// A rows x cols 4-connected grid problem (right edges, then down edges, then
/// extra edges), shaped like segmentation: smooth pairwise terms, terminal
/// weights that favour the source on the left and the sink on the right.
template <class Cap>
struct grid_problem {
    std::size_t rows = 0, cols = 0;
    std::vector<Cap> right, right_rev, down, down_rev;  // rows x cols, unused in the last column / row
    std::vector<test_edge<Cap>> extra;
    std::vector<Cap> source, sink;

    problem<Cap> as_problem() const {
        problem<Cap> p;
        p.n = rows * cols;
        p.source = source;
        p.sink = sink;
        for (std::size_t r = 0; r < rows; ++r)
            for (std::size_t c = 0; c + 1 < cols; ++c)
                p.edges.push_back({r * cols + c, r * cols + c + 1, right[r * cols + c], right_rev[r * cols + c]});
        for (std::size_t r = 0; r + 1 < rows; ++r)
            for (std::size_t c = 0; c < cols; ++c)
                p.edges.push_back({r * cols + c, (r + 1) * cols + c, down[r * cols + c], down_rev[r * cols + c]});
        for (const auto& e : extra) p.edges.push_back(e);
        return p;
    }
};

template <class Cap>
grid_problem<Cap> random_grid(anima::random_source& rng, std::size_t rows, std::size_t cols, std::size_t extras,
                              int max_units) {
    grid_problem<Cap> g;
    g.rows = rows;
    g.cols = cols;
    const std::size_t n = rows * cols;
    for (auto* v : {&g.right, &g.right_rev, &g.down, &g.down_rev, &g.source, &g.sink}) v->assign(n, Cap(0));
    for (std::size_t r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < cols; ++c) {
            const std::size_t i = r * cols + c;
            const double x = cols > 1 ? double(c) / double(cols - 1) : 0.5;
            if (rng.uniform() < 0.6 * (1 - x)) g.source[i] = random_capacity<Cap>(rng, max_units, 0.0);
            if (rng.uniform() < 0.6 * x) g.sink[i] = random_capacity<Cap>(rng, max_units, 0.0);
            if (c + 1 < cols) {
                g.right[i] = random_capacity<Cap>(rng, max_units, 0.1);
                g.right_rev[i] = rng.uniform() < 0.8 ? g.right[i] : random_capacity<Cap>(rng, max_units, 0.1);
            }
            if (r + 1 < rows) {
                g.down[i] = random_capacity<Cap>(rng, max_units, 0.1);
                g.down_rev[i] = rng.uniform() < 0.8 ? g.down[i] : random_capacity<Cap>(rng, max_units, 0.1);
            }
        }
    for (std::size_t k = 0; k < extras; ++k)
        g.extra.push_back({rng.below(n), rng.below(n), random_capacity<Cap>(rng, max_units, 0.2),
                           random_capacity<Cap>(rng, max_units, 0.5)});
    return g;
}

template <class Cap>
anima::flow_graph<Cap> make_graph(const problem<Cap>& p) {
    anima::flow_graph<Cap> g(p.n);
    for (const auto& e : p.edges) g.add_edge(e.u, e.v, e.cap, e.rev);
    for (std::size_t i = 0; i < p.n; ++i) g.add_tweights(i, p.source[i], p.sink[i]);
    return g;
}

template <class Cap>
anima::grid_flow_graph<Cap> make_grid(const grid_problem<Cap>& p) {
    anima::grid_flow_graph<Cap> g(p.rows, p.cols);
    for (std::size_t r = 0; r < p.rows; ++r)
        for (std::size_t c = 0; c < p.cols; ++c) {
            const std::size_t i = r * p.cols + c;
            if (c + 1 < p.cols) g.set_right(r, c, p.right[i], p.right_rev[i]);
            if (r + 1 < p.rows) g.set_down(r, c, p.down[i], p.down_rev[i]);
            g.set_tweights(r, c, p.source[i], p.sink[i]);
        }
    for (const auto& e : p.extra) g.add_edge(e.u, e.v, e.cap, e.rev);
    return g;
}

/// What a solved graph says about its flow, for check_solution.
template <class Cap>
struct solution {
    flow_t<Cap> flow;
    std::function<Cap(std::size_t)> edge_flow, source_flow, sink_flow;
    std::function<anima::cut_side(std::size_t)> side;
};

template <class Cap>
solution<Cap> solution_of(const anima::flow_graph<Cap>& g, flow_t<Cap> flow) {
    return {flow, [&g](std::size_t e) { return g.edge_flow(e); }, [&g](std::size_t i) { return g.source_flow(i); },
            [&g](std::size_t i) { return g.sink_flow(i); }, [&g](std::size_t i) { return g.side(i); }};
}

template <class Cap>
solution<Cap> solution_of(const anima::grid_flow_graph<Cap>& g, const grid_problem<Cap>& p, flow_t<Cap> flow) {
    const std::size_t rows = p.rows, cols = p.cols, nr = rows * (cols - 1), nd = (rows - 1) * cols;
    auto edge = [&g, rows, cols, nr, nd](std::size_t e) -> Cap {
        if (e < nr) return g.right_flow(e / (cols - 1), e % (cols - 1));
        if (e < nr + nd) return g.down_flow((e - nr) / cols, (e - nr) % cols);
        (void)rows;
        return g.edge_flow(e - nr - nd);
    };
    return {flow, edge, [&g, cols](std::size_t i) { return g.source_flow(i / cols, i % cols); },
            [&g, cols](std::size_t i) { return g.sink_flow(i / cols, i % cols); },
            [&g](std::size_t i) { return g.side(i); }};
}

/// Checks a solution on its own (capacities, conservation, cut capacity =
/// flow, source side = residual reachability) and against the reference.
/// Exact: every quantity here is an exact sum in the types used.
template <class Cap>
void check_solution(const problem<Cap>& p, const solution<Cap>& s, flow_t<Cap> expected) {
    using F = flow_t<Cap>;
    REQUIRE(s.flow == expected);
    std::vector<F> net(p.n, F(0));  // inflow - outflow over graph edges
    for (std::size_t k = 0; k < p.edges.size(); ++k) {
        const auto& e = p.edges[k];
        const Cap f = s.edge_flow(k);
        REQUIRE(f <= e.cap);
        REQUIRE(-f <= e.rev);
        if (e.u == e.v) REQUIRE(f == Cap(0));
        net[e.v] += F(f);
        net[e.u] -= F(f);
    }
    F from_source = 0, to_sink = 0;
    for (std::size_t i = 0; i < p.n; ++i) {
        const Cap fs = s.source_flow(i), ft = s.sink_flow(i);
        REQUIRE(fs >= Cap(0));
        REQUIRE(ft >= Cap(0));
        REQUIRE(fs <= p.source[i]);
        REQUIRE(ft <= p.sink[i]);
        REQUIRE(net[i] + F(fs) - F(ft) == F(0));  // conservation
        from_source += F(fs);
        to_sink += F(ft);
    }
    REQUIRE(from_source == s.flow);
    REQUIRE(to_sink == s.flow);

    // The cut's capacity equals the flow.
    std::vector<bool> src(p.n);
    for (std::size_t i = 0; i < p.n; ++i) src[i] = s.side(i) == anima::cut_side::source;
    F cut = 0;
    for (std::size_t i = 0; i < p.n; ++i) cut += F(src[i] ? p.sink[i] : p.source[i]);
    for (const auto& e : p.edges) {
        if (src[e.u] && !src[e.v]) cut += F(e.cap);
        if (src[e.v] && !src[e.u]) cut += F(e.rev);
    }
    REQUIRE(cut == s.flow);

    // The source side is exactly what the source reaches in the residual graph.
    std::vector<std::vector<std::size_t>> residual(p.n);
    for (std::size_t k = 0; k < p.edges.size(); ++k) {
        const auto& e = p.edges[k];
        const Cap f = s.edge_flow(k);
        if (e.cap - f > Cap(0)) residual[e.u].push_back(e.v);
        if (e.rev + f > Cap(0)) residual[e.v].push_back(e.u);
    }
    std::vector<bool> reached(p.n, false);
    std::vector<std::size_t> stack;
    for (std::size_t i = 0; i < p.n; ++i)
        if (p.source[i] - s.source_flow(i) > Cap(0)) {
            reached[i] = true;
            stack.push_back(i);
        }
    while (!stack.empty()) {
        const std::size_t u = stack.back();
        stack.pop_back();
        for (std::size_t v : residual[u])
            if (!reached[v]) {
                reached[v] = true;
                stack.push_back(v);
            }
    }
    for (std::size_t i = 0; i < p.n; ++i) {
        REQUIRE(reached[i] == src[i]);
        if (reached[i]) REQUIRE(p.sink[i] - s.sink_flow(i) == Cap(0));  // no augmenting path left
    }
}

#ifdef ANIMA_HAVE_MAXFLOW
template <class Cap>
constexpr bool libmaxflow_has = std::is_same_v<Cap, int> || std::is_same_v<Cap, float> || std::is_same_v<Cap, double>;

/// libmaxflow's flow value (its flow type is the capacity type).
template <class Cap>
double libmaxflow_flow(const problem<Cap>& p) {
    using G = maxflow::Graph<Cap, Cap, Cap>;
    G g(static_cast<int>(p.n), static_cast<int>(p.edges.size()));
    if (p.n > 0) g.add_node(static_cast<int>(p.n));
    for (const auto& e : p.edges)
        if (e.u != e.v) g.add_edge(static_cast<int>(e.u), static_cast<int>(e.v), e.cap, e.rev);
    for (std::size_t i = 0; i < p.n; ++i) g.add_tweights(static_cast<int>(i), p.source[i], p.sink[i]);
    return static_cast<double>(g.maxflow());
}
#endif

#ifdef ANIMA_HAVE_BOOST_GRAPH
/// Boost.Graph's boykov_kolmogorov_max_flow, with the terminals as vertices n
/// and n + 1 (its flow type is the capacity type).
template <class Cap>
double boost_flow(const problem<Cap>& p) {
    using traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
    struct arc {
        Cap cap, residual;
        traits::edge_descriptor reverse;
    };
    using graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::directedS, boost::no_property, arc>;
    graph g(p.n + 2);
    auto add = [&g](std::size_t u, std::size_t v, Cap cap, Cap rev) {
        const auto a = boost::add_edge(u, v, g).first, b = boost::add_edge(v, u, g).first;
        g[a] = {cap, Cap(0), b};
        g[b] = {rev, Cap(0), a};
    };
    for (const auto& e : p.edges)
        if (e.u != e.v) add(e.u, e.v, e.cap, e.rev);
    for (std::size_t i = 0; i < p.n; ++i) {
        if (p.source[i] > Cap(0)) add(p.n, i, p.source[i], Cap(0));
        if (p.sink[i] > Cap(0)) add(i, p.n + 1, p.sink[i], Cap(0));
    }
    return static_cast<double>(boost::boykov_kolmogorov_max_flow(g, boost::get(&arc::cap, g),
                                                                 boost::get(&arc::residual, g),
                                                                 boost::get(&arc::reverse, g),
                                                                 boost::get(boost::vertex_index, g), p.n, p.n + 1));
}
#endif

/// Solves p with flow_graph, checks it, and compares with the peers found.
/// Returns the number of peer comparisons made.
template <class Cap>
int solve_and_check(const problem<Cap>& p) {
    auto g = make_graph(p);
    const auto f = g.maxflow();
    check_solution(p, solution_of(g, f), reference_max_flow(p));
    int peers = 0;
#ifdef ANIMA_HAVE_MAXFLOW
    if constexpr (libmaxflow_has<Cap>) {
        REQUIRE(static_cast<double>(f) == libmaxflow_flow(p));
        ++peers;
    }
#endif
#ifdef ANIMA_HAVE_BOOST_GRAPH
    if constexpr (std::is_same_v<Cap, int> || std::is_same_v<Cap, double>) {
        REQUIRE(static_cast<double>(f) == boost_flow(p));
        ++peers;
    }
#endif
    return peers;
}

/// Two disjoint paths source -> i -> i + 2 -> sink (i = 0, 1), every
/// capacity c: a flow of 2c.
template <class Cap>
anima::flow_graph<Cap> two_paths(Cap c) {
    anima::flow_graph<Cap> g(4);
    for (std::size_t i = 0; i < 2; ++i) {
        g.add_tweights(i, c, 0);
        g.add_edge(i, i + 2, c, 0);
        g.add_tweights(i + 2, 0, c);
    }
    return g;
}

}  // namespace

TEST_CASE_TEMPLATE("random graphs: flow_graph equals Edmonds-Karp (and libmaxflow), the cut is valid and minimal", Cap,
                   int, long long, float, double) {
    anima::random_source rng(20240601 + sizeof(Cap) + std::is_floating_point_v<Cap>);
    int graphs = 0, peer = 0;
    // Sizes from empty to 60 nodes; densities from a few edges to 6 per node;
    // few or many terminal links; small capacity ranges give many ties.
    for (int k = 0; k < 2000; ++k) {
        const std::size_t n = k < 20 ? std::size_t(k % 4) : 1 + rng.below(k % 10 == 0 ? 60 : 25);
        const std::size_t m = rng.below(6 * n + 2);
        const int units = k % 3 == 0 ? 3 : (k % 3 == 1 ? 20 : 1000);
        const double terminals = k % 4 == 0 ? 0.1 : (k % 4 == 1 ? 0.9 : 0.4);
        const auto p = random_problem<Cap>(rng, n, m, units, terminals);
        CAPTURE(k);
        peer += solve_and_check(p);
        ++graphs;
    }
    MESSAGE(graphs << " random graphs, " << peer << " peer comparisons (libmaxflow, Boost.Graph)");
}

TEST_CASE_TEMPLATE("random grids: grid_flow_graph and flow_graph agree with Edmonds-Karp and libmaxflow", Cap, int,
                   double) {
    anima::random_source rng(77 + sizeof(Cap));
    int grids = 0;
    for (int k = 0; k < 300; ++k) {
        const std::size_t rows = 1 + rng.below(k % 5 == 0 ? 12 : 6), cols = 1 + rng.below(k % 5 == 0 ? 12 : 6);
        const std::size_t extras = k % 2 == 0 ? 0 : rng.below(rows * cols + 1);
        const auto gp = random_grid<Cap>(rng, rows, cols, extras, k % 2 == 0 ? 10 : 500);
        const auto p = gp.as_problem();
        CAPTURE(k);
        CAPTURE(rows);
        CAPTURE(cols);
        auto grid = make_grid(gp);
        const auto f = grid.maxflow();
        check_solution(p, solution_of(grid, gp, f), reference_max_flow(p));
        solve_and_check(p);
        ++grids;
    }
    MESSAGE(grids << " random grids");
}

#ifdef ANIMA_HAVE_MAXFLOW
TEST_CASE_TEMPLATE("larger grids and graphs against libmaxflow", Cap, int, double) {
    anima::random_source rng(5 + sizeof(Cap));
    for (int k = 0; k < 12; ++k) {
        const std::size_t rows = 20 + rng.below(60), cols = 20 + rng.below(60);
        const auto gp = random_grid<Cap>(rng, rows, cols, k % 3 == 0 ? rows * cols / 10 : 0, k % 2 ? 100 : 10000);
        const auto p = gp.as_problem();
        CAPTURE(k);
        auto grid = make_grid(gp);
        const auto f = grid.maxflow();
        const auto expected = libmaxflow_flow(p);
        REQUIRE(static_cast<double>(f) == expected);
        // The self-checks need no reference beyond the flow value.
        check_solution(p, solution_of(grid, gp, f), f);
        auto g = make_graph(p);
        const auto fg = g.maxflow();
        check_solution(p, solution_of(g, fg), f);
    }
    for (int k = 0; k < 30; ++k) {
        const std::size_t n = 100 + rng.below(1500);
        const auto p = random_problem<Cap>(rng, n, rng.below(8 * n), k % 2 ? 50 : 5000, 0.3);
        CAPTURE(k);
        auto g = make_graph(p);
        const auto f = g.maxflow();
        REQUIRE(static_cast<double>(f) == libmaxflow_flow(p));
        check_solution(p, solution_of(g, f), f);
    }
}
#endif

TEST_CASE("non-dyadic double capacities: the flow matches the reference to rounding") {
    anima::random_source rng(99);
    for (int k = 0; k < 300; ++k) {
        const std::size_t n = 1 + rng.below(30);
        problem<double> p;
        p.n = n;
        p.source.assign(n, 0.0);
        p.sink.assign(n, 0.0);
        for (std::size_t i = 0; i < n; ++i) {
            if (rng.uniform() < 0.4) p.source[i] = rng.uniform() * 10;
            if (rng.uniform() < 0.4) p.sink[i] = rng.uniform() * 10;
        }
        for (std::size_t e = 0, m = rng.below(5 * n); e < m; ++e)
            p.edges.push_back({rng.below(n), rng.below(n), rng.uniform() * 3, rng.uniform() < 0.5 ? 0.0 : rng.uniform()});
        auto g = make_graph(p);
        const double f = g.maxflow();
        CAPTURE(k);
        REQUIRE(f == doctest::Approx(reference_max_flow(p)).epsilon(1e-12));
        double cut = 0;
        for (std::size_t i = 0; i < n; ++i) cut += g.side(i) == anima::cut_side::source ? p.sink[i] : p.source[i];
        for (const auto& e : p.edges) {
            const bool su = g.side(e.u) == anima::cut_side::source, sv = g.side(e.v) == anima::cut_side::source;
            if (su && !sv) cut += e.cap;
            if (sv && !su) cut += e.rev;
        }
        REQUIRE(cut == doctest::Approx(f).epsilon(1e-12));
#ifdef ANIMA_HAVE_MAXFLOW
        REQUIRE(f == doctest::Approx(libmaxflow_flow(p)).epsilon(1e-12));
#endif
    }
}

TEST_CASE_TEMPLATE("a floating-point flow that overflows throws instead of returning inf", Cap, float, double) {
    using flow_type = typename anima::flow_graph<Cap>::flow_type;
    const Cap big = std::numeric_limits<Cap>::max();
    // Straight through five nodes: float sums in double and fits, double
    // reaches inf.
    anima::flow_graph<Cap> g(5);
    for (std::size_t i = 0; i < 5; ++i) g.add_tweights(i, big, big);
    anima::grid_flow_graph<Cap> grid(1, 5);
    for (int c = 0; c < 5; ++c) grid.set_tweights(0, c, big, big);
    // Two paths of big / 2 + a bit each, through edges.
    const Cap half = big / Cap(2) + big / Cap(1000);
    auto h = two_paths(half);
    if constexpr (std::is_same_v<flow_type, Cap>) {
        const std::string expected = "overflows the flow type (largest " + anima::detail::argument_text(big) +
                                     "); the hard constraints may contradict each other, or scale the capacities down";
        CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)g.maxflow(); }), expected));
        CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)grid.maxflow(); }), expected));
        CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)h.maxflow(); }), expected));
        h.set_tweights(3, 0, big / Cap(4));
        CHECK(std::isfinite(h.maxflow()));
    } else {
        const flow_type five = 5 * static_cast<flow_type>(big);
        CHECK(g.maxflow() == five);
        CHECK(grid.maxflow() == five);
        CHECK(h.maxflow() == 2 * static_cast<flow_type>(half));
    }
}

TEST_CASE_TEMPLATE("disconnected graphs, isolated nodes and missing terminals give flow 0 or the flow of each part", Cap,
                   int, double) {
    SUBCASE("no nodes") {
        anima::flow_graph<Cap> g;
        CHECK(g.maxflow() == 0);
        CHECK(g.min_cut().side.empty());
    }
    SUBCASE("nodes without edges or terminal links") {
        anima::flow_graph<Cap> g(5);
        CHECK(g.maxflow() == 0);
        for (std::size_t i = 0; i < 5; ++i) CHECK(g.side(i) == anima::cut_side::sink);
    }
    SUBCASE("source and sink links in different components") {
        // 0-1-2 holds the source links, 3-4-5 the sink links.
        anima::flow_graph<Cap> g(6);
        g.add_edge(0, 1, Cap(5), Cap(5));
        g.add_edge(1, 2, Cap(5), Cap(5));
        g.add_edge(3, 4, Cap(5), Cap(5));
        g.add_edge(4, 5, Cap(5), Cap(5));
        g.add_tweights(0, Cap(9), Cap(0));
        g.add_tweights(5, Cap(0), Cap(9));
        const auto r = g.min_cut();
        CHECK(r.flow == 0);
        CHECK(r.source_count() == 3);
        for (std::size_t i = 0; i < 3; ++i) CHECK(r.side[i] == anima::cut_side::source);
        for (std::size_t i = 3; i < 6; ++i) CHECK(r.side[i] == anima::cut_side::sink);
    }
    SUBCASE("two independent components add up") {
        anima::flow_graph<Cap> g(4);
        g.add_tweights(0, Cap(3), Cap(0));
        g.add_edge(0, 1, Cap(2), Cap(0));
        g.add_tweights(1, Cap(0), Cap(7));
        g.add_tweights(2, Cap(4), Cap(0));
        g.add_edge(2, 3, Cap(6), Cap(0));
        g.add_tweights(3, Cap(0), Cap(1));
        CHECK(g.maxflow() == 3);  // 2 + 1
    }
    SUBCASE("a node with both terminal links carries their minimum directly") {
        anima::flow_graph<Cap> g(1);
        g.add_tweights(0, Cap(4), Cap(6));
        CHECK(g.maxflow() == 4);
        CHECK(g.side(0) == anima::cut_side::sink);
        CHECK(g.source_flow(0) == 4);
        CHECK(g.sink_flow(0) == 4);
    }
    SUBCASE("a grid whose two halves are not connected") {
        anima::grid_flow_graph<Cap> g(3, 4);
        for (std::size_t r = 0; r < 3; ++r) {
            g.set_right(r, 0, Cap(9), Cap(9));
            g.set_right(r, 2, Cap(9), Cap(9));  // column 1 -/- column 2
            g.set_tweights(r, 0, Cap(5), Cap(0));
            g.set_tweights(r, 3, Cap(0), Cap(5));
        }
        const auto r = g.min_cut();
        CHECK(r.flow == 0);
        CHECK(r.source_count() == 6);
        CHECK(g.side(2, 1) == anima::cut_side::source);
        CHECK(g.side(0, 2) == anima::cut_side::sink);
    }
}

TEST_CASE_TEMPLATE("zero capacities everywhere", Cap, int, double) {
    anima::flow_graph<Cap> g(4);
    g.add_edge(0, 1, Cap(0), Cap(0));
    g.add_edge(1, 2, Cap(0), Cap(0));
    g.add_tweights(0, Cap(0), Cap(0));
    CHECK(g.maxflow() == 0);
    CHECK(g.edge_flow(0) == 0);
    CHECK(g.min_cut().source_count() == 0);
    anima::grid_flow_graph<Cap> grid(2, 2);
    grid.set_tweights(0, 0, Cap(0), Cap(0));
    CHECK(grid.maxflow() == 0);
}

TEST_CASE("huge capacities: infinity for hard constraints, flow sums beyond the capacity type, overflow is an error") {
    SUBCASE("int infinity in both directions and on terminals") {
        constexpr int inf = anima::capacity_traits<int>::infinity();
        anima::flow_graph<int> g(3);
        g.add_tweights(0, inf, 0);
        g.add_tweights(0, inf, 0);  // twice: still representable
        g.add_edge(0, 1, inf, inf);
        g.add_edge(1, 2, 7, inf);
        g.add_tweights(2, 0, inf);
        CHECK(g.maxflow() == 7);
        CHECK(g.side(1) == anima::cut_side::source);
        CHECK(g.side(2) == anima::cut_side::sink);
    }
    SUBCASE("an int flow larger than INT_MAX is summed in long long") {
        constexpr int big = std::numeric_limits<int>::max();
        static_assert(std::is_same_v<anima::flow_graph<int>::flow_type, long long>);
        anima::flow_graph<int> g(4);
        for (std::size_t i = 0; i < 4; ++i) g.add_tweights(i, big, big);  // 4 x INT_MAX straight through
        CHECK(g.maxflow() == 4LL * big);
        // Through grid edges: (0, 1) passes INT_MAX straight through and INT_MAX from (0, 0) to (0, 2).
        anima::grid_flow_graph<int> grid(1, 3);
        grid.set_tweights(0, 0, big, 0);
        grid.set_tweights(0, 1, big, big);
        grid.set_tweights(0, 2, 0, big);
        grid.set_right(0, 0, big, 0);
        grid.set_right(0, 1, big, 0);
        CHECK(grid.maxflow() == 2LL * big);
        CHECK(grid.right_flow(0, 1) == big);
    }
    SUBCASE("a long long flow that overflows throws instead of wrapping") {
        constexpr long long big = std::numeric_limits<long long>::max() / 2 + 1;
        anima::flow_graph<long long> g(3);
        for (std::size_t i = 0; i < 3; ++i) g.add_tweights(i, big, big);
        CHECK_THROWS_AS(g.maxflow(), anima::invalid_argument);
        auto h = two_paths(big);  // two paths of 2^62 each, through edges
        CHECK_THROWS_AS(h.maxflow(), anima::invalid_argument);
        h.set_tweights(3, 0, big - 2);
        CHECK(h.maxflow() == std::numeric_limits<long long>::max() - 1);
    }
    SUBCASE("double infinity") {
        const double inf = anima::max_flow_infinity<double>();
        anima::flow_graph<double> g(2);
        g.add_tweights(0, inf, 0);
        g.add_edge(0, 1, 1e-3, inf);
        g.add_tweights(1, 0, inf);
        CHECK(g.maxflow() == 1e-3);
    }
}

TEST_CASE("capacities and ids are checked at the API") {
    anima::flow_graph<double> g(3);
    CHECK_THROWS_AS(g.add_edge(0, 3, 1, 1), anima::invalid_argument);
    CHECK_THROWS_AS(g.add_edge(0, 1, -1, 0), anima::invalid_argument);
    CHECK_THROWS_AS(g.add_edge(0, 1, std::nan(""), 0), anima::invalid_argument);
    CHECK_THROWS_AS(g.add_edge(0, 1, 0, std::numeric_limits<double>::infinity()), anima::invalid_argument);
    CHECK_THROWS_AS(g.add_edge(0, 1, std::numeric_limits<double>::max(), std::numeric_limits<double>::max()),
                    anima::invalid_argument);
    CHECK_THROWS_AS(g.add_tweights(3, 1, 0), anima::invalid_argument);
    CHECK_THROWS_AS(g.add_tweights(0, -0.5, 0), anima::invalid_argument);
    CHECK_THROWS_AS(g.side(0), anima::invalid_argument);  // not solved yet
    CHECK_THROWS_AS(g.set_edge(0, 1, 1), anima::invalid_argument);
    try {
        g.add_edge(0, 1, -2, 0);
        FAIL("no exception");
    } catch (const anima::invalid_argument& e) {
        CHECK(std::string(e.what()).find("add_edge") != std::string::npos);
        CHECK(std::string(e.what()).find("-2") != std::string::npos);
    }

    anima::flow_graph<int> h(1);
    h.add_tweights(0, std::numeric_limits<int>::max(), 0);
    CHECK_THROWS_AS(h.add_tweights(0, 1, 0), anima::invalid_argument);
    CHECK_THROWS_AS(h.add_edge(0, 0, std::numeric_limits<int>::max(), 1), anima::invalid_argument);

    CHECK_THROWS_AS(anima::grid_flow_graph<int>(0, 5), anima::invalid_argument);
    anima::grid_flow_graph<int> grid(2, 3);
    CHECK_THROWS_AS(grid.set_right(0, 2, 1, 1), anima::invalid_argument);  // last column
    CHECK_THROWS_AS(grid.set_down(1, 0, 1, 1), anima::invalid_argument);   // last row
    CHECK_THROWS_AS(grid.set_tweights(2, 0, 1, 1), anima::invalid_argument);
    CHECK_THROWS_AS(grid.add_edge(0, 6, 1, 1), anima::invalid_argument);
    CHECK_THROWS_AS(grid.set_right(0, 0, -1, 1), anima::invalid_argument);
    CHECK_THROWS_AS(grid.side(0, 0), anima::invalid_argument);
    CHECK(grid.node(1, 2) == 5);
}

TEST_CASE_TEMPLATE("self-loops are ignored and parallel edges add up", Cap, int, double) {
    anima::flow_graph<Cap> g(2);
    const auto loop = g.add_edge(0, 0, Cap(100), Cap(100));
    g.add_edge(0, 1, Cap(2), Cap(0));
    g.add_edge(0, 1, Cap(3), Cap(0));
    g.add_edge(1, 0, Cap(0), Cap(4));
    g.add_tweights(0, Cap(50), Cap(0));
    g.add_tweights(1, Cap(0), Cap(50));
    CHECK(g.maxflow() == 9);
    CHECK(g.edge_flow(loop) == 0);
    CHECK(g.edge_flow(1) + g.edge_flow(2) - g.edge_flow(3) == 9);
}

TEST_CASE_TEMPLATE("re-solving after changes gives the answer of a fresh graph", Cap, int, double) {
    anima::random_source rng(4242);
    for (int k = 0; k < 100; ++k) {
        auto p = random_problem<Cap>(rng, 2 + rng.below(20), rng.below(60), 20, 0.4);
        auto g = make_graph(p);
        g.maxflow();
        CHECK(g.maxflow() == reference_max_flow(p));  // cached
        // Change some edges (including from zero capacity), terminal weights, add nodes and edges.
        for (std::size_t e = 0; e < p.edges.size(); e += 3) {
            p.edges[e].cap = random_capacity<Cap>(rng, 20, 0.3);
            p.edges[e].rev = random_capacity<Cap>(rng, 20, 0.6);
            g.set_edge(e, p.edges[e].cap, p.edges[e].rev);
        }
        const std::size_t i = rng.below(p.n);
        p.source[i] = random_capacity<Cap>(rng, 20, 0.3);
        p.sink[i] = random_capacity<Cap>(rng, 20, 0.3);
        g.set_tweights(i, p.source[i], p.sink[i]);
        CAPTURE(k);
        auto f = g.maxflow();
        check_solution(p, solution_of(g, f), reference_max_flow(p));
        if (k % 2 == 0) {
            g.add_nodes(2);
            p.n += 2;
            p.source.resize(p.n, Cap(0));
            p.sink.resize(p.n, Cap(0));
            p.source[p.n - 1] = Cap(7);
            g.add_tweights(p.n - 1, Cap(7), Cap(0));
            p.edges.push_back({p.n - 1, 0, Cap(5), Cap(0)});
            g.add_edge(p.n - 1, 0, Cap(5), Cap(0));
            f = g.maxflow();
            check_solution(p, solution_of(g, f), reference_max_flow(p));
        }
    }
    // The grid too.
    auto gp = random_grid<Cap>(rng, 5, 7, 6, 30);
    auto grid = make_grid(gp);
    grid.maxflow();
    gp.right[3] = Cap(0);
    grid.set_right(0, 3, Cap(0), gp.right_rev[3]);
    gp.source[10] = Cap(25);
    grid.set_tweights(1, 3, Cap(25), gp.sink[10]);
    gp.extra[0].cap = Cap(13);
    grid.set_edge(0, Cap(13), gp.extra[0].rev);
    const auto p = gp.as_problem();
    const auto f = grid.maxflow();
    check_solution(p, solution_of(grid, gp, f), reference_max_flow(p));

    anima::flow_graph<Cap> g(2);
    g.add_edge(0, 1, Cap(3), Cap(0));
    g.add_tweights(0, Cap(5), Cap(0));
    g.add_tweights(1, Cap(0), Cap(5));
    CHECK(g.maxflow() == 3);
    g.clear();
    CHECK(g.nodes() == 0);
    CHECK(g.maxflow() == 0);
}

TEST_CASE("a (DOF x frame) seam lattice: rows switch where their own costs are lowest, tied rows switch together") {
    // 3 DOF rows x 8 frames. Column 0 is tied to the source, column 7 to the
    // sink; cutting between frames c and c+1 of a row costs cost[r][c].
    const int inf = anima::max_flow_infinity<int>();
    const int cost[3][7] = {{9, 9, 1, 9, 9, 9, 9}, {9, 9, 9, 9, 9, 2, 9}, {9, 9, 20, 9, 9, 3, 9}};
    auto seam = [&](int tie) {
        anima::grid_flow_graph<int> g(3, 8);
        for (std::size_t r = 0; r < 3; ++r) {
            g.set_tweights(r, 0, inf, 0);
            g.set_tweights(r, 7, 0, inf);
            for (std::size_t c = 0; c < 7; ++c) g.set_right(r, c, cost[r][c], cost[r][c]);
        }
        // Rows 0 and 2 are skeleton neighbours (not adjacent rows): extra edges per frame.
        for (std::size_t c = 0; c < 8; ++c) g.add_edge(g.node(0, c), g.node(2, c), tie, tie);
        g.maxflow();
        std::vector<std::size_t> switch_frame(3);
        for (std::size_t r = 0; r < 3; ++r) {
            std::size_t c = 0;
            while (c < 8 && g.side(r, c) == anima::cut_side::source) ++c;
            switch_frame[r] = c;  // first frame on the sink side
        }
        return std::make_pair(g.maxflow(), switch_frame);
    };
    const auto [loose_flow, loose] = seam(0);
    CHECK(loose_flow == 1 + 2 + 3);
    CHECK(loose == std::vector<std::size_t>{3, 6, 6});
    // A strong tie makes row 0 switch with row 2: 9 + 2 + 3 beats 1 + 2 + 3 + 3 ties of 5
    // and every other placement.
    const auto [tied_flow, tied] = seam(5);
    CHECK(tied_flow == 9 + 2 + 3);
    CHECK(tied == std::vector<std::size_t>{6, 6, 6});
}

// ---------------------------------------------------------------------------
// DIMACS
// ---------------------------------------------------------------------------

TEST_CASE("DIMACS: a valid file") {
    const char* text =
        "c a small example\r\n"
        "c\n"
        "\n"
        "p max 6 9\n"
        "n 1 s\n"
        "n 6 t\n"
        "a 1 2 5\n"
        "a 1 3 15\n"
        "a 2 4 5\n"
        "a 2 5 5\n"
        "a 3 4 5\n"
        "a 3 5 5\n"
        "a 4 6 15\n"
        "a 5 6 5\n"
        "  a\t5 5 3   \n";  // a self-loop
    const auto p = anima::parse_dimacs_max_flow<int>(text, "small.max");
    CHECK(p.nodes == 6);
    CHECK(p.source == 0);
    CHECK(p.sink == 5);
    REQUIRE(p.arcs.size() == 9);
    CHECK(p.arcs[1].from == 0);
    CHECK(p.arcs[1].to == 2);
    CHECK(p.arcs[1].capacity == 15);
    const auto r = anima::solve_max_flow(p);
    CHECK(r.flow == 15);
    CHECK(r.side[0] == anima::cut_side::source);
    CHECK(r.side[5] == anima::cut_side::sink);
    // The same in double, and a direct source -> sink arc, arcs into the
    // source and out of the sink.
    const auto q = anima::parse_dimacs_max_flow<double>(
        "p max 4 6\nn 4 t\nn 1 s\na 1 4 2.5\na 2 1 10\na 4 3 10\na 1 2 1.25\na 2 3 8\na 3 4 0.5\n");
    CHECK(q.source == 0);
    CHECK(q.sink == 3);
    CHECK(anima::solve_max_flow(q).flow == 2.5 + 0.5);
}

TEST_CASE("DIMACS: errors name the line") {
    auto error_of = [](const std::string& text) -> std::string {
        try {
            anima::parse_dimacs_max_flow<int>(text, "f.max");
        } catch (const anima::parse_error& e) {
            return e.what();
        }
        return "no error";
    };
    auto line_of = [](const std::string& text) -> std::size_t {
        try {
            anima::parse_dimacs_max_flow<int>(text, "f.max");
        } catch (const anima::parse_error& e) {
            CHECK(e.file() == "f.max");
            return e.line();
        }
        return 0;
    };
    const std::string head = "p max 3 2\nn 1 s\nn 3 t\n";
    CHECK(error_of("") == "f.max:1: no problem line (p max NODES ARCS)");
    CHECK(error_of("c only\nc comments\n") == "f.max:2: no problem line (p max NODES ARCS)");
    CHECK(error_of("a 1 2 3\n") == "f.max:1: 'a' line before the problem line (p max NODES ARCS)");
    CHECK(error_of("n 1 s\n") == "f.max:1: 'n' line before the problem line (p max NODES ARCS)");
    CHECK(error_of(head + "p max 3 2\n") == "f.max:4: second problem line (the first is on line 1)");
    CHECK(error_of("p min 3 2\n") == "f.max:1: problem type 'min' is not 'max' (p max NODES ARCS)");
    CHECK(error_of("p max x 2\n") == "f.max:1: 'x' is not a node count (a whole number >= 0)");
    CHECK(error_of("p max 3\n") == "f.max:1: the line ends where the arc count was expected");
    CHECK(error_of("p max 1 0\n").find("at least 2 nodes") != std::string::npos);
    CHECK(error_of("p max 3 -2\n") == "f.max:1: '-2' is not a arc count (a whole number >= 0)");
    CHECK(error_of("p max 3 2 7\n") == "f.max:1: unexpected '7' at the end of the line");
    CHECK(error_of(head + "a 1 2 3\na 2 4 1\n") == "f.max:5: node 4 is out of range 1..3");
    CHECK(error_of(head + "a 0 2 3\n") == "f.max:4: node 0 is out of range 1..3");
    CHECK(error_of(head + "a 1 2 -3\n") == "f.max:4: negative capacity -3");
    CHECK(error_of(head + "a 1 2 2.5\n") == "f.max:4: '2.5' is not a capacity (a whole number)");
    CHECK(error_of(head + "a 1 2 99999999999\n").find("f.max:4: capacity 99999999999 is out of the range") == 0);
    CHECK(error_of(head + "a 1 two 3\n") == "f.max:4: 'two' is not a node id (a whole number)");
    CHECK(error_of(head + "a 1 2\n") == "f.max:4: the line ends where the arc's capacity was expected");
    CHECK(error_of(head + "a 1 2 3\na 2 3 3\na 1 3 1\n") == "f.max:6: more arcs than the 2 announced on line 1");
    CHECK(error_of(head + "a 1 2 3\n") == "f.max:1: the problem line announces 2 arcs, the file has 1");
    CHECK(error_of("p max 3 0\nn 1 s\n") == "f.max:2: no sink (n ID t)");
    CHECK(error_of("p max 3 0\nn 3 t\nc\n") == "f.max:3: no source (n ID s)");
    CHECK(error_of("p max 3 0\nn 2 s\nn 2 t\n") == "f.max:3: node 2 is both the source and the sink");
    CHECK(error_of("p max 3 0\nn 1 s\nn 2 s\n") == "f.max:3: second source (the first is on line 2)");
    CHECK(error_of("p max 3 0\nn 1 s\nn 2 x\n") == "f.max:3: 'x' is not 's' (source) or 't' (sink)");
    CHECK(error_of("p max 3 0\nn 1 s\nx 2 t\n") == "f.max:3: unknown line type 'x' (expected c, p, n or a)");
    CHECK(line_of("p max 3 1\r\nn 1 s\r\nn 3 t\r\na 1 3 q\r\n") == 4);
    // Floating capacities.
    CHECK_THROWS_AS(anima::parse_dimacs_max_flow<double>(head + "a 1 2 nan\na 2 3 1\n"), anima::parse_error);
    CHECK_THROWS_AS(anima::parse_dimacs_max_flow<double>(head + "a 1 2 inf\na 2 3 1\n"), anima::parse_error);
    CHECK_THROWS_AS(anima::parse_dimacs_max_flow<float>(head + "a 1 2 1e300\na 2 3 1\n"), anima::parse_error);
    CHECK(anima::parse_dimacs_max_flow<double>(head + "a 1 2 +1e3\na 2 3 .5\n").arcs[0].capacity == 1000.0);
    // The largest value, short, not in 309 digits.
    try {
        anima::parse_dimacs_max_flow<double>(head + "a 1 2 1e400\na 2 3 1\n", "f.max");
        FAIL("no error for 1e400");
    } catch (const anima::parse_error& e) {
        CHECK(std::string(e.what()) == "f.max:4: capacity 1e400 is out of the range of the capacity type (largest 1.79769e+308)");
    }
}

TEST_CASE("DIMACS: a node's capacities that overflow name the arc, with the file's node ids") {
    // Two arcs into node 3 whose sum is beyond double.
    const auto p = anima::parse_dimacs_max_flow<double>("p max 4 3\nn 1 s\nn 2 t\na 1 3 1e308\na 1 3 1e308\na 3 2 1e308\n");
    try {
        (void)anima::to_flow_graph(p);
        FAIL("no error for an overflowing sum");
    } catch (const anima::invalid_argument& e) {
        CHECK(std::string(e.what()) ==
              "anima::to_flow_graph: arc 2 (a 1 3): the sum of a node's capacities overflows the capacity type");
    }
}

TEST_CASE("DIMACS: files") {
    CHECK_THROWS_AS(anima::read_dimacs_max_flow<int>("/nonexistent/dir/graph.max"), anima::io_error);
    // The bundled examples: a 4-connected grid and a small graph, with known flows.
    const std::string dir = ANIMA_TEST_DATA_DIR;
    const auto grid = anima::read_dimacs_max_flow<long long>(dir + "/maxflow_grid_16x24.max");
    const auto r = anima::solve_max_flow(grid);
    CHECK(r.flow == 9460);
    CHECK(r.source_count() == 129);
    CHECK(r.side[grid.source] == anima::cut_side::source);
    CHECK(r.side[grid.sink] == anima::cut_side::sink);
    // The same problem in double, and against the reference.
    const auto gd = anima::read_dimacs_max_flow<double>(dir + "/maxflow_grid_16x24.max");
    CHECK(anima::solve_max_flow(gd).flow == static_cast<double>(r.flow));
    problem<long long> p;
    p.n = grid.nodes;
    p.source.assign(p.n, 0);
    p.sink.assign(p.n, 0);
    for (const auto& a : grid.arcs) {
        if (a.from == grid.source)
            p.source[a.to] += a.capacity;
        else if (a.to == grid.sink)
            p.sink[a.from] += a.capacity;
        else if (a.to != grid.source && a.from != grid.sink)
            p.edges.push_back({a.from, a.to, a.capacity, 0});
    }
    CHECK(r.flow == reference_max_flow(p));
    const auto small = anima::read_dimacs_max_flow<int>(dir + "/maxflow_small.max");
    CHECK(anima::solve_max_flow(small).flow == 23);
    try {
        anima::read_dimacs_max_flow<int>(dir + "/walk_cmu31_02_01.bvh");
        FAIL("a BVH file parsed as DIMACS");
    } catch (const anima::parse_error& e) {
        CHECK(e.line() == 1);
        CHECK(e.file() == dir + "/walk_cmu31_02_01.bvh");
    }
}

TEST_CASE("DIMACS: counts that would size memory are checked against the file before allocating") {
    const auto message = [](const std::string& text) {
        try {
            (void)anima::parse_dimacs_max_flow<long long>(text, "big.max");
        } catch (const anima::parse_error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    // Two billion nodes for one arc: refused on the problem line, nothing allocated.
    const std::string nodes = message("c tiny\np max 2000000000 1\nn 1 s\nn 2 t\na 1 2 3\n");
    CHECK(anima_test::contains(nodes, "big.max:2:"));
    CHECK(anima_test::contains(nodes, "2000000000 nodes for 1 arcs"));
    // More arcs announced than the file has bytes for.
    const std::string arcs = message("p max 2 1000000000\nn 1 s\nn 2 t\na 1 2 3\n");
    CHECK(anima_test::contains(arcs, "big.max:1:"));
    CHECK(anima_test::contains(arcs, "more than the file's"));
    // Up to dimacs_max_isolated_nodes isolated nodes are fine, and so are
    // many nodes justified by arcs.
    const auto p = anima::parse_dimacs_max_flow<int>("p max 1000000 1\nn 1 s\nn 2 t\na 1 2 3\n");
    CHECK(p.nodes == 1000000);
    CHECK(anima::solve_max_flow(p).flow == 3);
    std::string many = "p max 2000000 1000000\nn 1 s\nn 2 t\n";
    for (int k = 0; k < 1000000; ++k) many += "a 1 2 1\n";
    CHECK(anima::parse_dimacs_max_flow<int>(many).arcs.size() == 1000000);
}
