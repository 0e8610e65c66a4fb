// Textons and long textures: the offset search finds a planted repeat in a
// clip, textures have exactly N frames of unit quaternions and finite
// values, every seam keeps each joint's angular speed and the root's speed
// within the input's own range (where a cut-and-paste loop does not), the
// root keeps travelling and turning instead of snapping back, symmetric
// playback mixes in reproducibly, and bad input is refused by name.
#include "texture_test_support.hpp"

#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/rotation/quaternion.hpp>
#include <anima/rotation/swing_twist.hpp>
#include <anima/texture/measure_texture.hpp>
#include <anima/texture/motion_texture.hpp>
#include <anima/texture/seam_speed.hpp>
#include <anima/texture/texton.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace {

using namespace texture_test;

template <class T>
void check_well_formed(const anima::clip<T>& c, std::size_t frames) {
    REQUIRE(c.frames() == frames);
    const T tol = tolerance<T>(1e-12, 1e-5);
    for (std::size_t f = 0; f < c.frames(); ++f)
        for (std::size_t j = 0; j < c.joints(); ++j) {
            const auto& q = c.rotation(f, j);
            REQUIRE(q.coeffs().allFinite());
            REQUIRE(std::abs(q.norm() - T(1)) < tol);
            REQUIRE(c.translation(f, j).allFinite());
        }
}

template <class T>
T worst_joint(const std::vector<anima::seam_speed<T>>& s) {
    return anima::worst_seam_speed(s).joint_ratio;
}
template <class T>
T worst_root(const std::vector<anima::seam_speed<T>>& s) {
    return anima::worst_seam_speed(s).root_ratio;
}

// ---------------------------------------------------------------------------
// Textons
// ---------------------------------------------------------------------------

TEST_CASE_TEMPLATE("texton: a periodic clip is cut where it repeats, and loops exactly", T, float, double) {
    const std::size_t period = 40;
    const auto c = walker<T>(230, period);
    anima::texton_params<T> p;
    p.m = 60;
    p.overlap = 30;
    const auto x = anima::make_texton(c, p);
    // M2's frame F - m + a must be a whole number of periods after M1's frame b.
    CHECK((c.frames() - p.m + x.offset_m2 - x.offset_m1) % period == 0);
    CHECK(x.motion.frames() == c.frames() - p.m + x.offset_m2 - x.offset_m1);
    CHECK(x.motion.frames() % period == 0);
    CHECK(x.search_cost < T(1e-3) * x.search_costs.mean());
    CHECK(std::abs(x.heading_turn) < T(1e-3));
    CHECK(x.overlap_start == c.frames() - 2 * p.m + x.offset_m2);
    // Both sides of the overlap are the same motion: the texton is the clip's
    // own frames from frame m on, period after period.
    const T tol = tolerance<T>(1e-6, 2e-3);
    for (std::size_t k = 0; k < x.motion.frames(); ++k)
        for (std::size_t j = 1; j < c.joints(); ++j)
            REQUIRE(anima::angle_between(x.motion.rotation(k, j), c.rotation((p.m + k) % period, j)) < tol);
    for (std::size_t r = 0; r < x.rows(); ++r) {
        CHECK(x.cut.seam[r] >= 1);
        CHECK(x.cut.seam[r] < p.overlap);
    }
}

TEST_CASE_TEMPLATE("texton: the search finds a repeat planted in a clip that never repeats", T, float, double) {
    const std::size_t F = 230, m = 60, n = 30, a0 = 17, b0 = 6;
    auto c = walker<T>(F, 37.3, 1.5);
    // M2's frames a0 .. a0+n-1 become copies of M1's frames b0 .. b0+n-1,
    // and so do the frames on either side: velocities (central
    // differences) match inside the window too.
    const std::size_t into = F - m + a0;
    Eigen::Matrix<T, 3, 1> shift = c.root_position(into - 1) - c.root_position(b0 - 1);
    shift.y() = 0;  // the same height, somewhere else on the ground
    for (std::size_t t = 0; t < n + 2; ++t) {
        for (std::size_t j = 0; j < c.joints(); ++j) c.set_rotation(into - 1 + t, j, c.rotation(b0 - 1 + t, j));
        c.set_root_position(into - 1 + t, c.root_position(b0 - 1 + t) + shift);
    }
    anima::texton_params<T> p;
    p.m = m;
    p.overlap = n;
    for (const auto metric : {anima::frame_metric::mahalanobis, anima::frame_metric::l2}) {
        p.distance.metric = metric;
        const auto x = anima::make_texton(c, p);
        CHECK(x.offset_m2 == a0);
        CHECK(x.offset_m1 == b0);
        CHECK(x.search_cost < T(1e-3) * x.search_costs.mean());
    }
}

TEST_CASE_TEMPLATE("texton: fitted lengths and refused input", T, float, double) {
    const auto c = walker<T>(149, 30.0);
    anima::texton_params<T> p;
    const auto fitted = anima::fit_texton_lengths(p, c.frames());
    CHECK(fitted.m == 74);
    CHECK(fitted.overlap == 37);
    CHECK(anima::fit_texton_lengths(p, 400).m == 100);
    CHECK(anima::make_texton(c, fitted).motion.frames() >= fitted.overlap);

    CHECK(contains(invalid_argument_message([&] { (void)anima::make_texton(c, p); }), "m = 100 is too large for a clip of 149 frames"));
    auto q = fitted;
    q.overlap = 75;
    CHECK(contains(invalid_argument_message([&] { (void)anima::make_texton(c, q); }), "longer than m"));
    q.overlap = 1;
    CHECK(contains(invalid_argument_message([&] { (void)anima::make_texton(c, q); }), "at least 2 frames"));
    q = fitted;
    q.blend.frames = 38;
    CHECK(contains(invalid_argument_message([&] { (void)anima::make_texton(c, q); }), "does not fit the overlap"));
    const anima::clip<T> empty(figure<T>(), 0, T(1) / T(30));
    CHECK(contains(invalid_argument_message([&] { (void)anima::make_texton(empty, fitted); }), "too large for a clip of 0 frames"));
    const anima::clip<T> one(figure<T>(), 1, T(1) / T(30));
    CHECK(contains(invalid_argument_message([&] { (void)anima::make_texton(one, anima::fit_texton_lengths(p, 1)); }),
                   "clip of 1 frames"));
    const anima::clip<T> bare(anima::skeleton<T>(), 10, T(1) / T(30));
    CHECK(contains(invalid_argument_message([&] { (void)anima::make_texton(bare, q); }), "no joints"));
    // 2m must not wrap around to a size that fits.
    q = fitted;
    q.m = std::size_t(1) << 63;
    CHECK(contains(invalid_argument_message([&] { (void)anima::make_texton(c, q); }),
                   "anima::make_texton: m = 9223372036854775808 is too large for a clip of 149 frames"));
    anima::motion_texture_params<T> tp;
    tp.texton.m = std::size_t(1) << 63;
    CHECK(contains(invalid_argument_message([&] { (void)anima::make_motion_texture(c, 10, tp); }),
                   "m = 9223372036854775808 is too large"));
    CHECK(contains(invalid_argument_message([&] { (void)anima::make_motion_texture(c, 0, {}); }), "N = 0"));
    CHECK(contains(invalid_argument_message([&] { (void)anima::patch_texton(anima::make_texton(c, fitted), 0); }), "N = 0"));
}

// ---------------------------------------------------------------------------
// Textures
// ---------------------------------------------------------------------------

TEST_CASE_TEMPLATE("texture: exactly N frames of unit quaternions and finite values", T, float, double) {
    const auto c = walker<T>(250, 37.3, 0.4);
    auto p = unplanted<T>();
    p.texton.m = 80;
    p.texton.overlap = 40;
    const auto texton = anima::make_texton(c, p.texton);
    for (std::size_t n : {1u, 2u, 3u, 17u, 400u, 1700u}) {
        const auto t = anima::patch_texton(texton, n, p);
        check_well_formed(t.motion, n);
        CHECK(t.stream.size() == n);
        CHECK(t.row_seams.size() == texton.rows());
        for (std::size_t r = 0; r < texton.rows(); ++r)
            for (std::size_t k : t.row_seams[r]) {
                const std::size_t s = texton.blend_centre(r);
                CHECK(((t.stream[k] == s && t.stream[k - 1] + 1 == s) || (t.stream[k] + 1 == s && t.stream[k - 1] == s)));
            }
    }
    // Played forwards, the stream passes each seam once per loop of the
    // texton: every row's crossings are one texton length apart, at its
    // graph-cut frame or at its fade's middle as asked. A fade as long as
    // the overlap has its middle away from most rows' cuts.
    auto faded = p;
    faded.texton.blend.frames = faded.texton.overlap;
    const auto wide = anima::make_texton(c, faded.texton);
    std::size_t apart = 0;
    for (std::size_t r = 0; r < wide.rows(); ++r) apart += wide.seam_frame(r) != wide.blend_centre(r);
    REQUIRE(apart > 0);
    const auto forward = anima::patch_texton(wide, 1700, faded);
    const std::size_t L = wide.motion.frames();
    for (const auto mark : {anima::seam_mark::cut, anima::seam_mark::fade_centre}) {
        const auto crossings = anima::seam_crossings(wide, forward.stream, mark);
        REQUIRE(crossings.size() == wide.rows());
        for (std::size_t r = 0; r < wide.rows(); ++r) {
            const std::size_t s = mark == anima::seam_mark::cut ? wide.seam_frame(r) : wide.blend_centre(r);
            REQUIRE(s > 0);
            std::vector<std::size_t> expected;  // the output frames after the first that show s
            for (std::size_t k = (s + L - forward.stream[0]) % L; k < 1700; k += L)
                if (k > 0) expected.push_back(k);
            CHECK(crossings[r] == expected);
        }
        if (mark == anima::seam_mark::fade_centre) CHECK(crossings == forward.row_seams);
    }
    const auto t = anima::make_motion_texture(c, 1700, p);
    CHECK(t.timings.total == doctest::Approx(t.timings.features + t.timings.search + t.timings.cut + t.timings.blend +
                                             t.timings.patch + t.timings.smoothing + t.timings.planting));
    CHECK(t.smoothing.solves > 0);
    CHECK(t.smoothing.converged);
    CHECK(!t.overlap_spans.empty());
}

template <class T>
void check_seams_smooth(const anima::clip<T>& c, const anima::motion_texture_params<T>& p, std::size_t frames, T tolerance) {
    // A third under the sanitizers: still several seams of every kind.
    if (anima_test::sanitized_build) frames = std::min<std::size_t>(frames, 600);
    const auto t = anima::make_motion_texture(c, frames, p);
    check_well_formed(t.motion, frames);
    REQUIRE(t.overlap_spans.size() >= 2);
    const auto limits = anima::clip_speed_limits(c);
    const auto speeds = anima::seam_speeds(t.motion, t.overlap_spans, limits);
    CHECK(worst_joint(speeds) <= T(1) + tolerance);
    CHECK(worst_root(speeds) <= T(1) + tolerance);
    // The paper's rearrangement without the seam machinery jumps.
    std::vector<std::pair<std::size_t, std::size_t>> jumps;
    const auto naive = cut_and_paste(c, p.texton.m, frames, jumps);
    REQUIRE(!jumps.empty());
    CHECK(worst_joint(anima::seam_speeds(naive, jumps, limits)) > T(1.5));
}

TEST_CASE_TEMPLATE("texture: seams stay within the input's speeds; a cut-and-paste loop does not", T, float, double) {
    SUBCASE("synthetic walk") {
        auto p = unplanted<T>();
        p.texton.m = 80;
        p.texton.overlap = 40;
        check_seams_smooth(walker<T>(250, 37.3, 0.4), p, 1700, T(0.02));
    }
    SUBCASE("bundled CMU walk") {
        const auto c = walk<T>();
        check_seams_smooth(c, unplanted<T>(), 1700, T(0.02));
    }
    SUBCASE("bundled run, shorter than 2m: fitted lengths") {
        const auto c = run<T>();
        auto p = unplanted<T>();
        p.texton = anima::fit_texton_lengths(p.texton, c.frames());
        check_seams_smooth(c, p, 1700, T(0.02));
    }
}

TEST_CASE_TEMPLATE("texture: planting holds feet across seams of the bundled run", T, float, double) {
    const auto c = run<T>();
    anima::motion_texture_params<T> p;
    p.texton = anima::fit_texton_lengths(p.texton, c.frames());
    anima::contact_params<T> cp;
    cp.use_speed = false;  // sliding feet count as planted
    const auto skate = [&](const anima::clip<T>& m) { return anima::foot_skate(anima::find_contacts(m, cp)).median; };
    // 1700 frames; 500 in float, whose IK runs unoptimised in this unit; 300
    // under the sanitizers (every path, a sixth of the IK).
    const std::size_t frames = anima_test::sanitized_build ? 300 : std::is_same_v<T, float> ? 500 : 1700;
    CHECK(p.planting.enabled);  // the default
    const auto planted = anima::make_motion_texture(c, frames, p);
    p.planting.enabled = false;
    const auto loose = anima::make_motion_texture(c, frames, p);
    CHECK(loose.planted_runs == 0);
    check_well_formed(planted.motion, frames);
    CHECK(planted.planted_runs > (frames < 1700 ? 2u : 10u));
    MESSAGE("run texture skate / input: " << skate(loose.motion) / skate(c) << " loose, "
                                          << skate(planted.motion) / skate(c) << " planted");
    CHECK(skate(planted.motion) < T(0.8) * skate(loose.motion));
    // The legs catching the feet stay within the run's joint speeds, as the
    // seams do (unlimited, rThigh reached 1.15 times its fastest).
    const auto limits = anima::clip_speed_limits(c);
    for (const auto& s : anima::seam_speeds(planted.motion, planted.overlap_spans, limits)) {
        CAPTURE(s.first);
        CHECK(s.joint_ratio <= T(1.001));
    }
    // The frames are the same stream: planting moves legs, never the root.
    for (std::size_t f = 0; f < frames; ++f) REQUIRE(planted.motion.root_position(f) == loose.motion.root_position(f));
}

TEST_CASE("texture: planting finds contacts along the texton's up axis unless told its own") {
    const auto c = run<double>();
    anima::motion_texture_params<double> p;
    p.texton = anima::fit_texton_lengths(p.texton, c.frames());
    const std::size_t frames = 300;
    // Up the wrong way (-Y), so that the planting's own guess (+Y) differs.
    const anima::signed_axis down{anima::axis::y, -1};
    p.texton.up = down;
    const auto t = anima::make_motion_texture(c, frames, p);
    auto explicit_up = p;
    explicit_up.planting.feet.contacts.up = down;
    const auto told = anima::make_motion_texture(c, frames, explicit_up);
    auto guessing = p;
    guessing.planting.feet.contacts.up = anima::signed_axis{anima::axis::y, 1};
    const auto other = anima::make_motion_texture(c, frames, guessing);
    const auto same = [](const anima::clip<double>& x, const anima::clip<double>& y) {
        for (std::size_t i = 0; i < x.rotations().size(); ++i)
            if (x.rotations()[i].coeffs() != y.rotations()[i].coeffs()) return false;
        return x.translations() == y.translations();
    };
    CHECK(same(t.motion, told.motion));
    CHECK(t.planted_runs == told.planted_runs);
    CHECK_FALSE(same(t.motion, other.motion));
}

TEST_CASE_TEMPLATE("texture: progress reports each stage once, in order, with its time; the motion is the same",
                   T, float, double) {
    const auto c = run<T>();
    anima::motion_texture_params<T> p;
    p.texton = anima::fit_texton_lengths(p.texton, c.frames());
    p.planting.enabled = false;
    const std::size_t frames = 300;
    const auto quiet = anima::make_motion_texture(c, frames, p);
    std::vector<std::string> stages;
    std::vector<double> seconds;
    p.progress = [&](std::string_view stage, double s) {
        stages.emplace_back(stage);
        seconds.push_back(s);
    };
    const auto t = anima::make_motion_texture(std::vector<anima::clip<T>>{c}, frames, p);
    REQUIRE(stages == std::vector<std::string>{"texton", "patch", "smoothing", "planting"});
    CHECK(seconds[0] == t.texton.timings.total);
    CHECK(seconds[1] == t.timings.patch);
    CHECK(seconds[2] == t.timings.smoothing);
    CHECK(seconds[3] == t.timings.planting);
    REQUIRE(t.motion.frames() == quiet.motion.frames());
    for (std::size_t i = 0; i < t.motion.rotations().size(); ++i)
        REQUIRE(t.motion.rotations()[i].coeffs() == quiet.motion.rotations()[i].coeffs());
    CHECK(t.motion.translations() == quiet.motion.translations());
    // patch_texton alone reports its own stages.
    stages.clear();
    (void)anima::patch_texton(t.texton, frames, p);
    CHECK(stages == std::vector<std::string>{"patch", "smoothing", "planting"});
}

TEST_CASE_TEMPLATE("measure_texture: the seams' speeds and the skate, as the single measures give them", T, float,
                   double) {
    const auto c = run<T>();
    auto p = unplanted<T>();
    p.texton = anima::fit_texton_lengths(p.texton, c.frames());
    const std::size_t frames = 400;
    const auto t = anima::make_motion_texture(c, frames, p);
    const auto up = anima::guess_up_axis(c.skeleton()).up;
    const auto q = anima::measure_texture(c, t, up);
    // One measure per pass through an overlap, each the direct call's.
    const auto direct = anima::seam_speeds(t.motion, t.overlap_spans, t.texton.source_speeds);
    REQUIRE(q.seams.size() == t.overlap_spans.size());
    REQUIRE(q.seams.size() >= 2);
    for (std::size_t i = 0; i < q.seams.size(); ++i) {
        CHECK(q.seams[i].first == direct[i].first);
        CHECK(q.seams[i].last == direct[i].last);
        CHECK(q.seams[i].joint_ratio == direct[i].joint_ratio);
        CHECK(q.seams[i].worst_joint == direct[i].worst_joint);
        CHECK(q.seams[i].root_ratio == direct[i].root_ratio);
    }
    // The worst is the largest of them, by joint and by root.
    T joint = T(0), root = T(0);
    for (const auto& s : q.seams) {
        joint = std::max(joint, s.joint_ratio);
        root = std::max(root, s.root_ratio);
    }
    CHECK(q.worst.joint_ratio == joint);
    CHECK(q.worst.root_ratio == root);
    CHECK(q.worst.within(T(0.02)));  // the texture's seams are smooth
    CHECK(q.input_skate.median == anima::clip_foot_skate(c, up).median);
    CHECK(q.skate.median == anima::clip_foot_skate(t.motion, up).median);
    CHECK(q.skate.samples > 0);
    // Several inputs pool their contacts, as clip_foot_skate of all of them does.
    const std::vector<anima::clip<T>> two{c, c.slice(0, c.frames() / 2)};
    CHECK(anima::measure_texture(two, t, up).input_skate.median == anima::clip_foot_skate(two, up).median);

    SUBCASE("a pose jump inside a pass is found, at its joint") {
        auto broken = t;
        const std::size_t f = (t.overlap_spans[1].first + t.overlap_spans[1].second) / 2;
        const std::size_t knee = c.skeleton().index_of("lShin");
        const Eigen::Quaternion<T> kick(Eigen::AngleAxis<T>(T(1), Eigen::Matrix<T, 3, 1>::UnitX()));
        broken.motion.set_rotation(f, knee, kick * broken.motion.rotation(f, knee));
        const auto b = anima::measure_texture(c, broken, up);
        CHECK(b.seams[1].joint_ratio > T(2));
        CHECK(b.seams[1].worst_joint == knee);
        CHECK(b.worst.worst_joint == knee);
        CHECK(b.seams[0].joint_ratio == q.seams[0].joint_ratio);  // the other passes as they were
    }
    SUBCASE("refused: no input, or another skeleton") {
        CHECK(contains(invalid_argument_message([&] { (void)anima::measure_texture(std::vector<anima::clip<T>>{}, t); }),
                       "anima::measure_texture: no input clip"));
        CHECK(contains(invalid_argument_message([&] { (void)anima::measure_texture(walk<T>(), t); }),
                       "anima::measure_texture: input 0 is not of the texture's skeleton"));
    }
}

TEST_CASE_TEMPLATE("texton: the loop is at least twice the overlap unless asked otherwise", T, float, double) {
    // 80 frames whose frames 40..59 repeat frames 20..39 (the root going on
    // from where it is): M2 (frames 40..79) overlaps M1 (0..39) perfectly
    // at a = 0, b = 20, a loop of only F - m + a - b = 20 frames, every one
    // of them blended. The swing's period is longer than the clip, so
    // nothing else repeats.
    const auto base = walker<T>(60, 200.0, 0.6);
    anima::clip<T> c(base.skeleton(), 80, base.frame_time());
    const Eigen::Matrix<T, 3, 1> ahead = base.root_position(40) - base.root_position(20);
    for (std::size_t f = 0; f < 80; ++f) {
        const std::size_t from = f < 40 ? f : f - 20;
        for (std::size_t j = 0; j < c.joints(); ++j) {
            c.set_rotation(f, j, base.rotation(from, j));
            if (c.skeleton().translation_slot(j) >= 0) c.set_translation(f, j, base.translation(from, j));
        }
        if (f >= 40) c.set_root_position(f, base.root_position(from) + ahead);
    }
    anima::texton_params<T> p;
    p.m = 40;
    p.overlap = 20;
    p.blend.frames = 10;
    const auto fitted = anima::make_texton(c, p);
    CHECK(fitted.motion.frames() >= 40);
    CHECK(fitted.offset_m2 >= fitted.offset_m1);
    p.min_frames = 20;  // allowed: the perfect, all-blended loop
    const auto short_loop = anima::make_texton(c, p);
    CHECK(short_loop.motion.frames() == 20);
    CHECK(short_loop.offset_m2 == 0);
    CHECK(short_loop.offset_m1 == 20);
    CHECK(short_loop.search_cost < fitted.search_cost);
    p.min_frames = 61;
    CHECK(contains(invalid_argument_message([&] { (void)anima::make_texton(c, p); }),
                   "longest loop a clip of 80 frames allows with an overlap of 20 (60)"));
}

TEST_CASE_TEMPLATE("texture: the root keeps travelling instead of snapping back", T, float, double) {
    const auto c = walker<T>(250, 37.3, 0.4);
    auto p = unplanted<T>();
    p.texton.m = 80;
    p.texton.overlap = 40;
    const auto t = anima::make_motion_texture(c, 1200, p);
    for (std::size_t k = 1; k < t.motion.frames(); ++k) REQUIRE(t.motion.root_position(k).z() > t.motion.root_position(k - 1).z());
    const T per_frame = (c.root_position(c.frames() - 1).z() - c.root_position(0).z()) / T(c.frames() - 1);
    const T travelled = t.motion.root_position(t.motion.frames() - 1).z() - t.motion.root_position(0).z();
    CHECK(travelled == doctest::Approx(per_frame * T(t.motion.frames() - 1)).epsilon(0.05));

    const auto w = walk<T>();
    const auto tw = anima::make_motion_texture(w, 1700, unplanted<T>());
    const auto ground = [](Eigen::Matrix<T, 3, 1> v) {
        v.y() = 0;
        return v.norm();
    };
    const T input_rate = ground(w.root_position(w.frames() - 1) - w.root_position(0)) / T(w.frames() - 1);
    const T texture_rate = ground(tw.motion.root_position(1699) - tw.motion.root_position(0)) / T(1699);
    CHECK(texture_rate > T(0.5) * input_rate);
}

TEST_CASE_TEMPLATE("texture: a clip that turns keeps turning (heading alignment)", T, float, double) {
    const double turn = 0.004;  // rad per frame, 1 rad over the clip
    const auto c = walker<T>(250, 37.3, 0.2, turn);
    auto p = unplanted<T>();
    p.texton.m = 80;
    p.texton.overlap = 40;
    const auto t = anima::make_motion_texture(c, 1200, p);
    CHECK(static_cast<double>(t.texton.heading_turn) == doctest::Approx(turn * static_cast<double>(t.texton.motion.frames())).epsilon(0.1));
    const Eigen::Matrix<T, 3, 1> up(0, 1, 0);
    double total = 0;
    for (std::size_t k = 1; k < t.motion.frames(); ++k) {
        const double step = std::remainder(static_cast<double>(anima::twist_angle(t.motion.rotation(k, 0), up) -
                                                               anima::twist_angle(t.motion.rotation(k - 1, 0), up)),
                                           2 * anima::pi<double>);
        REQUIRE(step > -0.01);  // never turns back
        total += step;
    }
    CHECK(total == doctest::Approx(turn * 1199).epsilon(0.15));
    const auto speeds = anima::seam_speeds(t.motion, t.overlap_spans, anima::clip_speed_limits(c));
    CHECK(worst_joint(speeds) <= T(1.02));
    CHECK(worst_root(speeds) <= T(1.02));

    // Without alignment the figure turns back inside every overlap.
    p.texton.align_heading = false;
    const auto back = anima::make_motion_texture(c, 1200, p);
    CHECK(back.texton.heading_turn == T(0));
    const T net = anima::twist_angle(back.motion.rotation(back.motion.frames() - 1, 0), up) -
                  anima::twist_angle(back.motion.rotation(0, 0), up);
    CHECK(std::abs(static_cast<double>(net)) < 1.2);
}

TEST_CASE_TEMPLATE("texture: symmetric playback mixed in, reproducibly", T, float, double) {
    const auto c = walk<T>();
    auto p = unplanted<T>();
    p.mixing.symmetric = true;
    p.mixing.probability = T(1);
    p.mixing.playback.seed = 7;
    const auto texton = anima::make_texton(c, p.texton);
    const std::size_t n = anima_test::sanitized_build ? 800 : 2400;  // a third under the sanitizers
    const auto t = anima::patch_texton(texton, n, p);
    check_well_formed(t.motion, n);
    CHECK(t.passages > 0);
    CHECK(!t.turns.empty());
    const std::size_t L = texton.motion.frames();
    for (std::size_t k = 1; k < t.stream.size(); ++k) {
        const std::size_t a = t.stream[k - 1], b = t.stream[k];
        REQUIRE((b == (a + 1) % L || a == b + 1));  // forwards around the loop, or backwards in a passage
    }
    for (std::size_t k : t.turns) REQUIRE(k < n);
    const auto speeds = anima::seam_speeds(t.motion, t.overlap_spans, anima::clip_speed_limits(c));
    CHECK(worst_joint(speeds) <= T(1.02));
    CHECK(anima::patch_texton(texton, n, p).stream == t.stream);
    p.mixing.playback.seed = 8;
    CHECK(anima::patch_texton(texton, n, p).stream != t.stream);
    p.mixing.probability = T(0);
    const auto plain = anima::patch_texton(texton, n, p);
    CHECK(plain.passages == 0);
    for (std::size_t k = 0; k < plain.stream.size(); ++k) REQUIRE(plain.stream[k] == k % L);
    p.mixing.probability = T(2);
    CHECK(contains(invalid_argument_message([&] { (void)anima::patch_texton(texton, 10, p); }), "probability"));
}

TEST_CASE_TEMPLATE("texture: every option gives N well-formed frames", T, float, double) {
    const auto c = walker<T>(250, 37.3, 0.4);
    auto base = unplanted<T>();
    base.texton.m = 80;
    base.texton.overlap = 40;
    std::vector<anima::motion_texture_params<T>> variants(9, base);
    variants[0].smoothing.poisson.form = anima::seam_smoothing_form::image;
    variants[1].smoothing.poisson.solver = anima::poisson_method::dst;
    variants[2].texton.blend.enabled = false;
    variants[3].smoothing.enabled = false;
    variants[4].texton.cut.cost.capacity = anima::seam_capacity::exponential;
    variants[5].texton.cut.cost.capacity = anima::seam_capacity::plain;
    variants[6].texton.cut.neighbour_weight = T(0);
    variants[7].root = anima::root_path::in_place;
    variants[8].smoothing.poisson.radius = 3;
    for (const auto& p : variants) {
        const auto t = anima::make_motion_texture(c, 900, p);
        check_well_formed(t.motion, 900);
        const auto speeds = anima::seam_speeds(t.motion, t.overlap_spans, anima::clip_speed_limits(c));
        // Fades alone (no Poisson) may speed a joint up a little.
        CHECK(worst_joint(speeds) <= T(p.smoothing.enabled ? 1.05 : 1.5));
    }
    // A hard cut with Poisson smoothing: the jump is spread, not shown.
    const auto hard = anima::make_motion_texture(c, 900, variants[2]);
    CHECK(hard.texton.blend_frames == 0);
    CHECK(worst_joint(anima::seam_speeds(hard.motion, hard.overlap_spans, anima::clip_speed_limits(c))) <= T(1.05));
}

TEST_CASE_TEMPLATE("seam speeds: limits and ratios by hand", T, float, double) {
    anima::clip<T> c(figure<T>(), 4, T(0.5));
    for (std::size_t f = 0; f < 4; ++f) {
        c.set_rotation(f, 2, Eigen::Quaternion<T>(Eigen::AngleAxis<T>(T(0.1) * T(f * f), Eigen::Matrix<T, 3, 1>::UnitX())));
        c.set_root_position(f, Eigen::Matrix<T, 3, 1>(T(f), 0, 0));
    }
    const auto limits = anima::clip_speed_limits(c);
    CHECK(limits.joint[2] == doctest::Approx(0.5 / 0.5));  // 0.9 - 0.4 rad in 0.5 s
    CHECK(limits.joint[1] == 0);
    CHECK(limits.root == doctest::Approx(2));
    const auto s = anima::seam_speeds(c, {{1, 1}}, limits);
    REQUIRE(s.size() == 1);
    CHECK(s[0].joint_ratio == doctest::Approx(0.6));  // steps 0->1, 1->2: 0.3 rad / 0.5 s of the 1 rad/s limit
    CHECK(s[0].worst_joint == 2);
    CHECK(s[0].root_ratio == doctest::Approx(1));
    CHECK(s[0].within());
    // The worst of several: the largest joint ratio with its joint and span,
    // the largest root ratio wherever it is; zero for none.
    const auto several = anima::seam_speeds(c, {{1, 1}, {2, 2}, {0, 0}}, limits);
    REQUIRE(several.size() == 3);
    const auto worst = anima::worst_seam_speed(several);
    CHECK(worst.joint_ratio == doctest::Approx(1.0));  // steps 1->2, 2->3: 0.5 rad / 0.5 s
    CHECK(worst.worst_joint == 2);
    CHECK(worst.first == 2);
    CHECK(worst.root_ratio == doctest::Approx(1));
    std::vector<anima::seam_speed<T>> made(2);
    made[0].joint_ratio = T(3);
    made[0].worst_joint = 4;
    made[0].root_ratio = T(0.5);
    made[1].joint_ratio = T(2);
    made[1].root_ratio = T(7);
    made[1].first = 9;
    const auto mixed = anima::worst_seam_speed(made);
    CHECK(mixed.joint_ratio == T(3));
    CHECK(mixed.worst_joint == 4);
    CHECK(mixed.first == 0);
    CHECK(mixed.root_ratio == T(7));
    CHECK(anima::worst_seam_speed(std::vector<anima::seam_speed<T>>{}).joint_ratio == T(0));
    CHECK(contains(invalid_argument_message([&] { (void)anima::seam_speeds(c, {{2, 4}}, limits); }), "[2, 4]"));
    anima::speed_limits<T> wrong;
    CHECK(contains(invalid_argument_message([&] { (void)anima::seam_speeds(c, {{0, 1}}, wrong); }), "limits for 0 joints"));
    CHECK(invalid_argument_message([&] { (void)anima::seam_speeds(c, {{1, 1}}, limits, T(-0.5)); }) ==
          "anima::seam_speeds: floor must be non-negative, got -0.5");
}

TEST_CASE_TEMPLATE("texture: a texture larger than max_memory is refused before any work", T, float, double) {
    const auto c = walker<T>(149, 30.0);
    auto p = unplanted<T>();
    p.texton = anima::fit_texton_lengths(p.texton, c.frames());
    // 9 joints, the root translated: 39 scalars and a stream entry a frame.
    const std::size_t frame_bytes = sizeof(T) * 39 + sizeof(std::size_t);
    const std::size_t most = (std::size_t(1) << 30) / frame_bytes;
    const std::string bound = "frames must be at most " + std::to_string(most) + " (" + std::to_string(frame_bytes) +
                              " bytes a frame, max_memory 1024 MiB), got ";
    for (const std::size_t frames : {std::numeric_limits<std::size_t>::max(), std::size_t(1) << 62, most + 1}) {
        CHECK(invalid_argument_message([&] { (void)anima::make_motion_texture(c, frames, p); }) ==
              "anima::make_motion_texture: " + bound + std::to_string(frames));
        CHECK(invalid_argument_message([&] { (void)anima::make_motion_texture(std::vector<anima::clip<T>>{c}, frames, p); }) ==
              "anima::make_motion_texture: " + bound + std::to_string(frames));
    }
    const auto texton = anima::make_texton(c, p.texton);
    CHECK(contains(invalid_argument_message([&] { (void)anima::patch_texton(texton, most + 1, p); }),
                   "anima::patch_texton: " + bound));
    // A smaller limit, and none but the address space.
    p.max_memory = static_cast<double>(3 * frame_bytes);
    CHECK(anima::patch_texton(texton, 3, p).motion.frames() == 3);
    CHECK(contains(invalid_argument_message([&] { (void)anima::patch_texton(texton, 4, p); }), "frames must be at most 3 ("));
    p.max_memory = 0;
    CHECK(contains(invalid_argument_message([&] { (void)anima::make_motion_texture(c, std::size_t(1) << 62, p); }),
                   "bytes a frame, the address space), got 4611686018427387904"));
    p.max_memory = -1;
    CHECK(invalid_argument_message([&] { (void)anima::make_motion_texture(c, 10, p); }) ==
          "anima::make_motion_texture: max_memory must be non-negative, got -1");
}

TEST_CASE_TEMPLATE("seam smoothing: errors name the function called", T, float, double) {
    const matrix<T> two = matrix<T>::Ones(2, 3);
    CHECK(contains(invalid_argument_message([&] { (void)anima::smooth_seams(two, {1}); }),
                   "anima::smooth_seams: the motion has 2 frames"));
    CHECK(contains(invalid_argument_message([&] { (void)anima::smooth_seams(matrix<T>::Ones(5, 3), {0}); }),
                   "anima::smooth_seams: seam at frame 0 is outside 1..4"));
    const anima::clip<T> one(figure<T>(), 1, T(1) / T(30));
    CHECK(contains(invalid_argument_message([&] { (void)anima::smooth_seams(one, {1}); }),
                   "anima::smooth_seams: the motion has 1 frames"));
    const auto c = walker<T>(40, 20.0);
    const auto layout = anima::make_dof_layout(c);
    const matrix<T> m = anima::to_dof_matrix(c, layout);
    CHECK(contains(invalid_argument_message([&] { (void)anima::measure_seam_jump(m, 0, layout); }),
                   "anima::measure_seam_jump: seam at frame 0 is outside 1..39"));
    CHECK(contains(invalid_argument_message([&] { (void)anima::measure_seam_jump(m.topRows(2), 1, layout); }),
                   "anima::measure_seam_jump: the motion has 2 frames"));
    CHECK(contains(invalid_argument_message([&] { (void)anima::seam_target_differences(two, {1}); }),
                   "anima::seam_target_differences: the motion has 2 frames"));
}

}  // namespace

TEST_CASE("make_motion_texture on float mocap with subnormal components: a texture, the caller's mode kept") {
    const auto f = anima::read_bvh<float>(anima_test::bundled("run_cmu_09_01.bvh"));
    anima::motion_texture_params<float> params;
    params.texton.m = 60;
    params.texton.overlap = 30;
    REQUIRE(anima_test::gradual_underflow());
    const auto t = anima::make_motion_texture(f, 300, params);
    CHECK(anima_test::gradual_underflow());
    CHECK(t.motion.frames() == 300);
    bool finite = true;
    for (const auto& q : t.motion.rotations()) finite = finite && q.coeffs().allFinite();
    CHECK(finite);
    const std::vector<anima::clip<float>> clips{f};
    CHECK(anima::make_motion_texture(clips, 300, params).motion.frames() == 300);
    CHECK(anima_test::gradual_underflow());
}
