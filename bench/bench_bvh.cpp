// BVH reading and writing speed on the bundled clips, loaded into memory
// before timing (no file I/O is measured).
//
//   BM_parse_bvh_document<double>/<clip>  text -> bvh_document (skeleton + raw channel values)
//   BM_parse_bvh<double>/<clip>           text -> clip (adds Euler angles -> quaternions)
//   BM_format_bvh<double>/<clip>          bvh_document -> text (6 decimals, the default)
//
// GLM and Eigen have no BVH support, so there is no peer library here.
// Instead two reference loops bound what any BVH code can do with the same
// standard-library number conversions:
//
//   BM_reference_scan_from_chars/<clip>   split the whole text at whitespace and
//                                         std::from_chars every token as a double
//   BM_reference_to_chars/<clip>          std::to_chars (fixed, 6 decimals) of every
//                                         channel value, space-separated, into a string
//
// Bytes/s counts the BVH text read (parse) or produced (format).
//
//   BM_parse_wide_skeleton/<N>            a root with N sibling joints and no frames,
//                                         with Google Benchmark's complexity fit: hashed
//                                         name lookups keep it near N log N, where a
//                                         linear name search would be N^2

#include <anima/bvh/document.hpp>
#include <anima/bvh/reader.hpp>
#include <anima/bvh/writer.hpp>

#include <benchmark/benchmark.h>

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#ifndef ANIMA_BENCH_DATA_DIR
#error "ANIMA_BENCH_DATA_DIR must name the examples/data directory"
#endif

namespace {

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "bench_bvh: %s\n", what.c_str());
    std::abort();
}

struct sample {
    std::string name;       // file name without .bvh
    std::string text;       // the file's bytes
    anima::bvh_document<double> document;
    std::size_t formatted_bytes = 0;
};

sample load(const std::string& name) {
    sample s;
    s.name = name;
    const std::string path = std::string(ANIMA_BENCH_DATA_DIR) + "/" + name + ".bvh";
    try {
        std::ifstream in(path, std::ios::binary);
        if (!in) fail("cannot open " + path);
        s.text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        s.document = anima::parse_bvh_document<double>(s.text, path);
        s.formatted_bytes = anima::format_bvh(s.document).size();
    } catch (const std::exception& e) {
        fail(e.what());
    }
    return s;
}

const std::vector<sample>& samples() {
    static const std::vector<sample> all{load("walk_cmu31_02_01"), load("run_cmu_09_01")};
    return all;
}

void set_bytes(benchmark::State& state, std::size_t bytes) {
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(bytes));
}

void parse_document(benchmark::State& state, std::size_t i) {
    const sample& s = samples()[i];
    for (auto _ : state) {
        auto doc = anima::parse_bvh_document<double>(s.text);
        benchmark::DoNotOptimize(doc.values.data());
    }
    set_bytes(state, s.text.size());
}

void parse_clip(benchmark::State& state, std::size_t i) {
    const sample& s = samples()[i];
    for (auto _ : state) {
        auto c = anima::parse_bvh<double>(s.text);
        benchmark::DoNotOptimize(c.rotations().data());
    }
    set_bytes(state, s.text.size());
}

void format_document(benchmark::State& state, std::size_t i) {
    const sample& s = samples()[i];
    for (auto _ : state) {
        std::string out = anima::format_bvh(s.document);
        benchmark::DoNotOptimize(out.data());
    }
    set_bytes(state, s.formatted_bytes);
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

void reference_scan(benchmark::State& state, std::size_t i) {
    const sample& s = samples()[i];
    const char* const begin = s.text.data();
    const char* const end = begin + s.text.size();
    for (auto _ : state) {
        double sum = 0;
        std::size_t numbers = 0;
        for (const char* p = begin; p < end;) {
            while (p < end && is_space(*p)) ++p;
            const char* q = p;
            while (q < end && !is_space(*q)) ++q;
            double v = 0;
            const auto r = std::from_chars(p, q, v);
            if (r.ec == std::errc() && r.ptr == q) {
                sum += v;
                ++numbers;
            }
            p = q;
        }
        benchmark::DoNotOptimize(sum);
        benchmark::DoNotOptimize(numbers);
    }
    set_bytes(state, s.text.size());
}

void reference_to_chars(benchmark::State& state, std::size_t i) {
    const sample& s = samples()[i];
    const std::vector<double>& values = s.document.values;
    std::size_t produced = 0;
    for (auto _ : state) {
        std::string out;
        out.reserve(values.size() * 12);
        char buf[64];
        for (double v : values) {
            const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, 6);
            out.append(buf, static_cast<std::size_t>(r.ptr - buf));
            out += ' ';
        }
        produced = out.size();
        benchmark::DoNotOptimize(out.data());
    }
    set_bytes(state, produced);
}

std::string wide_skeleton(std::size_t n) {
    std::string text = "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 0\n";
    for (std::size_t k = 0; k < n; ++k) text += "JOINT s" + std::to_string(k) + "\n{\nOFFSET 0 1 0\nCHANNELS 0\n}\n";
    return text + "}\nMOTION\nFrames: 0\nFrame Time: 0.1\n";
}

void parse_wide_skeleton(benchmark::State& state) {
    const std::string text = wide_skeleton(static_cast<std::size_t>(state.range(0)));
    for (auto _ : state) {
        auto doc = anima::parse_bvh_document<double>(text);
        benchmark::DoNotOptimize(doc.skeleton.size());
    }
    state.SetComplexityN(state.range(0));
    set_bytes(state, text.size());
}

const bool registered = [] {
    benchmark::RegisterBenchmark("BM_parse_wide_skeleton", parse_wide_skeleton)
        ->RangeMultiplier(8)
        ->Range(1 << 9, 1 << 15)
        ->Unit(benchmark::kMillisecond)
        ->Complexity();
    const std::vector<std::string> names{"walk_cmu31_02_01", "run_cmu_09_01"};
    for (std::size_t i = 0; i < names.size(); ++i) {
        const std::string& n = names[i];
        benchmark::RegisterBenchmark(("BM_parse_bvh_document<double>/" + n).c_str(), parse_document, i);
        benchmark::RegisterBenchmark(("BM_parse_bvh<double>/" + n).c_str(), parse_clip, i);
        benchmark::RegisterBenchmark(("BM_reference_scan_from_chars/" + n).c_str(), reference_scan, i);
        benchmark::RegisterBenchmark(("BM_format_bvh<double>/" + n).c_str(), format_document, i);
        benchmark::RegisterBenchmark(("BM_reference_to_chars/" + n).c_str(), reference_to_chars, i);
    }
    return true;
}();

}  // namespace
