// Skeleton and clip model: validation, storage, forward kinematics against
// independent 4x4 matrix references (Eigen and GLM), finite differences,
// velocities, the DOF view, figure guesses and whole-clip reorientation.
#include <anima/bvh/reader.hpp>
#include <anima/core/error.hpp>
#include <anima/core/text.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/dof_view.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/finite_difference.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/reorient.hpp>
#include <anima/motion/resample.hpp>
#include <anima/motion/rest_pose.hpp>
#include <anima/motion/skeleton.hpp>
#include <anima/motion/velocities.hpp>
#include <anima/rotation/quaternion.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

using anima::channel;
using v3d = Eigen::Vector3d;

constexpr channel xp = channel::x_position, yp = channel::y_position, zp = channel::z_position;
constexpr channel xr = channel::x_rotation, yr = channel::y_rotation, zr = channel::z_rotation;

std::string data_path(const char* name) { return std::string(ANIMA_TEST_DATA_DIR) + "/" + name; }

const anima::bvh_document<double>& walk_document() {
    static const auto doc = anima::read_bvh_document<double>(data_path("walk_cmu31_02_01.bvh"));
    return doc;
}
const anima::bvh_document<double>& run_document() {
    static const auto doc = anima::read_bvh_document<double>(data_path("run_cmu_09_01.bvh"));
    return doc;
}
template <class T>
const anima::clip<T>& walk_clip() {
    static const auto c = anima::read_bvh<T>(data_path("walk_cmu31_02_01.bvh"));
    return c;
}
template <class T>
const anima::clip<T>& run_clip() {
    static const auto c = anima::read_bvh<T>(data_path("run_cmu_09_01.bvh"));
    return c;
}

template <class T>
T tolerance(double for_double, double for_float) {
    return static_cast<T>(std::is_same_v<T, double> ? for_double : for_float);
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The message of the anima::invalid_argument thrown by f ("" if none).
template <class F>
std::string invalid_argument_message(F&& f) {
    try {
        f();
    } catch (const anima::invalid_argument& e) {
        return e.what();
    }
    return "";
}

// root (position + rotation), spine (rotation), slider (position only), fixed (no channels).
template <class T>
anima::skeleton<T> small_skeleton() {
    using V = Eigen::Matrix<T, 3, 1>;
    anima::skeleton<T> sk;
    sk.add_joint("root", -1, V(0, 1, 0), {xp, yp, zp, zr, xr, yr});
    sk.add_joint("spine", 0, V(0, 2, 0), {zr, xr, yr});
    sk.add_joint("slider", 1, V(1, 0, 0), {xp, yp, zp});
    sk.add_joint("fixed", 1, V(-1, 0, 0));
    return sk;
}

// ---- independent reference: 4x4 homogeneous matrices from the document's numbers ----

Eigen::Matrix4d translation4(const v3d& t) {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m(0, 3) = t.x();
    m(1, 3) = t.y();
    m(2, 3) = t.z();
    return m;
}
// Elementary rotation about a coordinate axis, written out (column vectors).
Eigen::Matrix4d rotation4(anima::axis a, double degrees) {
    const double r = degrees * 3.14159265358979323846 / 180.0, c = std::cos(r), s = std::sin(r);
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    if (a == anima::axis::x) {
        m(1, 1) = c, m(1, 2) = -s, m(2, 1) = s, m(2, 2) = c;
    } else if (a == anima::axis::y) {
        m(0, 0) = c, m(0, 2) = s, m(2, 0) = -s, m(2, 2) = c;
    } else {
        m(0, 0) = c, m(0, 1) = -s, m(1, 0) = s, m(1, 1) = c;
    }
    return m;
}
// Global transform of every joint at frame f: M_j = M_parent * T(offset + positions) * R1 * R2 * R3.
std::vector<Eigen::Matrix4d> reference_globals(const anima::bvh_document<double>& doc, std::size_t f) {
    const auto& sk = doc.skeleton;
    std::vector<Eigen::Matrix4d> g(sk.size());
    std::size_t col = 0;
    for (std::size_t j = 0; j < sk.size(); ++j) {
        v3d t = sk[j].offset;
        Eigen::Matrix4d r = Eigen::Matrix4d::Identity();
        for (channel c : sk[j].channels) {
            const double v = doc.value(f, col++);
            const int k = static_cast<int>(c) % 3;
            if (static_cast<int>(c) < 3)
                t[k] += v;
            else
                r = r * rotation4(static_cast<anima::axis>(k), v);
        }
        const Eigen::Matrix4d local = translation4(t) * r;
        g[j] = sk[j].parent < 0 ? local : Eigen::Matrix4d(g[static_cast<std::size_t>(sk[j].parent)] * local);
    }
    return g;
}
// The same with GLM: glm::translate and glm::mat4_cast of a product of glm::angleAxis.
std::vector<glm::dmat4> reference_globals_glm(const anima::bvh_document<double>& doc, std::size_t f) {
    const auto& sk = doc.skeleton;
    std::vector<glm::dmat4> g(sk.size());
    std::size_t col = 0;
    for (std::size_t j = 0; j < sk.size(); ++j) {
        glm::dvec3 t(sk[j].offset.x(), sk[j].offset.y(), sk[j].offset.z());
        glm::dquat q(1.0, 0.0, 0.0, 0.0);
        for (channel c : sk[j].channels) {
            const double v = doc.value(f, col++);
            const int k = static_cast<int>(c) % 3;
            if (static_cast<int>(c) < 3) {
                t[k] += v;
            } else {
                glm::dvec3 axis(0.0);
                axis[k] = 1.0;
                q = q * glm::angleAxis(glm::radians(v), axis);
            }
        }
        const glm::dmat4 local = glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(q);
        g[j] = sk[j].parent < 0 ? local : g[static_cast<std::size_t>(sk[j].parent)] * local;
    }
    return g;
}

template <class T>
T max_abs_diff(const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& a,
               const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>& b) {
    REQUIRE(a.rows() == b.rows());
    REQUIRE(a.cols() == b.cols());
    return a.size() ? (a - b).cwiseAbs().maxCoeff() : T(0);
}

}  // namespace

// =====================================================================================
// skeleton
// =====================================================================================

TEST_CASE("skeleton::add_joint appends joints and validates its arguments") {
    anima::skeleton<double> sk;
    CHECK(sk.empty());
    CHECK(sk.add_joint("root", -1, v3d(0, 0, 0), {xp, yp, zp, zr, yr, xr}) == 0);
    CHECK(sk.add_joint("a", 0, v3d(1, 0, 0), {zr, yr, xr}) == 1);
    CHECK(sk.add_joint("b", 1, v3d(0, 1, 0)) == 2);
    CHECK(sk.add_joint("second root", -1, v3d(5, 0, 0)) == 3);  // a forest is allowed
    REQUIRE(sk.size() == 4);
    CHECK(sk[1].parent == 0);
    CHECK(sk[2].parent == 1);
    CHECK(sk[3].parent == -1);
    CHECK(sk[1].offset == v3d(1, 0, 0));
    CHECK(sk.find("b") == std::optional<std::size_t>(2));
    CHECK_FALSE(sk.find("nope").has_value());
    CHECK(sk.index_of("a") == 1);
    CHECK_THROWS_AS(sk.index_of("nope"), anima::invalid_argument);
    // Names match exactly; a name that differs only in case is suggested.
    CHECK_FALSE(sk.find("ROOT").has_value());
    CHECK(contains(invalid_argument_message([&] { (void)sk.index_of("ROOT"); }),
                   "no joint named 'ROOT' (did you mean 'root'?)"));
    CHECK(sk.did_you_mean("nope").empty());
    CHECK(sk.did_you_mean("Second Root") == " (did you mean 'second root'?)");

    SUBCASE("unknown parent") {
        const std::string m = invalid_argument_message([&] { sk.add_joint("c", 4, v3d::Zero()); });
        CHECK(contains(m, "parent index 4"));
        CHECK(contains(m, "'c'"));
        CHECK_THROWS_AS(sk.add_joint("c", -2, v3d::Zero()), anima::invalid_argument);
        CHECK_THROWS_AS(sk.add_joint("c", 100, v3d::Zero()), anima::invalid_argument);
    }
    SUBCASE("duplicate name") {
        const std::string m = invalid_argument_message([&] { sk.add_joint("a", 0, v3d::Zero()); });
        CHECK(contains(m, "'a'"));
        CHECK(contains(m, "already exists"));
    }
    SUBCASE("empty name") { CHECK_THROWS_AS(sk.add_joint("", 0, v3d::Zero()), anima::invalid_argument); }
    SUBCASE("repeated channel") {
        const std::string m = invalid_argument_message([&] { sk.add_joint("c", 0, v3d::Zero(), {zr, xr, zr}); });
        CHECK(contains(m, "Zrotation"));
        CHECK(contains(m, "twice"));
        CHECK_THROWS_AS(sk.add_joint("c", 0, v3d::Zero(), {xp, xp}), anima::invalid_argument);
    }
    SUBCASE("non-finite offset") {
        CHECK_THROWS_AS(sk.add_joint("c", 0, v3d(0, std::nan(""), 0)), anima::invalid_argument);
        CHECK_THROWS_AS(sk.add_joint("c", 0, v3d(std::numeric_limits<double>::infinity(), 0, 0)),
                        anima::invalid_argument);
    }
    // A refused joint leaves the skeleton as it was.
    CHECK(sk.size() == 4);
    CHECK(sk.translated_joint_count() == 1);
    CHECK(sk.channel_count() == 9);
}

TEST_CASE("skeleton::from_parents sorts parents first and rejects cycles and bad indices") {
    const std::vector<v3d> offsets = {v3d(0, 0, 3), v3d(0, 0, 0), v3d(0, 0, 2), v3d(0, 0, 1)};
    SUBCASE("re-sorted parents-first") {
        // hand -> arm -> shoulder -> root, given children first.
        const auto sk =
            anima::skeleton<double>::from_parents({"hand", "root", "arm", "shoulder"}, {2, -1, 3, 1}, offsets);
        REQUIRE(sk.size() == 4);
        CHECK(sk[0].name == "root");
        CHECK(sk[1].name == "shoulder");
        CHECK(sk[2].name == "arm");
        CHECK(sk[3].name == "hand");
        for (std::size_t j = 0; j < sk.size(); ++j) CHECK(sk[j].parent < static_cast<int>(j));
        CHECK(sk[1].parent == 0);
        CHECK(sk[2].parent == 1);
        CHECK(sk[3].parent == 2);
        // Offsets travel with their joints.
        CHECK(sk[sk.index_of("hand")].offset == v3d(0, 0, 3));
        CHECK(sk[sk.index_of("shoulder")].offset == v3d(0, 0, 1));
        CHECK(sk[sk.index_of("arm")].offset == v3d(0, 0, 2));
    }
    SUBCASE("already sorted input is kept as is, siblings in input order") {
        const auto sk = anima::skeleton<double>::from_parents({"r", "a", "b", "c"}, {-1, 0, 0, 1}, offsets);
        CHECK(sk[0].name == "r");
        CHECK(sk[1].name == "a");
        CHECK(sk[2].name == "b");
        CHECK(sk[3].name == "c");
        CHECK(sk.children(0) == std::vector<std::size_t>{1, 2});
    }
    SUBCASE("a cycle names a joint on it") {
        // r is a root; a -> b -> c -> a loop.
        const std::string m = invalid_argument_message([&] {
            anima::skeleton<double>::from_parents({"r", "a", "b", "c"}, {-1, 3, 1, 2}, offsets);
        });
        CHECK(contains(m, "cycle"));
        CHECK((contains(m, "'a'") || contains(m, "'b'") || contains(m, "'c'")));
        // A joint that is its own parent.
        const std::string self = invalid_argument_message([&] {
            anima::skeleton<double>::from_parents({"r", "me"}, {-1, 1}, {v3d::Zero(), v3d::Zero()});
        });
        CHECK(contains(self, "'me'"));
        CHECK(contains(self, "cycle"));
    }
    SUBCASE("the joint named for a cycle is on the cycle, not merely below it") {
        // "below" hangs off the a <-> b loop without being part of it, and its
        // walk up is the first to loop. The documented contract is "naming a
        // joint on it".
        const std::string m = invalid_argument_message([&] {
            anima::skeleton<double>::from_parents({"below", "a", "b"}, {1, 2, 1},
                                                  {v3d::Zero(), v3d::Zero(), v3d::Zero()});
        });
        CHECK(contains(m, "cycle"));
        CHECK((contains(m, "'a'") || contains(m, "'b'")));
        CHECK_FALSE(contains(m, "'below'"));
    }
    SUBCASE("bad indices and sizes") {
        const std::string m = invalid_argument_message([&] {
            anima::skeleton<double>::from_parents({"r", "a"}, {-1, 2}, {v3d::Zero(), v3d::Zero()});
        });
        CHECK(contains(m, "'a'"));
        CHECK(contains(m, "out of range"));
        CHECK_THROWS_AS(anima::skeleton<double>::from_parents({"r", "a"}, {-1, -2}, {v3d::Zero(), v3d::Zero()}),
                        anima::invalid_argument);
        CHECK_THROWS_AS(anima::skeleton<double>::from_parents({"r", "a"}, {-1}, {v3d::Zero(), v3d::Zero()}),
                        anima::invalid_argument);
        CHECK_THROWS_AS(anima::skeleton<double>::from_parents({"r", "a"}, {-1, 0}, {v3d::Zero()}),
                        anima::invalid_argument);
        CHECK_THROWS_AS(anima::skeleton<double>::from_parents({"r", "r"}, {-1, 0}, {v3d::Zero(), v3d::Zero()}),
                        anima::invalid_argument);
    }
    SUBCASE("empty input") { CHECK(anima::skeleton<double>::from_parents({}, {}, {}).empty()); }
}

TEST_CASE("skeleton children, translation slots and channel counts") {
    const auto& sk = walk_clip<double>().skeleton();
    REQUIRE(sk.size() == 31);
    const auto names = [&](const std::vector<std::size_t>& idx) {
        std::vector<std::string> out;
        for (std::size_t i : idx) out.push_back(sk[i].name);
        return out;
    };
    CHECK(names(sk.children(0)) == std::vector<std::string>{"LHipJoint", "RHipJoint", "LowerBack"});
    CHECK(names(sk.children(sk.index_of("Spine1"))) ==
          std::vector<std::string>{"Neck", "LeftShoulder", "RightShoulder"});
    CHECK(names(sk.children(sk.index_of("LeftHand"))) == std::vector<std::string>{"LeftFingerBase", "LThumb"});
    CHECK(sk.children(sk.index_of("Head")).empty());
    CHECK_THROWS_AS(sk.children(31), anima::invalid_argument);
    CHECK_THROWS_AS(sk.at(31), anima::invalid_argument);
    CHECK(sk.channel_count() == 96);
    CHECK(sk.translated_joint_count() == 1);
    CHECK(sk.translation_slot(0) == 0);
    for (std::size_t j = 1; j < sk.size(); ++j) CHECK(sk.translation_slot(j) == -1);

    auto s = small_skeleton<double>();
    CHECK(s.channel_count() == 12);
    CHECK(s.translated_joint_count() == 2);
    CHECK(s.translation_slot(0) == 0);
    CHECK(s.translation_slot(1) == -1);
    CHECK(s.translation_slot(2) == 1);
    CHECK(s.translation_slot(3) == -1);
    CHECK(s.has_rotation_channels(1));
    CHECK_FALSE(s.has_rotation_channels(2));
    CHECK_FALSE(s.has_position_channels(3));
    CHECK(s.rotation_axes(0) == std::vector<anima::axis>{anima::axis::z, anima::axis::x, anima::axis::y});
    CHECK(s.rotation_axes(3).empty());
    // Dropping the root's position channels renumbers the remaining slots.
    s.set_channels(0, {zr, xr, yr});
    CHECK(s.translated_joint_count() == 1);
    CHECK(s.translation_slot(0) == -1);
    CHECK(s.translation_slot(2) == 0);
    CHECK(s.channel_count() == 9);
    CHECK_THROWS_AS(s.set_channels(0, {zr, zr}), anima::invalid_argument);
    CHECK_THROWS_AS(s.set_channels(9, {zr}), anima::invalid_argument);
    CHECK_THROWS_AS(s.set_end_site(1, v3d(0, std::nan(""), 0)), anima::invalid_argument);
    CHECK_THROWS_AS(s.set_offset(1, v3d(0, std::nan(""), 0)), anima::invalid_argument);
    // Channel names.
    for (channel c : {xp, yp, zp, xr, yr, zr}) CHECK(anima::parse_channel(anima::to_string(c)) == c);
    CHECK(anima::parse_channel("zROTATION") == zr);
    for (const char* bad : {"Wrotation", "Xrot", "", "Xrotation ", "Xposition2"}) {
        CHECK_FALSE(anima::try_parse_channel(bad).has_value());
        const std::string expected = "anima::parse_channel: '" + std::string(bad) + "' is not a BVH channel";
        CHECK_THROWS_WITH_AS(anima::parse_channel(bad), doctest::Contains(expected.c_str()), anima::invalid_argument);
    }
    for (channel c : {xp, yp, zp, xr, yr, zr}) CHECK(anima::try_parse_channel(anima::to_string(c)) == c);
}

// =====================================================================================
// clip
// =====================================================================================

TEST_CASE_TEMPLATE("resample: slerp and lerp between the nearest frames, bounded output", T, float, double) {
    using V = Eigen::Matrix<T, 3, 1>;
    using Q = Eigen::Quaternion<T>;
    anima::clip<T> c(small_skeleton<T>(), 3, T(0.1));
    c.set_rotation(1, 1, Q(Eigen::AngleAxis<T>(T(1.2), V(0, 0, 1))));
    c.set_rotation(2, 1, Q(Eigen::AngleAxis<T>(T(-2.5), V(1, 2, 0).normalized())));
    c.set_translation(1, 0, V(1, 2, 3));
    c.set_translation(2, 0, V(-4, 0, 2));
    // 0.2 s every 0.03 s: frames at 0, 0.03, ..., 0.18 (0.21 is past the end).
    const anima::clip<T> r = anima::resample(c, T(0.03));
    REQUIRE(r.frames() == 7);
    CHECK(r.frame_time() == T(0.03));
    const T tol = std::is_same<T, float>::value ? T(2e-6) : T(1e-14);
    for (std::size_t f = 0; f < r.frames(); ++f) {
        const double s = 0.3 * static_cast<double>(f);  // position in source frames
        const auto i = std::min<std::size_t>(static_cast<std::size_t>(s), 1);
        const T u = T(s - static_cast<double>(i));
        CAPTURE(f);
        // Eigen's slerp and a plain lerp are the independent references.
        CHECK(r.rotation(f, 1).angularDistance(c.rotation(i, 1).slerp(u, c.rotation(i + 1, 1))) <= tol);
        CHECK((r.translation(f, 0) - ((T(1) - u) * c.translation(i, 0) + u * c.translation(i + 1, 0))).norm() <=
              tol * 8);
    }
    // One-frame and empty clips keep their frames and take the new frame time.
    CHECK(anima::resample(anima::clip<T>(small_skeleton<T>(), 1, T(0.1)), T(0.5)).frames() == 1);
    CHECK(anima::resample(anima::clip<T>(small_skeleton<T>(), 0, T(0.1)), T(0.5)).frame_time() == T(0.5));
    // 0.2 s every 1e-9 s would be 2e8 frames (35 GB in double): refused by
    // the default 1 GiB limit, naming the frame time.
    CHECK_THROWS_WITH_AS(anima::resample(c, T(1e-9)), doctest::Contains("anima::resample: frame time"),
                         anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::resample(c, T(1e-30)), doctest::Contains("more than max_memory"),
                         anima::invalid_argument);
    CHECK(anima::resample(c, T(1e-4), 1e9).frames() == 2001);  // a larger limit lets it through
    CHECK_THROWS_AS(anima::resample(c, T(1e-4), 1e3), anima::invalid_argument);
    for (T bad : {T(0), T(-1), std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::infinity()})
        CHECK_THROWS_WITH_AS(anima::resample(c, bad), doctest::Contains("anima::resample: frame time"),
                             anima::invalid_argument);
    // rotate_clip names itself for a rotation that is no rotation.
    CHECK_THROWS_WITH_AS(anima::rotate_clip(c, Q(0, 0, 0, 0)), doctest::Contains("anima::rotate_clip"),
                         anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::rotate_clip(c, Q(std::numeric_limits<T>::quiet_NaN(), 0, 0, 0)),
                         doctest::Contains("anima::rotate_clip"), anima::invalid_argument);
}

TEST_CASE_TEMPLATE("clip construction, frame time, resize", T, float, double) {
    using V = Eigen::Matrix<T, 3, 1>;
    using Q = Eigen::Quaternion<T>;
    anima::clip<T> c(small_skeleton<T>(), 4, T(0.125));
    CHECK(c.frames() == 4);
    CHECK(c.joints() == 4);
    CHECK_FALSE(c.empty());
    CHECK(c.frame_time() == T(0.125));
    CHECK(c.frame_rate() == T(8));
    CHECK(c.duration() == T(0.375));
    CHECK(c.rotations().size() == 16);
    CHECK(c.translations().size() == 8);
    // clip_frame_bytes is what the storage holds a frame.
    CHECK(anima::clip_frame_bytes(c.skeleton()) * 4 ==
          static_cast<double>(c.rotations().size() * 4 * sizeof(T) + c.translations().size() * 3 * sizeof(T)));
    for (std::size_t f = 0; f < 4; ++f)
        for (std::size_t j = 0; j < 4; ++j) {
            CHECK(c.rotation(f, j).coeffs() == Q::Identity().coeffs());
            CHECK(c.translation(f, j) == c.skeleton()[j].offset);  // rest pose
        }
    CHECK(c.root_position(3) == V(0, 1, 0));
    CHECK(anima::clip<T>(small_skeleton<T>(), 1, T(0.5)).duration() == T(0));
    CHECK(anima::clip<T>().empty());

    SUBCASE("frame time must be positive and finite") {
        for (T bad : {T(0), T(-0.1), std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::infinity()}) {
            CHECK_THROWS_AS(anima::clip<T>(small_skeleton<T>(), 2, bad), anima::invalid_argument);
            CHECK_THROWS_AS(c.set_frame_time(bad), anima::invalid_argument);
        }
        CHECK(c.frame_time() == T(0.125));
        c.set_frame_time(T(0.25));
        CHECK(c.frame_rate() == T(4));
        // A subnormal frame time would make the frame rate infinite.
        const T subnormal = std::numeric_limits<T>::denorm_min();
        CHECK(std::isinf(T(1) / subnormal));
        CHECK_THROWS_WITH_AS(c.set_frame_time(subnormal), doctest::Contains("positive, normal and finite"),
                             anima::invalid_argument);
        c.set_frame_time(std::numeric_limits<T>::min());
        CHECK(std::isfinite(c.frame_rate()));
    }
    SUBCASE("resize repeats the last frame") {
        const Q q1(Eigen::AngleAxis<T>(T(0.5), V(0, 0, 1)));
        const Q q3(Eigen::AngleAxis<T>(T(-0.7), V(1, 0, 0)));
        c.set_rotation(1, 1, q1);
        c.set_rotation(3, 1, q3);
        // set_rotation renormalises; resize copies the stored values exactly.
        const Q stored1 = c.rotation(1, 1), stored3 = c.rotation(3, 1);
        CHECK(anima::angle_between(stored1, q1) <= tolerance<T>(1e-15, 1e-6));
        CHECK(anima::angle_between(stored3, q3) <= tolerance<T>(1e-15, 1e-6));
        c.set_translation(3, 0, V(7, 8, 9));
        c.set_translation(3, 2, V(-1, -2, -3));
        c.resize(7);
        REQUIRE(c.frames() == 7);
        CHECK(c.rotations().size() == 28);
        CHECK(c.translations().size() == 14);
        for (std::size_t f = 3; f < 7; ++f) {
            CHECK(c.rotation(f, 1).coeffs() == stored3.coeffs());
            CHECK(c.translation(f, 0) == V(7, 8, 9));
            CHECK(c.translation(f, 2) == V(-1, -2, -3));
            CHECK(c.translation(f, 3) == V(-1, 0, 0));
        }
        CHECK(c.rotation(1, 1).coeffs() == stored1.coeffs());
        c.resize(2);
        CHECK(c.frames() == 2);
        CHECK(c.rotation(1, 1).coeffs() == stored1.coeffs());
        CHECK_THROWS_AS(c.rotation(2, 1), anima::invalid_argument);
        c.resize(0);
        CHECK(c.empty());
        CHECK(c.rotations().empty());
        c.resize(2);  // from empty: the rest pose
        CHECK(c.rotation(1, 1).coeffs() == Q::Identity().coeffs());
        CHECK(c.translation(1, 0) == V(0, 1, 0));
        CHECK(c.translation(1, 2) == V(1, 0, 0));
    }
}

TEST_CASE("clip slice and append") {
    const auto& walk = walk_clip<double>();
    const auto s = walk.slice(10, 20);
    REQUIRE(s.frames() == 10);
    CHECK(s.skeleton() == walk.skeleton());
    CHECK(s.frame_time() == walk.frame_time());
    for (std::size_t f = 0; f < 10; ++f)
        for (std::size_t j = 0; j < walk.joints(); ++j) {
            CHECK(s.rotation(f, j).coeffs() == walk.rotation(f + 10, j).coeffs());
            CHECK(s.translation(f, j) == walk.translation(f + 10, j));
        }
    CHECK(walk.slice(5, 5).empty());
    CHECK(walk.slice(0, walk.frames()).frames() == walk.frames());
    CHECK_THROWS_AS(walk.slice(6, 5), anima::invalid_argument);
    CHECK_THROWS_AS(walk.slice(0, walk.frames() + 1), anima::invalid_argument);

    auto joined = walk.slice(0, 10);
    joined.append(s);
    joined.append(walk.slice(0, 0));
    REQUIRE(joined.frames() == 20);
    for (std::size_t f = 0; f < 20; ++f) {
        CHECK(joined.rotation(f, 5).coeffs() == walk.rotation(f, 5).coeffs());
        CHECK(joined.root_position(f) == walk.root_position(f));
    }
    // Appending to an empty clip of the same skeleton.
    anima::clip<double> empty(walk.skeleton(), 0, walk.frame_time());
    empty.append(s);
    CHECK(empty.frames() == 10);
    CHECK(empty.rotation(9, 3).coeffs() == walk.rotation(19, 3).coeffs());

    anima::clip<double> other(small_skeleton<double>(), 3, 0.1);
    const std::string m = invalid_argument_message([&] { joined.append(other); });
    CHECK(contains(m, "different skeletons"));
    CHECK(joined.frames() == 20);
    // Same names and structure but one offset differs: still a different skeleton.
    auto sk2 = walk.skeleton();
    sk2.set_offset(3, v3d(1, 2, 3));
    CHECK_THROWS_AS(joined.append(anima::clip<double>(sk2, 1, walk.frame_time())), anima::invalid_argument);
}

TEST_CASE_TEMPLATE("clip setters normalise, validate and range-check", T, float, double) {
    using V = Eigen::Matrix<T, 3, 1>;
    using Q = Eigen::Quaternion<T>;
    anima::clip<T> c(small_skeleton<T>(), 3, T(0.1));
    c.set_rotation(1, 1, Q(T(2), T(0), T(0), T(2)));
    CHECK(std::abs(c.rotation(1, 1).norm() - T(1)) <= tolerance<T>(1e-15, 1e-6));
    CHECK(std::abs(c.rotation(1, 1).w() - std::sqrt(T(0.5))) <= tolerance<T>(1e-15, 1e-6));
    CHECK(std::abs(c.rotation(1, 1).z() - std::sqrt(T(0.5))) <= tolerance<T>(1e-15, 1e-6));
    c.set_rotation(2, 0, Q(T(1e-20), T(0), T(0), T(0)));  // tiny but non-zero: fine
    CHECK(c.rotation(2, 0).w() == doctest::Approx(1.0));

    const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    const std::string zero = invalid_argument_message([&] { c.set_rotation(0, 1, Q(T(0), T(0), T(0), T(0))); });
    CHECK(contains(zero, "'spine'"));
    CHECK(contains(zero, "frame 0"));
    CHECK_THROWS_AS(c.set_rotation(0, 1, Q(nan, T(0), T(0), T(0))), anima::invalid_argument);
    CHECK_THROWS_AS(c.set_rotation(0, 1, Q(T(1), inf, T(0), T(0))), anima::invalid_argument);
    CHECK(c.rotation(0, 1).coeffs() == Q::Identity().coeffs());  // unchanged

    c.set_translation(2, 2, V(4, 5, 6));
    CHECK(c.translation(2, 2) == V(4, 5, 6));
    c.set_root_position(1, V(1, 2, 3));
    CHECK(c.root_position(1) == V(1, 2, 3));
    const std::string no_pos = invalid_argument_message([&] { c.set_translation(0, 1, V(1, 1, 1)); });
    CHECK(contains(no_pos, "no position channels"));
    CHECK_THROWS_AS(c.set_translation(0, 3, V(1, 1, 1)), anima::invalid_argument);
    CHECK_THROWS_AS(c.set_translation(0, 0, V(nan, 1, 1)), anima::invalid_argument);
    CHECK(c.translation(0, 1) == V(0, 2, 0));

    // Out-of-range frames and joints throw rather than read or write out of bounds.
    CHECK_THROWS_AS(c.rotation(3, 0), anima::invalid_argument);
    CHECK_THROWS_AS(c.rotation(0, 4), anima::invalid_argument);
    CHECK_THROWS_AS(c.rotation(static_cast<std::size_t>(-1), 0), anima::invalid_argument);
    CHECK_THROWS_AS(c.translation(3, 0), anima::invalid_argument);
    CHECK_THROWS_AS(c.translation(0, 4), anima::invalid_argument);
    CHECK_THROWS_AS(c.root_position(3), anima::invalid_argument);
    CHECK_THROWS_AS(c.set_rotation(3, 0, Q::Identity()), anima::invalid_argument);
    CHECK_THROWS_AS(c.set_rotation(0, 4, Q::Identity()), anima::invalid_argument);
    CHECK_THROWS_AS(c.set_translation(3, 0, V::Zero()), anima::invalid_argument);
    CHECK_THROWS_AS(c.set_translation(0, 4, V::Zero()), anima::invalid_argument);
    CHECK_THROWS_AS(c.set_translation(0, static_cast<std::size_t>(-1), V::Zero()), anima::invalid_argument);
    CHECK_THROWS_AS(anima::forward_kinematics(c, 3), anima::invalid_argument);
    const anima::clip<T> empty(small_skeleton<T>(), 0, T(0.1));
    CHECK_THROWS_AS(empty.rotation(0, 0), anima::invalid_argument);
    CHECK_THROWS_AS(empty.translation(0, 0), anima::invalid_argument);
    CHECK_THROWS_AS(anima::forward_kinematics(empty, 0), anima::invalid_argument);
    const std::string range = invalid_argument_message([&] { (void)c.rotation(7, 0); });
    CHECK(contains(range, "frame 7"));
}

TEST_CASE_TEMPLATE("clip::set_joint_rotations: unit rotations as given, others normalised, bad ones refused", T, float,
                   double) {
    using Q = Eigen::Quaternion<T>;
    anima::clip<T> c(small_skeleton<T>(), 4, T(0.1));
    // A unit rotation to rounding (not exactly: its squared norm is 1 - eps)
    // is stored bit for bit; one of length 2 is normalised as set_rotation does.
    Q unit(std::sqrt(T(0.5)), std::sqrt(T(0.5)), T(0), T(0));
    unit.w() = std::nextafter(unit.w(), T(0));
    const Q twice(T(2), T(0), T(0), T(2));
    const Q column[] = {unit, twice};
    c.set_joint_rotations(1, 2, column, 2);
    CHECK(c.rotation(2, 1).coeffs() == unit.coeffs());
    anima::clip<T> reference = c;
    reference.set_rotation(3, 1, twice);
    CHECK(c.rotation(3, 1).coeffs() == reference.rotation(3, 1).coeffs());
    CHECK(c.rotation(1, 1).coeffs() == Q::Identity().coeffs());  // other frames and joints untouched
    CHECK(c.rotation(2, 0).coeffs() == Q::Identity().coeffs());
    CHECK(c.rotation(2, 2).coeffs() == Q::Identity().coeffs());
    c.set_joint_rotations(1, 4, column, 0);  // nothing to set, even at the end

    const T nan = std::numeric_limits<T>::quiet_NaN();
    const Q bad[] = {Q::Identity(), Q(nan, T(0), T(0), T(0))};
    const std::string refused = invalid_argument_message([&] { c.set_joint_rotations(2, 0, bad, 2); });
    CHECK(contains(refused, "frame 1"));
    CHECK(contains(refused, "'slider'"));
    const std::string past = invalid_argument_message([&] { c.set_joint_rotations(0, 3, column, 2); });
    CHECK(contains(past, "out of range"));
    CHECK_THROWS_AS(c.set_joint_rotations(0, static_cast<std::size_t>(-1), column, 2), anima::invalid_argument);
    CHECK_THROWS_AS(c.set_joint_rotations(4, 0, column, 2), anima::invalid_argument);
}

// =====================================================================================
// forward kinematics
// =====================================================================================

TEST_CASE("forward kinematics of the walk clip matches a 4x4 matrix reference (double)") {
    const auto& doc = walk_document();
    const auto& c = walk_clip<double>();
    REQUIRE(c.frames() == 343);
    double worst_position = 0, worst_orientation = 0;
    anima::global_pose<double> pose;
    for (std::size_t f : {std::size_t(0), std::size_t(1), std::size_t(57), std::size_t(171), std::size_t(342)}) {
        anima::forward_kinematics(c, f, pose);
        const auto ref = reference_globals(doc, f);
        REQUIRE(pose.positions.size() == 31);
        REQUIRE(pose.orientations.size() == 31);
        for (std::size_t j = 0; j < c.joints(); ++j) {
            const v3d p = ref[j].block<3, 1>(0, 3);
            const Eigen::Matrix3d r = ref[j].block<3, 3>(0, 0);
            worst_position = std::max(worst_position, (pose.positions[j] - p).cwiseAbs().maxCoeff());
            worst_orientation =
                std::max(worst_orientation, (pose.orientations[j].toRotationMatrix() - r).cwiseAbs().maxCoeff());
        }
        // The value-returning overload agrees with the in-place one.
        const auto again = anima::forward_kinematics(c, f);
        for (std::size_t j = 0; j < c.joints(); ++j) CHECK(again.positions[j] == pose.positions[j]);
    }
    CHECK(worst_position <= 1e-9);
    CHECK(worst_orientation <= 1e-9);
    MESSAGE("walk FK vs 4x4 reference: max position error " << worst_position << ", max rotation-matrix error "
                                                               << worst_orientation);
    // Sanity: the reference is not trivial (the hips move, the feet are below the hips).
    const auto ref0 = reference_globals(doc, 0), ref_last = reference_globals(doc, 342);
    CHECK((ref0[0].block<3, 1>(0, 3) - ref_last[0].block<3, 1>(0, 3)).norm() > 10);
    CHECK(ref0[c.skeleton().index_of("LeftFoot")](1, 3) < ref0[0](1, 3) - 5);
}

TEST_CASE("forward kinematics of the float walk clip matches a GLM dmat4 reference") {
    const auto& doc = walk_document();
    const auto& c = walk_clip<float>();
    REQUIRE(c.frames() == 343);
    double worst = 0;
    anima::global_pose<float> pose;
    for (std::size_t f : {std::size_t(0), std::size_t(100), std::size_t(250), std::size_t(342)}) {
        anima::forward_kinematics(c, f, pose);
        const auto ref = reference_globals_glm(doc, f);
        for (std::size_t j = 0; j < c.joints(); ++j)
            for (int k = 0; k < 3; ++k)
                worst = std::max(worst, std::abs(double(pose.positions[j][k]) - ref[j][3][k]));  // column 3 = translation
    }
    CHECK(worst <= 1e-3);
    MESSAGE("float walk FK vs glm::dmat4 reference: max position error " << worst);
    // The GLM and Eigen references agree with each other.
    const auto a = reference_globals(doc, 200);
    const auto b = reference_globals_glm(doc, 200);
    for (std::size_t j = 0; j < a.size(); ++j)
        for (int r = 0; r < 4; ++r)
            for (int k = 0; k < 4; ++k) CHECK(std::abs(a[j](r, k) - b[j][k][r]) <= 1e-9);
}

TEST_CASE("end_site_positions and rest_positions") {
    SUBCASE("against the matrix reference on the run clip (14 End Sites)") {
        const auto& doc = run_document();
        const auto& c = run_clip<double>();
        std::size_t ends = 0;
        for (const auto& j : c.skeleton().joints()) ends += j.end_site.has_value();
        CHECK(ends == 14);
        for (std::size_t f : {std::size_t(0), std::size_t(80)}) {
            const auto pose = anima::forward_kinematics(c, f);
            const auto tips = anima::end_site_positions(c.skeleton(), pose);
            const auto ref = reference_globals(doc, f);
            REQUIRE(tips.size() == c.joints());
            for (std::size_t j = 0; j < c.joints(); ++j) {
                const auto& jt = c.skeleton()[j];
                const Eigen::Vector4d local = jt.end_site ? Eigen::Vector4d(jt.end_site->x(), jt.end_site->y(),
                                                                            jt.end_site->z(), 1.0)
                                                          : Eigen::Vector4d(0, 0, 0, 1);
                const v3d expected = (ref[j] * local).head<3>();
                CHECK((tips[j] - expected).cwiseAbs().maxCoeff() <= 1e-9);
                if (!jt.end_site) CHECK(tips[j] == pose.positions[j]);
            }
        }
    }
    SUBCASE("rest pose of a small skeleton") {
        anima::skeleton<double> sk;
        sk.add_joint("root", -1, v3d(1, 2, 3));
        sk.add_joint("a", 0, v3d(0, 1, 0));
        sk.add_joint("b", 1, v3d(1, 0, 0));
        sk.add_joint("c", 0, v3d(0, 0, -1));
        sk.set_end_site(2, v3d(0, 0, 2));
        sk.set_end_site(3, v3d(0, -4, 0));
        const auto [joints, ends] = anima::rest_positions(sk);
        REQUIRE(joints.size() == 4);
        CHECK(joints[0] == v3d(1, 2, 3));
        CHECK(joints[1] == v3d(1, 3, 3));
        CHECK(joints[2] == v3d(2, 3, 3));
        CHECK(joints[3] == v3d(1, 2, 2));
        REQUIRE(ends.size() == 2);
        CHECK(ends[0] == v3d(2, 3, 5));
        CHECK(ends[1] == v3d(1, -2, 2));
        const auto rest_empty = anima::rest_positions(anima::skeleton<double>());
        CHECK(rest_empty.first.empty());
        CHECK(rest_empty.second.empty());
    }
    SUBCASE("rest positions equal FK of a rest-pose clip (walk skeleton)") {
        const auto& sk = walk_clip<double>().skeleton();
        const anima::clip<double> rest(sk, 1, 0.1);
        const auto pose = anima::forward_kinematics(rest, 0);
        const auto [joints, ends] = anima::rest_positions(sk);
        for (std::size_t j = 0; j < sk.size(); ++j) CHECK((joints[j] - pose.positions[j]).norm() <= 1e-12);
        CHECK(ends.size() == 7);
        const auto tips = anima::end_site_positions(sk, pose);
        std::size_t k = 0;
        for (std::size_t j = 0; j < sk.size(); ++j)
            if (sk[j].end_site) CHECK((tips[j] - ends[k++]).norm() <= 1e-12);
    }
}

// =====================================================================================
// finite differences and velocities
// =====================================================================================

TEST_CASE_TEMPLATE("time_derivative: exact for a quadratic inside, one-sided at the ends", T, float, double) {
    using M = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const T dt = T(0.25);
    const int n = 9;
    // Column 0: 3t^2 - 2t + 1; column 1: 5 - 4t; column 2: constant.
    const auto f0 = [](T t) { return T(3) * t * t - T(2) * t + T(1); };
    M s(n, 3);
    for (int i = 0; i < n; ++i) {
        const T t = dt * T(i);
        s(i, 0) = f0(t);
        s(i, 1) = T(5) - T(4) * t;
        s(i, 2) = T(7);
    }
    const M d = anima::time_derivative(s, dt);
    REQUIRE(d.rows() == n);
    REQUIRE(d.cols() == 3);
    const T eps = tolerance<T>(1e-12, 1e-4);
    for (int i = 1; i + 1 < n; ++i) {
        const T t = dt * T(i);
        CHECK(std::abs(d(i, 0) - (T(6) * t - T(2))) <= eps);  // central differences are exact for quadratics
        CHECK(std::abs(d(i, 1) - T(-4)) <= eps);
        CHECK(std::abs(d(i, 2)) <= eps);
    }
    // One-sided: forward difference at the start = f'(0) + 3 dt, backward at the end = f'(T) - 3 dt.
    const T t_end = dt * T(n - 1);
    CHECK(std::abs(d(0, 0) - (T(-2) + T(3) * dt)) <= eps);
    CHECK(std::abs(d(0, 0) - (s(1, 0) - s(0, 0)) / dt) <= eps);
    CHECK(std::abs(d(n - 1, 0) - (T(6) * t_end - T(2) - T(3) * dt)) <= eps);
    CHECK(std::abs(d(n - 1, 0) - (s(n - 1, 0) - s(n - 2, 0)) / dt) <= eps);
    CHECK(std::abs(d(0, 1) - T(-4)) <= eps);
    CHECK(std::abs(d(n - 1, 1) - T(-4)) <= eps);

    // Any Eigen expression works (a block here).
    const M left = anima::time_derivative(s.leftCols(1), dt);
    CHECK(left.cols() == 1);
    CHECK((left - d.leftCols(1)).cwiseAbs().maxCoeff() == T(0));

    SUBCASE("0, 1 and 2 frames") {
        const M none = anima::time_derivative(M(0, 3), dt);
        CHECK(none.rows() == 0);
        CHECK(none.cols() == 3);
        const M one = anima::time_derivative(s.topRows(1), dt);
        REQUIRE(one.rows() == 1);
        CHECK(one.cwiseAbs().maxCoeff() == T(0));
        const M two = anima::time_derivative(s.topRows(2), dt);
        REQUIRE(two.rows() == 2);
        for (int k = 0; k < 3; ++k) {
            CHECK(two(0, k) == (s(1, k) - s(0, k)) / dt);
            CHECK(two(1, k) == (s(1, k) - s(0, k)) / dt);
        }
    }
    SUBCASE("dt must be positive and finite") {
        for (T bad : {T(0), T(-0.25), std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::infinity()})
            CHECK_THROWS_AS(anima::time_derivative(s, bad), anima::invalid_argument);
        CHECK_THROWS_AS(anima::time_derivative(M(0, 3), T(0)), anima::invalid_argument);
    }
}

TEST_CASE_TEMPLATE("joint_linear_velocities are the time derivative of global_positions", T, float, double) {
    using M = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const auto c = walk_clip<T>().slice(100, 130);
    const M p = anima::global_positions(c);
    REQUIRE(p.rows() == 30);
    REQUIRE(p.cols() == 93);
    // Rows of global_positions are the FK positions.
    for (std::size_t f : {std::size_t(0), std::size_t(17)}) {
        const auto pose = anima::forward_kinematics(c, f);
        for (std::size_t j = 0; j < c.joints(); ++j)
            for (int k = 0; k < 3; ++k)
                CHECK(p(static_cast<Eigen::Index>(f), static_cast<Eigen::Index>(3 * j) + k) == pose.positions[j][k]);
    }
    const M v = anima::joint_linear_velocities(c);
    REQUIRE(v.rows() == 30);
    REQUIRE(v.cols() == 93);
    const T dt = c.frame_time();
    const T eps = tolerance<T>(1e-9, 1e-3);
    T worst = 0;
    for (Eigen::Index f = 0; f < 30; ++f) {
        const Eigen::Index lo = f == 0 ? 0 : f - 1, hi = f == 29 ? 29 : f + 1;
        const M expected = (p.row(hi) - p.row(lo)) / (dt * T(hi - lo));
        worst = std::max(worst, (v.row(f) - expected).cwiseAbs().maxCoeff());
    }
    CHECK(worst <= eps);
    // The walk moves at roughly a metre per second (a CMU unit is about 5.6 cm).
    const T speed = std::hypot(v(15, 0), v(15, 2));
    CHECK(speed > T(5));
    CHECK(speed < T(60));
    // Empty and one-frame clips.
    CHECK(anima::joint_linear_velocities(c.slice(0, 0)).rows() == 0);
    const M one = anima::joint_linear_velocities(c.slice(3, 4));
    REQUIRE(one.rows() == 1);
    CHECK(one.cwiseAbs().maxCoeff() == T(0));
}

TEST_CASE_TEMPLATE("joint_angular_velocities of a constant-rate rotation equal that rate", T, float, double) {
    using V = Eigen::Matrix<T, 3, 1>;
    using Q = Eigen::Quaternion<T>;
    anima::skeleton<T> sk;
    sk.add_joint("root", -1, V::Zero(), {xp, yp, zp, zr, xr, yr});
    sk.add_joint("arm", 0, V(1, 0, 0), {zr, xr, yr});
    const T dt = T(1) / T(120);
    const std::size_t n = 50;
    anima::clip<T> c(sk, n, dt);
    const V axis = V(1, 2, 2) / T(3);
    const T rate = T(2.5);  // radians per second
    const Q q0(Eigen::AngleAxis<T>(T(0.8), V(0, 1, 0)));
    const V axis2 = V(0, 0, 1);
    const T rate2 = T(-7);
    for (std::size_t f = 0; f < n; ++f) {
        const T t = dt * T(f);
        c.set_rotation(f, 0, Q(Eigen::AngleAxis<T>(rate * t, axis)) * q0);
        c.set_rotation(f, 1, Q(Eigen::AngleAxis<T>(rate2 * t, axis2)));
    }
    const T eps = tolerance<T>(1e-9, 2e-3);
    const auto parent = anima::joint_angular_velocities(c, 0);
    const auto local = anima::joint_angular_velocities(c, 0, anima::angular_frame::local);
    const auto arm = anima::joint_angular_velocities(c, 1);
    REQUIRE(parent.size() == n);
    REQUIRE(local.size() == n);
    REQUIRE(arm.size() == n);
    const V expected_local = q0.conjugate() * (rate * axis);
    T worst = 0;
    for (std::size_t f = 0; f < n; ++f) {
        worst = std::max(worst, (parent[f] - rate * axis).cwiseAbs().maxCoeff());
        worst = std::max(worst, (local[f] - expected_local).cwiseAbs().maxCoeff());
        worst = std::max(worst, (arm[f] - rate2 * axis2).cwiseAbs().maxCoeff());
    }
    CHECK(worst <= eps);
    CHECK(anima::joint_angular_velocities(c.slice(0, 0), 0).empty());
    const auto single = anima::joint_angular_velocities(c.slice(2, 3), 1);
    REQUIRE(single.size() == 1);
    CHECK(single[0] == V::Zero());
    CHECK_THROWS_AS(anima::joint_angular_velocities(c, 2), anima::invalid_argument);
}

// =====================================================================================
// DOF view
// =====================================================================================

TEST_CASE("make_dof_layout of the walk clip: 3 translation DOFs and 3 per rotated joint") {
    const auto& c = walk_clip<double>();
    const auto layout = anima::make_dof_layout(c);
    REQUIRE(layout.size() == 3 + 3 * 31);
    REQUIRE(layout.reference.size() == 31);
    const auto& sk = c.skeleton();
    CHECK(layout.name(sk, 0) == "Hips.tx");
    CHECK(layout.name(sk, 1) == "Hips.ty");
    CHECK(layout.name(sk, 2) == "Hips.tz");
    CHECK(layout.name(sk, 3) == "Hips.rx");
    CHECK(layout.name(sk, 4) == "Hips.ry");
    CHECK(layout.name(sk, 5) == "Hips.rz");
    CHECK(layout.name(sk, 6) == "LHipJoint.rx");
    CHECK(layout.name(sk, 95) == "RThumb.rz");
    CHECK_THROWS(layout.name(sk, 96));
    for (std::size_t col = 0; col < layout.size(); ++col) {
        const auto& d = layout.dofs[col];
        CHECK(d.component == static_cast<int>(col % 3));
        CHECK(d.type == (col < 3 ? anima::dof::kind::translation : anima::dof::kind::rotation));
        CHECK(d.joint == (col < 3 ? 0 : (col - 3) / 3));
    }
    // The mean reference is a unit quaternion near the rotations it averages.
    for (std::size_t j = 0; j < 31; ++j) CHECK(std::abs(layout.reference[j].norm() - 1) <= 1e-12);
    const auto identity = anima::make_dof_layout(c, anima::dof_reference::identity);
    for (const auto& q : identity.reference) CHECK(q.coeffs() == Eigen::Quaterniond::Identity().coeffs());
    const auto first = anima::make_dof_layout(c, anima::dof_reference::first_frame);
    for (std::size_t j = 0; j < 31; ++j) CHECK(first.reference[j].coeffs() == c.rotation(0, j).coeffs());

    // Joints without rotation channels get no rotation DOFs; position-only joints get translation DOFs.
    const anima::clip<double> small(small_skeleton<double>(), 2, 0.1);
    const auto sl = anima::make_dof_layout(small);
    REQUIRE(sl.size() == 12);  // root t + r, spine r, slider t, fixed nothing
    CHECK(sl.name(small.skeleton(), 0) == "root.tx");
    CHECK(sl.name(small.skeleton(), 3) == "root.rx");
    CHECK(sl.name(small.skeleton(), 6) == "spine.rx");
    CHECK(sl.name(small.skeleton(), 9) == "slider.tx");
    CHECK(sl.name(small.skeleton(), 11) == "slider.tz");
}

TEST_CASE_TEMPLATE("to_dof_matrix / from_dof_matrix round trip for every reference", T, float, double) {
    using M = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const auto& c = walk_clip<T>();
    const T rot_eps = tolerance<T>(1e-9, 2e-5);
    const T pos_eps = tolerance<T>(1e-9, 1e-4);
    for (auto ref : {anima::dof_reference::identity, anima::dof_reference::first_frame, anima::dof_reference::mean}) {
        CAPTURE(static_cast<int>(ref));
        const auto layout = anima::make_dof_layout(c, ref);
        const M m = anima::to_dof_matrix(c, layout);
        REQUIRE(m.rows() == 343);
        REQUIRE(m.cols() == 96);
        CHECK(m.allFinite());
        for (Eigen::Index f = 0; f < 343; f += 57) CHECK(m(f, 1) == c.root_position(static_cast<std::size_t>(f))[1]);
        if (ref == anima::dof_reference::first_frame) CHECK(m.row(0).tail(93).cwiseAbs().maxCoeff() <= rot_eps);
        // Rotation DOFs are rotation vectors: |v| <= pi.
        for (Eigen::Index col = 3; col < 96; col += 3)
            CHECK(m.block(0, col, 343, 3).rowwise().norm().maxCoeff() <= anima::pi<T> + rot_eps);

        anima::clip<T> back(c.skeleton(), 5, c.frame_time());  // resized by from_dof_matrix
        anima::from_dof_matrix(m, layout, back);
        REQUIRE(back.frames() == c.frames());
        T worst_rot = 0, worst_pos = 0;
        for (std::size_t f = 0; f < c.frames(); ++f)
            for (std::size_t j = 0; j < c.joints(); ++j) {
                worst_rot = std::max(worst_rot, anima::angle_between(back.rotation(f, j), c.rotation(f, j)));
                worst_pos = std::max(worst_pos, (back.translation(f, j) - c.translation(f, j)).cwiseAbs().maxCoeff());
            }
        CHECK(worst_rot <= rot_eps);
        CHECK(worst_pos <= pos_eps);
    }
}

TEST_CASE("from_dof_matrix rejects a wrong column count and non-finite values, naming the DOF") {
    using M = Eigen::MatrixXd;
    const auto c = walk_clip<double>().slice(0, 4);
    const auto layout = anima::make_dof_layout(c);
    M m = anima::to_dof_matrix(c, layout);
    anima::clip<double> out(c.skeleton(), 0, c.frame_time());
    const std::string cols = invalid_argument_message([&] { anima::from_dof_matrix(M(m.leftCols(95)), layout, out); });
    CHECK(contains(cols, "95 columns"));
    CHECK_THROWS_AS(anima::from_dof_matrix(M(M::Zero(4, 97)), layout, out), anima::invalid_argument);
    m(2, 4) = std::numeric_limits<double>::quiet_NaN();
    const std::string nan = invalid_argument_message([&] { anima::from_dof_matrix(m, layout, out); });
    CHECK(contains(nan, "frame 2"));
    CHECK(contains(nan, "Hips.ry"));
    m(2, 4) = 0;
    m(3, 8) = std::numeric_limits<double>::infinity();
    const std::string inf = invalid_argument_message([&] { anima::from_dof_matrix(m, layout, out); });
    CHECK(contains(inf, "frame 3"));
    CHECK(contains(inf, "LHipJoint.rz"));
    CHECK(out.frames() == 0);  // nothing written on failure
    // A layout from another skeleton.
    anima::clip<double> small(small_skeleton<double>(), 2, 0.1);
    CHECK_THROWS_AS(anima::to_dof_matrix(small, layout), anima::invalid_argument);
    CHECK_THROWS_AS(anima::from_dof_matrix(M(M::Zero(2, 96)), layout, small), anima::invalid_argument);
    CHECK(small.frames() == 2);
}

TEST_CASE("DOF view of an empty clip") {
    const auto empty = walk_clip<double>().slice(0, 0);
    for (auto ref : {anima::dof_reference::identity, anima::dof_reference::first_frame, anima::dof_reference::mean}) {
        const auto layout = anima::make_dof_layout(empty, ref);
        CHECK(layout.size() == 96);
        for (const auto& q : layout.reference) CHECK(q.coeffs() == Eigen::Quaterniond::Identity().coeffs());
        const Eigen::MatrixXd m = anima::to_dof_matrix(empty, layout);
        CHECK(m.rows() == 0);
        CHECK(m.cols() == 96);
        anima::clip<double> out = walk_clip<double>().slice(0, 3);
        anima::from_dof_matrix(m, layout, out);
        CHECK(out.frames() == 0);
        // And back up from empty.
        const auto some = walk_clip<double>().slice(10, 12);
        anima::from_dof_matrix(anima::to_dof_matrix(some, layout), layout, out);
        REQUIRE(out.frames() == 2);
        CHECK(anima::angle_between(out.rotation(1, 4), some.rotation(1, 4)) <= 1e-9);
    }
}

// =====================================================================================
// figure guesses and reorientation
// =====================================================================================

TEST_CASE("parse_signed_axis reads back what to_string writes, in any case, the sign optional; try_parse_signed_axis is empty where it throws") {
    for (const anima::axis a : {anima::axis::x, anima::axis::y, anima::axis::z})
        for (const int sign : {1, -1}) {
            const anima::signed_axis s{a, sign};
            CHECK(anima::parse_signed_axis(anima::to_string(s)) == s);
            CHECK(anima::parse_signed_axis(anima::ascii_lower(anima::to_string(s))) == s);
        }
    CHECK(anima::parse_signed_axis("Z") == anima::signed_axis{anima::axis::z, 1});
    CHECK(anima::try_parse_signed_axis("-x") == anima::signed_axis{anima::axis::x, -1});
    for (const char* bad : {"", "+", "-", "W", "+XY", "++X", " X", "X "}) {
        CHECK_FALSE(anima::try_parse_signed_axis(bad));
        const std::string expected = "anima::parse_signed_axis: '" + std::string(bad) + "' is not a signed axis";
        CHECK_THROWS_WITH_AS(anima::parse_signed_axis(bad), doctest::Contains(expected.c_str()), anima::invalid_argument);
    }
}

TEST_CASE("guess_up_axis and guess_units on the bundled clips") {
    const auto& walk = walk_clip<double>().skeleton();
    const auto& run = run_clip<double>().skeleton();
    const anima::signed_axis plus_y{anima::axis::y, 1};
    for (const auto* sk : {&walk, &run}) {
        const auto g = anima::guess_up_axis(*sk);
        CHECK(g.confident);
        CHECK(g.up == plus_y);
        CHECK(anima::to_string(g.up) == "+Y");
    }
    const auto run_units = anima::guess_units(run, plus_y);
    CHECK(run_units.name == "centimetres");
    CHECK(run_units.metres_per_unit == 0.01);
    CHECK(run_units.confident);
    CHECK(run_units.height > 140);
    CHECK(run_units.height < 190);
    const auto walk_units = anima::guess_units(walk, plus_y);
    CHECK(walk_units.name == "cmu-asf");
    CHECK(walk_units.metres_per_unit == doctest::Approx(0.056444));
    CHECK(walk_units.confident);
    CHECK(walk_units.height > 20);
    CHECK(walk_units.height < 30);
    // float gives the same answers.
    CHECK(anima::guess_up_axis(run_clip<float>().skeleton()).up == plus_y);
    CHECK(anima::guess_units(walk_clip<float>().skeleton(), plus_y).name == "cmu-asf");
}

TEST_CASE("guess_up_axis and guess_units on synthetic figures") {
    SUBCASE("no head or foot names: not confident, +Y assumed") {
        anima::skeleton<double> sk;
        sk.add_joint("a", -1, v3d::Zero());
        sk.add_joint("b", 0, v3d(0, 0, 1));
        sk.add_joint("c", 1, v3d(0, 0, 1));
        const auto g = anima::guess_up_axis(sk);
        CHECK_FALSE(g.confident);
        CHECK(g.up == anima::signed_axis{anima::axis::y, 1});
        CHECK_FALSE(anima::guess_up_axis(anima::skeleton<double>()).confident);
    }
    SUBCASE("a head along -X") {
        anima::skeleton<double> sk;
        sk.add_joint("pelvis", -1, v3d::Zero());
        sk.add_joint("Neck", 0, v3d(-0.5, 0.1, 0));
        sk.add_joint("HEAD", 1, v3d(-0.2, 0, 0.05));
        const auto g = anima::guess_up_axis(sk);
        CHECK(g.confident);
        CHECK(g.up == anima::signed_axis{anima::axis::x, -1});
    }
    SUBCASE("only feet, Z up, metres") {
        anima::skeleton<double> sk;
        sk.add_joint("pelvis", -1, v3d(0, 0, 1.0));
        sk.add_joint("l_knee", 0, v3d(0.1, 0, -0.5));
        sk.add_joint("left_ankle", 1, v3d(0, 0, -0.45));
        sk.set_end_site(2, v3d(0, 0.1, -0.05));
        sk.add_joint("spine", 0, v3d(0, 0, 0.7));
        const auto g = anima::guess_up_axis(sk);
        CHECK(g.confident);
        CHECK(g.up == anima::signed_axis{anima::axis::z, 1});
        const auto u = anima::guess_units(sk, g.up);
        CHECK(u.height == doctest::Approx(1.7));
        CHECK(u.name == "metres");
        CHECK(u.confident);
        const auto mm = anima::guess_units(sk, anima::signed_axis{anima::axis::x, 1});  // height 0.1 along X
        CHECK_FALSE(mm.confident);
        CHECK(anima::guess_units(anima::skeleton<double>(), g.up).name == "unknown");
    }
}

TEST_CASE("change_up_axis rotates every global position by R") {
    using T = double;
    using V = Eigen::Matrix<T, 3, 1>;
    using M = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const anima::signed_axis plus_y{anima::axis::y, 1}, plus_z{anima::axis::z, 1};
    // R takes +Y to +Z: a quarter turn about +X.
    Eigen::Matrix<T, 3, 3> r;
    r << 1, 0, 0, 0, 0, -1, 0, 1, 0;
    for (const auto* source : {&walk_clip<T>(), &run_clip<T>()}) {
        const auto c = source->slice(0, std::min<std::size_t>(source->frames(), 120));
        const auto z_up = anima::change_up_axis(c, plus_y, plus_z);
        const auto g = anima::guess_up_axis(z_up.skeleton());
        CHECK(g.confident);
        CHECK(g.up == plus_z);
        REQUIRE(z_up.frames() == c.frames());
        const M p = anima::global_positions(c), q = anima::global_positions(z_up);
        T worst = 0;
        for (Eigen::Index f = 0; f < p.rows(); ++f)
            for (Eigen::Index j = 0; j < p.cols(); j += 3) {
                const V a = p.row(f).segment(j, 3).transpose(), b = q.row(f).segment(j, 3).transpose();
                worst = std::max(worst, (b - r * a).cwiseAbs().maxCoeff() / std::max(T(1), a.norm()));
            }
        CHECK(worst <= tolerance<T>(1e-12, 1e-5));
        // Global orientations become R G R^-1.
        const auto pa = anima::forward_kinematics(c, 7), pb = anima::forward_kinematics(z_up, 7);
        for (std::size_t j = 0; j < c.joints(); ++j) {
            const Eigen::Matrix<T, 3, 3> expected = r * pa.orientations[j].toRotationMatrix() * r.transpose();
            CHECK((pb.orientations[j].toRotationMatrix() - expected).cwiseAbs().maxCoeff() <=
                  tolerance<T>(1e-12, 1e-5));
        }
    }
    // Every target direction is recognised afterwards.
    const auto one = walk_clip<T>().slice(0, 1);
    for (int a = 0; a < 3; ++a)
        for (int s : {1, -1}) {
            const anima::signed_axis to{static_cast<anima::axis>(a), s};
            CAPTURE(anima::to_string(to));
            CHECK(anima::guess_up_axis(anima::change_up_axis(one, plus_y, to).skeleton()).up == to);
        }
}

TEST_CASE_TEMPLATE("scale_clip scales global positions; with_rotation_order keeps the motion", T, float, double) {
    using M = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    const auto c = run_clip<T>().slice(0, 40);
    const M p = anima::global_positions(c);
    const T s = T(0.01);
    const auto scaled = anima::scale_clip(c, s);
    const M ps = anima::global_positions(scaled);
    const T size = std::max(T(1), p.cwiseAbs().maxCoeff());
    const T pos_eps = tolerance<T>(1e-12, 1e-6) * size, rot_eps = tolerance<T>(1e-14, 1e-6);
    CHECK((ps - s * p).cwiseAbs().maxCoeff() <= s * pos_eps);
    for (std::size_t f = 0; f < c.frames(); f += 13)
        for (std::size_t j = 0; j < c.joints(); ++j)
            CHECK(anima::angle_between(scaled.rotation(f, j), c.rotation(f, j)) <= rot_eps);
    CHECK(anima::guess_units(scaled.skeleton(), {anima::axis::y, 1}).name == "metres");
    for (T bad : {T(0), T(-1), std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::infinity()})
        CHECK_THROWS_AS(anima::scale_clip(c, bad), anima::invalid_argument);
    // Scalar arguments take their type from the clip: double literals work on
    // a float clip (this failed to compile for float before).
    CHECK(anima::scale_clip(c, 2.0).skeleton()[1].offset == T(2) * c.skeleton()[1].offset);
    CHECK(anima::resample(c, 1.0 / 60).frame_time() == T(1.0 / 60));
    CHECK(anima::starts_at_rest_pose(c, 10.0) == anima::starts_at_rest_pose(c));
    CHECK(anima::rest_pose_lead_in(c, 10.0) == anima::rest_pose_lead_in(c));
    // A finite scale that overflows a position names scale_clip, not clip::set_translation.
    CHECK_THROWS_WITH_AS(anima::scale_clip(c, std::numeric_limits<T>::max() / T(10)),
                         doctest::Contains("anima::scale_clip: scale"), anima::invalid_argument);

    for (auto order : {anima::euler_order::xyz, anima::euler_order::xzy, anima::euler_order::yxz,
                       anima::euler_order::yzx, anima::euler_order::zxy, anima::euler_order::zyx}) {
        CAPTURE(anima::to_string(order));
        const auto o = anima::with_rotation_order(c, order);
        const auto ax = anima::axes_of(order);
        const std::vector<channel> rot = {static_cast<channel>(3 + static_cast<int>(ax[0])),
                                          static_cast<channel>(3 + static_cast<int>(ax[1])),
                                          static_cast<channel>(3 + static_cast<int>(ax[2]))};
        std::vector<channel> root = {xp, yp, zp};
        root.insert(root.end(), rot.begin(), rot.end());
        CHECK(o.skeleton()[0].channels == root);
        for (std::size_t j = 1; j < o.joints(); ++j) CHECK(o.skeleton()[j].channels == rot);
        CHECK(o.skeleton().channel_count() == c.skeleton().channel_count());
        CHECK((anima::global_positions(o) - p).cwiseAbs().maxCoeff() <= pos_eps);
        for (std::size_t f = 0; f < c.frames(); f += 13) {
            const auto pa = anima::forward_kinematics(c, f), pb = anima::forward_kinematics(o, f);
            T worst = 0;
            for (std::size_t j = 0; j < c.joints(); ++j)
                worst = std::max(worst, anima::angle_between(pa.orientations[j], pb.orientations[j]));
            CHECK(worst <= tolerance<T>(1e-13, 1e-5));
        }
    }
    // Joints without rotation channels stay without them.
    const anima::clip<T> small(small_skeleton<T>(), 1, T(0.1));
    const auto o = anima::with_rotation_order(small, anima::euler_order::xyz);
    CHECK(o.skeleton()[2].channels == std::vector<channel>{xp, yp, zp});
    CHECK(o.skeleton()[3].channels.empty());
    CHECK(o.skeleton()[0].channels == std::vector<channel>{xp, yp, zp, xr, yr, zr});
}

namespace {

TEST_CASE_TEMPLATE("check_same_hierarchy: names, parents and position channels, not offsets", T, float, double) {
    const auto& walk = walk_clip<T>().skeleton();
    const auto& run = run_clip<T>().skeleton();
    anima::check_same_hierarchy(walk, walk);
    // Other bone lengths and rotation orders are the same hierarchy.
    anima::skeleton<T> longer;
    for (std::size_t j = 0; j < walk.size(); ++j) {
        std::vector<channel> channels = walk[j].channels;
        std::reverse(channels.begin() + (walk.has_position_channels(j) ? 3 : 0), channels.end());
        longer.add_joint(walk[j].name, walk[j].parent, T(1.5) * walk[j].offset, channels);
    }
    anima::check_same_hierarchy(walk, longer);
    // A renamed joint is named with its index.
    anima::skeleton<T> renamed;
    for (std::size_t j = 0; j < walk.size(); ++j)
        renamed.add_joint(j == 5 ? std::string("knee") : walk[j].name, walk[j].parent, walk[j].offset, walk[j].channels);
    std::string e = invalid_argument_message([&] { anima::check_same_hierarchy(walk, renamed); });
    CHECK(contains(e, "joint 5"));
    CHECK(contains(e, "'knee'"));
    // Another layout altogether, and a prefix of the same one.
    CHECK(!invalid_argument_message([&] { anima::check_same_hierarchy(walk, run); }).empty());
    anima::skeleton<T> prefix;
    for (std::size_t j = 0; j + 1 < walk.size(); ++j) prefix.add_joint(walk[j].name, walk[j].parent, walk[j].offset, walk[j].channels);
    e = invalid_argument_message([&] { anima::check_same_hierarchy(walk, prefix); });
    CHECK(contains(e, std::to_string(walk.size()) + " vs " + std::to_string(walk.size() - 1)));
    CHECK(contains(e, walk[walk.size() - 1].name));
}

TEST_CASE("largest_dof_change: the largest change of a rotation DOF and of a translation DOF") {
    const auto& c = walk_clip<double>();
    const auto layout = anima::make_dof_layout(c);
    const Eigen::MatrixXd before = anima::to_dof_matrix(c, layout);
    Eigen::MatrixXd after = before;
    after(10, 1) += 0.5;    // Hips.ty
    after(20, 2) -= 2.0;    // Hips.tz
    after(5, 40) -= 0.25;   // a rotation
    after(300, 95) += 0.1;  // RThumb.rz
    const auto change = anima::largest_dof_change(before, after, layout);
    CHECK(change.rotation == doctest::Approx(0.25));
    CHECK(change.translation == doctest::Approx(2.0));
    const auto none = anima::largest_dof_change(before, before, layout);
    CHECK(none.rotation == 0);
    CHECK(none.translation == 0);
    CHECK_THROWS_AS(anima::largest_dof_change(before, Eigen::MatrixXd(after.leftCols(95)), layout), anima::invalid_argument);
}

TEST_CASE("lowest_along: the lowest joint or End Site over every frame") {
    const auto& c = walk_clip<double>();
    const v3d up(0, 1, 0);
    double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
    for (std::size_t f = 0; f < c.frames(); ++f) {
        const auto pose = anima::forward_kinematics(c, f);
        auto points = anima::end_site_positions(c.skeleton(), pose);
        points.insert(points.end(), pose.positions.begin(), pose.positions.end());
        for (const auto& p : points) {
            lowest = std::min(lowest, p.y());
            highest = std::max(highest, p.y());
        }
    }
    CHECK(anima::lowest_along(c, up) == lowest);
    CHECK(anima::lowest_along(c, v3d(-up)) == -highest);
    CHECK(anima::lowest_along(anima::clip<double>(c.skeleton(), 0, c.frame_time()), up) ==
          std::numeric_limits<double>::infinity());
}

TEST_CASE("rotation_orders lists each order of rotation channels once, in order of first appearance") {
    CHECK(anima::rotation_orders(small_skeleton<double>()) == std::vector<std::string>{"ZXY"});
    anima::skeleton<double> sk;
    sk.add_joint("a", -1, v3d::Zero(), {xp, yp, zp, yr, xr, zr});
    sk.add_joint("b", 0, v3d::Zero(), {zr});
    sk.add_joint("c", 1, v3d::Zero(), {yr, xr, zr});
    sk.add_joint("d", 2, v3d::Zero());
    sk.add_joint("e", 3, v3d::Zero(), {xr, zr});
    CHECK(anima::rotation_orders(sk) == std::vector<std::string>{"YXZ", "Z", "XZ"});
    CHECK(anima::rotation_orders(anima::skeleton<double>()).empty());
}

TEST_CASE("depth_first_order visits each joint once, children in index order, with its depth") {
    anima::skeleton<double> sk;
    sk.add_joint("a", -1, v3d::Zero());  // 0
    sk.add_joint("b", 0, v3d::Zero());   // 1
    sk.add_joint("c", -1, v3d::Zero());  // 2: a second root
    sk.add_joint("d", 0, v3d::Zero());   // 3
    sk.add_joint("e", 1, v3d::Zero());   // 4
    sk.add_joint("f", 2, v3d::Zero());   // 5
    using order = std::vector<std::pair<std::size_t, std::size_t>>;
    CHECK(anima::depth_first_order(sk) == order{{0, 0}, {1, 1}, {4, 2}, {3, 1}, {2, 0}, {5, 1}});
    CHECK(anima::depth_first_order(anima::skeleton<double>()).empty());
    // A chain of 100000 joints: no recursion, so no stack overflow.
    anima::skeleton<double> chain;
    for (int j = 0; j < 100000; ++j) chain.add_joint("j" + std::to_string(j), j - 1, v3d::Zero());
    const auto deep = anima::depth_first_order(chain);
    REQUIRE(deep.size() == 100000);
    CHECK(deep.back() == std::pair<std::size_t, std::size_t>{99999, 99999});
}

}  // namespace
