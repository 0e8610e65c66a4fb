// Stick figures: the view bases are right-handed and put the figure's left
// where each view says, and the projected bones (and the pose's bounding
// diagonal) match values worked out by hand for a small skeleton posed by
// hand, as do all frames' joint and End Site positions.
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/stick_figure.hpp>

#include <doctest/doctest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <vector>

namespace {

using anima::body_side;
using anima::signed_axis;

TEST_CASE_TEMPLATE("make_stick_view: front shows the left on the right, side faces right, top looks down", T, float,
                   double) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    const signed_axis up{anima::axis::y, 1}, left{anima::axis::x, 1};
    const auto front = anima::make_stick_view<T>(anima::stick_view::front, up, left);
    CHECK(front.right == vec3(1, 0, 0));
    CHECK(front.up == vec3(0, 1, 0));
    CHECK(front.toward == vec3(0, 0, 1));  // left x up: the figure faces +Z, toward the viewer
    CHECK(front.vertical);
    const auto side = anima::make_stick_view<T>(anima::stick_view::side, up, left);
    CHECK(side.right == vec3(0, 0, 1));
    CHECK(side.toward == vec3(-1, 0, 0));  // seen from the figure's right
    const auto top = anima::make_stick_view<T>(anima::stick_view::top, up, left);
    CHECK(top.right == vec3(-1, 0, 0));
    CHECK(top.up == vec3(0, 0, 1));
    CHECK(top.toward == vec3(0, 1, 0));
    CHECK_FALSE(top.vertical);
    // Every basis is orthonormal and right-handed (right x up = toward).
    for (const auto view : {anima::stick_view::front, anima::stick_view::side, anima::stick_view::top})
        for (const signed_axis u : {signed_axis{anima::axis::z, 1}, signed_axis{anima::axis::y, -1}}) {
            const signed_axis l{u.axis == anima::axis::x ? anima::axis::y : anima::axis::x, -1};
            const auto b = anima::make_stick_view<T>(view, u, l);
            CHECK((b.right.cross(b.up) - b.toward).norm() < T(1e-6));
        }
    CHECK_THROWS_AS(anima::make_stick_view<T>(anima::stick_view::front, up, signed_axis{anima::axis::y, -1}),
                    anima::invalid_argument);
    CHECK(anima::parse_stick_view("side") == anima::stick_view::side);
    CHECK_THROWS_AS(anima::parse_stick_view("back"), anima::invalid_argument);
}

/// Hips at (1, 2, 3) in frame 1 (the origin in frame 0); LeftLeg 1 below
/// and 0.5 to the left (+X), with an End Site 1 further down; RightArm 1 to
/// the right (-X), no End Site. Frame 1: the hips turn 90 degrees about +Y,
/// +X going to -Z.
template <class T>
anima::clip<T> posed_clip() {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    using anima::channel;
    anima::skeleton<T> sk;
    sk.add_joint("Hips", -1, vec3(0, 0, 0),
                 {channel::x_position, channel::y_position, channel::z_position, channel::z_rotation,
                  channel::x_rotation, channel::y_rotation});
    sk.add_joint("LeftLeg", 0, vec3(T(0.5), -1, 0));
    sk.set_end_site(1, vec3(0, -1, 0));
    sk.add_joint("RightArm", 0, vec3(-1, 0, 0));
    anima::clip<T> c(sk, 2, T(1) / 30);
    c.set_translation(1, 0, vec3(1, 2, 3));
    c.set_rotation(1, 0, Eigen::Quaternion<T>(Eigen::AngleAxis<T>(T(std::acos(-1.0) / 2), vec3::UnitY())));
    return c;
}

TEST_CASE_TEMPLATE("project_stick_figure matches hand-worked coordinates", T, float, double) {
    const anima::clip<T> c = posed_clip<T>();
    const auto bones = anima::stick_bones(c.skeleton());
    REQUIRE(bones.size() == 3);
    CHECK((bones[0].from == 0 && bones[0].to == 1 && !bones[0].end_site && bones[0].side == body_side::left));
    CHECK((bones[1].from == 1 && bones[1].to == 1 && bones[1].end_site && bones[1].side == body_side::left));
    CHECK((bones[2].from == 0 && bones[2].to == 2 && bones[2].side == body_side::right));

    const signed_axis up{anima::axis::y, 1}, left{anima::axis::x, 1};
    const auto front = anima::make_stick_view<T>(anima::stick_view::front, up, left);
    const auto s = anima::project_stick_figure(c, 1, bones, front);
    REQUIRE(s.size() == 3);
    // Root-relative across, absolute up: hips (0, 2); LeftLeg at (1, 1, 3 - 0.5)
    // -> (0, 1), depth of the bone (3 + 2.5) / 2; its End Site (0, 0).
    const T eps = T(1e-5);
    CHECK(std::abs(s[0].x1) < eps);
    CHECK(s[0].y1 == doctest::Approx(2).epsilon(1e-5));
    CHECK(std::abs(s[0].x2) < eps);
    CHECK(s[0].y2 == doctest::Approx(1).epsilon(1e-5));
    CHECK(s[0].depth == doctest::Approx(2.75).epsilon(1e-5));
    CHECK(s[0].length == doctest::Approx(std::sqrt(1.25)).epsilon(1e-5));
    CHECK(s[1].y2 == doctest::Approx(0).epsilon(1e-5));
    CHECK(s[1].length == doctest::Approx(1).epsilon(1e-5));
    // RightArm: -X turned to +Z: (1, 2, 4), straight toward the viewer.
    CHECK(std::abs(s[2].x2) < eps);
    CHECK(s[2].depth == doctest::Approx(3.5).epsilon(1e-5));
    CHECK(s[2].side == body_side::right);
    // The top view keeps the root at the origin in both directions.
    const auto top = anima::project_stick_figure(c, 1, bones, anima::make_stick_view<T>(anima::stick_view::top, up, left));
    CHECK(std::abs(top[0].x1) < eps);
    CHECK(std::abs(top[0].y1) < eps);
    CHECK(top[2].y2 == doctest::Approx(1).epsilon(1e-5));  // +Z, the way a figure with its left at +X faces: up the page

    CHECK_THROWS_AS(anima::project_stick_figure(c, 2, bones, front), anima::invalid_argument);
    CHECK_THROWS_AS(anima::project_stick_figure(c, 0, {anima::stick_bone{0, 3, false, body_side::centre}}, front),
                    anima::invalid_argument);
}

TEST_CASE_TEMPLATE("global_points: every frame's joints, then End Sites, at hand-worked positions", T, float, double) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    const anima::clip<T> c = posed_clip<T>();
    const anima::clip_points<T> pts = anima::global_points(c);
    constexpr std::size_t none = anima::clip_points<T>::npos;
    CHECK(pts.per_frame == 4);
    CHECK(pts.end_site_point == std::vector<std::size_t>{none, 3, none});
    REQUIRE(pts.points.size() == 8);
    // Frame 0, the rest pose; frame 1 turned and moved as posed_clip says.
    const std::vector<vec3> expected{vec3(0, 0, 0),       vec3(T(0.5), -1, 0), vec3(-1, 0, 0),  vec3(T(0.5), -2, 0),
                                     vec3(1, 2, 3),       vec3(1, 1, T(2.5)),  vec3(1, 2, 4),   vec3(1, 0, T(2.5))};
    for (std::size_t i = 0; i < expected.size(); ++i) CHECK((pts.points[i] - expected[i]).norm() < T(1e-5));
    // The same as forward kinematics frame by frame.
    for (std::size_t f = 0; f < c.frames(); ++f) {
        const auto pose = anima::forward_kinematics(c, f);
        const auto sites = anima::end_site_positions(c.skeleton(), pose);
        for (std::size_t j = 0; j < c.joints(); ++j) {
            CHECK(pts.points[f * pts.per_frame + j] == pose.positions[j]);
            if (pts.end_site_point[j] != none) CHECK(pts.points[f * pts.per_frame + pts.end_site_point[j]] == sites[j]);
        }
    }
    // lowest_along on the points is lowest_along on the clip, bit for bit.
    for (const vec3& d : {vec3(0, 1, 0), vec3(0, -1, 0), vec3(0, 0, 1)}) {
        CHECK(anima::lowest_along(pts, d) == anima::lowest_along(c, d));
    }
    CHECK(anima::lowest_along(pts, vec3(0, 1, 0)) == T(-2));  // frame 0's End Site
    const anima::clip_points<T> empty = anima::global_points(anima::clip<T>(c.skeleton(), 0, T(1) / 30));
    CHECK(empty.points.empty());
    CHECK(empty.per_frame == 4);
    CHECK(anima::lowest_along(empty, vec3(0, 1, 0)) == std::numeric_limits<T>::infinity());
}

TEST_CASE_TEMPLATE("pose_diagonal is the diagonal of the box the joints span", T, float, double) {
    anima::clip<T> c = posed_clip<T>();
    // Frame 0 (rest pose): [-1, 0.5] x [-1, 0] x [0, 0]. Frame 1:
    // [1, 1] x [1, 2] x [2.5, 4]; the End Site at (1, 0, 2.5) does not count.
    CHECK(anima::pose_diagonal(c, 0) == doctest::Approx(std::sqrt(2.25 + 1)).epsilon(1e-5));
    CHECK(anima::pose_diagonal(c, 1) == doctest::Approx(std::sqrt(1 + 2.25)).epsilon(1e-5));
    // Unturned at (1, 5, 3): (1, 5, 3), (1.5, 4, 3), (0, 5, 3).
    c.set_translation(1, 0, Eigen::Matrix<T, 3, 1>(1, 5, 3));
    c.set_rotation(1, 0, Eigen::Quaternion<T>::Identity());
    CHECK(anima::pose_diagonal(c, 1) == doctest::Approx(std::sqrt(2.25 + 1)).epsilon(1e-5));
    CHECK_THROWS_AS(anima::pose_diagonal(c, 2), anima::invalid_argument);
}

}  // namespace
