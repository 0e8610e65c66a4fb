// Textons and textures of several clips: one clip through the several-clip
// form is the one-clip texton; a clip cut in two overlapping parts is
// joined where the parts coincide, and the loop through it is the clip
// again; three different clips are laid end to end with every piece in
// its place and turned to the heading before it; the seams between clips
// are smoothed and planted like the loop's own; clips that do not fit are
// refused by name; the least-cost order is the brute-force one, and puts
// shuffled parts of a clip back in recorded order.
#include "texture_test_support.hpp"

#include <anima/bvh/reader.hpp>
#include <anima/core/error.hpp>
#include <anima/core/random.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/contacts.hpp>
#include <anima/motion/speed_limits.hpp>
#include <anima/rotation/quaternion.hpp>
#include <anima/rotation/swing_twist.hpp>
#include <anima/texture/clip_order.hpp>
#include <anima/texture/motion_texture.hpp>
#include <anima/texture/seam_speed.hpp>
#include <anima/texture/texton.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using namespace texture_test;

// Largest angle between the non-root joints of texton frame k and source frame f.
template <class T>
T pose_gap(const anima::clip<T>& texton, std::size_t k, const anima::clip<T>& source, std::size_t f) {
    T worst = T(0);
    for (std::size_t j = 1; j < source.joints(); ++j)
        worst = std::max(worst, anima::angle_between(texton.rotation(k, j), source.rotation(f, j)));
    return worst;
}

TEST_CASE_TEMPLATE("texton of several clips: one clip is the one-clip texton", T, float, double) {
    const auto c = walker<T>(230, 37.3, 1.5, 0.004);
    anima::texton_params<T> p;
    p.m = 60;
    p.overlap = 30;
    const auto one = anima::make_texton(c, p);
    const auto many = anima::make_texton(std::vector<anima::clip<T>>{c}, p);
    CHECK(many.clips == 1);
    CHECK(many.joins.empty());
    CHECK(many.offset_m2 == one.offset_m2);
    CHECK(many.offset_m1 == one.offset_m1);
    CHECK(many.search_cost == one.search_cost);
    CHECK(many.heading_turn == one.heading_turn);
    CHECK(many.cut.seam == one.cut.seam);
    REQUIRE(many.motion.frames() == one.motion.frames());
    for (std::size_t k = 0; k < one.motion.frames(); ++k)
        for (std::size_t j = 0; j < c.joints(); ++j) REQUIRE(many.motion.rotation(k, j).coeffs() == one.motion.rotation(k, j).coeffs());
    CHECK(many.fade_correction == one.fade_correction);
    const auto seams = one.seams();
    REQUIRE(seams.size() == 1);
    CHECK(seams[0].from == 0);
    CHECK(seams[0].to == 0);
    CHECK(seams[0].overlap_start == one.overlap_start);
    CHECK(seams[0].heading_turn == one.heading_turn);
    for (std::size_t r = 0; r < one.rows(); ++r) CHECK(seams[0].blend_centre(r) == one.blend_centre(r));
}

TEST_CASE_TEMPLATE("texton of several clips: a clip cut in two is joined where the parts coincide", T, float, double) {
    // The bundled CMU walk as two overlapping parts: A = frames 0..229, B =
    // frames 110..end. A's M2 (frames 130..229) and B's M1 (110..209)
    // share frames 130..209: A's frame 130 + a is B's frame a + 20.
    const auto c = walk<T>();
    REQUIRE(c.frames() > 330);
    const std::size_t split = 230, resume = 110;
    const auto a = c.slice(0, split), b = c.slice(resume, c.frames());
    anima::texton_params<T> p;
    p.m = 100;
    p.overlap = 50;
    const auto x = anima::make_texton(std::vector<anima::clip<T>>{a, b}, p);
    CHECK(x.clips == 2);
    REQUIRE(x.joins.size() == 1);
    const auto& join = x.joins[0];
    CHECK(join.from == 0);
    CHECK(join.to == 1);
    CHECK(join.offset_b == join.offset_a + (split - p.m - resume));
    CHECK(join.search_cost < T(1e-3) * x.search_costs.mean());
    CHECK(std::abs(join.heading_turn) < T(1e-4));
    // The loop is the walk again from frame m up to the closing seam: the
    // join blends two copies of the same frames.
    const T tol = tolerance<T>(1e-9, 1e-4);
    for (std::size_t k = 0; k < x.overlap_start; ++k) REQUIRE(pose_gap(x.motion, k, c, p.m + k) < tol);
    CHECK(x.motion.frames() == x.overlap_start + p.overlap + (p.m - x.offset_m1 - p.overlap));
    const auto seams = x.seams();
    REQUIRE(seams.size() == 2);
    CHECK(seams[1].from == 1);
    CHECK(seams[1].to == 0);
    CHECK(seams[0].heading_turn + seams[1].heading_turn == doctest::Approx(static_cast<double>(x.heading_turn)));
}

TEST_CASE_TEMPLATE("texton of several clips: every piece is in its place, turned to the heading before it", T, float,
                   double) {
    // Three different walks (periods, growth, one turning): the texton must
    // be clip 0 from frame m, the join into clip 1, clip 1's own frames,
    // the join into clip 2, clip 2's own frames, the closing seam, clip 0's
    // frames up to m.
    const std::vector<anima::clip<T>> clips{walker<T>(200, 37.3, 0.5), walker<T>(260, 41.0, 0.2, 0.006),
                                            walker<T>(180, 33.5, 0.8)};
    anima::texton_params<T> p;
    p.m = 70;
    p.overlap = 30;
    const auto x = anima::make_texton(clips, p);
    REQUIRE(x.clips == 3);
    const auto seams = x.seams();
    REQUIRE(seams.size() == 3);
    const std::size_t n = p.overlap, m = p.m;
    const T tol = tolerance<T>(1e-9, 1e-4);
    // Clip 0 from frame m to the first overlap.
    CHECK(seams[0].overlap_start == clips[0].frames() - 2 * m + seams[0].offset_a);
    for (std::size_t k = 0; k < seams[0].overlap_start; ++k) REQUIRE(pose_gap(x.motion, k, clips[0], m + k) < tol);
    T turn = T(0);
    for (std::size_t i = 0; i < 3; ++i) {
        const auto& s = seams[i];
        const std::size_t next = (i + 1) % 3;
        CHECK(s.from == i);
        CHECK(s.to == next);
        turn += s.heading_turn;
        // After the overlap: the next clip's own frames, from b + n up to
        // the next seam's overlap (or to frame m of clip 0).
        const std::size_t first = s.overlap_start + n;
        const std::size_t last = i + 1 < 3 ? seams[i + 1].overlap_start : x.motion.frames();
        if (i + 1 < 3) CHECK(last - first == clips[next].frames() - m + seams[i + 1].offset_a - s.offset_b - n);
        else CHECK(last - first == m - s.offset_b - n);
        const Eigen::Matrix<T, 3, 1> up(0, 1, 0);
        for (std::size_t k = first; k < last; ++k) {
            const std::size_t f = s.offset_b + n + (k - first);
            REQUIRE(pose_gap(x.motion, k, clips[next], f) < tol);
            // The root: the source's, turned by every seam so far.
            const Eigen::Quaternion<T> expected = Eigen::Quaternion<T>(Eigen::AngleAxis<T>(turn, up)) * clips[next].rotation(f, 0);
            REQUIRE(anima::angle_between(x.motion.rotation(k, 0), expected) < tol);
        }
        // Every row switches inside its overlap.
        for (std::size_t r = 0; r < x.rows(); ++r) CHECK(s.seam_frame(r) < s.overlap_start + n);
    }
    CHECK(static_cast<double>(turn) == doctest::Approx(static_cast<double>(x.heading_turn)).epsilon(1e-4));
    CHECK(std::abs(x.heading_turn) > T(0.01));  // clip 1 turns: the loop does
    // The legs are kept within the fastest of the clips.
    for (std::size_t j = 0; j < clips[0].joints(); ++j) {
        T fastest = T(0);
        for (const auto& c : clips) fastest = std::max(fastest, anima::clip_speed_limits(c).joint[j]);
        CHECK(x.source_speeds.joint[j] == fastest);
    }
}

TEST_CASE_TEMPLATE("texture of several clips: the joins are smoothed and planted like the loop's seam", T, float, double) {
    const auto c = walk<T>();
    // The walk's first 200 frames and the rest, as two clips: the join
    // has to find where the end of the first steps into the second.
    const auto a = c.slice(0, 200), b = c.slice(200, c.frames());
    auto p = unplanted<T>();
    p.texton.m = 70;
    p.texton.overlap = 30;
    const std::size_t frames = anima_test::sanitized_build ? 500 : 1200;
    const auto t = anima::make_motion_texture(std::vector<anima::clip<T>>{a, b}, frames, p);
    REQUIRE(t.motion.frames() == frames);
    const auto seams = t.texton.seams();
    REQUIRE(seams.size() == 2);
    // Every pass over a join's fade centre is a seam of the smoothing.
    std::size_t join_crossings = 0;
    for (std::size_t r = 0; r < t.texton.rows(); ++r) {
        const std::size_t centre = seams[0].blend_centre(r);
        for (std::size_t k = 1; k < frames; ++k)
            if (t.stream[k - 1] + 1 == centre && t.stream[k] == centre) {
                ++join_crossings;
                REQUIRE(std::find(t.row_seams[r].begin(), t.row_seams[r].end(), k) != t.row_seams[r].end());
            }
    }
    CHECK(join_crossings >= t.texton.rows());
    // The passes over both overlaps are spans (the planting ranges).
    std::size_t join_frames = 0;
    for (const auto& [first, last] : t.overlap_spans)
        for (std::size_t k = first; k <= last; ++k)
            if (t.stream[k] >= seams[0].overlap_start && t.stream[k] < seams[0].overlap_start + seams[0].overlap) ++join_frames;
    CHECK(join_frames >= seams[0].overlap);
    // Seams stay within the clips' own speeds.
    const auto speeds = anima::seam_speeds(t.motion, t.overlap_spans, t.texton.source_speeds);
    for (const auto& s : speeds) {
        CHECK(s.joint_ratio <= T(1.02));
        CHECK(s.root_ratio <= T(1.02));
    }
    for (std::size_t f = 0; f < frames; ++f)
        for (std::size_t j = 0; j < t.motion.joints(); ++j) REQUIRE(t.motion.rotation(f, j).coeffs().allFinite());
}

TEST_CASE_TEMPLATE("texture of two bundled runs of two subjects: seams within their speeds, feet planted", T, float,
                   double) {
    // The Daz-layout runs of subjects 9 and 2 without their T-pose and the
    // frames that swing out of it.
    const auto a = run<T>();
    const auto full = anima::read_bvh<T>(bundled("run_cmu_02_03.bvh"));
    const auto b = full.slice(6, full.frames());
    const std::vector<anima::clip<T>> runs{a, b};
    anima::motion_texture_params<T> p;
    p.texton = anima::fit_texton_lengths(p.texton, std::min(a.frames(), b.frames()));
    // Planting runs unoptimised in float in this unit, and a sixth of it
    // under the sanitizers: fewer frames there.
    const std::size_t frames = anima_test::sanitized_build ? 300 : std::is_same_v<T, float> ? 400 : 1200;
    const auto t = anima::make_motion_texture(runs, frames, p);
    REQUIRE(t.motion.frames() == frames);
    REQUIRE(t.texton.joins.size() == 1);
    CHECK(t.planted_runs > 0);
    for (std::size_t f = 0; f < frames; ++f)
        for (std::size_t j = 0; j < t.motion.joints(); ++j) {
            REQUIRE(t.motion.rotation(f, j).coeffs().allFinite());
            REQUIRE(std::abs(t.motion.rotation(f, j).norm() - T(1)) < tolerance<T>(1e-9, 1e-4));
        }
    // No seam faster than the faster run; less foot skate than the runs.
    const auto speeds = anima::seam_speeds(t.motion, t.overlap_spans, t.texton.source_speeds);
    REQUIRE(speeds.size() >= 2);
    for (const auto& s : speeds) {
        CHECK(s.joint_ratio <= T(1.02));
        CHECK(s.root_ratio <= T(1.02));
    }
    const T input_skate = anima::clip_foot_skate(runs).median, output_skate = anima::clip_foot_skate(t.motion).median;
    MESSAGE("two runs: texture skate / inputs' " << output_skate / input_skate);
    CHECK(output_skate < input_skate);
}

TEST_CASE_TEMPLATE("texton of several clips: clips that do not fit are refused by name", T, float, double) {
    anima::texton_params<T> p;
    p.m = 60;
    p.overlap = 30;
    const auto c = walker<T>(200, 37.3);
    CHECK(contains(invalid_argument_message([&] { anima::make_texton(std::vector<anima::clip<T>>{}, p); }), "no clips"));
    // Another hierarchy.
    anima::skeleton<T> other;
    for (std::size_t j = 0; j < c.joints(); ++j) {
        const auto& joint = c.skeleton()[j];
        other.add_joint(j == 4 ? "leftKnee" : joint.name, joint.parent, joint.offset, joint.channels);
    }
    anima::clip<T> renamed(other, c.frames(), c.frame_time());
    for (std::size_t f = 0; f < c.frames(); ++f)
        for (std::size_t j = 0; j < c.joints(); ++j) renamed.set_rotation(f, j, c.rotation(f, j));
    std::string e = invalid_argument_message([&] { anima::make_texton(std::vector<anima::clip<T>>{c, renamed}, p); });
    CHECK(contains(e, "clip 1"));
    CHECK(contains(e, "leftKnee"));
    // Another frame time.
    anima::clip<T> slower(c.skeleton(), c.frames(), c.frame_time() * T(2));
    e = invalid_argument_message([&] { anima::make_texton(std::vector<anima::clip<T>>{c, c, slower}, p); });
    CHECK(contains(e, "clip 2"));
    CHECK(contains(e, "frame time"));
    // Too short for m.
    e = invalid_argument_message([&] { anima::make_texton(std::vector<anima::clip<T>>{c, c.slice(0, 100)}, p); });
    CHECK(contains(e, "clip 1"));
    CHECK(contains(e, "m = 60"));
    // A loop shorter than asked for.
    p.min_frames = 10000;
    e = invalid_argument_message([&] { anima::make_texton(std::vector<anima::clip<T>>{c, c}, p); });
    CHECK(contains(e, "min_frames = 10000"));
}

}  // namespace

namespace {

TEST_CASE_TEMPLATE("clip order: Held-Karp finds the brute-force least-cost loop", T, float, double) {
    anima::random_source rng(11);
    for (std::size_t n = 1; n <= 8; ++n) {
        CAPTURE(n);
        matrix<T> costs(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
        for (Eigen::Index i = 0; i < costs.rows(); ++i)
            for (Eigen::Index j = 0; j < costs.cols(); ++j) costs(i, j) = i == j ? T(0) : static_cast<T>(rng.uniform());
        const auto order = anima::detail::least_cost_cycle(costs);
        REQUIRE(order.size() == n);
        CHECK(order[0] == 0);
        std::vector<std::size_t> sorted = order;
        std::sort(sorted.begin(), sorted.end());
        for (std::size_t i = 0; i < n; ++i) CHECK(sorted[i] == i);
        // Every loop from node 0, by brute force.
        std::vector<std::size_t> p(n);
        for (std::size_t i = 0; i < n; ++i) p[i] = i;
        T least = std::numeric_limits<T>::infinity();
        do least = std::min(least, anima::detail::cycle_cost(costs, p));
        while (std::next_permutation(p.begin() + 1, p.end()));
        CHECK(anima::detail::cycle_cost(costs, order) <= least * (T(1) + tolerance<T>(1e-12, 1e-6)));
    }
}

TEST_CASE_TEMPLATE("clip order: shuffled overlapping parts of a clip are put back in recorded order", T, float, double) {
    // Parts A = 0..149, B = 100..249, C = 200..349, D = 300..449 of a walk
    // of period 37.3 frames: A's last 50 frames are B's first 50, B's last
    // C's first, C's last D's first; only D -> A is a real seam, and every
    // other loop has two or more. Given as C, A, D, B, the loop from C must
    // be C, D, A, B.
    const auto c = walker<T>(450, 37.3);
    const std::vector<anima::clip<T>> parts{c.slice(200, 350), c.slice(0, 150), c.slice(300, 450), c.slice(100, 250)};
    anima::texton_params<T> p;
    p.m = 50;
    p.overlap = 25;
    const auto order = anima::least_cost_clip_order(parts, p);
    CHECK(order.order == std::vector<std::size_t>{0, 2, 1, 3});
    CHECK(order.cost < order.given_cost);
    const T scale = order.costs.sum() / static_cast<T>(12);
    CHECK(order.costs(0, 2) < T(1e-3) * scale);  // C -> D
    CHECK(order.costs(1, 3) < T(1e-3) * scale);  // A -> B
    CHECK(order.costs(3, 0) < T(1e-3) * scale);  // B -> C
    CHECK(order.costs(2, 1) > T(0.05) * scale);  // D -> A: the one real seam
    // The texton in that order joins the parts where they coincide.
    std::vector<anima::clip<T>> ordered;
    for (const std::size_t i : order.order) ordered.push_back(parts[i]);
    const auto x = anima::make_texton(ordered, p);
    REQUIRE(x.joins.size() == 3);
    CHECK(x.joins[0].search_cost < T(1e-3) * scale);  // C -> D
    // D -> A, the search's own cost (to rounding: the pooled variances are
    // summed over the clips in another order).
    CHECK(static_cast<double>(x.joins[1].search_cost) ==
          doctest::Approx(static_cast<double>(order.costs(2, 1))).epsilon(tolerance<T>(1e-12, 1e-5)));
    CHECK(x.joins[2].search_cost < T(1e-3) * scale);  // A -> B
    CHECK(x.search_cost < T(1e-3) * scale);           // B -> C closes the loop
    // Refused: clips make_texton refuses, and more than the exact search takes.
    const std::string none = invalid_argument_message([&] { anima::least_cost_clip_order(std::vector<anima::clip<T>>{}, p); });
    CHECK(contains(none, "anima::least_cost_clip_order"));
    CHECK(contains(none, "no clips"));
    const std::vector<anima::clip<T>> many(anima::max_ordered_clips + 1, parts[0]);
    CHECK(contains(invalid_argument_message([&] { anima::least_cost_clip_order(many, p); }), "at most 16"));
}

}  // namespace
