// libFuzzer target for flight key sets read into a flight problem. Any input
// must either give a problem whose objective at its own key times is finite
// and non-negative, or raise an anima::error; in float and double. Inputs
// whose "skeleton" is not a bundled clip are skipped, so that the fuzzer
// reads no other file.
#include <anima/core/error.hpp>
#include <anima/core/json_reader.hpp>
#include <anima/flight/flight_objective.hpp>
#include <anima/flight/key_set.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"

namespace {

/// A key file in the bundled data's folder: a relative "skeleton" names a clip there.
const std::string key_file = std::string(ANIMA_TEST_DATA_DIR) + "/fuzz.json";

template <class T>
void fuzz_key_set(const std::string& text) {
    using anima_fuzz::require;
    try {
        const auto in = anima::parse_flight_key_set<T>(text, key_file);
        require(in.keys.times.size() == in.keys.rotations.size());
        require(in.keys.times.size() == in.keys.root_positions.size());
        const anima::flight_problem<T> problem(in.model, in.keys, in.settings);
        const T value = problem.objective(in.keys.times);
        require(std::isfinite(value) && value >= T(0));
    } catch (const anima::error&) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > anima_fuzz::max_input) return 0;
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const anima::json_value doc = anima::parse_json(text, "fuzz");
        const anima::json_value* skeleton = doc.is_object() ? doc.find("skeleton") : nullptr;
        if (!skeleton || !skeleton->is_string()) return 0;
        const std::string& name = skeleton->string();
        if (name != "walk_cmu31_02_01.bvh" && name != "run_cmu_02_03.bvh") return 0;
    } catch (const anima::error&) {
        return 0;
    }
    fuzz_key_set<double>(text);
    fuzz_key_set<float>(text);
    return 0;
}
