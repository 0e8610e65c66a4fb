// Poisson seam smoothing of stitched motion: synthetic frames x DOF signals
// with known jumps (the smoothed differences must equal the target, the
// correction must be piecewise linear in time), the paper's 2D form, both
// solvers, a stitched CMU walk, float, and the errors.
#include <anima/bvh/reader.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/dof_view.hpp>
#include <anima/texture/motion_smoothing.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>
#include <string>
#include <vector>

namespace {

using matd = Eigen::MatrixXd;

template <class T>
T tolerance_of() {
    return static_cast<T>(std::is_same_v<T, double> ? 1e-6 : 1e-2);
}

// A smooth motion with steps added from each seam on.
matd stitched(Eigen::Index frames, Eigen::Index dofs, const std::vector<std::size_t>& seams, matd* smooth = nullptr) {
    matd m(frames, dofs);
    for (Eigen::Index c = 0; c < dofs; ++c)
        for (Eigen::Index f = 0; f < frames; ++f)
            m(f, c) = std::sin(0.05 * static_cast<double>(f) * (1 + 0.3 * static_cast<double>(c))) + 0.1 * static_cast<double>(c);
    if (smooth) *smooth = m;
    for (std::size_t k = 0; k < seams.size(); ++k)
        for (Eigen::Index c = 0; c < dofs; ++c)
            m.bottomRows(frames - static_cast<Eigen::Index>(seams[k])).col(c).array() +=
                (k % 2 ? -0.7 : 0.9) * (1 + 0.5 * static_cast<double>(c));
    return m;
}

// The jump at a seam beyond the mean of the neighbouring differences.
double excess_jump(const matd& m, std::size_t seam, Eigen::Index c) {
    const auto s = static_cast<Eigen::Index>(seam);
    const double jump = m(s, c) - m(s - 1, c);
    const double before = m(s - 1, c) - m(s - 2, c), after = m(s + 1, c) - m(s, c);
    return jump - 0.5 * (before + after);
}

}  // namespace

TEST_CASE("seam_target_differences replaces the jumps by the neighbours' trend") {
    const std::vector<std::size_t> seams = {40, 90};
    const matd m = stitched(150, 3, seams);
    const matd d = anima::seam_target_differences(m, seams);
    CHECK(d.rows() == 149);
    for (Eigen::Index k = 0; k < 149; ++k) {
        if (k == 39 || k == 89) continue;
        CHECK((d.row(k) - (m.row(k + 1) - m.row(k))).norm() == 0);
    }
    CHECK((d.row(39) - 0.5 * (d.row(38) + d.row(40))).norm() < 1e-15);
    // radius 2: five differences, linear between the nearest kept ones
    const matd w = anima::seam_target_differences(m, {40}, 2);
    for (Eigen::Index k = 37; k <= 41; ++k) {
        const double t = static_cast<double>(k - 36) / 6.0;
        CHECK((w.row(k) - ((1 - t) * w.row(36) + t * w.row(42))).norm() < 1e-14);
    }
    // A seam at the last frame keeps only its left neighbour.
    const matd e = anima::seam_target_differences(m, {149});
    CHECK((e.row(148) - e.row(147)).norm() == 0);
}

TEST_CASE_TEMPLATE("temporal smoothing removes each jump and keeps every other difference", T, double, float) {
    using mat = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const std::vector<std::size_t> seams = {60, 61, 150};
    const matd md = stitched(220, 4, seams);
    const mat m = md.cast<T>();
    for (auto solver : {anima::poisson_method::multigrid, anima::poisson_method::dst}) {
        CAPTURE(anima::to_string(solver));
        anima::seam_smoothing_params<T> prm;
        prm.solver = solver;
        if (std::is_same<T, double>::value) prm.multigrid.tolerance = T(1e-12);
        const auto out = anima::smooth_seams(m, seams, prm);
        CHECK(out.stats.converged);
        CHECK(out.stats.solves == 4);
        const matd u = out.motion.template cast<double>();
        const matd target = anima::seam_target_differences(md, seams);
        const double tol = std::is_same<T, float>::value ? 2e-3 : 1e-8;
        // First and last frames stay.
        CHECK((out.motion.row(0) - m.row(0)).norm() == 0);
        CHECK((out.motion.row(219) - m.row(219)).norm() == 0);
        // The correction u - m is linear between seams: its differences are
        // the target's minus the motion's plus one constant per DOF.
        const matd du = u.bottomRows(219) - u.topRows(219);
        for (Eigen::Index c = 0; c < 4; ++c) {
            const double drift = du(0, c) - target(0, c);
            for (Eigen::Index k = 0; k < 219; ++k) CHECK(std::abs(du(k, c) - target(k, c) - drift) < tol);
            CHECK(std::abs(excess_jump(md, 150, c)) > 0.5);
            CHECK(std::abs(excess_jump(u, 150, c)) < 10 * tol);
        }
    }
}

TEST_CASE("without seams the motion comes back unchanged, in both forms") {
    matd m = stitched(90, 5, {});
    for (auto form : {anima::seam_smoothing_form::temporal, anima::seam_smoothing_form::image})
        for (auto sides : {anima::boundary::neumann, anima::boundary::dirichlet}) {
            anima::seam_smoothing_params<double> prm;
            prm.form = form;
            prm.dof_sides = sides;
            prm.multigrid.tolerance = 1e-12;
            CHECK((anima::smooth_seams(m, {}, prm).motion - m).cwiseAbs().maxCoeff() < 1e-9);
            prm.solver = anima::poisson_method::dst;
            CHECK((anima::smooth_seams(m, {}, prm).motion - m).cwiseAbs().maxCoeff() < 1e-9);
        }
}

TEST_CASE("the 2D form: one DOF is the 1D form, several DOFs share their jumps") {
    const std::vector<std::size_t> seams = {70};
    anima::seam_smoothing_params<double> one_d, two_d;
    two_d.form = anima::seam_smoothing_form::image;
    one_d.multigrid.tolerance = two_d.multigrid.tolerance = 1e-12;
    const matd single = stitched(160, 1, seams);
    CHECK((anima::smooth_seams(single, seams, two_d).motion - anima::smooth_seams(single, seams, one_d).motion)
              .cwiseAbs()
              .maxCoeff() < 1e-9);

    const matd m = stitched(160, 6, seams);
    const auto mg = anima::smooth_seams(m, seams, two_d);
    CHECK(mg.stats.solves == 1);
    CHECK(mg.stats.converged);
    auto fast_prm = two_d;
    fast_prm.solver = anima::poisson_method::dst;
    CHECK((anima::smooth_seams(m, seams, fast_prm).motion - mg.motion).cwiseAbs().maxCoeff() < 1e-8);
    for (Eigen::Index c = 0; c < 6; ++c) CHECK(std::abs(excess_jump(mg.motion, 70, c)) < std::abs(excess_jump(m, 70, c)));
    // The paper's zero padding on the DOF sides also solves.
    two_d.dof_sides = anima::boundary::dirichlet;
    CHECK(anima::smooth_seams(m, seams, two_d).stats.converged);
}

TEST_CASE("a stitched CMU walk is smoothed at the seam and kept elsewhere") {
    const auto walk = anima::read_bvh<double>(std::string(ANIMA_TEST_DATA_DIR) + "/walk_cmu31_02_01.bvh");
    REQUIRE(walk.frames() > 300);
    auto c = walk.slice(0, 120);
    c.append(walk.slice(200, 330));  // a jump in pose and root position at frame 120
    const auto out = anima::smooth_seams(c, {120});
    CHECK(out.stats.converged);
    CHECK(out.motion.frames() == c.frames());
    const auto layout = anima::make_dof_layout(c);
    const matd before = anima::to_dof_matrix(c, layout);
    const matd after = anima::to_dof_matrix(out.motion, layout);
    double worst_before = 0, worst_after = 0;
    for (Eigen::Index d = 0; d < before.cols(); ++d) {
        worst_before = std::max(worst_before, std::abs(excess_jump(before, 120, d)));
        worst_after = std::max(worst_after, std::abs(excess_jump(after, 120, d)));
    }
    CHECK(worst_before > 1.0);
    CHECK(worst_after < 1e-6);
    // measure_seam_jump: the same excess, split by kind of DOF.
    double rotation = 0, translation = 0;
    std::size_t worst = 0;
    for (Eigen::Index d = 0; d < before.cols(); ++d) {
        const double e = std::abs(excess_jump(before, 120, d));
        if (layout.dofs[static_cast<std::size_t>(d)].type == anima::dof::kind::translation) {
            translation = std::max(translation, e);
        } else if (e > rotation) {
            rotation = e;
            worst = static_cast<std::size_t>(d);
        }
    }
    const auto jump = anima::measure_seam_jump(before, 120, layout);
    CHECK(jump.rotation == doctest::Approx(rotation).epsilon(1e-12));
    CHECK(jump.worst_rotation_dof == worst);
    CHECK(jump.translation == doctest::Approx(translation).epsilon(1e-12));
    CHECK(translation > 0);
    const auto smoothed = anima::measure_seam_jump(after, 120, layout);
    CHECK(smoothed.rotation < 1e-6);
    CHECK(smoothed.translation < 1e-6);
    CHECK_THROWS_AS(anima::measure_seam_jump(before.leftCols(5), 120, layout), anima::invalid_argument);
    CHECK_THROWS_AS(anima::measure_seam_jump(before, 0, layout), anima::invalid_argument);
    // The end frames are the input's.
    for (std::size_t j = 0; j < c.joints(); ++j) {
        CHECK(c.rotation(0, j).angularDistance(out.motion.rotation(0, j)) < 1e-9);
        CHECK(c.rotation(249, j).angularDistance(out.motion.rotation(249, j)) < 1e-9);
    }
    CHECK((c.root_position(0) - out.motion.root_position(0)).norm() < 1e-9);
}

TEST_CASE_TEMPLATE("measure_smoothing: each seam's jump before and after, and the largest change", T, double, float) {
    using mat = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const auto walk = anima::read_bvh<T>(std::string(ANIMA_TEST_DATA_DIR) + "/walk_cmu31_02_01.bvh");
    auto c = walk.slice(0, 120);
    c.append(walk.slice(200, 260));
    c.append(walk.slice(60, 120));  // jumps at frames 120 and 180
    const auto out = anima::smooth_seams(c, {180, 120});
    // Seams given out of order and twice are measured once each, in order.
    const auto m = anima::measure_smoothing(c, out.motion, {180, 120, 180});
    REQUIRE(m.seams == std::vector<std::size_t>{120, 180});
    REQUIRE(m.before.size() == 2);
    REQUIRE(m.after.size() == 2);
    const auto layout = anima::make_dof_layout(c);
    const mat before = anima::to_dof_matrix(c, layout), after = anima::to_dof_matrix(out.motion, layout);
    for (std::size_t i = 0; i < 2; ++i) {
        CAPTURE(m.seams[i]);
        const auto b = anima::measure_seam_jump(before, m.seams[i], layout);
        const auto a = anima::measure_seam_jump(after, m.seams[i], layout);
        CHECK(m.before[i].rotation == b.rotation);
        CHECK(m.before[i].worst_rotation_dof == b.worst_rotation_dof);
        CHECK(m.before[i].translation == b.translation);
        CHECK(m.after[i].rotation == a.rotation);
        CHECK(m.after[i].translation == a.translation);
        // Smoothing takes the jump out.
        CHECK(m.before[i].rotation > T(0.1));
        CHECK(m.after[i].rotation < T(0.01) * m.before[i].rotation);
    }
    const auto change = anima::largest_dof_change(before, after, layout);
    CHECK(m.largest_change.rotation == change.rotation);
    CHECK(m.largest_change.translation == change.translation);
    CHECK(m.largest_change.rotation > 0);
    CHECK(m.layout.size() == layout.size());
    // A clip against itself: nothing changed, the jumps are the same.
    const auto same = anima::measure_smoothing(c, c, {120});
    CHECK(same.largest_change.rotation == 0);
    CHECK(same.largest_change.translation == 0);
    CHECK(same.before[0].rotation == same.after[0].rotation);
    // Refused: other lengths, a seam outside, a clip too short.
    CHECK_THROWS_WITH_AS(anima::measure_smoothing(c, c.slice(0, 100), {50}),
                         doctest::Contains("anima::measure_smoothing"), anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::measure_smoothing(c, c, {c.frames()}), doctest::Contains("outside 1.."),
                         anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::measure_smoothing(c.slice(0, 2), c.slice(0, 2), {1}), doctest::Contains("at least 3"),
                         anima::invalid_argument);
}

TEST_CASE("smooth_seams rejects bad input") {
    const matd m = stitched(50, 2, {});
    CHECK_THROWS_WITH_AS(anima::smooth_seams(m, {0}), doctest::Contains("seam at frame 0"), anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::smooth_seams(m, {50}), doctest::Contains("outside 1..49"), anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::smooth_seams(matd(matd::Zero(2, 3)), {1}), doctest::Contains("at least 3"),
                         anima::invalid_argument);
    matd nan = m;
    nan(10, 1) = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_WITH_AS(anima::smooth_seams(nan, {20}), doctest::Contains("motion(10, 1) is not finite"),
                         anima::invalid_argument);
    anima::seam_smoothing_params<double> prm;
    prm.form = anima::seam_smoothing_form::image;
    prm.dof_spacing = 0;
    CHECK_THROWS_WITH_AS(anima::smooth_seams(m, {20}, prm), doctest::Contains("dof_spacing"), anima::invalid_argument);
    CHECK(anima::parse_seam_smoothing_form("2d") == anima::seam_smoothing_form::image);
    CHECK(anima::parse_poisson_method("dst") == anima::poisson_method::dst);
    CHECK_THROWS_AS(anima::parse_seam_smoothing_form("3d"), anima::invalid_argument);
    CHECK_THROWS_AS(anima::parse_poisson_method("cg"), anima::invalid_argument);
}

TEST_CASE_TEMPLATE("a radius beyond the clip (up to SIZE_MAX) replaces every difference, without wrapping", T, double, float) {
    using mat = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const mat m = stitched(60, 2, {20, 40}).template cast<T>();
    const mat whole = anima::seam_target_differences(m, {20, 40}, 59);
    for (const std::size_t radius : {std::size_t{60}, std::size_t{1000}, std::numeric_limits<std::size_t>::max() - 3,
                                     std::numeric_limits<std::size_t>::max()})
        CHECK(anima::seam_target_differences(m, {20, 40}, radius) == whole);
    // Every difference replaced, no kept row on either side: zero targets.
    CHECK(whole.isZero());
    anima::seam_smoothing_params<T> prm;
    prm.radius = std::numeric_limits<std::size_t>::max();
    const auto r = anima::smooth_seams(m, {20, 40}, prm);
    CHECK(r.motion.allFinite());
    // The first and last frames are kept, and the rest lies between them (a straight line).
    CHECK(r.motion.row(0) == m.row(0));
    CHECK(r.motion.row(59) == m.row(59));
    for (Eigen::Index f = 0; f < 60; ++f)
        for (Eigen::Index c = 0; c < 2; ++c) {
            const T lo = std::min(m(0, c), m(59, c)), hi = std::max(m(0, c), m(59, c));
            CHECK(r.motion(f, c) >= lo - tolerance_of<T>());
            CHECK(r.motion(f, c) <= hi + tolerance_of<T>());
        }
}
