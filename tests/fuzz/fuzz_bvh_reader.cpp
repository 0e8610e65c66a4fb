// libFuzzer target for the BVH reader. Any input must either parse or raise an
// anima::error; anything else (another exception, a sanitizer report, a hang)
// is a bug. A parsed file must also satisfy the document invariants and
// survive the writer and a second parse.
//
// Build: clang++ -std=c++17 -g -O1 -fsanitize=fuzzer,address,undefined
//        -Iinclude -isystem /usr/include/eigen3 tests/fuzz/fuzz_bvh_reader.cpp
// Define ANIMA_FUZZ_STRICT to treat an anima::invalid_argument from writing a
// parsed clip as a failure too (none is expected).
#include <anima/bvh/document.hpp>
#include <anima/bvh/reader.hpp>
#include <anima/bvh/writer.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>

#include "fuzz_support.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace {

using anima_fuzz::max_input;
using anima_fuzz::require;

template <class T>
void check_document(const anima::bvh_document<T>& doc) {
    const std::size_t channels = doc.channels();
    require(!doc.skeleton.empty());
    require(doc.values.size() == doc.frames * channels);
    for (T v : doc.values) require(std::isfinite(v));
    require(std::isfinite(doc.frame_time) && doc.frame_time > T(0));
    for (const auto& j : doc.skeleton.joints()) {
        require(j.offset.allFinite());
        require(!j.end_site || j.end_site->allFinite());
    }

    // The writer accepts every parsed document, and its text parses back to
    // the same shape.
    std::string text;
    try {
        text = anima::format_bvh(doc);
    } catch (const anima::error&) {
        require(false);
    }
    try {
        const auto back = anima::parse_bvh_document<T>(text, "format_bvh(document)");
        require(back.frames == doc.frames);
        require(back.channels() == channels);
        require(back.skeleton.size() == doc.skeleton.size());
    } catch (const anima::error&) {
        require(false);
    }
}

template <class T>
void check_clip(const anima::clip<T>& c) {
    require(c.joints() > 0);
    std::string text;
    try {
        text = anima::format_bvh(c);
    } catch (const anima::invalid_argument&) {
#ifdef ANIMA_FUZZ_STRICT
        require(false);
#endif
        return;
    } catch (const anima::error&) {
        require(false);
    }
    try {
        const auto back = anima::parse_bvh<T>(text, "format_bvh(clip)");
        require(back.frames() == c.frames());
        require(back.joints() == c.joints());
    } catch (const anima::error&) {
        require(false);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > max_input) return 0;
    const std::string_view text(reinterpret_cast<const char*>(data), size);

    try {
        const auto doc = anima::parse_bvh_document<double>(text, "fuzz");
        check_document(doc);
    } catch (const anima::error&) {
        // Rejected input: fine. Any other exception escapes and aborts.
    }

    try {
        const auto c = anima::parse_bvh<float>(text, "fuzz");
        check_clip(c);
    } catch (const anima::error&) {
    }
    return 0;
}
