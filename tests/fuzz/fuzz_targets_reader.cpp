// libFuzzer target for the per-frame position targets of clip IK. Any input
// must either parse into goals on joints of the skeleton, at frames inside
// the clip, in increasing frame order, with finite targets, or raise an
// anima::error; in float and double.
#include <anima/bvh/reader.hpp>
#include <anima/core/error.hpp>
#include <anima/ik/position_targets.hpp>

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"

namespace {

template <class T>
const anima::skeleton<T>& walk_skeleton() {
    static const anima::skeleton<T> sk =
        anima::read_bvh<T>(std::string(ANIMA_TEST_DATA_DIR) + "/walk_cmu31_02_01.bvh").skeleton();
    return sk;
}

template <class T>
void fuzz_targets(const std::string& text) {
    using anima_fuzz::require;
    constexpr std::size_t frames = 300;
    const auto& sk = walk_skeleton<T>();
    try {
        const auto goals = anima::parse_position_targets<T>(text, "fuzz", sk, frames);
        require(!goals.empty());
        for (std::size_t i = 0; i < goals.size(); ++i) {
            require(goals[i].frame < frames);
            require(i == 0 || goals[i - 1].frame < goals[i].frame);
            require(!goals[i].goals.empty());
            for (const auto& g : goals[i].goals) {
                require(g.joint < sk.size());
                require(g.position.allFinite());
            }
        }
    } catch (const anima::error&) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > anima_fuzz::max_input) return 0;
    const std::string text(reinterpret_cast<const char*>(data), size);
    fuzz_targets<double>(text);
    fuzz_targets<float>(text);
    return 0;
}
