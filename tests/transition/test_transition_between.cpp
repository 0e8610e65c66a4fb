// transition_between: the whole of `anima transition` in one call. Checked
// against the single steps called one after another (make_transition + join
// or a baseline, plant_transition_feet, measure_transition) on the bundled
// walk, in float and double, for every method; planting must lower the skate
// the crossfade leaves; bad parameters and degenerate clips.
#include "../test_support.hpp"

#include <anima/bvh/reader.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/joint_roles.hpp>
#include <anima/transition.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

namespace {

using anima::transition_method;
using anima_test::contains;

template <class T>
const anima::clip<T>& walk_clip() {
    static const anima::clip<T> c = anima::read_bvh<T>(anima_test::bundled("walk_cmu31_02_01.bvh"));
    return c;
}

/// Same frames, the same numbers to the bit.
template <class T>
bool same_motion(const anima::joined_clip<T>& x, const anima::joined_clip<T>& y) {
    if (x.start_frame != y.start_frame || x.end_frame != y.end_frame || x.motion.frames() != y.motion.frames() ||
        x.motion.frame_time() != y.motion.frame_time())
        return false;
    for (std::size_t i = 0; i < x.motion.rotations().size(); ++i)
        if (x.motion.rotations()[i].coeffs() != y.motion.rotations()[i].coeffs()) return false;
    return x.motion.translations() == y.motion.translations();
}

template <class T>
bool same_quality(const anima::transition_quality<T>& x, const anima::transition_quality<T>& y) {
    return x.length == y.length && x.peak_angular_acceleration == y.peak_angular_acceleration &&
           x.peak_angular_jerk == y.peak_angular_jerk && x.peak_root_acceleration == y.peak_root_acceleration &&
           x.foot_slide == y.foot_slide && x.foot_skate_window == y.foot_skate_window &&
           x.foot_skate_clips == y.foot_skate_clips && x.foot_skate_ratio == y.foot_skate_ratio &&
           x.root_speed_min == y.root_speed_min && x.root_speed_ends == y.root_speed_ends &&
           x.root_speed_ratio == y.root_speed_ratio;
}

/// The joined clip the method makes, by its own function.
template <class T>
anima::joined_clip<T> by_steps(const anima::clip<T>& a, std::size_t at, const anima::clip<T>& b, std::size_t to,
                               const anima::transition_between_params<T>& p) {
    switch (p.method) {
        case transition_method::variable: return anima::join(a, at, anima::make_transition(a, at, b, to, p.variable));
        case transition_method::cut: return anima::direct_cut(a, at, b, to);
        case transition_method::crossfade: return anima::crossfade(a, at, b, to, static_cast<T>(p.crossfade_time));
        case transition_method::inertialize: return anima::inertialize(a, at, b, to, static_cast<T>(p.halflife));
    }
    return {};
}

}  // namespace

TEST_CASE_TEMPLATE("transition_between: the single steps' results bit for bit, every method", T, float, double) {
    const anima::clip<T>& w = walk_clip<T>();
    const std::size_t at = 100, to = 250;
    const auto roles = anima::joint_roles(w.skeleton());
    const auto up = anima::guess_up_axis(w.skeleton()).up;
    const double mpu = anima::guess_units(w.skeleton(), up).metres_per_unit;
    for (const transition_method method : {transition_method::variable, transition_method::cut,
                                           transition_method::crossfade, transition_method::inertialize}) {
        CAPTURE(anima::to_string(method));
        anima::transition_between_params<T> p;
        p.method = method;
        p.crossfade_time = 0.25;
        p.halflife = 0.08;
        const auto r = anima::transition_between(w, at, w, to, p);
        const auto unplanted = by_steps(w, at, w, to, p);
        const auto planted = anima::plant_transition_feet(unplanted, p.feet);
        CHECK(same_motion(r.unplanted, unplanted));
        CHECK(same_motion(r.joined, planted));
        CHECK(same_quality(r.unplanted_quality, anima::measure_transition(unplanted, roles, up, mpu)));
        CHECK(same_quality(r.quality, anima::measure_transition(planted, roles, up, mpu)));
        CHECK(r.roles == roles);
        CHECK(r.up == up);
        CHECK(r.metres_per_unit == mpu);
        CHECK(r.variable.has_value() == (method == transition_method::variable));
        if (r.variable) {
            const auto t = anima::make_transition(w, at, w, to, p.variable);
            CHECK(r.variable->duration == t.duration);
            CHECK(r.variable->timing.limiting_joint == t.timing.limiting_joint);
            CHECK(r.variable->methods == t.methods);
            CHECK(r.variable->frames.frames() == t.frames.frames());
        }

        // Without planting, the joined clip is the method's.
        p.plant_feet = false;
        const auto bare = anima::transition_between(w, at, w, to, p);
        CHECK(same_motion(bare.joined, unplanted));
        CHECK(same_quality(bare.quality, bare.unplanted_quality));
    }
}

TEST_CASE("transition_between: planting takes out most of the skate a crossfade leaves") {
    anima::transition_between_params<double> p;
    p.method = transition_method::crossfade;
    const auto r = anima::transition_between(walk_clip<double>(), 100, walk_clip<double>(), 250, p);
    // The crossfade's legs blend two stances: feet on the ground slide.
    CHECK(r.unplanted_quality.foot_skate_ratio > 1.5);
    CHECK(r.quality.foot_skate_ratio < 0.5 * r.unplanted_quality.foot_skate_ratio);
    CHECK(r.quality.length == r.unplanted_quality.length);
}

TEST_CASE("transition_between: given up axis, units and roles are used by the methods and the measures") {
    const auto& w = walk_clip<double>();
    anima::transition_between_params<double> p;
    p.method = transition_method::cut;
    p.plant_feet = false;
    p.variable.classification.up = anima::signed_axis{anima::axis::y, 1};
    p.variable.classification.metres_per_unit = 0.5;
    p.variable.roles = anima::joint_roles(w.skeleton());
    const auto r = anima::transition_between(w, 100, w, 250, p);
    CHECK(r.metres_per_unit == 0.5);
    const auto by_hand = anima::measure_transition(anima::direct_cut(w, 100, w, 250), p.variable.roles, r.up, 0.5);
    CHECK(same_quality(r.quality, by_hand));
    // A root speed in metres doubles with the metres per unit.
    p.variable.classification.metres_per_unit = 1.0;
    const auto r1 = anima::transition_between(w, 100, w, 250, p);
    CHECK(r1.quality.root_speed_ends == doctest::Approx(2 * r.quality.root_speed_ends).epsilon(1e-12));
}

TEST_CASE("transition_between: the given up axis is the planting's too, unless the planting names its own") {
    const auto& w = walk_clip<double>();
    anima::transition_between_params<double> p;
    p.method = transition_method::crossfade;
    // Up the wrong way (-Y): the feet are then "lowest" at the other end of
    // the body, and planting finds other contacts than along +Y.
    const anima::signed_axis down{anima::axis::y, -1};
    p.variable.classification.up = down;
    const auto r = anima::transition_between(w, 100, w, 250, p);
    anima::transition_feet_params<double> along = p.feet;
    along.planting.contacts.up = down;
    CHECK(same_motion(r.joined, anima::plant_transition_feet(r.unplanted, along)));
    CHECK_FALSE(same_motion(r.joined, anima::plant_transition_feet(r.unplanted, p.feet)));
    // An up axis of the planting's own is kept.
    p.feet.planting.contacts.up = anima::signed_axis{anima::axis::y, 1};
    const auto own = anima::transition_between(w, 100, w, 250, p);
    CHECK(same_motion(own.joined, anima::plant_transition_feet(own.unplanted, p.feet)));
}

TEST_CASE_TEMPLATE("transition_between: bad parameters and clips name what is wrong", T, float, double) {
    const anima::clip<T>& w = walk_clip<T>();
    anima::transition_between_params<T> p;
    p.crossfade_time = -0.1;
    std::string m = anima_test::invalid_argument_message([&] { anima::transition_between(w, 10, w, 20, p); });
    CHECK(contains(m, "anima::transition_between"));
    CHECK(contains(m, "crossfade_time"));
    p.crossfade_time = 0.3;
    for (const double bad : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()}) {
        p.halflife = bad;
        m = anima_test::invalid_argument_message([&] { anima::transition_between(w, 10, w, 20, p); });
        CHECK(contains(m, "halflife"));
    }
    p.halflife = 0.1;
    // A trigger outside A: the method's own check.
    for (const transition_method method : {transition_method::variable, transition_method::cut,
                                           transition_method::crossfade, transition_method::inertialize}) {
        p.method = method;
        m = anima_test::invalid_argument_message([&] { anima::transition_between(w, w.frames(), w, 0, p); });
        CHECK(contains(m, std::to_string(w.frames())));
    }
    // Another hierarchy.
    anima::skeleton<T> other;
    other.add_joint("Hips", -1, Eigen::Matrix<T, 3, 1>::Zero(), {anima::channel::x_position, anima::channel::y_position, anima::channel::z_position,
                                     anima::channel::z_rotation, anima::channel::x_rotation, anima::channel::y_rotation});
    const anima::clip<T> lone(other, 5, w.frame_time());
    CHECK_THROWS_AS(anima::transition_between(w, 10, lone, 0, p), anima::invalid_argument);
}

TEST_CASE_TEMPLATE("transition_between: one-frame clips make a finite joined clip", T, float, double) {
    const anima::clip<T>& w = walk_clip<T>();
    const anima::clip<T> one = w.slice(120, 121);
    for (const transition_method method : {transition_method::variable, transition_method::cut,
                                           transition_method::crossfade, transition_method::inertialize}) {
        CAPTURE(anima::to_string(method));
        anima::transition_between_params<T> p;
        p.method = method;
        const auto r = anima::transition_between(one, 0, one, 0, p);
        CHECK(r.joined.start_frame == 0);
        CHECK(r.joined.end_frame < r.joined.motion.frames());
        bool finite = true;
        for (const auto& q : r.joined.motion.rotations()) finite = finite && q.coeffs().allFinite();
        for (const auto& v : r.joined.motion.translations()) finite = finite && v.allFinite();
        CHECK(finite);
        CHECK(std::isfinite(r.quality.foot_skate_ratio));
        CHECK(std::isfinite(r.quality.root_speed_ratio));
    }
}
