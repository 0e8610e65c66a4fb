// The frame folder reader (anima/sadm/frame_folder.hpp): hold-out rules
// against an independent count, listing order and image/landmark pairing on
// folders of small PGM/PPM frames written here, decoding with the default and
// an injected decoder, and every error with the file it names.
#include "../test_support.hpp"

#include <anima/sadm/frame_folder.hpp>

#include <doctest/doctest.h>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace frame_folder_tests {

namespace fs = std::filesystem;
using anima_test::contains;

/// The message of the exception of type E that f throws ("" if it throws none).
template <class E, class F>
std::string message_of(F&& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    return "";
}

/// A fresh folder under the system's temporary folder, removed with its content.
class temp_folder {
public:
    temp_folder() {
        static unsigned counter = 0;
        std::random_device entropy;
        path_ = fs::temp_directory_path() /
                ("anima_frame_folder_" + std::to_string(entropy()) + "_" + std::to_string(counter++));
        fs::create_directories(path_);
    }
    ~temp_folder() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    temp_folder(const temp_folder&) = delete;
    temp_folder& operator=(const temp_folder&) = delete;

    const fs::path& path() const noexcept { return path_; }

private:
    fs::path path_;
};

void write_bytes(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
    REQUIRE(out.good());
}

/// The grey level the frames written here have at (x, y): distinct for every
/// pixel of a frame and every frame, so a swapped, transposed or mispaired
/// image shows.
int level(int base, int x, int y, int width) { return base + x + width * y; }

/// A folder with points/ and images/, and writers of frames into it.
struct face_folder {
    temp_folder root;
    static constexpr int width = 8, height = 6;

    face_folder() {
        fs::create_directories(root.path() / "points");
        fs::create_directories(root.path() / "images");
    }
    std::string dir() const { return root.path().string(); }
    std::string image(const std::string& file) const { return (root.path() / "images" / file).string(); }
    std::string pts(const std::string& name) const { return (root.path() / "points" / (name + ".pts")).string(); }

    /// images/NAME.pgm, binary, grey levels level(base, x, y).
    void pgm(const std::string& name, int base) const {
        std::string bytes = "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) bytes += static_cast<char>(level(base, x, y, width));
        write_bytes(image(name + ".pgm"), bytes);
    }
    /// images/NAME.ppm, text, the same level in R, G and B.
    void ppm(const std::string& name, int base) const {
        std::string text = "P3\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                for (int c = 0; c < 3; ++c) text += std::to_string(level(base, x, y, width)) + " ";
        write_bytes(image(name + ".ppm"), text);
    }
    /// points/NAME.pts with the given points.
    void points(const std::string& name, const std::vector<std::pair<double, double>>& p) const {
        std::string text = "version: 1\nn_points: " + std::to_string(p.size()) + "\n{\n";
        for (const auto& [x, y] : p) text += std::to_string(x) + " " + std::to_string(y) + "\n";
        write_bytes(pts(name), text + "}\n");
    }
    /// Frame `k`'s landmarks: three points inside the 8 x 6 image, exact in float.
    static std::vector<std::pair<double, double>> landmarks(int k) {
        return {{1 + 0.25 * k, 1.5}, {2, 2.5 + 0.5 * k}, {3.75, 1}};
    }
    /// A PGM frame and its landmarks, both numbered k.
    void frame(const std::string& name, int k) const {
        pgm(name, 10 * k);
        points(name, landmarks(k));
    }
};

TEST_CASE("frame_split: every:N and last:N parse, print back, and anything else is refused naming the spec") {
    const anima::frame_split every = anima::parse_frame_split("every:4");
    CHECK(every.kind == anima::frame_split::rule::every);
    CHECK(every.count == 4);
    const anima::frame_split last = anima::parse_frame_split("last:100");
    CHECK(last.kind == anima::frame_split::rule::last);
    CHECK(last.count == 100);
    CHECK(anima::parse_frame_split("").kind == anima::frame_split::rule::none);
    for (const char* spec : {"every:4", "last:100", "every:1", "last:007", ""}) {
        const std::string printed = anima::to_string(anima::parse_frame_split(spec));
        const anima::frame_split again = anima::parse_frame_split(printed);
        CHECK(again.kind == anima::parse_frame_split(spec).kind);
        CHECK(again.count == anima::parse_frame_split(spec).count);
    }
    CHECK(anima::to_string(anima::parse_frame_split("last:007")) == "last:7");
    for (const char* bad : {"every:0", "foo:3", "every:x", "every:", "every", "last:-1", "every:3x", " every:3",
                            "Every:3", "every:+3", ":3", "last:0"}) {
        const std::string m = message_of<anima::invalid_argument>([&] { (void)anima::parse_frame_split(bad); });
        CHECK_MESSAGE(contains(m, std::string("'") + bad + "' is not a hold-out rule: use every:N"), bad);
    }
    const std::string huge =
        message_of<anima::invalid_argument>([] { (void)anima::parse_frame_split("every:99999999999999999999999"); });
    CHECK(contains(huge, "'every:99999999999999999999999': N is larger than"));
}

TEST_CASE("held_out: the masks of every:N and last:N against an independent count") {
    for (std::size_t count = 0; count <= 40; ++count) {
        CHECK(anima::held_out({}, count) == std::vector<bool>(count, false));
        for (std::size_t n = 1; n <= 45; ++n) {
            // every:N: frames N-1, 2N-1, ... ; count / N of them.
            std::vector<bool> expected(count, false);
            std::size_t held = 0;
            for (std::size_t k = n - 1; k < count; k += n) {
                expected[k] = true;
                ++held;
            }
            const auto every = anima::held_out({anima::frame_split::rule::every, n}, count);
            CHECK(every == expected);
            CHECK(held == count / n);
            // last:N: the last min(N, count) frames.
            const std::size_t tail = n < count ? n : count;
            std::vector<bool> last_expected(count, false);
            for (std::size_t k = count - tail; k < count; ++k) last_expected[k] = true;
            CHECK(anima::held_out({anima::frame_split::rule::last, n}, count) == last_expected);
        }
    }
    CHECK(contains(message_of<anima::invalid_argument>([] {
                       (void)anima::held_out({anima::frame_split::rule::every, 0}, 5);
                   }),
                   "every:0"));
}

TEST_CASE("list_frame_folder: name order, image/landmark pairing, extensions, files that are not frames ignored") {
    const face_folder f;
    // Written out of order; "c10" sorts before "c2" (name order, not numeric).
    f.frame("c2", 3);
    f.frame("a", 1);
    f.ppm("b", 20);
    f.points("b", face_folder::landmarks(2));
    f.frame("c10", 4);
    write_bytes(f.image("a.jpg"), "not decoded by a listing");  // .jpg comes first in frame_image_extensions
    f.pgm("no_points", 50);                                     // an image without landmarks: not a frame
    write_bytes(fs::path(f.dir()) / "points" / "notes.txt", "not a .pts file");
    const anima::frame_files files = anima::list_frame_folder(f.dir());
    CHECK(files.folder == f.dir());
    REQUIRE(files.size() == 4);
    CHECK(files.names == std::vector<std::string>{"a", "b", "c10", "c2"});
    CHECK(files.image_paths ==
          std::vector<std::string>{f.image("a.jpg"), f.image("b.ppm"), f.image("c10.pgm"), f.image("c2.pgm")});
    CHECK(files.landmark_paths == std::vector<std::string>{f.pts("a"), f.pts("b"), f.pts("c10"), f.pts("c2")});
}

TEST_CASE_TEMPLATE("load_frame_folder: every frame's own image and landmarks, in name order", T, float, double) {
    const face_folder f;
    const std::vector<std::string> names{"f00", "f01", "f02", "f03", "f04"};
    for (int k = 4; k >= 0; --k) f.frame(names[static_cast<std::size_t>(k)], k);
    // One frame as a text PPM instead: grey as R = G = B.
    fs::remove(f.image("f03.pgm"));
    f.ppm("f03", 30);
    std::vector<std::pair<std::size_t, std::size_t>> progress;
    anima::frame_load_options<T> options;
    options.progress = [&](std::size_t loaded, std::size_t total) { progress.emplace_back(loaded, total); };
    const anima::frame_set<T> frames = anima::load_frame_folder<T>(f.dir(), {}, anima::frame_selection::all, options);
    CHECK(frames.names == names);
    REQUIRE(frames.images.size() == 5);
    REQUIRE(frames.landmarks.size() == 5);
    for (int k = 0; k < 5; ++k) {
        const auto& image = frames.images[static_cast<std::size_t>(k)];
        REQUIRE(image.rows() == face_folder::height);
        REQUIRE(image.cols() == face_folder::width);
        for (int y = 0; y < face_folder::height; ++y)
            for (int x = 0; x < face_folder::width; ++x)
                CHECK(static_cast<double>(image(y, x)) ==
                      doctest::Approx(level(10 * k, x, y, face_folder::width)).epsilon(1e-6));
        const auto& lm = frames.landmarks[static_cast<std::size_t>(k)];
        const auto expected = face_folder::landmarks(k);
        REQUIRE(lm.rows() == 3);
        for (Eigen::Index p = 0; p < 3; ++p) {
            CHECK(lm(p, 0) == static_cast<T>(expected[static_cast<std::size_t>(p)].first));
            CHECK(lm(p, 1) == static_cast<T>(expected[static_cast<std::size_t>(p)].second));
        }
    }
    CHECK(progress == std::vector<std::pair<std::size_t, std::size_t>>{{1, 5}, {2, 5}, {3, 5}, {4, 5}, {5, 5}});
}

TEST_CASE("load_frame_folder: training and test frames of every:N and last:N") {
    const face_folder f;
    std::vector<std::string> names;
    for (int k = 0; k < 7; ++k) {
        names.push_back("frame_0" + std::to_string(k));
        f.frame(names.back(), k);
    }
    const auto pick = [&](const char* spec, anima::frame_selection which) {
        return anima::load_frame_folder<double>(f.dir(), anima::parse_frame_split(spec), which).names;
    };
    using sel = anima::frame_selection;
    CHECK(pick("every:3", sel::test) == std::vector<std::string>{names[2], names[5]});
    CHECK(pick("every:3", sel::training) == std::vector<std::string>{names[0], names[1], names[3], names[4], names[6]});
    CHECK(pick("last:2", sel::test) == std::vector<std::string>{names[5], names[6]});
    CHECK(pick("last:2", sel::training) == std::vector<std::string>{names[0], names[1], names[2], names[3], names[4]});
    CHECK(pick("last:2", sel::all) == names);
    CHECK(pick("", sel::training) == names);
    // The listing alone, selected without decoding.
    const anima::frame_files test =
        anima::select_frames(anima::list_frame_folder(f.dir()), anima::parse_frame_split("every:2"), sel::test);
    CHECK(test.names == std::vector<std::string>{names[1], names[3], names[5]});
    CHECK(test.image_paths == std::vector<std::string>{f.image(names[1] + ".pgm"), f.image(names[3] + ".pgm"),
                                                       f.image(names[5] + ".pgm")});
    CHECK(test.landmark_paths == std::vector<std::string>{f.pts(names[1]), f.pts(names[3]), f.pts(names[5])});
    // Landmarks follow their image through the selection.
    const auto set = anima::load_frame_folder<double>(f.dir(), anima::parse_frame_split("every:3"), sel::test);
    CHECK(set.landmarks[1](0, 0) == 1 + 0.25 * 5);
    CHECK(set.images[1](0, 0) == 50);
}

TEST_CASE_TEMPLATE("load_frames: an injected decoder reads what the default one refuses", T, float, double) {
    const face_folder f;
    f.frame("a", 0);
    f.points("b", face_folder::landmarks(1));
    write_bytes(f.image("b.png"), "any bytes: the decoder below does not look");
    const anima::frame_files files = anima::list_frame_folder(f.dir());
    REQUIRE(files.image_paths[1] == f.image("b.png"));
    // The default decoder: PGM/PPM only, and says so naming the file.
    const std::string m = message_of<anima::io_error>([&] { (void)anima::load_frames<T>(files); });
    CHECK(contains(m, "'" + f.image("b.png") + "'"));
    CHECK(contains(m, "PGM/PPM"));
    CHECK(contains(m, "decoder"));
    CHECK(contains(message_of<anima::io_error>([&] { (void)anima::read_frame_image<T>(f.image("b.png")); }),
                   "reads PGM/PPM images"));
    // A decoder for .png, falling back on the default for the rest.
    std::vector<std::string> asked;
    anima::frame_load_options<T> options;
    options.decode = [&](const std::string& path) {
        asked.push_back(path);
        if (fs::path(path).extension() == ".png")
            return anima::grey_image<T>(anima::grey_image<T>::Constant(face_folder::height, face_folder::width, T(7)));
        return anima::read_frame_image<T>(path);
    };
    const anima::frame_set<T> frames = anima::load_frames(files, options);
    CHECK(asked == std::vector<std::string>{f.image("a.pgm"), f.image("b.png")});
    CHECK(frames.images[1](3, 4) == T(7));
    CHECK(frames.images[0](3, 4) == T(level(0, 4, 3, face_folder::width)));
    // A decoder that returns nothing is caught, naming the image.
    options.decode = [](const std::string&) { return anima::grey_image<T>(); };
    CHECK(contains(message_of<anima::invalid_argument>([&] { (void)anima::load_frames(files, options); }),
                   "'" + f.image("a.pgm") + "' was decoded to an empty image"));
}

TEST_CASE("list_frame_folder: missing folders, no .pts file, a frame without its image") {
    const temp_folder root;
    const std::string missing = (root.path() / "nowhere").string();
    CHECK(contains(message_of<anima::io_error>([&] { (void)anima::list_frame_folder(missing); }),
                   "'" + missing + "' does not exist"));
    write_bytes(root.path() / "file", "x");
    const std::string file = (root.path() / "file").string();
    CHECK(contains(message_of<anima::io_error>([&] { (void)anima::list_frame_folder(file); }),
                   "'" + file + "' is not a folder"));
    // Neither points/ nor images/, then only one of them.
    const std::string dir = root.path().string();
    const std::string points = (root.path() / "points").string(), images = (root.path() / "images").string();
    CHECK(contains(message_of<anima::io_error>([&] { (void)anima::list_frame_folder(dir); }),
                   "'" + points + "' does not exist"));
    fs::create_directories(points);
    const std::string no_images = message_of<anima::io_error>([&] { (void)anima::list_frame_folder(dir); });
    CHECK(contains(no_images, "'" + images + "' does not exist"));
    CHECK(contains(no_images, "images/NAME."));
    fs::create_directories(images);
    CHECK(contains(message_of<anima::io_error>([&] { (void)anima::list_frame_folder(dir); }),
                   "'" + points + "' holds no .pts file"));
    // A .pts whose image is missing (another name's image does not count).
    write_bytes(root.path() / "points" / "x.pts", "version: 1\nn_points: 1\n{\n1 1\n}\n");
    write_bytes(root.path() / "images" / "y.pgm", "P2\n1 1\n255\n0\n");
    const std::string m = message_of<anima::io_error>([&] { (void)anima::list_frame_folder(dir); });
    CHECK(contains(m, "no image for 'x.pts' in '" + images + "'"));
    CHECK(contains(m, "x.jpg, .png, .pgm"));
}

TEST_CASE_TEMPLATE("load_frames: landmark counts that differ, a landmark outside its image, too few frames", T, float,
                   double) {
    SUBCASE("a landmark count that differs from the first frame's names both files") {
        const face_folder f;
        f.frame("a", 0);
        f.frame("b", 1);
        f.pgm("c", 2);
        f.points("c", {{1, 1}, {2, 2}});
        const std::string m = message_of<anima::invalid_argument>([&] { (void)anima::load_frame_folder<T>(f.dir()); });
        CHECK(contains(m, "'" + f.pts("c") + "' has 2 points, '" + f.pts("a") + "' has 3"));
        CHECK(contains(m, "every frame needs the same landmarks"));
    }
    SUBCASE("a landmark outside its image names the .pts file, the point and the image") {
        const face_folder f;
        f.frame("a", 0);
        f.pgm("b", 1);
        f.points("b", {{1, 1}, {2, 2}, {8.5, 3}});  // x beyond the 8-pixel width
        const std::string m = message_of<anima::invalid_argument>([&] { (void)anima::load_frame_folder<T>(f.dir()); });
        CHECK(contains(m, "'" + f.pts("b") + "': landmark 2 (8.5, 3) is outside the 8 x 6 image '" + f.image("b.pgm") +
                              "'"));
        // On the border is inside.
        f.points("b", {{1, 1}, {2, 2}, {8, 6}});
        CHECK(anima::load_frame_folder<T>(f.dir()).landmarks[1](2, 1) == T(6));
    }
    SUBCASE("fewer than 2 frames") {
        const face_folder f;
        f.frame("only", 0);
        CHECK(contains(message_of<anima::invalid_argument>([&] { (void)anima::load_frame_folder<T>(f.dir()); }),
                       "'" + f.dir() + "' has 1 frame, at least 2 are needed"));
        CHECK(contains(message_of<anima::invalid_argument>([&] {
                           (void)anima::load_frames<T>(anima::list_frame_folder(f.dir()));
                       }),
                       "1 frame to load, at least 2 are needed"));
        f.frame("two", 1);
        f.frame("three", 2);
        CHECK(anima::load_frame_folder<T>(f.dir()).images.size() == 3);
        using sel = anima::frame_selection;
        const auto split = [](const char* s) { return anima::parse_frame_split(s); };
        CHECK(contains(message_of<anima::invalid_argument>([&] {
                           (void)anima::load_frame_folder<T>(f.dir(), split("every:100"), sel::test);
                       }),
                       "0 of its 3 frames are held out by every:100, at least 2 are needed"));
        CHECK(contains(message_of<anima::invalid_argument>([&] {
                           (void)anima::load_frame_folder<T>(f.dir(), split("last:2"), sel::training);
                       }),
                       "1 of its 3 frames is left for training by last:2"));
        CHECK(contains(message_of<anima::invalid_argument>([&] {
                           (void)anima::load_frame_folder<T>(f.dir(), {}, sel::test);
                       }),
                       "0 of its 3 frames are held out (no hold-out rule given)"));
        CHECK(anima::load_frame_folder<T>(f.dir(), split("last:2"), sel::test).images.size() == 2);
    }
}

TEST_CASE("load_frames: errors of the .pts reader and the image decoder name their file") {
    const face_folder f;
    f.frame("a", 0);
    f.frame("b", 1);
    write_bytes(f.pts("b"), "version: 1\nn_points: 3\n{\n1 1\n2 x\n3 3\n}\n");
    try {
        (void)anima::load_frame_folder<double>(f.dir());
        FAIL("no error");
    } catch (const anima::parse_error& e) {
        CHECK(e.file() == f.pts("b"));
        CHECK(e.line() == 5);
    }
    f.frame("b", 1);
    fs::remove(f.image("a.pgm"));
    fs::create_directories(f.image("a.pgm"));  // a folder where the image should be
    CHECK(contains(message_of<anima::io_error>([&] { (void)anima::load_frame_folder<double>(f.dir()); }),
                   "'" + f.image("a.pgm") + "': it is a directory"));
}

}  // namespace frame_folder_tests
