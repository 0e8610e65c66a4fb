// parse_position_targets: the per-frame goals of a "frame,effector,x,y,z"
// file, against goals built by hand, and every error naming its line.
#include <anima/core/error.hpp>
#include <anima/core/file_io.hpp>
#include <anima/ik/position_targets.hpp>
#include <anima/motion/skeleton.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <cstdio>
#include <string>

namespace {

template <class T>
anima::skeleton<T> arm() {
    anima::skeleton<T> sk;
    sk.add_joint("Hips", -1, Eigen::Matrix<T, 3, 1>::Zero());
    sk.add_joint("LeftShoulder", 0, Eigen::Matrix<T, 3, 1>(T(0.2), T(0.5), T(0)));
    sk.add_joint("LeftHand", 1, Eigen::Matrix<T, 3, 1>(T(0.5), T(0), T(0)));
    return sk;
}

std::string error_of(const std::string& text, std::size_t frames = 10) {
    try {
        anima::parse_position_targets(text, "t.csv", arm<double>(), frames);
    } catch (const anima::parse_error& e) {
        return e.what();
    }
    return "no error";
}

template <class T>
void check_goals() {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    // Frames out of order, two goals in one frame, comments, blanks, CRLF and
    // a lone CR, a byte order mark, spaces around fields.
    const std::string text =
        "\xEF\xBB\xBF# frame,effector,x,y,z\r\n"
        "7, LeftHand ,0.25,1,-2e-1\r\n"
        "\n"
        "  # nothing\r"
        "3,LeftShoulder,1,2,3   # shoulder first\n"
        "3,LeftHand,-0.5,0,4.5\n";
    const auto goals = anima::parse_position_targets(text, "t.csv", arm<T>(), 8);
    REQUIRE(goals.size() == 2);
    CHECK(goals[0].frame == 3);
    CHECK(goals[1].frame == 7);
    REQUIRE(goals[0].goals.size() == 2);
    REQUIRE(goals[1].goals.size() == 1);
    const auto same = [](const anima::ik_goal<T>& got, const anima::ik_goal<T>& expected) {
        return got.joint == expected.joint && got.kind == expected.kind && got.position == expected.position &&
               got.offset == expected.offset && got.weight == expected.weight;
    };
    CHECK(same(goals[0].goals[0], anima::position_goal<T>(1, vec3(T(1), T(2), T(3)))));
    CHECK(same(goals[0].goals[1], anima::position_goal<T>(2, vec3(T(-0.5), T(0), T(4.5)))));
    CHECK(same(goals[1].goals[0], anima::position_goal<T>(2, vec3(T(0.25), T(1), T(-0.2)))));
}

}  // namespace

TEST_CASE("parse_position_targets: one frame_goals per frame, in frame order, goals in line order") {
    check_goals<double>();
    check_goals<float>();
}

TEST_CASE("read_position_targets reads a file as parse_position_targets reads its text") {
    const std::string path = "position_targets_test.csv";
    anima::write_file_atomically(path, "2,LeftHand,1,2,3\n");
    const auto goals = anima::read_position_targets(path, arm<double>(), 3);
    std::remove(path.c_str());
    REQUIRE(goals.size() == 1);
    CHECK(goals[0].frame == 2);
    CHECK(goals[0].goals[0].position == Eigen::Vector3d(1, 2, 3));
    CHECK_THROWS_AS(anima::read_position_targets(path, arm<double>(), 3), anima::io_error);
}

TEST_CASE("parse_position_targets names the file and line of every error") {
    CHECK(error_of("1,LeftHand,1,2\n") == "t.csv:1: expected frame,effector,x,y,z (5 fields), got 4");
    CHECK(error_of("\n1,LeftHand,1,2,3,4\n") == "t.csv:2: expected frame,effector,x,y,z (5 fields), got 6");
    for (const char* frame : {"x", "-1", "+1", "1e3", "1.0", "", "99999999999999999999999"})
        CHECK(error_of(std::string(frame) + ",LeftHand,0,0,0\n") ==
              "t.csv:1: '" + std::string(frame) + "' is not a frame number");
    CHECK(error_of("10,LeftHand,0,0,0\n") == "t.csv:1: frame 10 is outside the clip (0..9)");
    CHECK(error_of("0,LeftHand,0,0,0\n", 0) == "t.csv:1: frame 0 is outside the clip (it has no frames)");
    CHECK(error_of("1,LeftHnad,0,0,0\n") == "t.csv:1: no joint named 'LeftHnad' in the clip");
    CHECK(error_of("1,lefthand,0,0,0\n") == "t.csv:1: no joint named 'lefthand' in the clip (did you mean 'LeftHand'?)");
    CHECK(error_of("1,LeftHand,0,0,z\n") == "t.csv:1: expected three numbers x,y,z, got '1,LeftHand,0,0,z'");
    CHECK(error_of("1,LeftHand,0,0 1,0\n") == "t.csv:1: expected three numbers x,y,z, got '1,LeftHand,0,0 1,0'");
    CHECK(error_of("1,LeftHand,nan,0,0\n") == "t.csv:1: the target is not finite");
    CHECK(error_of("1,LeftHand,0,1e999,0\n") == "t.csv:1: the target is not finite");
    CHECK(error_of("1, ,0,0,0\n") == "t.csv:1: the effector name is empty");
    CHECK(error_of("# only a comment\n\n") == "t.csv:2: no targets in the file");
    CHECK(error_of("") == "t.csv:0: no targets in the file");
}
