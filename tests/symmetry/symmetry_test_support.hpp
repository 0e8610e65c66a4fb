// Clips and small helpers shared by the symmetry tests.
#pragma once

#include "../test_support.hpp"

#include <anima/bvh/reader.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/frame_features.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

namespace symmetry_test {

using anima_test::bundled;
using anima_test::contains;
using anima_test::invalid_argument_message;
using anima_test::tolerance;

template <class T>
using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
template <class T>
using vector = Eigen::Matrix<T, Eigen::Dynamic, 1>;

// The bundled CMU-31 walk (02_01): 343 frames, no T-pose.
template <class T>
const anima::clip<T>& walk() {
    static const auto c = anima::read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    return c;
}

// The bundled Daz-layout run (09_01) without frames 0-5: frame 0 is the
// converter's T-pose and frames 1-5 blend out of it.
template <class T>
const anima::clip<T>& run() {
    static const auto c = [] {
        const auto full = anima::read_bvh<T>(bundled("run_cmu_09_01.bvh"));
        return full.slice(6, full.frames());
    }();
    return c;
}

// first, first+1, ..., last, then back down to `back_to`, not repeating
// `last` when `repeat_turn` is false: a forward-then-backward playback.
inline std::vector<std::size_t> there_and_back(std::size_t first, std::size_t last, std::size_t back_to,
                                               bool repeat_turn = false) {
    std::vector<std::size_t> out;
    for (std::size_t f = first; f <= last; ++f) out.push_back(f);
    if (repeat_turn) out.push_back(last);
    for (std::size_t f = last; f-- > back_to;) out.push_back(f);
    return out;
}

// The rows `indices` of m, in that order.
template <class T>
matrix<T> rows(const matrix<T>& m, const std::vector<std::size_t>& indices) {
    matrix<T> out(static_cast<Eigen::Index>(indices.size()), m.cols());
    for (std::size_t k = 0; k < indices.size(); ++k)
        out.row(static_cast<Eigen::Index>(k)) = m.row(static_cast<Eigen::Index>(indices[k]));
    return out;
}

}  // namespace symmetry_test
