// Body sides from joint names, the figure's left axis from the rest pose,
// and rest-pose lead-ins at the start of a clip: on the bundled CMU clips
// (31 and 43 joints), on skeletons built by hand and on clips made to start
// at the rest pose.
#include "../test_support.hpp"

#include <anima/bvh/reader.hpp>
#include <anima/motion/body_sides.hpp>
#include <anima/motion/reorient.hpp>
#include <anima/motion/rest_pose.hpp>

#include <doctest/doctest.h>

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace {

using anima::body_side;
using anima_test::bundled;

TEST_CASE("side_of reads left and right from CMU, Daz and other joint names") {
    for (const char* n : {"LeftUpLeg", "LHipJoint", "lShldr", "lThigh", "L_Foot", "l.hand", "L2", "leftEye",
                          "lhumerus", "lfemur", "ltoes", "LEFT_ARM"})
        CHECK_MESSAGE(anima::side_of(n) == body_side::left, n);
    for (const char* n : {"RightHand", "RHipJoint", "rShldr", "rFoot", "R-Knee", "rightEye", "rclavicle", "rtibia"})
        CHECK_MESSAGE(anima::side_of(n) == body_side::right, n);
    for (const char* n : {"Hips", "LowerBack", "Root", "root", "lowerneck", "Spine1", "Head", "r", "l", "", "ribs",
                          "lower", "rhythm"})
        CHECK_MESSAGE(anima::side_of(n) == body_side::centre, n);
    CHECK(std::string(anima::to_string(body_side::left)) == "left");
    CHECK(std::string(anima::to_string(body_side::centre)) == "centre");
}

TEST_CASE_TEMPLATE("left_axis follows the skeleton's left joints, turns with the figure, and falls back to width", T,
                   float, double) {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    const anima::signed_axis plus_y{anima::axis::y, 1}, plus_z{anima::axis::z, 1};
    // Built by hand: left hip at +X, right hip at -X, Y up.
    anima::skeleton<T> sk;
    sk.add_joint("Hips", -1, vec3::Zero());
    sk.add_joint("LeftHip", 0, vec3(T(0.1), T(0), T(0)));
    sk.add_joint("RightHip", 0, vec3(T(-0.1), T(0), T(0)));
    sk.add_joint("Spine", 0, vec3(T(0), T(0.5), T(0)));
    CHECK(anima::left_axis(sk, plus_y) == anima::signed_axis{anima::axis::x, 1});
    // Mirrored: the left hip at -X.
    anima::skeleton<T> mirrored;
    mirrored.add_joint("Hips", -1, vec3::Zero());
    mirrored.add_joint("LeftHip", 0, vec3(T(-0.1), T(0), T(0)));
    mirrored.add_joint("RightHip", 0, vec3(T(0.1), T(0), T(0)));
    CHECK(anima::left_axis(mirrored, plus_y) == anima::signed_axis{anima::axis::x, -1});
    // No side names: the widest horizontal axis (Z here), positive.
    anima::skeleton<T> plain;
    plain.add_joint("a", -1, vec3::Zero());
    plain.add_joint("b", 0, vec3(T(0.05), T(1), T(0)));
    plain.add_joint("c", 0, vec3(T(0), T(0), T(0.4)));
    CHECK(anima::left_axis(plain, plus_y) == anima::signed_axis{anima::axis::z, 1});

    // The CMU clips: left is horizontal, and turning the figure's up axis to
    // +Z turns its left axis by the same rotation.
    for (const char* name : {"walk_cmu31_02_01.bvh", "run_cmu_09_01.bvh"}) {
        const auto c = anima::read_bvh<T>(bundled(name));
        const auto left = anima::left_axis(c.skeleton(), plus_y);
        CHECK(left.axis != anima::axis::y);
        const auto turned = anima::change_up_axis(c.slice(0, 1), plus_y, plus_z);
        const vec3 expected = anima::axis_change<T>(plus_y, plus_z) * anima::axis_vector<T>(left);
        CHECK((anima::axis_vector<T>(anima::left_axis(turned.skeleton(), plus_z)) - expected).norm() < T(1e-5));
    }
}

/// The walk with `lead` frames put before it: the rest pose, then frames
/// swinging from it to the walk's first frame.
template <class T>
anima::clip<T> with_rest_pose_lead_in(const anima::clip<T>& walk, std::size_t lead) {
    anima::clip<T> c(walk.skeleton(), walk.frames() + lead, walk.frame_time());
    for (std::size_t f = 0; f < c.frames(); ++f)
        for (std::size_t j = 0; j < c.joints(); ++j) {
            const std::size_t source = f < lead ? 0 : f - lead;
            const T s = f < lead ? T(f) / T(lead) : T(1);
            c.set_rotation(f, j, Eigen::Quaternion<T>::Identity().slerp(s, walk.rotation(source, j)));
            if (walk.skeleton().translation_slot(j) >= 0) c.set_translation(f, j, walk.translation(source, j));
        }
    return c;
}

TEST_CASE_TEMPLATE("rest_pose_lead_in finds a T-pose start and the frames that swing out of it", T, float, double) {
    const auto walk = anima::read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    CHECK_FALSE(anima::starts_at_rest_pose(walk));
    CHECK(anima::rest_pose_lead_in(walk) == 0);
    // The bundled run's frame 0 is a T-pose its converter added (examples/data/README.md),
    // and its first frames swing out of it.
    const auto run = anima::read_bvh<T>(bundled("run_cmu_09_01.bvh"));
    CHECK(anima::starts_at_rest_pose(run));
    CHECK(anima::rest_pose_lead_in(run) == 5);

    for (const std::size_t lead : {1, 4, 8}) {
        const auto c = with_rest_pose_lead_in(walk, lead);
        CHECK(anima::starts_at_rest_pose(c));
        const std::size_t skip = anima::rest_pose_lead_in(c);
        INFO("lead " << lead << ": skip " << skip);
        CHECK(skip >= 1);
        CHECK(skip <= lead + 1);  // at most one frame past the swing
        if (lead == 1) CHECK(skip == 1);
    }
    // A frame 0 beyond the limit is not a rest pose; a looser limit takes it.
    auto bent = with_rest_pose_lead_in(walk, 4);
    bent.set_rotation(0, 2, Eigen::Quaternion<T>(Eigen::AngleAxis<T>(T(0.35), Eigen::Matrix<T, 3, 1>::UnitX())));
    CHECK_FALSE(anima::starts_at_rest_pose(bent));
    CHECK(anima::starts_at_rest_pose(bent, T(25)));
    // Nothing moves, one frame, no frames: no rest pose to skip.
    anima::clip<T> still(walk.skeleton(), 5, walk.frame_time());
    CHECK_FALSE(anima::starts_at_rest_pose(still));
    CHECK(anima::rest_pose_lead_in(walk.slice(0, 1)) == 0);
    CHECK(anima::rest_pose_lead_in(anima::clip<T>(walk.skeleton(), 0, walk.frame_time())) == 0);
}

}  // namespace
