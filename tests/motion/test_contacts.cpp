// anima::find_contacts and anima::foot_skate: a synthetic figure whose feet
// are planted, lifted and slid on a known schedule (Y up and Z up, metres and
// centimetres, a wrong frame time, float and double), the bundled clips, and
// the shared jump when it is there.
#include "../test_support.hpp"

#include <anima/bvh/reader.hpp>
#include <anima/motion/contacts.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/frame_features.hpp>
#include <anima/motion/reorient.hpp>
#include <anima/motion/resample.hpp>
#include <anima/motion/speed_limits.hpp>
#include <anima/motion/velocities.hpp>

#include <doctest/doctest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using anima::frame_interval;

constexpr std::size_t frames = 360;  // 3 s at 120 Hz
constexpr double dt = 1.0 / 120.0;
constexpr double slide = 0.1;        // m/s: the planted left foot slides this fast along x in its first stance

/// The schedule: when each foot is planted. Both are lifted over 150..209
/// (a jump); the left one slides during its first stance.
const std::vector<frame_interval> left_planted = {{0, 89}, {210, 299}};
const std::vector<frame_interval> right_planted = {{60, 149}, {240, 359}};
const frame_interval jump = {150, 209};

bool planted(const std::vector<frame_interval>& runs, std::size_t f) {
    for (const auto& r : runs)
        if (f >= r.first && f <= r.last) return true;
    return false;
}

/// Hips 1 m up, a head on top (1.8 m with its End Site), two feet whose
/// ankles are 8 cm up with toe tips on the ground; the feet carry position
/// channels so the test places them directly. `z_up` builds the same figure
/// with Z as the up axis; `names` false calls the feet by names nothing
/// recognises, so they must be found as the lowest leaves.
template <class T>
anima::clip<T> synthetic_clip(bool z_up = false, bool names = true) {
    using v3 = Eigen::Matrix<T, 3, 1>;
    const auto up = [&](double x, double h, double forward) {
        return z_up ? v3(T(x), T(-forward), T(h)) : v3(T(x), T(h), T(forward));
    };
    using anima::channel;
    const std::vector<channel> six = {channel::x_position, channel::y_position, channel::z_position,
                                      channel::z_rotation, channel::x_rotation, channel::y_rotation};
    anima::skeleton<T> sk;
    sk.add_joint("Hips", -1, up(0, 1, 0), six);
    const std::size_t head = sk.add_joint("Head", 0, up(0, 0.7, 0));
    sk.set_end_site(head, up(0, 0.1, 0));
    const std::size_t left = sk.add_joint(names ? "LeftFoot" : "PartA", 0, up(0.1, -0.92, 0), six);
    const std::size_t right = sk.add_joint(names ? "RightFoot" : "PartB", 0, up(-0.1, -0.92, 0), six);
    sk.set_end_site(left, up(0, -0.08, 0.12));
    sk.set_end_site(right, up(0, -0.08, 0.12));
    anima::clip<T> c(sk, frames, T(dt));
    for (std::size_t f = 0; f < frames; ++f) {
        c.set_root_position(f, up(0, 1, 0));
        const auto place = [&](std::size_t joint, double x, const std::vector<frame_interval>& runs, double lead) {
            // Lifted: an arc 25 cm high, moving forward at 1.5 m/s.
            double h = 0.08, forward = lead;
            if (!planted(runs, f)) {
                std::size_t a = f, b = f;
                while (a > 0 && !planted(runs, a - 1)) --a;
                while (b + 1 < frames && !planted(runs, b + 1)) ++b;
                const double s = (static_cast<double>(f - a) + 1) / (static_cast<double>(b - a) + 2);
                h += 0.25 * std::sin(3.14159265358979 * s);
                forward += 1.5 * static_cast<double>(f - a) * dt;
            } else if (joint == left && f <= left_planted[0].last) {
                forward += slide * static_cast<double>(f) * dt;
            }
            c.set_translation(f, joint, v3(up(x, h, forward) - up(0, 1, 0)));
        };
        place(left, 0.1, left_planted, 0.0);
        place(right, -0.1, right_planted, 0.3);
    }
    return c;
}

/// Detected runs match the schedule's within `slack` frames at each end.
void check_runs(const std::vector<frame_interval>& got, const std::vector<frame_interval>& expected, std::size_t slack) {
    REQUIRE(got.size() == expected.size());
    for (std::size_t k = 0; k < got.size(); ++k) {
        CAPTURE(k);
        CHECK(std::abs(static_cast<long>(got[k].first) - static_cast<long>(expected[k].first)) <= static_cast<long>(slack));
        CHECK(std::abs(static_cast<long>(got[k].last) - static_cast<long>(expected[k].last)) <= static_cast<long>(slack));
    }
}

template <class T>
void check_schedule(const anima::contact_set<T>& s, std::size_t slack) {
    REQUIRE(s.feet.size() == 2);
    check_runs(s.feet[0].contacts, left_planted, slack);
    check_runs(s.feet[1].contacts, right_planted, slack);
    check_runs(s.airborne_phases, {jump}, slack);
}

}  // namespace

TEST_CASE_TEMPLATE("find_contacts finds a planted schedule and its airborne phase", T, float, double) {
    const auto c = synthetic_clip<T>();
    const auto s = anima::find_contacts(c);
    CHECK(s.up == anima::signed_axis{anima::axis::y, 1});
    CHECK(s.body_height == doctest::Approx(1.8).epsilon(1e-5));
    CHECK(s.lead_in == 0);
    CHECK(s.feet[0].name == "LeftFoot");
    check_schedule(s, 3);
    // Per frame flags agree with the runs.
    for (std::size_t f = 0; f < frames; ++f) {
        const bool any = s.feet[0].in_contact[f] || s.feet[1].in_contact[f];
        CHECK(s.airborne[f] == !any);
    }
}

TEST_CASE("find_contacts: Z up, centimetres, a wrong frame time and unnamed feet give the same schedule") {
    const auto y_up = anima::find_contacts(synthetic_clip<double>());
    SUBCASE("Z up") {
        const auto s = anima::find_contacts(synthetic_clip<double>(true));
        CHECK(s.up == anima::signed_axis{anima::axis::z, 1});
        check_schedule(s, 3);
        CHECK(s.feet[0].contacts == y_up.feet[0].contacts);
        CHECK(s.airborne_phases == y_up.airborne_phases);
    }
    SUBCASE("centimetres: every threshold is in body heights") {
        const auto s = anima::find_contacts(anima::scale_clip(synthetic_clip<double>(), 100.0));
        CHECK(s.body_height == doctest::Approx(180.0));
        CHECK(s.feet[0].contacts == y_up.feet[0].contacts);
        CHECK(s.feet[1].contacts == y_up.feet[1].contacts);
        CHECK(s.airborne_phases == y_up.airborne_phases);
    }
    SUBCASE("the frame time claims twice the real rate's period") {
        auto c = synthetic_clip<double>();
        c.set_frame_time(2 * dt);
        check_schedule(anima::find_contacts(c), 3);
    }
    SUBCASE("feet found as the lowest leaves, or named") {
        const auto c = synthetic_clip<double>(false, false);
        const auto feet = anima::find_feet(c.skeleton(), anima::signed_axis{});
        REQUIRE(feet.size() == 2);  // not the head
        CHECK(c.skeleton()[feet[0]].name == "PartA");
        check_schedule(anima::find_contacts(c), 3);
        anima::contact_params<double> p;
        p.feet = {"PartB"};
        const auto one = anima::find_contacts(c, p);
        REQUIRE(one.feet.size() == 1);
        check_runs(one.feet[0].contacts, right_planted, 3);
        // With one foot looked at, the frames it is lifted are airborne.
        REQUIRE(one.airborne_phases.size() == 2);
        check_runs(one.airborne_phases, {{0, 59}, {150, 239}}, 3);
    }
}

TEST_CASE_TEMPLATE("foot_skate measures a sliding planted foot", T, float, double) {
    const auto s = anima::find_contacts(synthetic_clip<T>());
    // The left foot's first stance slides at 0.1 m/s, in body heights per second.
    const auto first = anima::foot_skate(s, 10, 80);
    CHECK(first.samples >= 85);  // the left foot over 10..80 and the right one over 60..80
    CHECK(first.max == doctest::Approx(slide / 1.8).epsilon(0.02));
    const auto still = anima::foot_skate(s, 220, 290);
    CHECK(still.max < T(1e-4));
    CHECK(still.samples > 0);
    // Nothing in contact: zeros.
    const auto air = anima::foot_skate(s, 160, 200);
    CHECK(air.samples == 0);
    CHECK(air.median == T(0));
}

TEST_CASE_TEMPLATE("clip_foot_skate: contacts by height, over every clip together", T, float, double) {
    const auto c = synthetic_clip<T>();
    // By height alone: the same as foot_skate of contacts found without the speed test.
    anima::contact_params<T> p;
    p.use_speed = false;
    p.skip_rest_pose = false;
    const auto direct = anima::foot_skate(anima::find_contacts(c, p));
    const auto one = anima::clip_foot_skate(c);
    CHECK(one.samples == direct.samples);
    CHECK(one.median == direct.median);
    // The speed test would leave sliding frames out of the measure.
    const auto with_speed = anima::foot_skate(anima::find_contacts(c));
    CHECK(with_speed.samples < one.samples);
    CHECK(with_speed.max < one.max);
    // Two clips: every sample of each, one median over all of them.
    const auto still = c.slice(220, c.frames());
    const auto both = anima::clip_foot_skate(std::vector<anima::clip<T>>{c, still});
    CHECK(both.samples == one.samples + anima::clip_foot_skate(still).samples);
    CHECK(both.median <= one.median);  // the still part only adds slow samples
    CHECK(both.max == one.max);
}

TEST_CASE_TEMPLATE("positions whose differences overflow the scalar type are refused, not measured as NaN", T, float,
                   double) {
    // The root jumps by 0.6 x the largest value every frame: each position is
    // finite, the frame-to-frame speeds (and their squares) are not.
    auto c = synthetic_clip<T>();
    const T big = std::numeric_limits<T>::max() * T(0.3);
    for (std::size_t f = 0; f < c.frames(); ++f)
        c.set_root_position(f, Eigen::Matrix<T, 3, 1>(f % 2 ? big : -big, c.root_position(f).y(), T(0)));
    CHECK_THROWS_WITH_AS(anima::find_contacts(c), doctest::Contains("overflows the scalar type; scale the clip down"),
                         anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::clip_foot_skate(c), doctest::Contains("overflows the scalar type"),
                         anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::clip_speed_limits(c),
                         doctest::Contains("anima::clip_speed_limits: the root's speed overflows"),
                         anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::joint_linear_velocities(c),
                         doctest::Contains("anima::joint_linear_velocities: a velocity overflows"),
                         anima::invalid_argument);
    // The same motion at a sane scale is measured.
    CHECK_NOTHROW(anima::find_contacts(synthetic_clip<T>()));
    CHECK(std::isfinite(anima::clip_speed_limits(synthetic_clip<T>()).root));
}

TEST_CASE_TEMPLATE("find_contacts: a window of more frames than a count can hold is a window over the whole clip", T,
                   float, double) {
    // 1e30 s at 1/120 s is 1.2e32 frames: converting that to a count was
    // undefined behaviour (UBSan: "outside the range of representable values").
    const auto c = synthetic_clip<T>();
    anima::contact_params<T> whole, huge;
    whole.standing_window_seconds = T(2) * c.frame_time() * static_cast<T>(c.frames());
    huge.standing_window_seconds = T(1e30);
    const auto a = anima::find_contacts(c, whole), b = anima::find_contacts(c, huge);
    REQUIRE(a.feet.size() == b.feet.size());
    CHECK_FALSE(a.feet[0].contacts.empty());
    for (std::size_t i = 0; i < a.feet.size(); ++i) {
        CHECK(a.feet[i].contacts == b.feet[i].contacts);
        CHECK(a.feet[i].in_contact == b.feet[i].in_contact);
    }
    CHECK(a.airborne == b.airborne);
}

TEST_CASE("find_contacts on empty, one-frame and standing clips, and bad parameters") {
    auto c = synthetic_clip<double>();
    SUBCASE("no frames") {
        const anima::clip<double> empty(c.skeleton(), 0, dt);
        const auto s = anima::find_contacts(empty);
        CHECK(s.airborne.empty());
        CHECK(s.airborne_phases.empty());
        REQUIRE(s.feet.size() == 2);
        CHECK(s.feet[0].contacts.empty());
    }
    SUBCASE("one frame, standing: both feet down, not airborne") {
        anima::clip<double> one(c.skeleton(), 1, dt);
        for (std::size_t j = 0; j < c.joints(); ++j)
            if (c.skeleton().translation_slot(j) >= 0) one.set_translation(0, j, c.translation(70, j));
        const auto s = anima::find_contacts(one);
        CHECK(s.feet[0].contacts == std::vector<frame_interval>{{0, 0}});
        CHECK(s.feet[1].contacts == std::vector<frame_interval>{{0, 0}});
        CHECK(s.airborne_phases.empty());
    }
    SUBCASE("bad input") {
        anima::contact_params<double> p;
        p.feet = {"Nose"};
        CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { anima::find_contacts(c, p); }), "no joint 'Nose'"));
        p = {};
        p.height_off = 0.01;
        CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { anima::find_contacts(c, p); }),
                       "height_off must be at least height_on, got 0.01"));
        p = {};
        p.speed_on = std::nan("");
        CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { anima::find_contacts(c, p); }),
                       "speed_on must be positive and finite, got nan"));
        const auto armless = anima::skeleton<double>::from_parents({"root", "a"}, {-1, 0},
                                                                    {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
        CHECK(anima_test::contains(anima_test::invalid_argument_message(
                           [&] { anima::find_contacts(anima::clip<double>(armless, 3, dt)); }),
                       "no height"));
    }
}

TEST_CASE("find_contacts on the bundled walk and run") {
    SUBCASE("a walk is never airborne and alternates its feet") {
        const auto s = anima::find_contacts(anima::read_bvh<double>(anima_test::bundled("walk_cmu31_02_01.bvh")));
        CHECK(s.airborne_phases.empty());
        for (const auto& foot : s.feet) CHECK(foot.contacts.size() >= 2);
        CHECK(anima::foot_skate(s).median < 0.1);  // under 15 cm/s for a 1.5 m figure
    }
    SUBCASE("a run has a flight phase between every two steps") {
        const auto c = anima::read_bvh<double>(anima_test::bundled("run_cmu_09_01.bvh"));
        const auto s = anima::find_contacts(c);
        CHECK(s.lead_in == 5);  // the converter's T-pose and the frames swinging out of it
        CHECK(s.airborne_phases.size() >= 3);
        std::vector<frame_interval> steps;
        for (const auto& foot : s.feet) steps.insert(steps.end(), foot.contacts.begin(), foot.contacts.end());
        CHECK(steps.size() >= 3);
        for (const auto& phase : s.airborne_phases) {
            CHECK(phase.frames() * c.frame_time() < 0.35);  // a running stride's flight, not a jump
        }
    }
}

TEST_CASE("find_contacts on the shared jump") {
    const std::string path = std::string(ANIMA_SHARED_DATA_DIR) + "/bvh/jump_cmu_02_04.bvh";
    if (!std::filesystem::exists(path)) {
        MESSAGE("skipped: " << path << " is not there (the shared data set)");
        return;
    }
    const auto c = anima::read_bvh<double>(path);
    const auto s = anima::find_contacts(c);
    // One jump: both feet leave the ground once, for about half a second.
    REQUIRE(s.airborne_phases.size() == 1);
    const double seconds = static_cast<double>(s.airborne_phases[0].frames()) * c.frame_time();
    CHECK(seconds > 0.4);
    CHECK(seconds < 0.7);
    CHECK(s.airborne_phases[0].first > 90);
    CHECK(s.airborne_phases[0].last < 200);
}

TEST_CASE("find_contacts on float mocap with subnormal components: double's contacts, the caller's mode kept") {
    // The run's channels of 1e-19 degrees make subnormal floats, which
    // find_contacts flushes inside its own scope (anima::flush_denormals).
    const auto f = anima::read_bvh<float>(anima_test::bundled("run_cmu_09_01.bvh"));
    const auto d = anima::read_bvh<double>(anima_test::bundled("run_cmu_09_01.bvh"));
    REQUIRE(anima_test::gradual_underflow());
    const auto cf = anima::find_contacts(f);
    CHECK(anima_test::gradual_underflow());
    const auto cd = anima::find_contacts(d);
    REQUIRE(cf.airborne.size() == cd.airborne.size());
    std::size_t differ = 0;
    for (std::size_t k = 0; k < cf.airborne.size(); ++k) differ += cf.airborne[k] != cd.airborne[k];
    CHECK(differ <= 1);
    CHECK(static_cast<double>(cf.body_height) == doctest::Approx(cd.body_height).epsilon(1e-5));
    // The module's other whole-clip functions hold a guard of their own.
    const auto positions = anima::global_positions(f);
    const auto features = anima::frame_features(f);
    const auto resampled = anima::resample(f, 1.0f / 30);
    const auto skate = anima::clip_foot_skate(f);
    CHECK(anima_test::gradual_underflow());
    CHECK((positions.cast<double>() - anima::global_positions(d)).cwiseAbs().maxCoeff() < 1e-3);
    CHECK((features.cast<double>() - anima::frame_features(d)).cwiseAbs().maxCoeff() < 1e-3);
    CHECK(resampled.frames() == anima::resample(d, 1.0 / 30).frames());
    CHECK(std::isfinite(skate.mean));
}

TEST_CASE_TEMPLATE("foot_points_of: the foot's subtree, each joint then its End Site, parents first", T, float, double) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    anima::skeleton<T> sk;
    const auto hips = sk.add_joint("Hips", -1, vec3::Zero());
    const auto foot = sk.add_joint("LeftFoot", static_cast<int>(hips), vec3(T(0.1), T(-0.8), T(0)));
    const auto spine = sk.add_joint("Spine", static_cast<int>(hips), vec3(T(0), T(0.2), T(0)));
    const auto toe = sk.add_joint("LeftToe", static_cast<int>(foot), vec3(T(0), T(-0.05), T(0.1)));
    const auto heel = sk.add_joint("LeftHeel", static_cast<int>(foot), vec3(T(0), T(-0.05), T(-0.05)));
    sk.set_end_site(toe, vec3(T(0), T(0), T(0.05)));
    sk.set_end_site(spine, vec3(T(0), T(0.3), T(0)));
    const auto points = anima::foot_points_of(sk, foot);
    REQUIRE(points.size() == 4);
    const std::pair<std::size_t, bool> expected[] = {{foot, false}, {toe, false}, {toe, true}, {heel, false}};
    for (std::size_t i = 0; i < points.size(); ++i) {
        CHECK(points[i].joint == expected[i].first);
        CHECK(points[i].end_site == expected[i].second);
    }
    const auto leaf = anima::foot_points_of(sk, toe);  // a joint with an End Site only
    REQUIRE(leaf.size() == 2);
    CHECK((leaf[0].joint == toe && !leaf[0].end_site && leaf[1].joint == toe && leaf[1].end_site));
    CHECK_THROWS_WITH_AS(anima::foot_points_of(sk, 5), doctest::Contains("joint 5 is outside the skeleton (5 joints)"),
                         anima::invalid_argument);
}
