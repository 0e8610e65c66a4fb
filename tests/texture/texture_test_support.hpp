// Clips and helpers shared by the motion-texture tests.
#pragma once

#include "../test_support.hpp"

#include <anima/bvh/reader.hpp>
#include <anima/core/constants.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/resequence.hpp>
#include <anima/motion/skeleton.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

namespace texture_test {

using anima_test::bundled;
using anima_test::contains;
using anima_test::invalid_argument_message;
using anima_test::tolerance;

template <class T>
using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

// A small Y-up figure: hips (6 channels), spine and head, two legs.
template <class T>
anima::skeleton<T> figure() {
    using anima::channel;
    using v3 = Eigen::Matrix<T, 3, 1>;
    const std::vector<channel> root{channel::x_position, channel::y_position, channel::z_position,
                                    channel::z_rotation, channel::x_rotation, channel::y_rotation};
    const std::vector<channel> rot{channel::z_rotation, channel::x_rotation, channel::y_rotation};
    anima::skeleton<T> s;
    s.add_joint("hips", -1, v3::Zero(), root);
    s.add_joint("spine", 0, v3(0, 10, 0), rot);
    s.add_joint("head", 1, v3(0, 15, 0), rot);
    s.add_joint("leftUpLeg", 0, v3(8, -3, 0), rot);
    s.add_joint("leftLeg", 3, v3(0, -40, 0), rot);
    s.add_joint("leftFoot", 4, v3(0, -40, 0), rot);
    s.add_joint("rightUpLeg", 0, v3(-8, -3, 0), rot);
    s.add_joint("rightLeg", 6, v3(0, -40, 0), rot);
    s.add_joint("rightFoot", 7, v3(0, -40, 0), rot);
    return s;
}

// Texture parameters for the tests of the stages before planting: planting
// (on by default) has tests of its own, and in float it runs unoptimised
// in the test's unit.
template <class T>
anima::motion_texture_params<T> unplanted() {
    anima::motion_texture_params<T> p;
    p.planting.enabled = false;
    return p;
}

// The same with M1 and M2 of m frames overlapping by `overlap`.
template <class T>
anima::motion_texture_params<T> unplanted(std::size_t m, std::size_t overlap) {
    anima::motion_texture_params<T> p = unplanted<T>();
    p.texton.m = m;
    p.texton.overlap = overlap;
    return p;
}

// A walking-like motion with period `period` frames: every joint swings
// about X with its own phase (and a little about Z), the hips bob and move
// forward; `growth` makes the swings grow over the clip (so no two periods
// are alike), `turn` turns the figure about +Y by that many radians per
// frame (and its walk with it).
template <class T>
anima::clip<T> walker(std::size_t frames, double period, double growth = 0, double turn = 0) {
    anima::clip<T> c(figure<T>(), frames, T(1) / T(60));
    const double two_pi = 2 * anima::pi<double>;
    Eigen::Vector3d position(0, 90, 0);
    for (std::size_t f = 0; f < frames; ++f) {
        const double phase = two_pi * static_cast<double>(f) / period;
        const double gain = 1 + growth * static_cast<double>(f) / static_cast<double>(frames);
        for (std::size_t j = 1; j < c.joints(); ++j) {
            const double amplitude = 0.25 + 0.05 * static_cast<double>(j);
            const double a = gain * amplitude * std::sin(phase + 0.7 * static_cast<double>(j));
            const double b = 0.3 * gain * amplitude * std::cos(phase + 0.3 * static_cast<double>(j));
            const Eigen::Quaterniond q = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(b, Eigen::Vector3d::UnitZ());
            c.set_rotation(f, j, q.cast<T>());
        }
        const double yaw = turn * static_cast<double>(f);
        const Eigen::Quaterniond heading(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()));
        const Eigen::Quaterniond sway(Eigen::AngleAxisd(0.08 * gain * std::sin(phase), Eigen::Vector3d::UnitZ()));
        c.set_rotation(f, 0, (heading * sway).cast<T>());
        if (f > 0) position += heading * Eigen::Vector3d(0, 0, 1.5 + 0.3 * std::sin(2 * phase));
        position.y() = 90 + 2 * std::sin(2 * phase);
        c.set_root_position(f, position.cast<T>());
    }
    return c;
}

// The paper's rearrangement M(m..end) then M(0..m) played in a loop with
// no overlap, cut, fade or smoothing: the baseline that jumps.
template <class T>
anima::clip<T> cut_and_paste(const anima::clip<T>& c, std::size_t m, std::size_t frames,
                             std::vector<std::pair<std::size_t, std::size_t>>& seams) {
    std::vector<std::size_t> stream;
    for (std::size_t k = 0; k < frames; ++k) {
        const std::size_t f = (m + k) % c.frames();
        if (k > 0 && f == 0) seams.emplace_back(k - 1, k);
        stream.push_back(f);
    }
    return anima::resequence(c, stream);
}

// The bundled Daz-layout run without its T-pose and the 5 frames that
// swing out of it.
template <class T>
anima::clip<T> run() {
    const auto full = anima::read_bvh<T>(bundled("run_cmu_09_01.bvh"));
    return full.slice(6, full.frames());
}

template <class T>
anima::clip<T> walk() {
    return anima::read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
}

}  // namespace texture_test
