// BVH reader and writer: the bundled CMU clips, document- and clip-level round
// trips (also on the shared clip set when it is present), odd but valid
// formatting, and malformed input, which must raise anima::parse_error with
// the right line.
#include <anima/bvh/document.hpp>
#include <anima/bvh/reader.hpp>
#include <anima/bvh/value_decimals.hpp>
#include <anima/bvh/writer.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/reorient.hpp>
#include <anima/rotation/quaternion.hpp>

#include "../test_support.hpp"

#include <doctest/doctest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;
using anima::channel;
using v3d = Eigen::Vector3d;

constexpr channel xp = channel::x_position, yp = channel::y_position, zp = channel::z_position;
constexpr channel xr = channel::x_rotation, yr = channel::y_rotation, zr = channel::z_rotation;

constexpr double rad_to_deg = 180.0 / 3.14159265358979323846;

// Six decimals keep every number within half a unit of the sixth decimal. A
// file value that is a decimal midpoint (0.0766935 in run_cmu_09_01.bvh) comes
// back exactly 5e-7 away, which the subtraction in double evaluates as
// 5.0000000000050e-7: the bound allows for that representation error only.
constexpr double half_unit = 5e-7 * (1 + 1e-9);

std::string data_path(const char* name) { return std::string(ANIMA_TEST_DATA_DIR) + "/" + name; }

using anima_test::contains;
bool starts_with(const std::string& s, const std::string& prefix) { return s.compare(0, prefix.size(), prefix) == 0; }

// A temporary file path, removed when the guard goes out of scope.
struct temp_file {
    fs::path path;
    explicit temp_file(const std::string& name) : path(fs::temp_directory_path() / name) { fs::remove(path); }
    ~temp_file() {
        std::error_code ec;
        fs::remove(path, ec);
    }
    temp_file(const temp_file&) = delete;
    temp_file& operator=(const temp_file&) = delete;
};

// ---- a tiny three-joint file, line by line (index i is line i + 1) ----
//  1 HIERARCHY            9 CHANNELS (mid)      17 }   (End Site)     25 frame 2
//  2 ROOT root           10 JOINT tip           18 }   (tip)
//  3 {                   11 {                   19 }   (mid)
//  4 OFFSET (root)       12 OFFSET (tip)        20 }   (root)
//  5 CHANNELS (root)     13 CHANNELS (tip)      21 MOTION
//  6 JOINT mid           14 End Site            22 Frames: 2
//  7 {                   15 {                   23 Frame Time: 0.1
//  8 OFFSET (mid)        16 OFFSET (end site)   24 frame 1
std::vector<std::string> tiny_lines() {
    return {"HIERARCHY",
            "ROOT root",
            "{",
            "\tOFFSET 0 0 0",
            "\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation",
            "\tJOINT mid",
            "\t{",
            "\t\tOFFSET 0 1 0",
            "\t\tCHANNELS 3 Zrotation Xrotation Yrotation",
            "\t\tJOINT tip",
            "\t\t{",
            "\t\t\tOFFSET 0 2 0",
            "\t\t\tCHANNELS 3 Zrotation Xrotation Yrotation",
            "\t\t\tEnd Site",
            "\t\t\t{",
            "\t\t\t\tOFFSET 0 1 0",
            "\t\t\t}",
            "\t\t}",
            "\t}",
            "}",
            "MOTION",
            "Frames: 2",
            "Frame Time: 0.1",
            "1 2 3 10 20 30 0 0 0 5 5 5",
            "4 5 6 -10 -20 -30 1 2 3 0 0 0"};
}

std::string join(const std::vector<std::string>& lines, const std::string& eol = "\n", bool final_eol = true) {
    std::string out;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        out += lines[i];
        if (i + 1 < lines.size() || final_eol) out += eol;
    }
    return out;
}
std::string tiny() { return join(tiny_lines()); }

// The tiny file with line `number` (1-based) replaced.
std::string tiny_with(std::size_t number, const std::string& line, bool final_eol = true) {
    auto lines = tiny_lines();
    lines.at(number - 1) = line;
    return join(lines, "\n", final_eol);
}
// The tiny file with several lines replaced.
std::string tiny_edited(std::initializer_list<std::pair<std::size_t, std::string>> edits) {
    auto lines = tiny_lines();
    for (const auto& e : edits) lines.at(e.first - 1) = e.second;
    return join(lines);
}
// The tiny file without line `number`.
std::string tiny_without(std::size_t number) {
    auto lines = tiny_lines();
    lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(number - 1));
    return join(lines);
}
// The first `count` lines, without a final newline.
std::string tiny_first(std::size_t count, const std::string& extra = "") {
    auto lines = tiny_lines();
    lines.resize(count);
    if (!extra.empty()) lines.push_back(extra);
    return join(lines, "\n", false);
}

void check_same_document(const anima::bvh_document<double>& a, const anima::bvh_document<double>& b) {
    CHECK(a.skeleton == b.skeleton);
    CHECK(a.frames == b.frames);
    CHECK(a.frame_time == b.frame_time);
    CHECK(a.values == b.values);
}

// ---- round trips ----

// Same joints, parents, channels and End Sites; offsets within half a unit of the sixth decimal.
void check_same_skeleton(const anima::skeleton<double>& a, const anima::skeleton<double>& b) {
    REQUIRE(b.size() == a.size());
    for (std::size_t j = 0; j < a.size(); ++j) {
        CHECK(b[j].name == a[j].name);
        CHECK(b[j].parent == a[j].parent);
        CHECK(b[j].channels == a[j].channels);
        CHECK((b[j].offset - a[j].offset).cwiseAbs().maxCoeff() <= half_unit);
        REQUIRE(b[j].end_site.has_value() == a[j].end_site.has_value());
        if (a[j].end_site) CHECK((*b[j].end_site - *a[j].end_site).cwiseAbs().maxCoeff() <= half_unit);
    }
}

// Document level: format_bvh(document) then parse; returns the largest channel-value change.
double document_round_trip(const anima::bvh_document<double>& doc) {
    const auto back = anima::parse_bvh_document<double>(anima::format_bvh(doc), "round-trip");
    check_same_skeleton(doc.skeleton, back.skeleton);
    CHECK(back.frames == doc.frames);
    CHECK(back.frame_time == doc.frame_time);  // written in the shortest exact form
    REQUIRE(back.values.size() == doc.values.size());
    double worst = 0;
    for (std::size_t i = 0; i < doc.values.size(); ++i) worst = std::max(worst, std::abs(back.values[i] - doc.values[i]));
    return worst;
}

struct clip_errors {
    double degrees = 0;  // largest angle_between of local rotations
    double units = 0;    // largest local translation difference
};
clip_errors compare_clips(const anima::clip<double>& a, const anima::clip<double>& b) {
    REQUIRE(a.frames() == b.frames());
    REQUIRE(a.joints() == b.joints());
    clip_errors e;
    for (std::size_t f = 0; f < a.frames(); ++f)
        for (std::size_t j = 0; j < a.joints(); ++j) {
            e.degrees = std::max(e.degrees, anima::angle_between(a.rotation(f, j), b.rotation(f, j)) * rad_to_deg);
            e.units = std::max(e.units, (a.translation(f, j) - b.translation(f, j)).cwiseAbs().maxCoeff());
        }
    return e;
}
// Clip level: format_bvh(clip) then parse.
clip_errors clip_round_trip(const anima::clip<double>& c, const anima::bvh_write_options& options = {}) {
    const auto back = anima::parse_bvh<double>(anima::format_bvh(c, options), "round-trip");
    check_same_skeleton(c.skeleton(), back.skeleton());
    CHECK(back.frame_time() == c.frame_time());
    return compare_clips(c, back);
}

// ---- malformed input ----

struct failure {
    bool parse_error = false;
    bool other_error = false;
    std::size_t line = 0;
    std::string file, message, what;
};
failure parse_failure(const std::string& text) {
    failure r;
    try {
        (void)anima::parse_bvh_document<double>(text, "tiny.bvh");
    } catch (const anima::parse_error& e) {
        r.parse_error = true;
        r.line = e.line();
        r.file = e.file();
        r.message = e.message();
        r.what = e.what();
    } catch (...) {
        r.other_error = true;
    }
    return r;
}

struct bad_case {
    std::string name;
    std::string text;
    std::size_t line;
    std::vector<std::string> words;  // all must appear in the message
};

void check_bad(const bad_case& c) {
    CAPTURE(c.name);
    const failure r = parse_failure(c.text);
    CHECK_FALSE(r.other_error);
    REQUIRE(r.parse_error);
    CAPTURE(r.what);
    CHECK(r.line == c.line);
    CHECK(r.file == "tiny.bvh");
    CHECK(starts_with(r.what, "tiny.bvh:" + std::to_string(c.line) + ": "));
    CHECK(r.what == "tiny.bvh:" + std::to_string(r.line) + ": " + r.message);
    for (const auto& w : c.words) CHECK_MESSAGE(contains(r.message, w), "missing '" << w << "'");
    // The same through every entry point, and catchable as the base class.
    CHECK_THROWS_AS(anima::parse_bvh<double>(c.text, "tiny.bvh"), anima::parse_error);
    CHECK_THROWS_AS(anima::parse_bvh<float>(c.text, "tiny.bvh"), anima::parse_error);
    CHECK_THROWS_AS(anima::parse_bvh_document<float>(c.text), anima::error);
    CHECK_THROWS_AS(anima::parse_bvh<double>(c.text), std::runtime_error);
}

const std::vector<std::string> walk_names = {
    "Hips",           "LHipJoint",      "LeftUpLeg",    "LeftLeg",      "LeftFoot",        "LeftToeBase",
    "RHipJoint",      "RightUpLeg",     "RightLeg",     "RightFoot",    "RightToeBase",    "LowerBack",
    "Spine",          "Spine1",         "Neck",         "Neck1",        "Head",            "LeftShoulder",
    "LeftArm",        "LeftForeArm",    "LeftHand",     "LeftFingerBase", "LeftHandIndex1", "LThumb",
    "RightShoulder",  "RightArm",       "RightForeArm", "RightHand",    "RightFingerBase", "RightHandIndex1",
    "RThumb"};
const std::vector<std::string> daz_names = {
    "hip",     "abdomen", "chest",   "neck",    "head",    "leftEye", "rightEye", "rCollar", "rShldr",
    "rForeArm", "rHand",  "rThumb1", "rThumb2", "rIndex1", "rIndex2", "rMid1",    "rMid2",   "rRing1",
    "rRing2",  "rPinky1", "rPinky2", "lCollar", "lShldr",  "lForeArm", "lHand",   "lThumb1", "lThumb2",
    "lIndex1", "lIndex2", "lMid1",   "lMid2",   "lRing1",  "lRing2",  "lPinky1", "lPinky2", "rButtock",
    "rThigh",  "rShin",   "rFoot",   "lButtock", "lThigh", "lShin",   "lFoot"};

std::vector<std::string> joint_names(const anima::skeleton<double>& sk) {
    std::vector<std::string> out;
    for (const auto& j : sk.joints()) out.push_back(j.name);
    return out;
}
std::size_t end_site_count(const anima::skeleton<double>& sk) {
    std::size_t n = 0;
    for (const auto& j : sk.joints()) n += j.end_site.has_value();
    return n;
}

// The clips of the shared data set, sorted, or empty when the folder is absent.
std::vector<fs::path> shared_clips() {
    const fs::path dir = fs::path(ANIMA_SHARED_DATA_DIR) / "bvh";
    std::vector<fs::path> out;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return out;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.is_regular_file() && entry.path().extension() == ".bvh") out.push_back(entry.path());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

// =====================================================================================
// the bundled clips
// =====================================================================================

TEST_CASE("the bundled CMU-31 walk clip parses") {
    const auto doc = anima::read_bvh_document<double>(data_path("walk_cmu31_02_01.bvh"));
    const auto& sk = doc.skeleton;
    CHECK(doc.frames == 343);
    CHECK(sk.size() == 31);
    CHECK(doc.channels() == 96);
    CHECK(doc.values.size() == 343 * 96);
    CHECK(doc.frame_time == 0.008333);
    CHECK(joint_names(sk) == walk_names);
    CHECK(end_site_count(sk) == 7);
    CHECK(sk[0].channels == std::vector<channel>{xp, yp, zp, zr, yr, xr});
    for (std::size_t j = 1; j < sk.size(); ++j) {
        CAPTURE(sk[j].name);
        CHECK(sk[j].channels == std::vector<channel>{zr, yr, xr});
    }
    CHECK(sk[0].parent == -1);
    CHECK(sk[sk.index_of("LeftUpLeg")].offset == v3d(1.363060, -1.794630, 0.839290));
    CHECK(sk[sk.index_of("LeftUpLeg")].parent == static_cast<int>(sk.index_of("LHipJoint")));
    CHECK(*sk[sk.index_of("LeftToeBase")].end_site == v3d(0, 0, 0));
    CHECK(doc.value(0, 0) == 11.077051);
    CHECK(doc.value(0, 1) == 17.759173);
    CHECK(doc.value(0, 95) == 0.339200);
    const auto c = anima::to_clip(doc);
    CHECK(c.frames() == 343);
    CHECK(c.root_position(0) == v3d(11.077051, 17.759173, -32.000170));
}

TEST_CASE("the bundled Daz-layout run clip parses") {
    const auto doc = anima::read_bvh_document<double>(data_path("run_cmu_09_01.bvh"));
    const auto& sk = doc.skeleton;
    CHECK(doc.frames == 149);
    CHECK(sk.size() == 43);
    CHECK(doc.channels() == 132);
    CHECK(doc.values.size() == 149 * 132);
    CHECK(doc.frame_time == 0.00833333);
    CHECK(joint_names(sk) == daz_names);
    CHECK(end_site_count(sk) == 14);
    for (const char* name : {"leftEye", "rightEye", "rThumb2", "rIndex2", "rMid2", "rRing2", "rPinky2", "lThumb2",
                             "lIndex2", "lMid2", "lRing2", "lPinky2", "rFoot", "lFoot"})
        CHECK_MESSAGE(sk[sk.index_of(name)].end_site.has_value(), name);
    CHECK_FALSE(sk[sk.index_of("head")].end_site.has_value());
    // Root ZYX, every other joint ZXY.
    CHECK(sk[0].channels == std::vector<channel>{xp, yp, zp, zr, yr, xr});
    for (std::size_t j = 1; j < sk.size(); ++j) {
        CAPTURE(sk[j].name);
        CHECK(sk[j].channels == std::vector<channel>{zr, xr, yr});
    }
    CHECK(sk[0].offset == v3d(0, 0, 0));
    CHECK(sk[1].offset == v3d(0, 20.6881, -0.73152));
    CHECK(doc.value(0, 0) == -1.645);
    CHECK(doc.value(0, 1) == 85.1103);
    CHECK(doc.value(0, 2) == -148.62);
}

// =====================================================================================
// round trips
// =====================================================================================

TEST_CASE("document and clip round trips on the bundled clips") {
    for (const std::string name : {"walk_cmu31_02_01.bvh", "run_cmu_09_01.bvh"}) {
        CAPTURE(name);
        const auto doc = anima::read_bvh_document<double>(data_path(name.c_str()));
        const double values = document_round_trip(doc);
        CHECK(values <= half_unit);
        const auto c = anima::to_clip(doc);
        const clip_errors e = clip_round_trip(c);
        CHECK(e.degrees <= 1e-4);
        CHECK(e.units <= 1e-4);
        MESSAGE(name << ": document round trip max value change " << values << "; clip round trip max "
                     << e.degrees << " degrees, " << e.units << " units");
    }
}

TEST_CASE("document and clip round trips on the shared clip set") {
    const auto clips = shared_clips();
    if (clips.empty()) {
        MESSAGE("skipped: shared BVH folder " << ANIMA_SHARED_DATA_DIR << "/bvh not found");
        return;
    }
    // Frame counts from the data set's README.
    const std::map<std::string, std::size_t> frames = {{"walk_cmu_02_01.bvh", 344},
                                                       {"run_cmu_02_03.bvh", 174},
                                                       {"jump_cmu_02_04.bvh", 484},
                                                       {"run_cmu_09_01.bvh", 149},
                                                       {"martialarts_frontkick_cmu_135_04.bvh", 1317},
                                                       {"dance_salsa_cmu_60_10.bvh", 1198},
                                                       {"dance_indian_cmu_94_13.bvh", 1996},
                                                       {"walk_cmu31_02_01.bvh", 343}};
    double worst_values = 0, worst_degrees = 0, worst_units = 0;
    for (const auto& path : clips) {
        const std::string name = path.filename().string();
        CAPTURE(name);
        const auto doc = anima::read_bvh_document<double>(path.string());
        const auto known = frames.find(name);
        if (known != frames.end()) CHECK(doc.frames == known->second);
        const bool cmu31 = doc.skeleton.size() == 31;
        CHECK(doc.skeleton.size() == (cmu31 ? 31u : 43u));
        CHECK(doc.channels() == (cmu31 ? 96u : 132u));
        CHECK(end_site_count(doc.skeleton) == (cmu31 ? 7u : 14u));
        const double values = document_round_trip(doc);
        CHECK(values <= half_unit);
        const clip_errors e = clip_round_trip(anima::to_clip(doc));
        CHECK(e.degrees <= 1e-4);
        CHECK(e.units <= 1e-4);
        MESSAGE(name << ": document max value change " << values << "; clip max " << e.degrees << " degrees, "
                     << e.units << " units");
        worst_values = std::max(worst_values, values);
        worst_degrees = std::max(worst_degrees, e.degrees);
        worst_units = std::max(worst_units, e.units);
    }
    MESSAGE(clips.size() << " shared clips: document max " << worst_values << ", clip max " << worst_degrees
                         << " degrees / " << worst_units << " units");
}

TEST_CASE("write_bvh writes a file that reads back") {
    const auto doc = anima::read_bvh_document<double>(data_path("run_cmu_09_01.bvh"));
    const auto c = anima::to_clip(doc);
    SUBCASE("a document") {
        temp_file tmp("anima_test_bvh_document.bvh");
        anima::write_bvh(doc, tmp.path.string());
        const auto back = anima::read_bvh_document<double>(tmp.path.string());
        CHECK(back.frames == doc.frames);
        CHECK(joint_names(back.skeleton) == daz_names);
        double worst = 0;
        for (std::size_t i = 0; i < doc.values.size(); ++i)
            worst = std::max(worst, std::abs(back.values[i] - doc.values[i]));
        CHECK(worst <= half_unit);
        // Same text as format_bvh.
        std::ifstream in(tmp.path, std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        CHECK(text == anima::format_bvh(doc));
        CHECK(starts_with(text, "HIERARCHY\nROOT hip\n"));
        CHECK(text.find('\r') == std::string::npos);
    }
    SUBCASE("a clip") {
        temp_file tmp("anima_test_bvh_clip.bvh");
        anima::write_bvh(c, tmp.path.string());
        const auto back = anima::read_bvh<double>(tmp.path.string());
        const clip_errors e = compare_clips(c, back);
        CHECK(e.degrees <= 1e-4);
        CHECK(e.units <= 1e-4);
    }
    SUBCASE("an unwritable path") {
        const std::string path = (fs::temp_directory_path() / "anima_no_such_dir" / "sub" / "x.bvh").string();
        CHECK_THROWS_AS(anima::write_bvh(doc, path), anima::io_error);
        CHECK_THROWS_AS(anima::write_bvh(c, path), anima::error);
    }
    SUBCASE("nothing is written when formatting fails") {
        temp_file tmp("anima_test_bvh_bad.bvh");
        auto bad = doc;
        bad.values[5] = std::numeric_limits<double>::quiet_NaN();
        CHECK_THROWS_AS(anima::write_bvh(bad, tmp.path.string()), anima::invalid_argument);
        CHECK_FALSE(fs::exists(tmp.path));
    }
}

TEST_CASE("euler_angles policies: principal ranges, continuous curves, both keep the motion") {
    for (const std::string name : {"walk_cmu31_02_01.bvh", "run_cmu_09_01.bvh"}) {
        CAPTURE(name);
        const auto c = anima::read_bvh<double>(data_path(name.c_str()));
        const anima::bvh_write_options principal{6, anima::euler_angles::principal};
        const clip_errors e = clip_round_trip(c, principal);
        CHECK(e.degrees <= 1e-4);
        CHECK(e.units <= 1e-4);

        const auto& sk = c.skeleton();
        const auto p = anima::to_document(c, anima::euler_angles::principal);
        const auto q = anima::to_document(c, anima::euler_angles::continuous);
        REQUIRE(p.values.size() == q.values.size());
        double largest_step = 0;
        for (std::size_t f = 0; f < c.frames(); ++f) {
            std::size_t col = 0;
            for (std::size_t j = 0; j < sk.size(); ++j) {
                std::size_t r = 0;
                for (channel ch : sk[j].channels) {
                    if (anima::is_rotation(ch)) {
                        const double a = p.value(f, col);
                        if (r == 1) {
                            CHECK(a >= -90.0);
                            CHECK(a <= 90.0);
                        } else {
                            CHECK(a > -180.0);
                            CHECK(a <= 180.0);
                        }
                        if (f > 0) largest_step = std::max(largest_step, std::abs(q.value(f, col) - q.value(f - 1, col)));
                        ++r;
                    }
                    ++col;
                }
            }
        }
        // Continuous curves never jump by a turn.
        CHECK(largest_step < 180.0);
        // The first frame is the principal solution under both policies.
        for (std::size_t k = 0; k < p.channels(); ++k) CHECK(p.value(0, k) == q.value(0, k));
        // The motion the two documents describe is the same.
        const clip_errors pq = compare_clips(anima::to_clip(p), anima::to_clip(q));
        CHECK(pq.degrees <= 1e-9);
    }
}

TEST_CASE("to_document refuses rotations the channels cannot express") {
    anima::skeleton<double> sk;
    sk.add_joint("root", -1, v3d::Zero(), {xp, yp, zp, zr, xr, yr});
    sk.add_joint("hinge", 0, v3d(0, 1, 0), {zr});
    sk.add_joint("saddle", 1, v3d(0, 1, 0), {xr, yr});
    sk.add_joint("fixed", 2, v3d(0, 1, 0));
    anima::clip<double> c(sk, 3, 0.1);
    const auto about = [](double degrees, const v3d& axis) {
        return Eigen::Quaterniond(Eigen::AngleAxisd(degrees / rad_to_deg, axis.normalized()));
    };
    c.set_rotation(0, 1, about(30, v3d::UnitZ()));
    c.set_rotation(1, 1, about(-170, v3d::UnitZ()));
    c.set_rotation(1, 2, about(20, v3d::UnitX()) * about(-40, v3d::UnitY()));
    // Expressible rotations are written with the joint's own channels.
    {
        const auto doc = anima::to_document(c);
        CHECK(doc.value(0, 6) == doctest::Approx(30).epsilon(1e-12));
        // Continuous: -170 is written as 190, 160 degrees on from 30 rather than 200 back.
        CHECK(doc.value(1, 6) == doctest::Approx(190).epsilon(1e-12));
        CHECK(doc.value(1, 7) == doctest::Approx(20).epsilon(1e-12));
        CHECK(doc.value(1, 8) == doctest::Approx(-40).epsilon(1e-12));
        const clip_errors e = clip_round_trip(c);
        CHECK(e.degrees <= 1e-4);
    }
    const auto message = [&](const anima::clip<double>& x) -> std::string {
        try {
            (void)anima::to_document(x);
        } catch (const anima::invalid_argument& e) {
            return e.what();
        }
        return "";
    };
    SUBCASE("one rotation channel, rotation about another axis") {
        c.set_rotation(2, 1, about(10, v3d::UnitX()));
        const std::string m = message(c);
        CHECK(contains(m, "'hinge'"));
        CHECK(contains(m, "frame 2"));
        CHECK_THROWS_AS(anima::format_bvh(c), anima::invalid_argument);
        temp_file tmp("anima_test_bvh_refused.bvh");
        CHECK_THROWS_AS(anima::write_bvh(c, tmp.path.string()), anima::invalid_argument);
        CHECK_FALSE(fs::exists(tmp.path));
    }
    SUBCASE("two rotation channels, a twist about the third axis") {
        c.set_rotation(2, 2, about(15, v3d::UnitZ()));
        const std::string m = message(c);
        CHECK(contains(m, "'saddle'"));
        CHECK(contains(m, "frame 2"));
    }
    SUBCASE("no rotation channels, any rotation") {
        c.set_rotation(0, 3, about(5, v3d(1, 1, 0)));
        CHECK(contains(message(c), "'fixed'"));
    }
    SUBCASE("with_rotation_order gives every joint three channels and then it writes") {
        c.set_rotation(2, 1, about(10, v3d::UnitX()));
        c.set_rotation(2, 3, about(5, v3d(1, 1, 0)));
        const auto fixed = anima::with_rotation_order(c, anima::euler_order::zxy);
        CHECK(fixed.skeleton()[1].channels == std::vector<channel>{zr, xr, yr});
        CHECK(fixed.skeleton()[3].channels.empty());  // no rotation channels: left alone
        CHECK_THROWS_AS(anima::to_document(fixed), anima::invalid_argument);
        c.set_rotation(2, 3, Eigen::Quaterniond::Identity());
        const clip_errors e = clip_round_trip(anima::with_rotation_order(c, anima::euler_order::zxy));
        CHECK(e.degrees <= 1e-4);
    }
}

TEST_CASE("euler_angles::principal keeps single-channel angles in (-180, 180]") {
    // A hinge at 30 then -170 degrees: continuous would write 190.
    anima::skeleton<double> sk;
    sk.add_joint("hinge", -1, v3d::Zero(), {zr});
    anima::clip<double> c(sk, 2, 0.1);
    c.set_rotation(0, 0, Eigen::Quaterniond(Eigen::AngleAxisd(30 / rad_to_deg, v3d::UnitZ())));
    c.set_rotation(1, 0, Eigen::Quaterniond(Eigen::AngleAxisd(-170 / rad_to_deg, v3d::UnitZ())));
    const auto principal = anima::to_document(c, anima::euler_angles::principal);
    CHECK(principal.value(0, 0) == doctest::Approx(30).epsilon(1e-12));
    CHECK(principal.value(1, 0) == doctest::Approx(-170).epsilon(1e-12));
    const auto continuous = anima::to_document(c, anima::euler_angles::continuous);
    CHECK(continuous.value(1, 0) == doctest::Approx(190).epsilon(1e-12));
}

TEST_CASE("a clip written in every rotation order reads back as the same motion") {
    const auto c = anima::read_bvh<double>(data_path("walk_cmu31_02_01.bvh")).slice(0, 40);
    for (auto order : {anima::euler_order::xyz, anima::euler_order::xzy, anima::euler_order::yxz,
                       anima::euler_order::yzx, anima::euler_order::zxy, anima::euler_order::zyx}) {
        CAPTURE(anima::to_string(order));
        const auto o = anima::with_rotation_order(c, order);
        const auto back = anima::parse_bvh<double>(anima::format_bvh(o));
        CHECK(back.skeleton() == o.skeleton());
        const clip_errors e = compare_clips(c, back);
        CHECK(e.degrees <= 1e-4);
        CHECK(e.units <= 1e-4);
    }
}

TEST_CASE("the writer emits joints depth-first and keeps each joint's motion") {
    // Parents-first but not depth-first: root, a, b (child of root), c (child of a).
    anima::skeleton<double> sk;
    sk.add_joint("root", -1, v3d(0, 1, 0), {xp, yp, zp, zr, xr, yr});
    sk.add_joint("a", 0, v3d(1, 0, 0), {zr, xr, yr});
    sk.add_joint("b", 0, v3d(-1, 0, 0), {xr, yr, zr});
    sk.add_joint("c", 1, v3d(0, 2, 0), {yr, zr, xr});
    sk.set_end_site(3, v3d(0, 0.5, 0));
    anima::clip<double> c(sk, 4, 1.0 / 60);
    for (std::size_t f = 0; f < 4; ++f) {
        c.set_root_position(f, v3d(0.5 * double(f), 1, -0.25 * double(f)));
        for (std::size_t j = 0; j < 4; ++j)
            c.set_rotation(f, j, Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * double(f + 1) * double(j + 1),
                                                                      v3d(double(j), 1, 2).normalized())));
    }
    const auto back = anima::parse_bvh<double>(anima::format_bvh(c));
    REQUIRE(back.joints() == 4);
    CHECK(joint_names(back.skeleton()) == std::vector<std::string>{"root", "a", "c", "b"});
    for (std::size_t j = 0; j < 4; ++j) {
        const std::size_t k = back.skeleton().index_of(sk[j].name);
        CHECK(back.skeleton()[k].channels == sk[j].channels);
        CHECK(back.skeleton()[k].offset == sk[j].offset);
        for (std::size_t f = 0; f < 4; ++f) {
            CHECK(anima::angle_between(back.rotation(f, k), c.rotation(f, j)) * rad_to_deg <= 1e-4);
            CHECK((back.translation(f, k) - c.translation(f, j)).norm() <= 1e-6);
        }
    }
    CHECK(back.skeleton()[2].end_site.has_value());
}

TEST_CASE("format_bvh options and refusals") {
    auto doc = anima::parse_bvh_document<double>(tiny_with(24, "1.23456789 2 3 10 20 30 0 0 0 5 5 5"));
    CHECK(contains(anima::format_bvh(doc), "1.234568 2.000000 3.000000"));
    CHECK(contains(anima::format_bvh(doc, {2}), "1.23 2.00 3.00"));
    CHECK(contains(anima::format_bvh(doc, {0}), "\n1 2 3 10 20 30"));
    CHECK(contains(anima::format_bvh(doc), "Frame Time: 0.1\n"));
    CHECK_THROWS_AS(anima::format_bvh(doc, {-1}), anima::invalid_argument);
    CHECK_THROWS_AS(anima::format_bvh(doc, {18}), anima::invalid_argument);
    // Negative zero is written as zero.
    doc.values[6] = -0.0;
    doc.values[7] = -1e-9;
    CHECK(contains(anima::format_bvh(doc), " 30.000000 0.000000 0.000000 "));
    auto bad = doc;
    bad.values[14] = std::numeric_limits<double>::infinity();  // frame 1, channel 2 of root
    try {
        (void)anima::format_bvh(bad);
        FAIL("format_bvh accepted an infinite value");
    } catch (const anima::invalid_argument& e) {
        CHECK(contains(e.what(), "frame 1"));
        CHECK(contains(e.what(), "'root'"));
        CHECK(contains(e.what(), "Zposition"));
    }
    bad = doc;
    bad.values.pop_back();
    CHECK_THROWS_AS(anima::format_bvh(bad), anima::invalid_argument);
    bad = doc;
    bad.frame_time = 0;
    CHECK_THROWS_AS(anima::format_bvh(bad), anima::invalid_argument);
    CHECK_THROWS_AS(anima::format_bvh(anima::bvh_document<double>()), anima::invalid_argument);
    bad = doc;
    bad.values.push_back(0);
    CHECK_THROWS_AS(anima::to_clip(bad), anima::invalid_argument);
}

// =====================================================================================
// odd but valid formatting
// =====================================================================================

TEST_CASE("the tiny file parses as expected") {
    const auto doc = anima::parse_bvh_document<double>(tiny());
    const auto& sk = doc.skeleton;
    REQUIRE(sk.size() == 3);
    CHECK(joint_names(sk) == std::vector<std::string>{"root", "mid", "tip"});
    CHECK(sk[1].parent == 0);
    CHECK(sk[2].parent == 1);
    CHECK(sk[2].offset == v3d(0, 2, 0));
    REQUIRE(sk[2].end_site.has_value());
    CHECK(*sk[2].end_site == v3d(0, 1, 0));
    CHECK(doc.frames == 2);
    CHECK(doc.frame_time == 0.1);
    CHECK(doc.values == std::vector<double>{1, 2, 3, 10, 20, 30, 0, 0, 0, 5, 5, 5, 4, 5, 6, -10, -20, -30, 1, 2, 3, 0, 0, 0});
    // Joint rotation = product of its channels in file order (Z X Y here); translation = OFFSET + positions.
    const auto c = anima::to_clip(doc);
    const auto r = [](double deg, const v3d& axis) { return Eigen::Quaterniond(Eigen::AngleAxisd(deg / rad_to_deg, axis)); };
    CHECK(anima::angle_between(c.rotation(0, 0), Eigen::Quaterniond(r(10, v3d::UnitZ()) * r(20, v3d::UnitX()) *
                                                                     r(30, v3d::UnitY()))) <= 1e-12);
    CHECK(anima::angle_between(c.rotation(1, 1), Eigen::Quaterniond(r(1, v3d::UnitZ()) * r(2, v3d::UnitX()) *
                                                                     r(3, v3d::UnitY()))) <= 1e-12);
    CHECK(c.translation(1, 0) == v3d(4, 5, 6));
    CHECK(c.translation(1, 1) == v3d(0, 1, 0));
}

TEST_CASE("whitespace and line endings do not matter") {
    const auto reference = anima::parse_bvh_document<double>(tiny());
    SUBCASE("CRLF") { check_same_document(anima::parse_bvh_document<double>(join(tiny_lines(), "\r\n")), reference); }
    SUBCASE("no final newline") {
        check_same_document(anima::parse_bvh_document<double>(join(tiny_lines(), "\n", false)), reference);
        check_same_document(anima::parse_bvh_document<double>(join(tiny_lines(), "\r\n", false)), reference);
    }
    SUBCASE("mixed LF and CRLF") {
        auto lines = tiny_lines();
        std::string text;
        for (std::size_t i = 0; i < lines.size(); ++i) text += lines[i] + (i % 3 == 0 ? "\r\n" : "\n");
        check_same_document(anima::parse_bvh_document<double>(text), reference);
    }
    SUBCASE("spaces instead of tabs, trailing spaces and tabs") {
        auto lines = tiny_lines();
        for (auto& l : lines) {
            std::string s;
            for (char ch : l) s += ch == '\t' ? std::string("    ") : std::string(1, ch);
            l = s + " \t ";
        }
        check_same_document(anima::parse_bvh_document<double>(join(lines)), reference);
    }
    SUBCASE("tabs between tokens") {
        auto lines = tiny_lines();
        lines[3] = "\tOFFSET\t0\t0\t0";
        lines[21] = "Frames:\t2";
        lines[22] = "Frame Time:\t0.1";
        lines[23] = "1\t2\t3\t10\t20\t30\t0\t0\t0\t5\t5\t5";
        check_same_document(anima::parse_bvh_document<double>(join(lines)), reference);
    }
    SUBCASE("extra blank lines everywhere") {
        std::string text = "\n\n";
        for (const auto& l : tiny_lines()) text += l + "\n\n \n";
        text += "\n\t\n";
        check_same_document(anima::parse_bvh_document<double>(text), reference);
    }
    SUBCASE("no indentation at all") {
        auto lines = tiny_lines();
        for (auto& l : lines) l.erase(0, l.find_first_not_of('\t'));
        check_same_document(anima::parse_bvh_document<double>(join(lines)), reference);
    }
}

TEST_CASE("number spellings") {
    SUBCASE("sign, exponent, negative zero, integers, underflow") {
        const auto doc = anima::parse_bvh_document<double>(
            tiny_with(24, "+1.5 2e0 3.0E+00 1e1 2.0e1 +3e1 -0.0 -0 1e-999 .5 5. -2.5E-1"));
        CHECK(std::vector<double>(doc.values.begin(), doc.values.begin() + 12) ==
              std::vector<double>{1.5, 2, 3, 10, 20, 30, 0, 0, 0, 0.5, 5, -0.25});
        const auto off = anima::parse_bvh_document<double>(tiny_with(12, "\t\t\tOFFSET +1 -2.5e-1 1.25E1"));
        CHECK(off.skeleton[2].offset == v3d(1, -0.25, 12.5));
    }
    SUBCASE("'Frames:' and 'Time:' glued to their numbers, keywords in any case") {
        auto lines = tiny_lines();
        lines[21] = "Frames:2";
        lines[22] = "Frame Time:0.1";
        const auto doc = anima::parse_bvh_document<double>(join(lines));
        CHECK(doc.frames == 2);
        CHECK(doc.frame_time == 0.1);
        lines[0] = "hierarchy";
        lines[20] = "motion";
        lines[21] = "FRAMES: 2";
        lines[22] = "frame time: 0.1";
        check_same_document(anima::parse_bvh_document<double>(join(lines)), doc);
    }
    SUBCASE("a sign on its own or doubled is not a number") {
        check_bad({"lone +", tiny_with(24, "+ 2 3 10 20 30 0 0 0 5 5 5"), 24, {"'+'", "not a number"}});
        check_bad({"++1", tiny_with(24, "++1 2 3 10 20 30 0 0 0 5 5 5"), 24, {"'++1'", "not a number"}});
        check_bad({"-+1", tiny_with(24, "-+1 2 3 10 20 30 0 0 0 5 5 5"), 24, {"'-+1'", "not a number"}});
        check_bad({"+-1", tiny_with(24, "+-1 2 3 10 20 30 0 0 0 5 5 5"), 24, {"'+-1'", "not a number"}});
    }
}

TEST_CASE("joint names, braces, channels and roots") {
    SUBCASE("names with spaces and a brace on the name line") {
        auto lines = tiny_lines();
        lines[1] = "ROOT my root {";
        lines[2] = "";
        lines[5] = "\tJOINT left upper arm";
        lines[9] = "\t\tJOINT tip{";
        lines[10] = "";
        const auto doc = anima::parse_bvh_document<double>(join(lines));
        CHECK(joint_names(doc.skeleton) == std::vector<std::string>{"my root", "left upper arm", "tip"});
        CHECK(doc.values.size() == 24);
        // And they survive the writer.
        const auto back = anima::parse_bvh_document<double>(anima::format_bvh(doc));
        CHECK(joint_names(back.skeleton) == joint_names(doc.skeleton));
    }
    SUBCASE("End Site with a name") {
        const auto doc = anima::parse_bvh_document<double>(tiny_with(14, "\t\t\tEnd Site tip_end"));
        CHECK(*doc.skeleton[2].end_site == v3d(0, 1, 0));
    }
    SUBCASE("position channels on a non-root joint") {
        auto lines = tiny_lines();
        lines[8] = "\t\tCHANNELS 6 Zrotation Xposition Yposition Xrotation Zposition Yrotation";
        lines[23] = "1 2 3 10 20 30 90 0.5 0.25 0 -2 0 5 5 5";
        lines[24] = "4 5 6 -10 -20 -30 0 0 0 0 0 0 0 0 0";
        const auto doc = anima::parse_bvh_document<double>(join(lines));
        CHECK(doc.channels() == 15);
        const auto c = anima::to_clip(doc);
        CHECK(c.skeleton().translated_joint_count() == 2);
        CHECK(c.skeleton().translation_slot(1) == 1);
        CHECK(c.translation(0, 1) == v3d(0.5, 1.25, -2));  // OFFSET (0 1 0) + (0.5, 0.25, -2)
        CHECK(c.translation(1, 1) == v3d(0, 1, 0));
        CHECK(anima::angle_between(c.rotation(0, 1), Eigen::Quaterniond(Eigen::AngleAxisd(
                                                         90 / rad_to_deg, v3d::UnitZ()))) <= 1e-12);
        const double e = document_round_trip(doc);
        CHECK(e <= half_unit);
        const clip_errors ce = clip_round_trip(c);
        CHECK(ce.units <= 1e-6);
        CHECK(ce.degrees <= 1e-4);
    }
    SUBCASE("every rotation order: the product of the channels in file order") {
        const char* names[3] = {"Xrotation", "Yrotation", "Zrotation"};
        const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
        const double angles[3] = {37, -64, 121};
        for (const auto& o : orders) {
            const std::string channels = std::string(names[o[0]]) + " " + names[o[1]] + " " + names[o[2]];
            CAPTURE(channels);
            const std::string text = "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 3 " + channels +
                                     "\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\nMOTION\nFrames: 1\nFrame Time: 0.5\n37 -64 121\n";
            const auto c = anima::parse_bvh<double>(text);
            Eigen::Quaterniond expected = Eigen::Quaterniond::Identity();
            for (int k = 0; k < 3; ++k)
                expected = expected * Eigen::Quaterniond(Eigen::AngleAxisd(angles[k] / rad_to_deg, v3d::Unit(o[k])));
            CHECK(anima::angle_between(c.rotation(0, 0), expected) <= 1e-12);
            const clip_errors e = clip_round_trip(c);
            CHECK(e.degrees <= 1e-4);
        }
    }
    SUBCASE("a joint with zero channels and one without a CHANNELS line") {
        auto lines = tiny_lines();
        lines[8] = "\t\tCHANNELS 0";
        lines[23] = "1 2 3 10 20 30 5 5 5";
        lines[24] = "4 5 6 -10 -20 -30 0 0 0";
        const auto doc = anima::parse_bvh_document<double>(join(lines));
        CHECK(doc.channels() == 9);
        CHECK(doc.skeleton[1].channels.empty());
        const auto c = anima::to_clip(doc);
        CHECK(c.rotation(1, 1).coeffs() == Eigen::Quaterniond::Identity().coeffs());
        const auto r5 = [](const v3d& axis) { return Eigen::Quaterniond(Eigen::AngleAxisd(5 / rad_to_deg, axis)); };
        CHECK(anima::angle_between(c.rotation(0, 2),
                                   Eigen::Quaterniond(r5(v3d::UnitZ()) * r5(v3d::UnitX()) * r5(v3d::UnitY()))) <= 1e-12);
        CHECK(document_round_trip(doc) <= half_unit);
        lines.erase(lines.begin() + 8);
        const auto without = anima::parse_bvh_document<double>(join(lines));
        CHECK(without.skeleton[1].channels.empty());
        CHECK(without.values == doc.values);
    }
    SUBCASE("no channels anywhere: no frame can be read, so none may be claimed") {
        const std::string text =
            "HIERARCHY\nROOT r\n{\nOFFSET 1 2 3\nCHANNELS 0\n}\nMOTION\nFrames: 4\nFrame Time: 0.25\n\n\n\n\n";
        CHECK_THROWS_AS(anima::parse_bvh_document<double>(text), anima::parse_error);
        const auto empty = anima::parse_bvh_document<double>(
            "HIERARCHY\nROOT r\n{\nOFFSET 1 2 3\nCHANNELS 0\n}\nMOTION\nFrames: 0\nFrame Time: 0.25\n");
        CHECK(empty.frames == 0);
        CHECK(anima::to_clip(empty).skeleton()[0].offset == v3d(1, 2, 3));
    }
    SUBCASE("multiple roots") {
        auto lines = tiny_lines();
        const std::vector<std::string> second = {"ROOT other", "{", "\tOFFSET 5 0 0",
                                                 "\tCHANNELS 3 Xposition Yposition Zposition", "}"};
        lines.insert(lines.begin() + 20, second.begin(), second.end());
        lines[28] = "1 2 3 10 20 30 0 0 0 5 5 5 7 8 9";
        lines[29] = "4 5 6 -10 -20 -30 1 2 3 0 0 0 -7 -8 -9";
        const auto doc = anima::parse_bvh_document<double>(join(lines));
        REQUIRE(doc.skeleton.size() == 4);
        CHECK(doc.skeleton[3].name == "other");
        CHECK(doc.skeleton[3].parent == -1);
        const auto c = anima::to_clip(doc);
        CHECK(c.translation(0, 3) == v3d(12, 8, 9));
        CHECK(c.translation(1, 3) == v3d(-2, -8, -9));
        CHECK(document_round_trip(doc) <= half_unit);
    }
    SUBCASE("deep nesting does not exhaust the stack") {
        const std::size_t depth = 3000;
        std::string text = "HIERARCHY\nROOT j0\n{\nOFFSET 0 0 0\nCHANNELS 1 Zrotation\n";
        for (std::size_t i = 1; i < depth; ++i)
            text += "JOINT j" + std::to_string(i) + "\n{\nOFFSET 0 1 0\nCHANNELS 1 Zrotation\n";
        text += "End Site\n{\nOFFSET 0 1 0\n}\n";
        for (std::size_t i = 0; i < depth; ++i) text += "}\n";
        text += "MOTION\nFrames: 1\nFrame Time: 1\n";
        for (std::size_t i = 0; i < depth; ++i) text += "0.1 ";
        text += "\n";
        const auto doc = anima::parse_bvh_document<double>(text);
        CHECK(doc.skeleton.size() == depth);
        CHECK(doc.skeleton[depth - 1].parent == static_cast<int>(depth - 2));
        CHECK(document_round_trip(doc) <= half_unit);
    }
}

TEST_CASE("a consistent empty motion section") {
    auto lines = tiny_lines();
    lines[21] = "Frames: 0";
    lines.resize(23);
    const auto doc = anima::parse_bvh_document<double>(join(lines));
    CHECK(doc.frames == 0);
    CHECK(doc.values.empty());
    const auto c = anima::to_clip(doc);
    CHECK(c.empty());
    const auto back = anima::parse_bvh<double>(anima::format_bvh(c));
    CHECK(back.empty());
    CHECK(back.skeleton() == c.skeleton());
}

// =====================================================================================
// malformed input
// =====================================================================================

TEST_CASE("malformed input raises anima::parse_error with the line and the reason") {
    const std::string frame = "1 2 3 10 20 30 0 0 0 5 5 5";
    const std::vector<bad_case> cases = {
        // truncation
        {"empty file", "", 1, {"HIERARCHY"}},
        {"garbage instead of HIERARCHY", "HIERARCH\nROOT a\n", 1, {"HIERARCHY"}},
        {"garbage after blank lines", "\n\nBVH file\n", 3, {"HIERARCHY"}},
        {"ends after HIERARCHY", "HIERARCHY", 1, {"ends", "MOTION"}},
        {"ends inside the root", tiny_first(3), 3, {"ends inside joint 'root'", "'}'"}},
        {"ends inside the hierarchy", tiny_first(12), 12, {"ends inside joint 'tip'"}},
        {"ends inside an OFFSET", tiny_first(11, "\t\t\tOFFSET 0 2"), 12, {"ends", "OFFSET"}},
        {"ends inside an End Site OFFSET", tiny_first(15, "\t\t\t\tOFFSET 0 1"), 16, {"ends", "End Site OFFSET"}},
        {"ends before the End Site's '}'", tiny_first(16), 16, {"ends", "End Site", "'tip'"}},
        {"ends before MOTION", tiny_first(20), 20, {"ends before the MOTION"}},
        {"ends after Frame Time:", tiny_first(22, "Frame Time:"), 23, {"frame time"}},
        {"ends inside the motion data", tiny_first(24, "4 5 6 -10"), 25, {"frame 1", "4 values", "expected 12"}},
        {"fewer frame lines than Frames:", tiny_first(24), 24, {"after 1 frames", "Frames: 2", "line 22"}},
        {"fewer frame lines, Frames: 3", tiny_with(22, "Frames: 3", false), 25, {"after 2 frames", "Frames: 3"}},
        // channels (the reader is token-based: a short list is reported at the
        // line of the first token that is not a channel name)
        {"CHANNELS count below the names", tiny_with(9, "\t\tCHANNELS 3 Zrotation Xrotation"), 10,
         {"declares 3 channels", "item 3", "'JOINT'", "'mid'"}},
        {"CHANNELS count above the names", tiny_with(9, "\t\tCHANNELS 2 Zrotation Xrotation Yrotation"), 9,
         {"unexpected 'Yrotation'", "'mid'"}},
        {"CHANNELS count 7", tiny_with(9, "\t\tCHANNELS 7 Zrotation Xrotation Yrotation"), 9,
         {"CHANNELS count '7'", "0 to 6"}},
        {"CHANNELS count -1", tiny_with(9, "\t\tCHANNELS -1"), 9, {"CHANNELS count '-1'"}},
        {"CHANNELS count not a number", tiny_with(9, "\t\tCHANNELS three Zrotation"), 9, {"CHANNELS count 'three'"}},
        {"unknown channel name", tiny_with(9, "\t\tCHANNELS 3 Zrotation Wrotation Yrotation"), 9,
         {"'Wrotation'", "not a channel name", "'mid'"}},
        {"repeated channel", tiny_with(9, "\t\tCHANNELS 3 Zrotation Xrotation Zrotation"), 9, {"Zrotation", "repeated", "'mid'"}},
        {"second CHANNELS", tiny_with(12, "\t\t\tCHANNELS 1 Xrotation"), 13, {"second CHANNELS", "'tip'"}},
        // numbers
        {"bad number 'abc' in an OFFSET", tiny_with(8, "\t\tOFFSET 0 abc 0"), 8, {"'abc'", "not a number", "OFFSET"}},
        {"bad number 'abc' in a frame", tiny_with(25, "4 5 6 -10 -20 -30 1 abc 3 0 0 0"), 25, {"'abc'", "not a number"}},
        {"'1.5.3'", tiny_with(24, "1 2 3 10 1.5.3 30 0 0 0 5 5 5"), 24, {"'1.5.3'", "not a number"}},
        {"'1,5'", tiny_with(24, "1 2 3 10 1,5 30 0 0 0 5 5 5"), 24, {"'1,5'", "not a number"}},
        {"'0x10'", tiny_with(24, "1 2 3 10 0x10 30 0 0 0 5 5 5"), 24, {"'0x10'", "not a number"}},
        {"'1e'", tiny_with(24, "1 2 3 10 1e 30 0 0 0 5 5 5"), 24, {"'1e'", "not a number"}},
        {"'nan' in a frame", tiny_with(24, "1 2 3 10 nan 30 0 0 0 5 5 5"), 24, {"non-finite", "'nan'"}},
        {"'NaN' in an OFFSET", tiny_with(12, "\t\t\tOFFSET 0 NaN 0"), 12, {"non-finite", "'NaN'"}},
        {"'inf' in a frame", tiny_with(25, "4 5 6 -10 -20 -30 1 2 3 0 0 inf"), 25, {"non-finite", "'inf'"}},
        {"'-infinity' in an End Site", tiny_with(16, "\t\t\t\tOFFSET 0 -infinity 0"), 16, {"non-finite", "'-infinity'"}},
        {"'1e999' in a frame", tiny_with(24, "1 2 3 10 20 30 0 1e999 0 5 5 5"), 24, {"non-finite", "'1e999'"}},
        {"'-1e999' in an OFFSET", tiny_with(4, "\tOFFSET -1e999 0 0"), 4, {"non-finite", "'-1e999'"}},
        // structure
        {"duplicate joint name", tiny_with(10, "\t\tJOINT mid"), 10, {"'mid'", "used twice"}},
        {"duplicate joint name across roots", tiny_with(10, "\t\tJOINT root"), 10, {"'root'", "used twice"}},
        {"missing OFFSET", tiny_without(12), 10, {"'tip'", "no OFFSET"}},
        {"missing OFFSET of the root", tiny_without(4), 2, {"'root'", "no OFFSET"}},
        {"missing End Site OFFSET", tiny_without(16), 16, {"End Site", "'tip'", "no OFFSET"}},
        {"OFFSET with two numbers", tiny_with(8, "\t\tOFFSET 0 1"), 9, {"'CHANNELS'", "not a number"}},
        {"missing '{' after JOINT", tiny_without(7), 7, {"expected '{'", "'mid'"}},
        {"missing '{' after ROOT", tiny_without(3), 3, {"expected '{'", "'root'"}},
        {"missing '{' after End Site", tiny_without(15), 15, {"expected '{'", "End Site"}},
        {"joint without a name", tiny_with(6, "\tJOINT"), 6, {"without a name"}},
        {"extra '}'", tiny_with(21, "}\nMOTION"), 21, {"'}'"}},
        {"missing '}'", tiny_without(20), 20, {"unexpected 'MOTION'", "'root'"}},
        {"'End' without 'Site'", tiny_with(14, "\t\t\tEnd Sight"), 14, {"End Site"}},
        {"second End Site", tiny_with(18, "\t\t\tEnd Site\n\t\t\t{\n\t\t\t\tOFFSET 0 1 0\n\t\t\t}\n\t\t}"), 18,
         {"second End Site", "'tip'"}},
        {"second OFFSET", tiny_with(19, "\t\tOFFSET 0 0 0\n\t}"), 19, {"second OFFSET", "'mid'"}},
        {"CHANNELS after a child joint",
         tiny_edited({{9, ""}, {19, "\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n\t}"}}), 19,
         {"CHANNELS of joint 'mid' after its children"}},
        {"unknown keyword in a joint", tiny_with(8, "\t\tOFFSET 0 1 0 SCALE 2"), 8, {"unexpected 'SCALE'", "'mid'"}},
        {"MOTION before any ROOT", "HIERARCHY\nMOTION\nFrames: 0\nFrame Time: 0.1\n", 2, {"MOTION before any ROOT"}},
        {"garbage before MOTION", tiny_with(21, "MOVEMENT"), 21, {"expected ROOT or MOTION", "'MOVEMENT'"}},
        // motion header
        {"missing Frames:", tiny_with(22, "Count: 2"), 22, {"expected 'Frames:'"}},
        {"negative frame count", tiny_with(22, "Frames: -2"), 22, {"'-2'", "non-negative integer"}},
        {"fractional frame count", tiny_with(22, "Frames: 2.5"), 22, {"'2.5'", "non-negative integer"}},
        {"huge frame count", tiny_with(22, "Frames: 99999999999999999999999"), 22, {"non-negative integer"}},
        {"missing Frame Time", tiny_with(23, "Time: 0.1"), 23, {"Frame Time"}},
        {"misspelt Frame Time", tiny_with(23, "Frame Rate: 0.1"), 23, {"Frame Time"}},
        {"negative Frame Time", tiny_with(23, "Frame Time: -0.1"), 23, {"frame time must be positive", "-0.1"}},
        {"zero Frame Time", tiny_with(23, "Frame Time: 0"), 23, {"frame time must be positive"}},
        {"zero Frame Time (0.0e0)", tiny_with(23, "Frame Time:0.0e0"), 23, {"frame time must be positive"}},
        // Subnormal in double (and so in float): the frame rate would be infinite.
        {"subnormal Frame Time", tiny_with(23, "Frame Time: 1e-310"), 23, {"positive and normal", "1e-310"}},
        {"non-numeric Frame Time", tiny_with(23, "Frame Time: fast"), 23, {"'fast'", "frame time"}},
        {"NaN Frame Time", tiny_with(23, "Frame Time: nan"), 23, {"non-finite", "frame time"}},
        // frame lines
        {"too few values", tiny_with(24, "1 2 3 10 20 30 0 0 0 5 5"), 24, {"frame 0", "11 values", "expected 12"}},
        {"too many values", tiny_with(25, "4 5 6 -10 -20 -30 1 2 3 0 0 0 9"), 25, {"frame 1", "more than 12", "expected 12"}},
        {"two frames on one line", tiny_with(24, frame + " " + frame), 24, {"more than 12"}},
        {"one frame split over two lines", tiny_with(24, "1 2 3 10 20 30\n0 0 0 5 5 5"), 24, {"6 values", "expected 12"}},
        {"more frame lines than Frames:", tiny_with(22, "Frames: 1"), 25, {"more frames than 'Frames: 1'", "line 22"}},
        {"more frame lines, Frames: 0", tiny_with(22, "Frames: 0"), 24, {"more frames than 'Frames: 0'"}},
        {"text after the motion", tiny() + "END\n", 26, {"more frames"}},
    };
    for (const auto& c : cases) check_bad(c);
}

TEST_CASE("a truncated file says that it ends") {
    check_bad({"ends inside CHANNELS", tiny_first(12, "\t\t\tCHANNELS 3 Zrotation"), 13, {"ends", "'tip'"}});
    check_bad({"ends inside an End Site", tiny_first(15), 15, {"ends", "End Site"}});
    check_bad({"ends after MOTION", tiny_first(21), 21, {"ends", "Frames:"}});
    check_bad({"ends after Frames", tiny_first(22), 22, {"ends", "Frame Time"}});
}

TEST_CASE("a Frame Time subnormal in float is refused in float only, on its line; subnormal values read as 0") {
    const std::string text = tiny_with(23, "Frame Time: 1e-40");
    CHECK(anima::parse_bvh<double>(text, "tiny.bvh").frame_time() == 1e-40);
    CHECK_THROWS_WITH_AS(anima::parse_bvh<float>(text, "tiny.bvh"),
                         "tiny.bvh:23: frame time must be positive and normal, got 1e-40", anima::parse_error);
    // A value subnormal in float is read as 0 there, exactly in double.
    const auto f = anima::parse_bvh_document<float>(tiny_with(24, "1e-40 2 3 10 20 30 0 0 0 5 5 -1e-39"));
    const auto d = anima::parse_bvh_document<double>(tiny_with(24, "1e-40 2 3 10 20 30 0 0 0 5 5 -1e-39"));
    CHECK(f.values.front() == 0.0f);
    CHECK(f.values[11] == 0.0f);
    CHECK(d.values.front() == 1e-40);
    CHECK(d.values[11] == -1e-39);
}

TEST_CASE("a huge Frames: count with little data fails cleanly") {
    // The reader must not size memory by the header.
    check_bad({"Frames: 2^64 - 1", tiny_with(22, "Frames: 18446744073709551615", false), 25, {"after 2 frames"}});
    check_bad({"Frames: 1e9", tiny_with(22, "Frames: 1000000000", false), 25, {"after 2 frames", "1000000000"}});
}

TEST_CASE("a file without channels cannot claim any number of frames") {
    // With zero channels no line holds a frame, so the count is unbounded.
    const std::string text =
        "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\nMOTION\nFrames: 18446744073709551615\nFrame Time: 1\n";
    bool anima_error = false;
    try {
        (void)anima::parse_bvh<double>(text, "tiny.bvh");
    } catch (const anima::error&) {
        anima_error = true;
    } catch (...) {
    }
    CHECK(anima_error);
}

TEST_CASE("a joint name the reader accepts survives the writer") {
    // "ROOT r {{" is read as joint "r {" with its '{' on the same line.
    // The reader refuses names with braces, so whatever it accepts, the
    // writer can write.
    const std::string text =
        "HIERARCHY\nROOT r {{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\nFrames: 1\nFrame Time: 1\n5\n";
    bool parsed = false;
    anima::bvh_document<double> doc;
    try {
        doc = anima::parse_bvh_document<double>(text, "tiny.bvh");
        parsed = true;
    } catch (const anima::parse_error&) {
    }
    if (parsed) {
        const std::string written = anima::format_bvh(doc);
        std::vector<std::string> names;
        CHECK_NOTHROW(names = joint_names(anima::parse_bvh_document<double>(written).skeleton));
        CHECK(names == joint_names(doc.skeleton));
    }
}

TEST_CASE("parse errors name the source; file errors are anima::io_error") {
    SUBCASE("default source name") {
        try {
            (void)anima::parse_bvh_document<double>("HIERARCHY\nROOT\n");
            FAIL("no exception");
        } catch (const anima::parse_error& e) {
            CHECK(e.file() == "<bvh>");
            CHECK(e.line() == 2);
            CHECK(starts_with(e.what(), "<bvh>:2: "));
        }
    }
    SUBCASE("a malformed file names its path") {
        temp_file tmp("anima_test_bvh_malformed.bvh");
        {
            std::ofstream out(tmp.path, std::ios::binary);
            out << tiny_with(23, "Frame Time: -1");
        }
        const std::string path = tmp.path.string();
        try {
            (void)anima::read_bvh_document<double>(path);
            FAIL("no exception");
        } catch (const anima::parse_error& e) {
            CHECK(e.file() == path);
            CHECK(e.line() == 23);
            CHECK(starts_with(e.what(), path + ":23: "));
        }
        CHECK_THROWS_AS(anima::read_bvh<float>(path), anima::parse_error);
    }
    SUBCASE("a missing file") {
        const std::string path = (fs::temp_directory_path() / "anima_no_such_file.bvh").string();
        CHECK_THROWS_AS(anima::read_bvh<double>(path), anima::io_error);
        CHECK_THROWS_AS(anima::read_bvh<float>(path), anima::io_error);
        CHECK_THROWS_AS(anima::read_bvh_document<double>(path), anima::error);
        try {
            (void)anima::read_bvh_document<double>(path);
        } catch (const anima::io_error& e) {
            CHECK(contains(e.what(), path));
        }
        // A directory is not a BVH file either.
        CHECK_THROWS_AS(anima::read_bvh<double>(fs::temp_directory_path().string()), anima::error);
    }
}

// =====================================================================================
// float
// =====================================================================================

TEST_CASE("parse_bvh<float>") {
    const auto d = anima::read_bvh<double>(data_path("run_cmu_09_01.bvh"));
    const auto f = anima::read_bvh<float>(data_path("run_cmu_09_01.bvh"));
    REQUIRE(f.frames() == 149);
    REQUIRE(f.joints() == 43);
    CHECK(f.frame_time() == 0.00833333f);
    double worst_angle = 0, worst_units = 0;
    for (std::size_t fr = 0; fr < f.frames(); ++fr)
        for (std::size_t j = 0; j < f.joints(); ++j) {
            worst_angle = std::max(worst_angle, anima::angle_between(f.rotation(fr, j).cast<double>(), d.rotation(fr, j)));
            worst_units = std::max(worst_units,
                                   (f.translation(fr, j).cast<double>() - d.translation(fr, j)).cwiseAbs().maxCoeff());
        }
    CHECK(worst_angle <= 1e-5);
    CHECK(worst_units <= 1e-4);

    const auto doc = anima::parse_bvh_document<float>(tiny());
    CHECK(doc.values == std::vector<float>{1, 2, 3, 10, 20, 30, 0, 0, 0, 5, 5, 5, 4, 5, 6, -10, -20, -30, 1, 2, 3, 0, 0, 0});
    CHECK(doc.frame_time == 0.1f);
    // float round trips.
    const auto back = anima::parse_bvh_document<float>(anima::format_bvh(doc));
    CHECK(back.values == doc.values);
    const auto fb = anima::parse_bvh<float>(anima::format_bvh(f.slice(0, 20)));
    for (std::size_t fr = 0; fr < 20; ++fr)
        for (std::size_t j = 0; j < f.joints(); ++j) CHECK(anima::angle_between(fb.rotation(fr, j), f.rotation(fr, j)) <= 1e-4f);
    // Finite as a double, infinite as a float.
    const std::string big = tiny_with(24, "1 2 3 10 20 30 0 1e39 0 5 5 5");
    CHECK(anima::parse_bvh_document<double>(big).values[7] == 1e39);
    try {
        (void)anima::parse_bvh_document<float>(big, "big.bvh");
        FAIL("float accepted 1e39");
    } catch (const anima::parse_error& e) {
        CHECK(e.line() == 24);
        CHECK(contains(e.message(), "non-finite"));
    }
}

TEST_CASE("bvh_value_decimals: plain-notation values only, the frame time and exponents left out") {
    CHECK(anima::bvh_value_decimals("") == 0);
    CHECK(anima::bvh_value_decimals("OFFSET 1.5 -2.25 3") == 2);
    CHECK(anima::bvh_value_decimals("Frame Time: 0.0083333\n1.0 2.000") == 3);  // not the 7 of the frame time
    CHECK(anima::bvh_value_decimals("1e-3 2.5e-7 -3.88251e-19 0.5") == 1);
    CHECK(anima::bvh_value_decimals(".5 +7.25") == 2);
    CHECK(anima::bvh_value_decimals("-0. 12") == 0);
    CHECK(anima::bvh_value_decimals("1.1234567890123456789012") == 17);  // at most 17
    CHECK(anima::bvh_value_decimals("CHANNELS 6 Xposition\tYposition\r\n0.123\r\n") == 3);
    // The bundled clips, against a count of their own: the longest run of
    // digits after a point in a plain number, skipping the frame time.
    for (const char* name : {"walk_cmu31_02_01.bvh", "run_cmu_09_01.bvh"}) {
        std::ifstream in(data_path(name));
        std::string word, previous;
        int most = 0;
        while (in >> word) {
            const bool frame_time = previous == "Time:";
            previous = word;
            const auto dot = word.find('.');
            if (frame_time || dot == std::string::npos || word.find_first_of("eE") != std::string::npos) continue;
            most = std::max(most, static_cast<int>(word.size() - dot - 1));
        }
        std::ifstream again(data_path(name));
        const std::string text((std::istreambuf_iterator<char>(again)), std::istreambuf_iterator<char>());
        CAPTURE(name);
        CHECK(most > 0);
        CHECK(anima::bvh_value_decimals(text) == most);
    }
}

TEST_CASE_TEMPLATE("a joint with one rotation channel writes every rotation about its own axis", T, float, double) {
    // 1,000 angles from -179.5 to 179.5 degrees about each axis, read from a
    // file whose joint has that one channel, written again and read back.
    // The test of the other two components once measured them as
    // sqrt(|q|^2 - w^2 - s^2), whose rounding refused most of these angles.
    const char* names[3] = {"Xrotation", "Yrotation", "Zrotation"};
    constexpr int frames = 1000;
    for (int axis = 0; axis < 3; ++axis) {
        CAPTURE(names[axis]);
        std::string text = std::string("HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 1 ") + names[axis] +
                           "\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\nMOTION\nFrames: " + std::to_string(frames) +
                           "\nFrame Time: 0.01\n";
        std::vector<double> angles;
        for (int f = 0; f < frames; ++f) {
            angles.push_back(-179.5 + 359.0 * f / (frames - 1));
            text += std::to_string(angles.back()) + "\n";
        }
        const auto c = anima::parse_bvh<T>(text);
        const auto doc = anima::to_document(c);  // threw for most angles before
        const double tolerance = std::is_same_v<T, float> ? 2e-4 : 1e-9;
        double worst = 0;
        for (int f = 0; f < frames; ++f)
            worst = std::max(worst, std::abs(static_cast<double>(doc.value(static_cast<std::size_t>(f), 0)) -
                                             std::stod(std::to_string(angles[static_cast<std::size_t>(f)]))));
        CHECK(worst <= tolerance);
        const auto back = anima::parse_bvh<T>(anima::format_bvh(c));
        for (int f = 0; f < frames; f += 97)
            CHECK(anima::angle_between(back.rotation(static_cast<std::size_t>(f), 0), c.rotation(static_cast<std::size_t>(f), 0)) <=
                  T(tolerance));
    }
}
