// anima::plant_feet: the bundled walk with its hips swayed sideways (every
// planted foot slides with them) is planted again: the slide of the feet's
// contact points goes, the joints above the legs do not move, frames away
// from the planted runs are left as they were, float and double.
#include "../test_support.hpp"

#include <anima/bvh/reader.hpp>
#include <anima/ik/plant_feet.hpp>
#include <anima/motion/contacts.hpp>
#include <anima/motion/speed_limits.hpp>
#include <anima/rotation/quaternion.hpp>

#include <doctest/doctest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace {

/// Height-only contacts: what plant_feet plants and what a sliding clip's
/// skate is measured on.
template <class T>
anima::contact_params<T> height_only() {
    anima::contact_params<T> p;
    p.use_speed = false;
    return p;
}

/// The bundled walk; under the sanitizers its first 180 frames (four
/// contact runs), which exercise every path at a third of the IK solves.
template <class T>
anima::clip<T> walk() {
    const auto c = anima::read_bvh<T>(anima_test::bundled("walk_cmu31_02_01.bvh"));
    return anima_test::sanitized_build ? c.slice(0, 180) : c;
}

/// The walk, with the root moved sideways by a 1.3 Hz sway of `amplitude`
/// file units: the feet, hanging from the root, slide with it.
template <class T>
anima::clip<T> swayed_walk(T amplitude) {
    auto c = walk<T>();
    for (std::size_t f = 0; f < c.frames(); ++f) {
        auto p = c.root_position(f);
        p.x() += amplitude * T(std::sin(2 * 3.14159265358979 * 1.3 * static_cast<double>(f) * c.frame_time()));
        c.set_root_position(f, p);
    }
    return c;
}

template <class T>
T skate_median(const anima::clip<T>& c) {
    return anima::foot_skate(anima::find_contacts(c, height_only<T>())).median;
}

}  // namespace

TEST_CASE_TEMPLATE("plant_feet takes the slide out of a swayed walk and touches nothing above the legs", T, float,
                   double) {
    const auto original = walk<T>();
    const auto swayed = swayed_walk<T>(T(1));  // 1 file unit: about 5 cm
    const T before = skate_median(swayed), recorded = skate_median(original);
    REQUIRE(before > T(2) * recorded);  // the sway is a real slide

    const auto result = anima::plant_feet(swayed);
    CHECK(result.runs >= (anima_test::sanitized_build ? 3u : 4u));
    CHECK(result.frames > 0);
    CHECK(result.largest_correction > T(0.5));
    const T after = skate_median(result.planted);
    MESSAGE("skate median: recorded " << recorded << ", swayed " << before << ", planted " << after);
    CHECK(after < T(0.5) * before);
    CHECK(after <= T(1.5) * recorded);  // the smoothing lets a little through where runs begin

    // Only leg joints change; the root and the upper body are as they were.
    const auto& sk = swayed.skeleton();
    std::vector<bool> leg(sk.size(), false);
    for (const auto& foot : result.contacts.feet) {
        const auto knee = static_cast<std::size_t>(sk[foot.joint].parent);
        leg[foot.joint] = leg[knee] = leg[static_cast<std::size_t>(sk[knee].parent)] = true;
    }
    bool others_same = true;
    for (std::size_t f = 0; f < swayed.frames(); ++f)
        for (std::size_t j = 0; j < sk.size(); ++j)
            if (!leg[j]) others_same = others_same && result.planted.rotation(f, j).coeffs() == swayed.rotation(f, j).coeffs();
    CHECK(others_same);
    for (std::size_t f = 0; f < swayed.frames(); ++f) REQUIRE(result.planted.root_position(f) == swayed.root_position(f));
    // Nothing is NaN.
    for (std::size_t f = 0; f < swayed.frames(); ++f)
        for (std::size_t j = 0; j < sk.size(); ++j) REQUIRE(result.planted.rotation(f, j).coeffs().allFinite());
}

TEST_CASE_TEMPLATE("plant_feet holds the stance and lets the step go: every run of the recorded walk slides less",
                   T, float, double) {
    // Height alone finds long contact runs in a walk: the swing skims the
    // floor for a few frames at each end. Dragged back as if sliding, those
    // steps slid more after planting than before (three of seven runs); the
    // plant now ends where the foot moves faster than slide_fraction of its
    // fast speed.
    const auto c = walk<T>();
    const auto before = anima::find_contacts(c, height_only<T>());
    const auto result = anima::plant_feet(c, before, {});
    const auto after = anima::find_contacts(result.planted, height_only<T>());
    REQUIRE(after.feet.size() == before.feet.size());
    std::size_t runs = 0;
    for (std::size_t i = 0; i < before.feet.size(); ++i)
        for (const auto& run : before.feet[i].contacts) {
            auto planted = after.feet[i];
            planted.in_contact = before.feet[i].in_contact;  // the same frames, measured on the planted clip
            const T was = anima::foot_skate(before.feet[i], run.first, run.last).median;
            const T is = anima::foot_skate(planted, run.first, run.last).median;
            CAPTURE(run.first);
            CHECK(is <= T(1.02) * was);
            ++runs;
        }
    CHECK(runs >= (anima_test::sanitized_build ? 3u : 7u));
    CHECK(anima::foot_skate(after).median < T(0.6) * anima::foot_skate(before).median);
    // The old rule: every low frame held (a fraction no speed reaches).
    anima::plant_feet_params<T> hold_all;
    hold_all.slide_fraction = T(100);
    const auto dragged = anima::find_contacts(anima::plant_feet(c, before, hold_all).planted, height_only<T>());
    CHECK(anima::foot_skate(after).median < anima::foot_skate(dragged).median);
}

TEST_CASE_TEMPLATE("plant_feet within ranges leaves the frames of other runs as they were", T, float, double) {
    const auto swayed = swayed_walk<T>(T(1));
    const auto contacts = anima::find_contacts(swayed, height_only<T>());
    // The second contact run of the first foot, and nothing else.
    const auto& runs = contacts.feet.front().contacts;
    REQUIRE(runs.size() >= 2);
    anima::plant_feet_params<T> p;
    p.ranges = {runs[1]};
    const auto result = anima::plant_feet(swayed, contacts, p);
    CHECK(result.runs >= 1);
    // Frames before the range's run (and before any other foot's run that
    // touches it) are untouched.
    std::size_t earliest = runs[1].first;
    for (const auto& foot : contacts.feet)
        for (const auto& r : foot.contacts)
            if (r.first <= runs[1].last && runs[1].first <= r.last) earliest = std::min(earliest, r.first);
    for (std::size_t f = 0; f < earliest; ++f)
        for (std::size_t j = 0; j < swayed.joints(); ++j)
            REQUIRE(result.planted.rotation(f, j).coeffs() == swayed.rotation(f, j).coeffs());
    // and the run itself moved.
    bool moved = false;
    for (std::size_t f = runs[1].first + 1; f <= runs[1].last && !moved; ++f)
        moved = result.planted.rotation(f, contacts.feet.front().joint).coeffs() !=
                swayed.rotation(f, contacts.feet.front().joint).coeffs();
    CHECK(moved);
}

TEST_CASE_TEMPLATE("plant_feet keeps the legs within the joint speed limits", T, float, double) {
    // A sway of 2 units (0.07 body heights) at 1.3 Hz: unlimited, the legs
    // catching and releasing the feet turn faster than the walk ever does.
    const auto swayed = swayed_walk<T>(T(2));
    const auto own = anima::clip_speed_limits(swayed).joint;
    const auto fastest = [](const anima::clip<T>& c, std::size_t j) {
        T out = 0;
        for (std::size_t f = 1; f < c.frames(); ++f)
            out = std::max(out, anima::angle_between(c.rotation(f - 1, j), c.rotation(f, j)) * c.frame_rate());
        return out;
    };
    // Unlimited, for comparison (not under the sanitizers: a third of the
    // test's time, and no path the limited runs do not take).
    anima::plant_feet_params<T> free;
    free.joint_speed_limits.assign(swayed.joints(), std::numeric_limits<T>::infinity());
    const auto unlimited = anima_test::sanitized_build ? swayed : anima::plant_feet(swayed, free).planted;
    const auto limited = anima::plant_feet(swayed, anima::plant_feet_params<T>{}).planted;
    anima::plant_feet_params<T> half;
    half.joint_speed_limits = own;
    for (T& l : half.joint_speed_limits) l /= T(2);
    const auto slow = anima::plant_feet(swayed, half).planted;
    std::size_t over = 0, changed = 0;
    for (std::size_t j = 0; j < swayed.joints(); ++j) {
        bool moved = false;
        for (std::size_t f = 0; f < swayed.frames() && !moved; ++f)
            moved = limited.rotation(f, j).coeffs() != swayed.rotation(f, j).coeffs();
        if (!moved) continue;
        ++changed;
        CAPTURE(swayed.skeleton()[j].name);
        if (fastest(unlimited, j) > own[j] * T(1.01)) ++over;
        CHECK(fastest(limited, j) <= own[j] * T(1.0001));
        CHECK(fastest(slow, j) <= half.joint_speed_limits[j] * T(1.0001));
    }
    CHECK(changed >= 4);  // hips, knees, ankles of both legs
    if (!anima_test::sanitized_build) CHECK(over >= 1);  // the limit had something to do
    if (!anima_test::sanitized_build)
        MESSAGE("swayed walk skate " << skate_median(swayed) << ", planted " << skate_median(unlimited)
                                     << " unlimited, " << skate_median(limited) << " within the walk's speeds");
    // Limited, the feet still slide less than swayed.
    CHECK(skate_median(limited) < T(0.6) * skate_median(swayed));
}

TEST_CASE_TEMPLATE("plant_feet: short clips and bad input", T, float, double) {
    const auto walk = anima::read_bvh<T>(anima_test::bundled("walk_cmu31_02_01.bvh"));
    SUBCASE("a one-frame clip comes back as it was") {
        const auto one = walk.slice(0, 1);
        anima::contact_set<T> none;
        const auto r = anima::plant_feet(one, none, {});
        CHECK(r.runs == 0);
        CHECK(r.planted.frames() == 1);
    }
    SUBCASE("contacts of another clip") {
        auto contacts = anima::find_contacts(walk, height_only<T>());
        contacts.feet.front().in_contact.pop_back();
        const auto message = anima_test::invalid_argument_message([&] { (void)anima::plant_feet(walk, contacts, {}); });
        CHECK(anima_test::contains(message, "anima::plant_feet"));
        CHECK(anima_test::contains(message, "frames"));
    }
    SUBCASE("a foot without a leg is left as it is") {
        auto contacts = anima::find_contacts(walk, height_only<T>());
        contacts.feet.resize(1);
        contacts.feet.front().joint = 0;  // the root: no parent
        contacts.feet.front().name = walk.skeleton()[0].name;
        const auto r = anima::plant_feet(walk, contacts, {});
        CHECK(r.frames == 0);
        for (std::size_t f = 0; f < walk.frames(); ++f)
            for (std::size_t j = 0; j < walk.joints(); ++j)
                REQUIRE(r.planted.rotation(f, j).coeffs() == walk.rotation(f, j).coeffs());
        contacts.feet.front().joint = walk.joints();
        const auto message = anima_test::invalid_argument_message([&] { (void)anima::plant_feet(walk, contacts, {}); });
        CHECK(anima_test::contains(message, "the skeleton has"));
    }
    SUBCASE("has_feet_to_plant") {
        CHECK(anima::has_feet_to_plant(walk));
        CHECK_FALSE(anima::has_feet_to_plant(walk.slice(0, 1)));
        anima::skeleton<T> prop;
        prop.add_joint("Box", -1, Eigen::Matrix<T, 3, 1>::Zero());
        CHECK_FALSE(anima::has_feet_to_plant(anima::clip<T>(prop, 10, T(1) / 30)));
    }
    SUBCASE("a negative release") {
        anima::plant_feet_params<T> p;
        p.release_seconds = T(-1);
        const auto message = anima_test::invalid_argument_message([&] { (void)anima::plant_feet(walk, p); });
        CHECK(anima_test::contains(message, "release_seconds"));
    }
    SUBCASE("joint speed limits of the wrong size or below 0") {
        anima::plant_feet_params<T> p;
        p.joint_speed_limits.assign(walk.joints() - 1, T(1));
        CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)anima::plant_feet(walk, p); }),
                                   "joint_speed_limits has 30 entries, the clip 31 joints"));
        p.joint_speed_limits.assign(walk.joints(), T(1));
        p.joint_speed_limits[3] = T(-1);
        CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)anima::plant_feet(walk, p); }),
                                   "a joint speed limit must be"));
    }
    SUBCASE("a slide fraction of 0") {
        anima::plant_feet_params<T> p;
        p.slide_fraction = T(0);
        const auto message = anima_test::invalid_argument_message([&] { (void)anima::plant_feet(walk, p); });
        CHECK(anima_test::contains(message, "slide_fraction"));
    }
}

TEST_CASE_TEMPLATE("plant_feet at a frame time too short to tell a stance from a step refuses, naming it", T, float,
                   double) {
    // The swayed walk's first 180 frames: at a frame time whose +-1/60 s
    // foot-speed window covers the clip, every point's speed is its mean
    // over the clip, nothing is slower than a step, and plant_feet planted
    // nothing without a word (frames 0 from 1e-4 s down).
    auto c = swayed_walk<T>(T(1)).slice(0, 180);
    c.set_frame_time(T(2e-4));  // the window (+-83 frames) still fits: planted
    const auto fits = anima::plant_feet(c);
    CHECK(fits.runs > 0);
    CHECK(fits.frames > 0);
    CHECK(fits.largest_correction > T(0.5));
    for (const T ft : {T(1e-4), T(1e-5), T(1e-7), T(1e-30)}) {
        CAPTURE(ft);
        c.set_frame_time(ft);
        const auto message = anima_test::invalid_argument_message([&] { (void)anima::plant_feet(c); });
        CHECK(anima_test::contains(message, "anima::plant_feet: the clip's frame time must be"));
        CHECK(anima_test::contains(message, "got " + anima::detail::argument_text(ft)));
        // plant_feet_in_ranges (textures, transitions) as well.
        CHECK_THROWS_AS(anima::plant_feet_in_ranges(c, {{0, 179}}, anima::plant_feet_params<T>{}, {}),
                        anima::invalid_argument);
    }
    // A clip of a few frames at a capture rate is short, not mistimed: it is
    // planted as before.
    const auto short_clip = swayed_walk<T>(T(1)).slice(0, 7);
    const auto planted = anima::plant_feet(short_clip);
    CHECK(planted.planted.frames() == 7);
    for (std::size_t f = 0; f < 7; ++f)
        for (std::size_t j = 0; j < short_clip.joints(); ++j) REQUIRE(planted.planted.rotation(f, j).coeffs().allFinite());
}

TEST_CASE_TEMPLATE("plant_feet finding its own contacts: the result with find_contacts' contacts, bit for bit", T, float,
                   double) {
    // The overload without contacts measures the feet once, for the contacts
    // and the planting both; the result must not change.
    const auto walk = anima::read_bvh<T>(anima_test::bundled("walk_cmu31_02_01.bvh")).slice(0, 240);
    anima::plant_feet_params<T> params;
    for (const bool height : {false, true}) {
        if (height) params.contacts = height_only<T>();
        const auto own = anima::plant_feet(walk, params);
        const auto given = anima::plant_feet(walk, anima::find_contacts(walk, params.contacts), params);
        CHECK(own.runs == given.runs);
        CHECK(own.frames == given.frames);
        CHECK(own.largest_error == given.largest_error);
        REQUIRE(own.planted.frames() == given.planted.frames());
        bool same = true;
        for (std::size_t i = 0; i < own.planted.rotations().size(); ++i)
            same = same && own.planted.rotations()[i].coeffs() == given.planted.rotations()[i].coeffs();
        for (std::size_t i = 0; i < own.planted.translations().size(); ++i)
            same = same && own.planted.translations()[i] == given.planted.translations()[i];
        CHECK(same);
        CHECK(own.runs > 0);
    }
}

TEST_CASE("plant_feet on float mocap with subnormal components: double's runs, the caller's mode kept") {
    const auto f = anima::read_bvh<float>(anima_test::bundled("run_cmu_09_01.bvh"));
    const auto d = anima::read_bvh<double>(anima_test::bundled("run_cmu_09_01.bvh"));
    REQUIRE(anima_test::gradual_underflow());
    const auto pf = anima::plant_feet(f);
    CHECK(anima_test::gradual_underflow());
    const auto pf_given = anima::plant_feet(f, pf.contacts, anima::plant_feet_params<float>{});
    CHECK(anima_test::gradual_underflow());
    const auto pd = anima::plant_feet(d);
    CHECK(pf.runs == pd.runs);
    CHECK(pf_given.runs == pf.runs);
    bool finite = true;
    for (const auto& q : pf.planted.rotations()) finite = finite && q.coeffs().allFinite();
    CHECK(finite);
}
