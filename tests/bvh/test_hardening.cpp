// Hostile input for the shared file helpers (anima/core/file_io.hpp), message
// escaping, the BVH reader and writer and the skeleton: sizes are checked
// before memory is allocated, parsing stays linear in the file size, a failed
// write leaves the existing file as it was, and bytes from a file are escaped
// in messages.
#include <anima/bvh/document.hpp>
#include <anima/bvh/reader.hpp>
#include <anima/bvh/writer.hpp>
#include <anima/core/error.hpp>
#include <anima/core/file_io.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/skeleton.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <csignal>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#define ANIMA_TEST_HAVE_RLIMIT 1
#define ANIMA_TEST_HAVE_FIFO 1
#endif

#include "../test_support.hpp"

namespace fs = std::filesystem;
using anima_test::contains;

namespace {

/// A fresh, empty folder under the system's temporary folder.
fs::path scratch_folder(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("anima_test_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::vector<fs::path> entries(const fs::path& dir) {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename());
    std::sort(out.begin(), out.end());
    return out;
}

/// The message of the anima::parse_error f throws (fails the test if none).
template <class F>
anima::parse_error parse_failure(F&& f) {
    try {
        f();
    } catch (const anima::parse_error& e) {
        return e;
    }
    FAIL("no parse_error thrown");
    return anima::parse_error("", 0, "");
}

const char* const two_joint_header =
    "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
    " JOINT Chest\n {\n  OFFSET 0 1 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 1 0\n  }\n"
    " }\n}\nMOTION\nFrames: 2\n";

/// A chain of `depth` nested joints, one rotation channel each, 1 frame.
std::string nested_bvh(std::size_t depth) {
    std::string s = "HIERARCHY\nROOT j0\n{\nOFFSET 0 0 0\nCHANNELS 1 Zrotation\n";
    for (std::size_t k = 1; k < depth; ++k) s += "JOINT j" + std::to_string(k) + "\n{\nOFFSET 0 1 0\nCHANNELS 1 Zrotation\n";
    for (std::size_t k = 0; k < depth; ++k) s += "}\n";
    s += "MOTION\nFrames: 1\nFrame Time: 0.1\n";
    for (std::size_t k = 0; k < depth; ++k) s += k ? " 0" : "0";
    return s + "\n";
}

}  // namespace

// ---------------------------------------------------------------------------
// core: reading and writing files
// ---------------------------------------------------------------------------

TEST_CASE("read_file names a missing file, a folder and a file over the limit") {
    const fs::path dir = scratch_folder("read_file");
    const auto message = [](const std::string& path, std::uintmax_t limit) {
        try {
            (void)anima::read_file(path, limit);
        } catch (const anima::io_error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    CHECK(contains(message((dir / "none.bvh").string(), 100), "does not exist"));
    CHECK(contains(message(dir.string(), 100), "is a directory"));
    std::ofstream(dir / "big.txt", std::ios::binary) << std::string(1000, 'x');
    const std::string big = message((dir / "big.txt").string(), 999);
    CHECK(contains(big, "1000 bytes"));
    CHECK(contains(big, "999"));
    CHECK(anima::read_file((dir / "big.txt").string(), 1000) == std::string(1000, 'x'));
    fs::remove_all(dir);
}

TEST_CASE("check_output_path refuses a folder and a path in a missing folder, naming the option") {
    const fs::path dir = scratch_folder("check_output");
    CHECK_NOTHROW(anima::check_output_path((dir / "new.bvh").string(), "--output"));
    try {
        anima::check_output_path((dir / "missing" / "x.png").string(), "--plot");
        FAIL("no error");
    } catch (const anima::io_error& e) {
        CHECK(contains(e.what(), "--plot: "));
        CHECK(contains(e.what(), "does not exist"));
    }
    CHECK_THROWS_AS(anima::check_output_path(dir.string(), "--plot"), anima::io_error);
    CHECK_THROWS_AS(anima::check_output_path("", "--plot"), anima::io_error);
    fs::remove_all(dir);
}

TEST_CASE("write_file_atomically replaces a file and leaves no temporary behind") {
    const fs::path dir = scratch_folder("atomic");
    const std::string path = (dir / "out.txt").string();
    anima::write_file_atomically(path, "first");
    CHECK(slurp(path) == "first");
    anima::write_file_atomically(path, "second, longer");
    CHECK(slurp(path) == "second, longer");
    anima::write_file_atomically(path, "");
    CHECK(slurp(path).empty());
    CHECK(entries(dir) == std::vector<fs::path>{"out.txt"});
    // Into a missing folder: an error, and nothing is created.
    CHECK_THROWS_AS(anima::write_file_atomically((dir / "missing" / "x").string(), "x"), anima::io_error);
    CHECK(entries(dir) == std::vector<fs::path>{"out.txt"});
    fs::remove_all(dir);
}

TEST_CASE("output_files: every file in place at the commit, or none") {
    const fs::path dir = scratch_folder("output_files");
    const std::string a = (dir / "a.bvh").string(), b = (dir / "b.svg").string();
    anima::write_file_atomically(a, "old a");
    {
        // A run that fails after its first write: both stay as they were, no temporary left.
        anima::output_files out;
        out.write(a, "new a");
        CHECK(out.pending() == 1);
        CHECK(slurp(a) == "old a");
        CHECK_THROWS_AS(out.write((dir / "missing" / "b.svg").string(), "b"), anima::io_error);
    }
    CHECK(slurp(a) == "old a");
    CHECK(entries(dir) == std::vector<fs::path>{"a.bvh"});
    {
        anima::output_files out;
        out.write(a, "new a");
        out.write(b, "new b");
        CHECK(entries(dir).size() == 3);  // a.bvh and the two temporaries
        out.commit();
        CHECK(out.pending() == 0);
    }
    CHECK(slurp(a) == "new a");
    CHECK(slurp(b) == "new b");
    CHECK(entries(dir) == std::vector<fs::path>{"a.bvh", "b.svg"});
    {
        anima::output_files out;
        out.write(a, "newer a");
        out.discard();
        out.commit();  // nothing left to commit
    }
    CHECK(slurp(a) == "new a");
    CHECK(entries(dir) == std::vector<fs::path>{"a.bvh", "b.svg"});
    fs::remove_all(dir);
}

TEST_CASE("output_files: a device that refuses its bytes replaces no file") {
    if (!fs::exists("/dev/full")) return;  // a system without it
    const fs::path dir = scratch_folder("output_files_device");
    const std::string a = (dir / "a.bvh").string();
    anima::write_file_atomically(a, "old a");
    {
        anima::output_files out;
        out.write(a, "new a");
        out.write("/dev/full", "bytes");
        CHECK_THROWS_AS(out.commit(), anima::io_error);
        CHECK(out.pending() == 0);
    }
    CHECK(slurp(a) == "old a");
    CHECK(entries(dir) == std::vector<fs::path>{"a.bvh"});
    fs::remove_all(dir);
}

#ifdef ANIMA_TEST_HAVE_FIFO
TEST_CASE("a FIFO is written in place, not replaced by a regular file") {
    const fs::path dir = scratch_folder("fifo");
    const std::string path = (dir / "out.pipe").string();
    REQUIRE(mkfifo(path.c_str(), 0600) == 0);
    // A reader that does not block, so the writer's open succeeds; a few
    // bytes fit in the pipe's buffer.
    const int reader = open(path.c_str(), O_RDONLY | O_NONBLOCK);
    REQUIRE(reader >= 0);
    anima::write_file_atomically(path, "through the pipe");
    char got[64] = {};
    const ssize_t n = read(reader, got, sizeof got - 1);
    close(reader);
    CHECK(std::string(got, n > 0 ? static_cast<std::size_t>(n) : 0) == "through the pipe");
    CHECK(fs::is_fifo(path));
    CHECK(entries(dir) == std::vector<fs::path>{"out.pipe"});
    fs::remove_all(dir);
}
#endif

#ifdef ANIMA_TEST_HAVE_RLIMIT
TEST_CASE("a write that fails half way (file size limit) leaves the existing file as it was") {
    const fs::path dir = scratch_folder("atomic_fail");
    const std::string path = (dir / "keep.bvh").string();
    anima::write_file_atomically(path, "the original content\n");
    rlimit old{};
    REQUIRE(getrlimit(RLIMIT_FSIZE, &old) == 0);
    const auto previous = std::signal(SIGXFSZ, SIG_IGN);  // a failed write, not a signal
    rlimit small = old;
    small.rlim_cur = 4096;
    REQUIRE(setrlimit(RLIMIT_FSIZE, &small) == 0);
    bool threw = false;
    std::string message;
    try {
        anima::write_file_atomically(path, std::string(1 << 20, 'x'));
    } catch (const anima::io_error& e) {
        threw = true;
        message = e.what();
    }
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, previous);
    CHECK(threw);
    CHECK(contains(message, "keep.bvh"));
    CHECK(slurp(path) == "the original content\n");
    CHECK(entries(dir) == std::vector<fs::path>{"keep.bvh"});
    fs::remove_all(dir);
}
#endif

TEST_CASE("write_bvh goes through the atomic writer: a failed write keeps the old file") {
    const fs::path dir = scratch_folder("write_bvh");
    const std::string path = (dir / "x.bvh").string();
    const auto doc = anima::parse_bvh_document<double>(std::string(two_joint_header) +
                                                       "Frame Time: 0.1\n0 0 0 0 0 0 0 0 0\n1 2 3 4 5 6 7 8 9\n");
    anima::write_bvh(doc, path);
    const std::string first = slurp(path);
    CHECK(anima::read_bvh_document<double>(path).frames == 2);
    // Formatting fails (decimals out of range): the file is not touched.
    anima::bvh_write_options bad;
    bad.decimals = 99;
    CHECK_THROWS_AS(anima::write_bvh(doc, path, bad), anima::invalid_argument);
    CHECK(slurp(path) == first);
    CHECK(entries(dir) == std::vector<fs::path>{"x.bvh"});
    fs::remove_all(dir);
}

// ---------------------------------------------------------------------------
// core: bytes from files in messages
// ---------------------------------------------------------------------------

TEST_CASE("escape_for_message escapes control bytes and invalid UTF-8 and keeps valid UTF-8") {
    using anima::escape_for_message;
    CHECK(escape_for_message(std::string("a\0b", 3)) == "a\\x00b");
    CHECK(escape_for_message("tab\tstays, bell\a and DEL\x7f go") == "tab\tstays, bell\\x07 and DEL\\x7f go");
    CHECK(escape_for_message("line\nbreak\r") == "line\\x0abreak\\x0d");
    CHECK(escape_for_message("H\xC3\xBC" "fte \xE6\x89\x8B") == "H\xC3\xBC" "fte \xE6\x89\x8B");  // Hüfte 手
    CHECK(escape_for_message("\xFF\xFE") == "\\xff\\xfe");
    CHECK(escape_for_message("cut \xC3") == "cut \\xc3");           // a sequence cut short
    CHECK(escape_for_message("\xC0\xAF") == "\\xc0\\xaf");          // overlong '/'
    CHECK(escape_for_message("\xED\xA0\x80") == "\\xed\\xa0\\x80");  // a surrogate
    const std::string long_text(10000, 'a');
    const std::string cut = escape_for_message(long_text, 100);
    CHECK(cut.size() < 120);
    CHECK(contains(cut, " ... "));
}

TEST_CASE("parse_error escapes what it quotes from a binary file") {
    const anima::parse_error e("f.bvh", 3, std::string("unexpected '\x01\x00\xff'", 16));
    CHECK(std::string(e.what()) == "f.bvh:3: unexpected '\\x01\\x00\\xff'");
    CHECK(e.message().size() == 16);  // the raw message stays available
}

// ---------------------------------------------------------------------------
// BVH reader
// ---------------------------------------------------------------------------

TEST_CASE_TEMPLATE("a UTF-8 byte order mark and CR-only line ends are read like LF files", T, float, double) {
    const std::string body = std::string(two_joint_header) + "Frame Time: 0.1\n0 0 0 0 0 0 0 0 0\n1 2 3 4 5 6 7 8 9\n";
    const auto plain = anima::parse_bvh_document<T>(body);
    const auto bom = anima::parse_bvh_document<T>("\xEF\xBB\xBF" + body);
    std::string cr = body, crlf;
    for (char& c : cr)
        if (c == '\n') c = '\r';
    for (char c : body) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    const auto mac = anima::parse_bvh_document<T>(cr);
    const auto dos = anima::parse_bvh_document<T>(crlf);
    for (const auto* d : {&bom, &mac, &dos}) {
        CHECK(d->skeleton == plain.skeleton);
        CHECK(d->frames == 2);
        CHECK(d->values == plain.values);
        CHECK(d->skeleton[1].name == "Chest");
    }
    // Line numbers count CR-only line ends: an error on line 20 is reported there.
    std::string bad = cr;
    bad.replace(bad.find("7 8 9"), 1, "x");
    CHECK(parse_failure([&] { (void)anima::parse_bvh_document<T>(bad, "mac.bvh"); }).line() == 20);
}

TEST_CASE("text after the frame time is refused with its line") {
    const std::string text = std::string(two_joint_header) + "Frame Time: 0.0333 garbage\n0 0 0 0 0 0 0 0 0\n1 2 3 4 5 6 7 8 9\n";
    const auto e = parse_failure([&] { (void)anima::parse_bvh_document<double>(text, "t.bvh"); });
    CHECK(e.line() == 18);
    CHECK(contains(e.message(), "'garbage'"));
    CHECK(contains(e.message(), "frame time"));
    // Trailing blanks (and CR) are fine.
    CHECK(anima::parse_bvh_document<double>(std::string(two_joint_header) +
                                            "Frame Time: 0.0333 \t\r\n0 0 0 0 0 0 0 0 0\n1 2 3 4 5 6 7 8 9\n")
              .frames == 2);
}

TEST_CASE("a duplicate joint name names the line of the first one") {
    std::string text = std::string(two_joint_header) + "Frame Time: 0.1\n0 0 0 0 0 0 0 0 0\n1 2 3 4 5 6 7 8 9\n";
    text.replace(text.find("Chest"), 5, "Hips");
    const auto e = parse_failure([&] { (void)anima::parse_bvh_document<double>(text, "d.bvh"); });
    CHECK(e.line() == 6);
    CHECK(contains(e.message(), "first on line 2"));
}

TEST_CASE("binary bytes quoted by the reader are escaped") {
    const std::string text = "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\n\x01\x02\xff\n}\n";
    const auto e = parse_failure([&] { (void)anima::parse_bvh_document<double>(text, "bin.bvh"); });
    CHECK(contains(e.what(), "\\x01\\x02\\xff"));
    CHECK(std::string(e.what()).find('\x01') == std::string::npos);
}

TEST_CASE("a deep hierarchy parses, converts and writes in linear size, without recursion") {
    const std::size_t depth = 100000;
    const std::string text = nested_bvh(depth);
    const auto doc = anima::parse_bvh_document<double>(text, "deep.bvh");
    REQUIRE(doc.skeleton.size() == depth);
    CHECK(doc.skeleton[depth - 1].parent == static_cast<int>(depth - 2));
    const std::string out = anima::format_bvh(doc);
    // Indentation stops growing: the text stays within a constant factor of the input.
    CHECK(out.size() < 40 * text.size());
    const auto back = anima::parse_bvh_document<double>(out, "back.bvh");
    CHECK(back.skeleton == doc.skeleton);
    const auto c = anima::to_clip(doc);
    CHECK(c.joints() == depth);
}

// Parse time against joint count is measured in bench_bvh (BM_parse_wide_skeleton,
// fitted as O(N)); here the wide skeleton must parse and index every name.
TEST_CASE("many sibling joints parse and every name is found") {
    const std::size_t n = 100000;
    std::string text = "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 0\n";
    for (std::size_t k = 0; k < n; ++k) text += "JOINT s" + std::to_string(k) + "\n{\nOFFSET 0 1 0\nCHANNELS 0\n}\n";
    text += "}\nMOTION\nFrames: 0\nFrame Time: 0.1\n";
    const auto doc = anima::parse_bvh_document<double>(text, "wide.bvh");
    CHECK(doc.skeleton.size() == n + 1);
    CHECK(doc.skeleton.find("s99999") == std::optional<std::size_t>(n));
    CHECK(!doc.skeleton.find("s100000"));
    for (std::size_t k = 0; k < n; k += 997) CHECK(doc.skeleton.find("s" + std::to_string(k)) == std::optional<std::size_t>(k + 1));
}

// ---------------------------------------------------------------------------
// BVH writer and skeleton
// ---------------------------------------------------------------------------

TEST_CASE("every joint name the reader accepts is writable and reads back the same") {
    for (const std::string name : {"a b", "L\xC3\xBC\x66t", "x(1)", "has\ttab inside", "Site", "MOTION"}) {
        const std::string text = "HIERARCHY\nROOT " + name + "\n{\nOFFSET 0 0 0\nCHANNELS 1 Zrotation\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n5\n";
        const auto doc = anima::parse_bvh_document<double>(text);
        REQUIRE(doc.skeleton[0].name == name);
        CHECK(anima::detail::bvh_writable_name(name));
        CHECK(anima::parse_bvh_document<double>(anima::format_bvh(doc)).skeleton == doc.skeleton);
    }
    // Names that cannot be written are refused by the writer, naming them escaped.
    anima::bvh_document<double> doc;
    doc.skeleton.add_joint("bad\nname", -1, Eigen::Vector3d::Zero());
    const std::string m = anima_test::invalid_argument_message([&] { (void)anima::format_bvh(doc); });
    CHECK(contains(m, "bad\\x0aname"));
    anima::bvh_document<double> edge;
    edge.skeleton.add_joint("\tedge", -1, Eigen::Vector3d::Zero());
    CHECK(contains(anima_test::invalid_argument_message([&] { (void)anima::format_bvh(edge); }), "cannot be written"));
}

TEST_CASE_TEMPLATE("skeleton::from_parents is linear on a deep chain and still finds cycles", T, float, double) {
    using vec = Eigen::Matrix<T, 3, 1>;
    const std::size_t n = 50000;
    std::vector<std::string> names(n);
    std::vector<int> parents(n);
    std::vector<vec> offsets(n, vec::UnitY());
    // Joint k's parent is k + 1: the chain is given children-first.
    for (std::size_t k = 0; k < n; ++k) {
        names[k] = "j" + std::to_string(k);
        parents[k] = k + 1 < n ? static_cast<int>(k + 1) : -1;
    }
    const auto sk = anima::skeleton<T>::from_parents(names, parents, offsets);
    REQUIRE(sk.size() == n);
    CHECK(sk[0].name == "j" + std::to_string(n - 1));
    CHECK(sk[n - 1].name == "j0");
    for (std::size_t k = 1; k < n; ++k) REQUIRE(sk[k].parent == static_cast<int>(k - 1));
    // A cycle 0 -> 1 -> 2 -> 0 hanging below nothing.
    const std::vector<std::string> cyc{"a", "b", "c", "d"};
    const std::vector<int> cyc_parents{1, 2, 0, -1};
    const std::vector<vec> cyc_offsets(4, vec::Zero());
    const std::string m = anima_test::invalid_argument_message(
        [&] { (void)anima::skeleton<T>::from_parents(cyc, cyc_parents, cyc_offsets); });
    CHECK(contains(m, "cycle"));
    // A joint below the cycle is reported too, naming a joint on the cycle.
    const std::vector<int> below{1, 2, 1, 0};
    const std::string m2 = anima_test::invalid_argument_message(
        [&] { (void)anima::skeleton<T>::from_parents(cyc, below, cyc_offsets); });
    CHECK((contains(m2, "'b'") || contains(m2, "'c'")));
}
