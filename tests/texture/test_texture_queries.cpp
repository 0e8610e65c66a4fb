// What a tool asks of a texture besides the motion: the texton lengths when
// the user gave m, the overlap, both or neither (hand-worked values), and
// the seams crossed in each pass through an overlap (against a brute-force
// search of every row's crossings).
#include "texture_test_support.hpp"

#include <anima/core/error.hpp>
#include <anima/texture/motion_texture.hpp>
#include <anima/texture/texton.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cstddef>
#include <optional>
#include <vector>

namespace {

using namespace texture_test;

TEST_CASE_TEMPLATE("choose_texton_lengths: defaults fit the clip, given values are kept", T, float, double) {
    const anima::texton_params<T> p;  // m = 100, overlap 50
    const std::optional<std::size_t> none;
    const auto lengths = [&](std::size_t frames, std::optional<std::size_t> m, std::optional<std::size_t> overlap) {
        const auto q = anima::choose_texton_lengths(p, frames, m, overlap);
        return std::vector<std::size_t>{q.m, q.overlap};
    };
    // Neither given: the defaults, shrunk in proportion for a short clip.
    CHECK(lengths(400, none, none) == std::vector<std::size_t>{100, 50});
    CHECK(lengths(149, none, none) == std::vector<std::size_t>{74, 37});
    // Only the overlap: m fits the clip, the overlap is the one given.
    CHECK(lengths(149, none, 10) == std::vector<std::size_t>{74, 10});
    CHECK(lengths(400, none, 80) == std::vector<std::size_t>{100, 80});
    // Only m: half of it, at least 2, at most the default 50; the clip's
    // length does not matter (make_texton judges a given m).
    CHECK(lengths(149, 30, none) == std::vector<std::size_t>{30, 15});
    CHECK(lengths(10, 3, none) == std::vector<std::size_t>{3, 2});
    CHECK(lengths(149, 200, none) == std::vector<std::size_t>{200, 50});
    // Both: as given.
    CHECK(lengths(20, 30, 7) == std::vector<std::size_t>{30, 7});
    CHECK(contains(invalid_argument_message([&] { (void)lengths(100, 1, none); }),
                   "anima::choose_texton_lengths: m = 1 is under 2 frames"));
    CHECK(contains(invalid_argument_message([&] { (void)lengths(100, none, 0); }),
                   "anima::choose_texton_lengths: overlap = 0 is under 2 frames"));
}

TEST_CASE_TEMPLATE("seams_per_pass: each pass's crossings, as a search of every row finds them", T, float, double) {
    const auto c = walker<T>(250, 37.3, 0.4);
    auto p = unplanted<T>(80, 40);
    p.texton.blend.frames = 40;  // fades as long as the overlap: cut and fade middle apart
    p.smoothing.enabled = false;
    const auto t = anima::patch_texton(anima::make_texton(c, p.texton), 900, p);
    REQUIRE(t.overlap_spans.size() >= 3);
    for (const auto mark : {anima::seam_mark::cut, anima::seam_mark::fade_centre}) {
        const auto crossings = anima::seam_crossings(t.texton, t.stream, mark);
        const auto passes = anima::seams_per_pass(t, mark);
        REQUIRE(passes.size() == t.overlap_spans.size());
        std::size_t total = 0, found = 0;
        for (const auto& row : crossings) total += row.size();
        for (std::size_t i = 0; i < passes.size(); ++i) {
            const auto [first, last] = t.overlap_spans[i];
            std::vector<std::size_t> in;
            for (const auto& row : crossings)
                for (const std::size_t k : row)
                    if (k >= first && k <= last) in.push_back(k);
            CHECK(passes[i].crossings == in.size());
            if (in.empty()) continue;
            CHECK(passes[i].first == *std::min_element(in.begin(), in.end()));
            CHECK(passes[i].last == *std::max_element(in.begin(), in.end()));
            found += in.size();
        }
        // Every crossing of a seam is inside an overlap; the first pass may
        // start past the seam, the others cross every row's.
        CHECK(found == total);
        CHECK(passes[1].crossings == t.texton.rows());
    }
}

}  // namespace
