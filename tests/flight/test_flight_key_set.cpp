// anima::parse_flight_key_set / read_flight_key_set / somersault_key_set:
// a key set written out by hand reads back to the keys it was written from,
// Euler keys give the rotations of their axes, and every bad member is
// reported with the file and its line.
#include "../test_support.hpp"

#include <anima/bvh/reader.hpp>
#include <anima/flight/key_set.hpp>
#include <anima/flight/somersault.hpp>

#include <doctest/doctest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

std::string number(double v) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.17g", v);
    return buffer;
}

/// A folder with a copy of the bundled walk, for key files that name their
/// skeleton relative to themselves.
struct key_folder {
    fs::path dir;
    key_folder() {
        dir = fs::temp_directory_path() / ("anima_key_set_" + std::to_string(std::random_device{}()));
        fs::create_directories(dir);
        fs::copy_file(anima_test::bundled("walk_cmu31_02_01.bvh"), dir / "walk.bvh");
    }
    ~key_folder() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(dir / name) << text;
        return (dir / name).string();
    }
};

template <class T>
std::string parse_error_of(const key_folder& folder, const std::string& text) {
    const std::string path = folder.write("bad.json", text);
    try {
        anima::read_flight_key_set<T>(path);
    } catch (const anima::parse_error& e) {
        CHECK(e.file() == path);
        return std::to_string(e.line()) + ": " + e.message();
    }
    return "";
}

const char* const two_keys_head = "{\"skeleton\": \"walk.bvh\", \"keys\": [\n";

}  // namespace

TEST_CASE_TEMPLATE("a key set written from the somersault reads back to its keys and settings", T, float, double) {
    const key_folder folder;
    const auto sk = anima::read_bvh<T>((folder.dir / "walk.bvh").string()).skeleton();
    const auto expected = anima::somersault_key_set<T>(sk, {T(62)});
    // The test's own writer: every rotation as a quaternion, by joint name.
    std::string json = "{\"skeleton\": \"walk.bvh\", \"body_mass\": 62, \"sex\": \"male\",\n";
    json += "\"gravity\": [0, -9.81, 0], \"root_tolerance\": 0.05, \"joint_tolerance\": 0.1,\n";
    const auto& b = *expected.settings.ballistic;
    json += "\"ballistic\": {\"start\": [" + number(b.start[0]) + ", " + number(b.start[1]) + ", " + number(b.start[2]) +
            "], \"velocity\": [" + number(b.velocity[0]) + ", " + number(b.velocity[1]) + ", " +
            number(b.velocity[2]) + "]},\n\"keys\": [\n";
    for (std::size_t k = 0; k < expected.keys.size(); ++k) {
        const auto& p = expected.keys.root_positions[k];
        json += std::string(k ? ",\n" : "") + "{\"time\": " + number(expected.keys.times[k]) + ", \"root_position\": [" +
                number(p[0]) + ", " + number(p[1]) + ", " + number(p[2]) + "], \"rotations\": {";
        for (std::size_t j = 0; j < sk.size(); ++j) {
            const auto& q = expected.keys.rotations[k][j];
            json += std::string(j ? ", " : "") + "\"" + sk[j].name + "\": {\"quaternion\": [" + number(q.w()) +
                    ", " + number(q.x()) + ", " + number(q.y()) + ", " + number(q.z()) + "]}";
        }
        json += "}}";
    }
    json += "]}\n";
    const auto got = anima::read_flight_key_set<T>(folder.write("somersault.json", json));

    CHECK(got.name == "somersault.json");
    CHECK(got.skeleton.size() == sk.size());
    CHECK(got.model.total_mass() == doctest::Approx(62.0));
    CHECK(got.metres_per_unit == doctest::Approx(anima::default_metres_per_unit(sk)));
    REQUIRE(got.keys.size() == expected.keys.size());
    REQUIRE(got.settings.ballistic.has_value());
    CHECK(got.settings.ballistic->velocity.isApprox(b.velocity));
    for (std::size_t k = 0; k < got.keys.size(); ++k) {
        CHECK(got.keys.times[k] == expected.keys.times[k]);
        CHECK(got.keys.root_positions[k] == expected.keys.root_positions[k]);
        for (std::size_t j = 0; j < sk.size(); ++j)
            CHECK(got.keys.rotations[k][j].coeffs() == expected.keys.rotations[k][j].coeffs());
    }
}

TEST_CASE_TEMPLATE("key set defaults and Euler keys", T, float, double) {
    const key_folder folder;
    const std::string path = folder.write(
        "keys.json", std::string(two_keys_head) +
                         "{\"time\": 0, \"rotations\": {\"LeftArm\": {\"euler_degrees\": [10, 20, 30], \"order\": "
                         "\"ZXY\"}}},\n"
                         "{\"time\": 0.5, \"root_position\": [1, 2, 3], \"rotations\": {\"Hips\": {\"euler_degrees\": "
                         "[90, 0, 0], \"order\": \"xyz\"}}}]}");
    const auto got = anima::read_flight_key_set<T>(path, {T(80)});
    using quat = Eigen::Quaternion<T>;
    using vec3 = Eigen::Matrix<T, 3, 1>;
    const auto deg = [](double d) { return static_cast<T>(d * 3.14159265358979323846 / 180.0); };
    CHECK(got.model.total_mass() == doctest::Approx(80.0));  // the caller's default
    CHECK_FALSE(got.settings.ballistic.has_value());
    CHECK(got.settings.gravity == vec3(T(0), T(-9.81), T(0)));
    CHECK(got.keys.root_positions[0] == vec3::Zero());
    CHECK(got.keys.root_positions[1] == vec3(T(1), T(2), T(3)));
    const std::size_t arm = *got.skeleton.find("LeftArm"), hips = *got.skeleton.find("Hips");
    // ZXY: Rz(a0) Rx(a1) Ry(a2), composed here from Eigen's axis-angles.
    const quat zxy = quat(Eigen::AngleAxis<T>(deg(10), vec3::UnitZ())) * quat(Eigen::AngleAxis<T>(deg(20), vec3::UnitX())) *
                     quat(Eigen::AngleAxis<T>(deg(30), vec3::UnitY()));
    CHECK(got.keys.rotations[0][arm].angularDistance(zxy) < T(1e-5));
    CHECK(got.keys.rotations[1][hips].angularDistance(quat(Eigen::AngleAxis<T>(deg(90), vec3::UnitX()))) < T(1e-5));
    // Joints a key does not name keep the rest rotation.
    CHECK(got.keys.rotations[0][hips].coeffs() == quat::Identity().coeffs());
    CHECK(got.keys.rotations[1][arm].coeffs() == quat::Identity().coeffs());
}

TEST_CASE("a key set with an absolute skeleton path reads from any folder") {
    const key_folder folder;
    const std::string path = folder.write(
        "abs.json", "{\"skeleton\": \"" + anima_test::bundled("walk_cmu31_02_01.bvh") +
                        "\", \"sex\": \"female\", \"keys\": [{\"time\": 0}, {\"time\": 1}]}");
    const auto got = anima::read_flight_key_set<double>(path);
    CHECK(got.keys.size() == 2);
    CHECK(got.model.total_mass() == doctest::Approx(70.0));
}

TEST_CASE_TEMPLATE("every bad member of a key set is reported with its line", T, float, double) {
    const key_folder folder;
    CHECK(parse_error_of<T>(folder, "[1, 2]") == "1: a key set is a JSON object");
    CHECK(parse_error_of<T>(folder, "{\"keys\": []}") == "1: missing \"skeleton\"");
    CHECK(parse_error_of<T>(folder, "{\"skeleton\": 3}") == "1: \"skeleton\" must be a string, got a number");
    CHECK(parse_error_of<T>(folder, "{\"skeleton\": \"walk.bvh\"}") == "1: missing \"keys\"");
    CHECK(parse_error_of<T>(folder, "{\"skeleton\": \"walk.bvh\",\n \"sex\": \"other\", \"keys\": []}") ==
          "2: \"sex\" must be \"male\" or \"female\", got \"other\"");
    CHECK(parse_error_of<T>(folder, "{\"skeleton\": \"walk.bvh\", \"gravity\": [0, 1], \"keys\": []}") ==
          "1: \"gravity\" must be an array of 3 numbers");
    CHECK(parse_error_of<T>(folder, std::string(two_keys_head) + "{\"time\": 0},\n{\"tme\": 1}]}") ==
          "3: missing \"time\"");
    CHECK(parse_error_of<T>(folder, std::string(two_keys_head) + "{\"time\": 0},\n 5]}") ==
          "3: \"keys[1]\" must be an object, got a number");
    CHECK(parse_error_of<T>(folder, std::string(two_keys_head) +
                                        "{\"time\": 0, \"rotations\": {\n\"Nose\": {\"quaternion\": [1, 0, 0, 0]}}}]}") ==
          "3: \"Nose\": the skeleton has no joint of that name");
    CHECK(parse_error_of<T>(folder, std::string(two_keys_head) +
                                        "{\"time\": 0, \"rotations\": {\"Hips\":\n {\"quaternion\": [1, 0, 0]}}}]}") ==
          "3: \"quaternion\" of \"Hips\" must be [w, x, y, z]");
    CHECK(parse_error_of<T>(folder, std::string(two_keys_head) +
                                        "{\"time\": 0, \"rotations\": {\"Hips\": {\"euler_degrees\": [1, 2, 3], "
                                        "\"order\": \"ZZY\"}}}]}")
              .rfind("2: \"Hips\": anima::parse_euler_order: 'ZZY'", 0) == 0);
    CHECK(parse_error_of<T>(folder, std::string(two_keys_head) + "{\"time\": 0, \"rotations\": {\"Hips\": {}}}]}") ==
          "2: \"Hips\": give \"quaternion\" or \"euler_degrees\"");
    CHECK(parse_error_of<T>(folder, "{\"skeleton\": \"walk.bvh\", \"body_mass\": -1, \"keys\": []}")
              .rfind("1: anima::make_body_model: body_mass must be positive", 0) == 0);
    CHECK(parse_error_of<T>(folder, "{\"skeleton\": \"walk.bvh\",\n\"keys\": [}") ==
          "2: unexpected '}', a value was expected");
    // A skeleton that is not there is an I/O error naming the BVH file.
    const std::string missing = folder.write("missing.json", "{\"skeleton\": \"nowhere.bvh\", \"keys\": []}");
    CHECK_THROWS_WITH_AS(anima::read_flight_key_set<T>(missing), doctest::Contains("nowhere.bvh"), anima::io_error);
}
