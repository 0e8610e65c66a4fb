// The DIMACS max-flow format (the first DIMACS implementation challenge):
//
//   c a comment                 (also any line starting with 'c'; blank lines are skipped)
//   p max NODES ARCS            (once, before any n or a line)
//   n ID s                      (the source)
//   n ID t                      (the sink)
//   a U V CAPACITY              (an arc U -> V; exactly ARCS of them)
//
// Node ids are 1-based in the file and 0-based in dimacs_max_flow. Every
// malformed line is reported as anima::parse_error (file:line: message).
// to_flow_graph turns a problem into a flow_graph: arcs out of the source
// become source capacities, arcs into the sink sink capacities, arcs into the
// source or out of the sink are dropped (they cannot carry flow from the
// source to the sink), self-loops are dropped too.
#pragma once

#include <anima/core/error.hpp>
#include <anima/core/file_io.hpp>
#include <anima/maxflow/capacity.hpp>
#include <anima/maxflow/graph.hpp>
#include <anima/maxflow/min_cut.hpp>

#include <algorithm>
#include <charconv>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

namespace anima {

/// A DIMACS file may declare up to this many nodes whatever its arcs; above
/// it, a node count more than twice the arc count plus 2 is refused (nodes no
/// arc touches carry no flow, and each one costs memory).
constexpr std::size_t dimacs_max_isolated_nodes = std::size_t{1} << 20;

/// A max-flow problem read from DIMACS text. Node ids are 0-based.
template <class Cap>
struct dimacs_max_flow {
    struct arc {
        std::size_t from, to;
        Cap capacity;
    };
    std::size_t nodes = 0;
    std::size_t source = 0, sink = 0;
    std::vector<arc> arcs;
};

namespace detail {

template <class Cap>
class dimacs_parser {
public:
    dimacs_parser(std::string_view text, std::string file) : text_(text), file_(std::move(file)) {}

    dimacs_max_flow<Cap> parse() {
        dimacs_max_flow<Cap> p;
        std::size_t line = 0, problem_line = 0, source_line = 0, sink_line = 0, declared_arcs = 0;
        std::size_t pos = 0;
        while (pos < text_.size()) {
            const std::size_t end = std::min(text_.find('\n', pos), text_.size());
            std::string_view rest = text_.substr(pos, end - pos);
            pos = end + 1;
            ++line;
            if (!rest.empty() && rest.back() == '\r') rest.remove_suffix(1);
            const std::string_view kind = token(rest);
            if (kind.empty() || kind[0] == 'c') continue;
            if (kind == "p") {
                if (problem_line != 0)
                    fail(line, "second problem line (the first is on line " + std::to_string(problem_line) + ")");
                problem_line = line;
                const std::string_view type = token(rest);
                if (type.empty()) fail(line, "the problem line ends where 'max' was expected (p max NODES ARCS)");
                if (type != "max")
                    fail(line, "problem type '" + std::string(type) + "' is not 'max' (p max NODES ARCS)");
                p.nodes = count(line, token(rest), "node count");
                declared_arcs = count(line, token(rest), "arc count");
                if (p.nodes < 2) fail(line, "a max-flow problem needs at least 2 nodes, the problem line says " +
                                                std::to_string(p.nodes));
                if (p.nodes > detail::bk_max_index)
                    fail(line, std::to_string(p.nodes) + " nodes are more than the solver's 32-bit node ids can hold");
                // The counts size memory: check them against what the file can
                // hold before anything is allocated. An arc line takes at
                // least 6 bytes ("a 1 2 3" and a line end).
                const std::size_t room = text_.size() / 6 + 1;
                if (declared_arcs > room)
                    fail(line, "the problem line announces " + std::to_string(declared_arcs) +
                                   " arcs, more than the file's " + std::to_string(text_.size()) +
                                   " bytes can hold (at most " + std::to_string(room) + ")");
                // Nodes no arc touches carry no flow: beyond dimacs_max_isolated_nodes
                // the node count must be justified by arcs.
                if (p.nodes > dimacs_max_isolated_nodes && p.nodes / 2 > declared_arcs + 1)
                    fail(line, "the problem line announces " + std::to_string(p.nodes) + " nodes for " +
                                   std::to_string(declared_arcs) + " arcs: more than " +
                                   std::to_string(dimacs_max_isolated_nodes) +
                                   " nodes need at least one arc per two nodes");
                p.arcs.reserve(declared_arcs);
            } else if (kind == "n") {
                need_problem(line, problem_line, "'n' line");
                const std::size_t id = node(line, token(rest), p.nodes);
                const std::string_view which = token(rest);
                if (which == "s") {
                    if (source_line != 0)
                        fail(line, "second source (the first is on line " + std::to_string(source_line) + ")");
                    source_line = line;
                    p.source = id;
                } else if (which == "t") {
                    if (sink_line != 0)
                        fail(line, "second sink (the first is on line " + std::to_string(sink_line) + ")");
                    sink_line = line;
                    p.sink = id;
                } else if (which.empty()) {
                    fail(line, "the 'n' line ends where 's' or 't' was expected (n ID s|t)");
                } else {
                    fail(line, "'" + std::string(which) + "' is not 's' (source) or 't' (sink)");
                }
                if (source_line != 0 && sink_line != 0 && p.source == p.sink)
                    fail(line, "node " + std::to_string(p.source + 1) + " is both the source and the sink");
            } else if (kind == "a") {
                need_problem(line, problem_line, "'a' line");
                if (p.arcs.size() == declared_arcs)
                    fail(line, "more arcs than the " + std::to_string(declared_arcs) + " announced on line " +
                                   std::to_string(problem_line));
                const std::size_t u = node(line, token(rest), p.nodes);
                const std::size_t v = node(line, token(rest), p.nodes);
                p.arcs.push_back({u, v, capacity(line, token(rest))});
            } else {
                fail(line, "unknown line type '" + std::string(kind) + "' (expected c, p, n or a)");
            }
            const std::string_view extra = token(rest);
            if (!extra.empty()) fail(line, "unexpected '" + std::string(extra) + "' at the end of the line");
        }
        const std::size_t last = line == 0 ? 1 : line;
        if (problem_line == 0) fail(last, "no problem line (p max NODES ARCS)");
        if (source_line == 0) fail(last, "no source (n ID s)");
        if (sink_line == 0) fail(last, "no sink (n ID t)");
        if (p.arcs.size() != declared_arcs)
            fail(problem_line, "the problem line announces " + std::to_string(declared_arcs) + " arcs, the file has " +
                                   std::to_string(p.arcs.size()));
        return p;
    }

private:
    [[noreturn]] void fail(std::size_t line, const std::string& message) const {
        throw parse_error(file_, line, message);
    }

    /// The next whitespace-separated token of s (empty at the end), removed from s.
    static std::string_view token(std::string_view& s) {
        std::size_t b = 0;
        while (b < s.size() && (s[b] == ' ' || s[b] == '\t' || s[b] == '\f' || s[b] == '\v')) ++b;
        std::size_t e = b;
        while (e < s.size() && s[e] != ' ' && s[e] != '\t' && s[e] != '\f' && s[e] != '\v') ++e;
        const std::string_view t = s.substr(b, e - b);
        s.remove_prefix(e);
        return t;
    }

    void need_problem(std::size_t line, std::size_t problem_line, const char* what) const {
        if (problem_line == 0) fail(line, std::string(what) + " before the problem line (p max NODES ARCS)");
    }

    std::size_t count(std::size_t line, std::string_view t, const char* what) const {
        if (t.empty()) fail(line, std::string("the line ends where the ") + what + " was expected");
        std::size_t v = 0;
        const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
        if (r.ec == std::errc::result_out_of_range) fail(line, std::string(what) + " '" + std::string(t) + "' is too large");
        if (r.ec != std::errc() || r.ptr != t.data() + t.size())
            fail(line, "'" + std::string(t) + "' is not a " + what + " (a whole number >= 0)");
        return v;
    }

    std::size_t node(std::size_t line, std::string_view t, std::size_t nodes) const {
        if (t.empty()) fail(line, "the line ends where a node id was expected");
        long long v = 0;
        const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
        if ((r.ec != std::errc() && r.ec != std::errc::result_out_of_range) || r.ptr != t.data() + t.size())
            fail(line, "'" + std::string(t) + "' is not a node id (a whole number)");
        if (r.ec == std::errc::result_out_of_range || v < 1 || static_cast<unsigned long long>(v) > nodes)
            fail(line, "node " + std::string(t) + " is out of range 1.." + std::to_string(nodes));
        return static_cast<std::size_t>(v - 1);
    }

    Cap capacity(std::size_t line, std::string_view t) const {
        if (t.empty()) fail(line, "the line ends where the arc's capacity was expected");
        std::string_view u = t;
        if (u.size() > 1 && u[0] == '+' && u[1] != '-' && u[1] != '+') u.remove_prefix(1);
        Cap v{};
        std::from_chars_result r{};
        if constexpr (std::is_floating_point_v<Cap>) {
            double d = 0;
            r = std::from_chars(u.data(), u.data() + u.size(), d);
            v = static_cast<Cap>(d);
            if (r.ec == std::errc() && !capacity_traits<Cap>::valid(v) && d >= 0) r.ec = std::errc::result_out_of_range;
        } else {
            r = std::from_chars(u.data(), u.data() + u.size(), v);
        }
        if (r.ptr != u.data() + u.size() || (r.ec != std::errc() && r.ec != std::errc::result_out_of_range))
            fail(line, "'" + std::string(t) + "' is not a capacity (" +
                           (std::is_floating_point_v<Cap> ? "a number" : "a whole number") + ")");
        if (!u.empty() && u[0] == '-') fail(line, "negative capacity " + std::string(t));
        if (r.ec == std::errc::result_out_of_range)
            fail(line, "capacity " + std::string(t) + " is out of the range of the capacity type (largest " +
                           largest_capacity() + ")");
        if (!capacity_traits<Cap>::valid(v)) fail(line, "capacity " + std::string(t) + " is not finite and non-negative");
        return v;
    }

    /// The capacity type's largest value, short ("1.79769e+308", not 309 digits).
    static std::string largest_capacity() {
        if constexpr (std::is_floating_point_v<Cap>) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%g", static_cast<double>(std::numeric_limits<Cap>::max()));
            return buf;
        } else {
            return std::to_string(std::numeric_limits<Cap>::max());
        }
    }

    std::string_view text_;
    std::string file_;
};

}  // namespace detail

/// Parses DIMACS max-flow text; `file` names it in error messages.
/// Capacities are read as Cap: with an integer Cap, "2.5" is an error.
template <class Cap = long long>
dimacs_max_flow<Cap> parse_dimacs_max_flow(std::string_view text, std::string file = "<dimacs>") {
    return detail::dimacs_parser<Cap>(text, std::move(file)).parse();
}

/// Reads a DIMACS max-flow file. Throws anima::io_error when it cannot be
/// read and anima::parse_error (file:line: message) when it is malformed.
template <class Cap = long long>
dimacs_max_flow<Cap> read_dimacs_max_flow(const std::string& path) {
    return parse_dimacs_max_flow<Cap>(read_file(path), path);
}

/// The problem as a flow_graph with one node per DIMACS node (id - 1). The
/// source and sink are nodes without edges there; an arc straight from the
/// source to the sink is given to the source node as equal source and sink
/// capacities, which carry exactly that flow. Throws anima::invalid_argument
/// naming the arc (its place among the arcs and its DIMACS node ids, 1-based
/// as in the file) whose capacity makes a node's sum overflow the capacity
/// type.
template <class Cap>
flow_graph<Cap> to_flow_graph(const dimacs_max_flow<Cap>& p) {
    flow_graph<Cap> g(p.nodes, p.arcs.size());
    for (std::size_t i = 0; i < p.arcs.size(); ++i) {
        const auto& a = p.arcs[i];
        if (a.from == a.to || a.to == p.source || a.from == p.sink) continue;
        try {
            if (a.from == p.source && a.to == p.sink)
                g.add_tweights(p.source, a.capacity, a.capacity);
            else if (a.from == p.source)
                g.add_tweights(a.to, a.capacity, Cap(0));
            else if (a.to == p.sink)
                g.add_tweights(a.from, Cap(0), a.capacity);
            else
                g.add_edge(a.from, a.to, a.capacity, Cap(0));
        } catch (const invalid_argument&) {
            throw invalid_argument("anima::to_flow_graph: arc " + std::to_string(i + 1) + " (a " +
                                   std::to_string(a.from + 1) + " " + std::to_string(a.to + 1) +
                                   "): the sum of a node's capacities overflows the capacity type");
        }
    }
    return g;
}

/// Solves a DIMACS problem: the maximum flow and the side of every node
/// (the source on the source side, the sink on the sink side).
template <class Cap>
min_cut_result<typename capacity_traits<Cap>::flow_type> solve_max_flow(const dimacs_max_flow<Cap>& p) {
    flow_graph<Cap> g = to_flow_graph(p);
    auto result = g.min_cut();
    result.side[p.source] = cut_side::source;
    result.side[p.sink] = cut_side::sink;
    return result;
}

}  // namespace anima
