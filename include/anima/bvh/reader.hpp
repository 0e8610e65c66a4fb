// BVH reader. Accepts any rotation channel order per joint, position channels
// on any joint, End Sites, tabs, LF, CRLF, CR-only or mixed line endings, a
// UTF-8 byte order mark, scientific notation. Rejects, with an anima::parse_error naming file and line:
// truncated files, wrong channel counts, bad or non-finite numbers, duplicate
// joint names, unbalanced braces, frame-count mismatches.
#pragma once

#include <anima/bvh/document.hpp>
#include <anima/core/error.hpp>
#include <anima/core/file_io.hpp>
#include <anima/motion/clip.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace anima {
namespace detail {

class bvh_parser {
public:
    bvh_parser(std::string_view text, std::string source) : s_(text), source_(std::move(source)) {
        if (s_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;  // UTF-8 byte order mark
    }

    template <class T>
    bvh_document<T> parse() {
        bvh_document<T> doc;
        if (!keyword(next(), "HIERARCHY")) fail(tok_line_, "expected HIERARCHY at the start of the file");
        bool roots = false;
        for (;;) {
            const std::string_view t = next();
            if (keyword(t, "ROOT")) {
                parse_joints(doc.skeleton);
                roots = true;
            } else if (keyword(t, "MOTION")) {
                break;
            } else if (t.empty()) {
                fail(line_, "file ends before the MOTION section");
            } else {
                fail(tok_line_, "expected ROOT or MOTION, found '" + std::string(t) + "'");
            }
        }
        if (!roots) fail(tok_line_, "MOTION before any ROOT joint");
        parse_motion(doc);
        return doc;
    }

private:
    [[noreturn]] void fail(std::size_t line, const std::string& message) const {
        throw parse_error(source_, line, message);
    }

    static bool space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

    /// Whether a line ends at byte i: LF, or a CR not followed by LF (CRLF
    /// ends at its LF, a lone CR is a line end of its own).
    bool line_end(std::size_t i) const {
        return s_[i] == '\n' || (s_[i] == '\r' && (i + 1 == s_.size() || s_[i + 1] != '\n'));
    }

    static bool keyword(std::string_view t, std::string_view k) {
        if (t.size() != k.size()) return false;
        for (std::size_t i = 0; i < t.size(); ++i) {
            char c = t[i];
            if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
            char d = k[i];
            if (d >= 'a' && d <= 'z') d = static_cast<char>(d - 'a' + 'A');
            if (c != d) return false;
        }
        return true;
    }

    /// Next whitespace-separated token (empty at end of input); tok_line_ is its line.
    std::string_view next() {
        while (pos_ < s_.size() && space(s_[pos_])) {
            if (line_end(pos_)) ++line_;
            ++pos_;
        }
        tok_line_ = line_;
        const std::size_t b = pos_;
        while (pos_ < s_.size() && !space(s_[pos_])) ++pos_;
        return s_.substr(b, pos_ - b);
    }

    /// The rest of the current line, trimmed (joint names may contain spaces).
    std::string_view rest_of_line() {
        while (pos_ < s_.size() && (s_[pos_] == ' ' || s_[pos_] == '\t')) ++pos_;
        const std::size_t b = pos_;
        while (pos_ < s_.size() && !line_end(pos_)) ++pos_;
        std::string_view r = s_.substr(b, pos_ - b);
        while (!r.empty() && space(r.back())) r.remove_suffix(1);
        return r;
    }

    template <class T>
    T number(std::string_view t, std::size_t line, const char* what) {
        if (t.empty()) fail(line, std::string("file ends where ") + what + " was expected");
        std::string_view u = t;
        if (u.size() > 1 && u[0] == '+' && u[1] != '-' && u[1] != '+') u.remove_prefix(1);
        double v = 0;
        const auto r = std::from_chars(u.data(), u.data() + u.size(), v);
        if (r.ec == std::errc::result_out_of_range && r.ptr == u.data() + u.size()) {
            // Underflow gives 0 and overflow infinity, as strtod does.
            v = std::strtod(std::string(u).c_str(), nullptr);
        } else if (r.ec != std::errc() || r.ptr != u.data() + u.size()) {
            fail(line, std::string("'") + std::string(t) + "' is not a number (" + what + ")");
        }
        const T x = static_cast<T>(v);
        if (!std::isfinite(x)) fail(line, std::string("non-finite value '") + std::string(t) + "' (" + what + ")");
        // A subnormal (below 1.2e-38 in float) is stored as 0: arithmetic on
        // subnormals is many times slower, and no motion is that small.
        return std::abs(x) < std::numeric_limits<T>::min() ? T(0) : x;
    }

    template <class T>
    Eigen::Matrix<T, 3, 1> offset(const char* what) {
        Eigen::Matrix<T, 3, 1> o;
        for (int k = 0; k < 3; ++k) {
            const std::string_view t = next();
            o[k] = number<T>(t, tok_line_, what);
        }
        return o;
    }

    struct open_joint {
        std::string name;
        std::size_t line;
        int parent;
        int index = -1;  // set once added to the skeleton
        bool has_offset = false, has_channels = false;
        std::vector<channel> channels;
    };

    template <class T>
    void commit(skeleton<T>& sk, open_joint& j, std::vector<Eigen::Matrix<T, 3, 1>>& offsets) {
        if (j.index >= 0) return;
        if (!j.has_offset) fail(j.line, "joint '" + j.name + "' has no OFFSET");
        if (const auto first = sk.find(j.name))
            fail(j.line, "joint name '" + j.name + "' is used twice (first on line " +
                             std::to_string(joint_lines_[*first]) + ")");
        joint_lines_.push_back(j.line);
        j.index = static_cast<int>(sk.add_joint(j.name, j.parent, offsets.back(), j.channels));
    }

    /// Parses a ROOT block (the ROOT keyword already read) without recursion,
    /// so that deeply nested input cannot overflow the stack.
    template <class T>
    void parse_joints(skeleton<T>& sk) {
        std::vector<open_joint> stack;
        std::vector<Eigen::Matrix<T, 3, 1>> offsets;  // parallel to stack
        const auto open = [&](int parent) {
            const std::size_t line = line_;
            std::string_view name = rest_of_line();
            bool brace = false;
            if (!name.empty() && name.back() == '{') {
                name.remove_suffix(1);
                while (!name.empty() && space(name.back())) name.remove_suffix(1);
                brace = true;
            }
            if (name.empty()) fail(line, "joint without a name");
            if (name.find_first_of("{}") != std::string_view::npos)
                fail(line, "joint name '" + std::string(name) + "' contains a brace");
            if (!brace && next() != "{") fail(tok_line_, "expected '{' after joint '" + std::string(name) + "'");
            stack.push_back(open_joint{std::string(name), line, parent, -1, false, false, {}});
            offsets.emplace_back(Eigen::Matrix<T, 3, 1>::Zero());
        };
        open(-1);
        while (!stack.empty()) {
            const std::string_view t = next();
            open_joint& j = stack.back();
            if (t.empty()) fail(line_, "file ends inside joint '" + j.name + "' (missing '}')");
            if (keyword(t, "OFFSET")) {
                if (j.has_offset) fail(tok_line_, "second OFFSET in joint '" + j.name + "'");
                if (j.index >= 0) fail(tok_line_, "OFFSET of joint '" + j.name + "' after its children");
                offsets.back() = offset<T>("OFFSET value");
                j.has_offset = true;
            } else if (keyword(t, "CHANNELS")) {
                if (j.has_channels) fail(tok_line_, "second CHANNELS in joint '" + j.name + "'");
                if (j.index >= 0) fail(tok_line_, "CHANNELS of joint '" + j.name + "' after its children");
                const std::size_t line = tok_line_;
                const std::string_view c = next();
                int n = -1;
                const auto r = std::from_chars(c.data(), c.data() + c.size(), n);
                if (r.ec != std::errc() || r.ptr != c.data() + c.size() || n < 0 || n > 6)
                    fail(line, "CHANNELS count '" + std::string(c) + "' is not a number from 0 to 6");
                for (int k = 0; k < n; ++k) {
                    const std::string_view name = next();
                    if (name.empty()) fail(line_, "file ends inside the CHANNELS of joint '" + j.name + "'");
                    const auto ch = try_parse_channel(name);
                    if (!ch)
                        fail(tok_line_, "CHANNELS of joint '" + j.name + "' declares " + std::to_string(n) +
                                            " channels but item " + std::to_string(k + 1) + " is '" +
                                            std::string(name) + "', not a channel name");
                    for (channel seen : j.channels)
                        if (seen == *ch) fail(tok_line_, "channel " + std::string(name) + " repeated in joint '" + j.name + "'");
                    j.channels.push_back(*ch);
                }
                j.has_channels = true;
            } else if (keyword(t, "JOINT")) {
                commit(sk, j, offsets);
                open(j.index);
            } else if (keyword(t, "End")) {
                commit(sk, j, offsets);
                const std::size_t line = tok_line_;
                if (!keyword(next(), "Site")) fail(line, "expected 'End Site'");
                rest_of_line();  // some exporters name the end site
                const auto end_site_token = [&] {
                    const std::string_view e = next();
                    if (e.empty()) fail(line_, "file ends inside the End Site of joint '" + j.name + "'");
                    return e;
                };
                if (end_site_token() != "{") fail(tok_line_, "expected '{' after End Site");
                if (!keyword(end_site_token(), "OFFSET")) fail(tok_line_, "End Site of joint '" + j.name + "' has no OFFSET");
                const auto o = offset<T>("End Site OFFSET value");
                if (end_site_token() != "}") fail(tok_line_, "expected '}' to close the End Site of joint '" + j.name + "'");
                if (sk[static_cast<std::size_t>(j.index)].end_site)
                    fail(line, "joint '" + j.name + "' has a second End Site");
                sk.set_end_site(static_cast<std::size_t>(j.index), o);
            } else if (t == "}") {
                commit(sk, j, offsets);
                stack.pop_back();
                offsets.pop_back();
            } else {
                fail(tok_line_, "unexpected '" + std::string(t) + "' in joint '" + j.name + "'");
            }
        }
    }

    template <class T>
    void parse_motion(bvh_document<T>& doc) {
        // "Frames: N" (also "Frames:N").
        std::string_view t = next();
        if (t.empty()) fail(line_, "file ends after MOTION (expected 'Frames:')");
        std::string_view count;
        if (keyword(t, "Frames:")) {
            count = next();
        } else if (t.size() > 7 && keyword(t.substr(0, 7), "Frames:")) {
            count = t.substr(7);
        } else {
            fail(tok_line_, "expected 'Frames:' after MOTION, found '" + std::string(t) + "'");
        }
        const std::size_t frames_line = tok_line_;
        unsigned long long frames = 0;
        const auto r = std::from_chars(count.data(), count.data() + count.size(), frames);
        if (r.ec != std::errc() || r.ptr != count.data() + count.size())
            fail(frames_line, "frame count '" + std::string(count) + "' is not a non-negative integer");
        t = next();
        if (t.empty()) fail(line_, "file ends before 'Frame Time:'");
        if (!keyword(t, "Frame")) fail(tok_line_, "expected 'Frame Time:' after the frame count");
        t = next();
        if (t.empty()) fail(line_, "file ends inside 'Frame Time:'");
        std::string_view time;
        if (keyword(t, "Time:")) {
            time = next();
        } else if (t.size() > 5 && keyword(t.substr(0, 5), "Time:")) {
            time = t.substr(5);
        } else {
            fail(tok_line_, "expected 'Frame Time:'");
        }
        doc.frame_time = number<T>(time, tok_line_, "frame time");
        // Normal, so that the frame rate 1 / frame time is finite (as clip asks).
        if (!(doc.frame_time >= std::numeric_limits<T>::min()))
            fail(tok_line_, "frame time must be positive and normal, got " + std::string(time));
        const std::size_t time_line = tok_line_;
        const std::string_view after = rest_of_line();
        if (!after.empty()) fail(time_line, "unexpected '" + std::string(after) + "' after the frame time");
        if (pos_ < s_.size()) ++pos_, ++line_;  // past the newline

        const std::size_t nc = doc.skeleton.channel_count();
        // Without channels no line holds a frame, so nothing would bound the
        // count the header claims.
        if (nc == 0 && frames > 0)
            fail(frames_line, "'Frames: " + std::to_string(frames) + "' but no joint has CHANNELS");
        // Each value takes at least two bytes: never trust the header to size memory.
        const std::size_t room = nc ? (s_.size() - pos_) / (2 * nc) + 1 : 0;
        doc.values.reserve(static_cast<std::size_t>(std::min<unsigned long long>(frames, room)) * nc);
        std::size_t done = 0;
        while (pos_ < s_.size()) {
            // One frame per line; blank lines are skipped.
            const std::size_t line = line_;
            std::size_t on_line = 0;
            for (;;) {
                while (pos_ < s_.size() && !line_end(pos_) && space(s_[pos_])) ++pos_;
                if (pos_ >= s_.size() || line_end(pos_)) break;
                const std::size_t b = pos_;
                while (pos_ < s_.size() && !space(s_[pos_])) ++pos_;
                ++on_line;
                if (done >= frames)
                    fail(line, "more frames than 'Frames: " + std::to_string(frames) + "' (line " +
                                   std::to_string(frames_line) + ")");
                if (on_line > nc) break;
                doc.values.push_back(number<T>(s_.substr(b, pos_ - b), line, "channel value"));
            }
            if (on_line > 0) {
                if (on_line != nc)
                    fail(line, "frame " + std::to_string(done) + " has " + (on_line > nc ? "more than " : "") +
                                   std::to_string(on_line > nc ? nc : on_line) + " values, expected " +
                                   std::to_string(nc) + " (one per channel)");
                ++done;
            }
            if (pos_ < s_.size()) ++pos_, ++line_;
        }
        if (done != frames)
            fail(line_, "file ends after " + std::to_string(done) + " frames, 'Frames: " + std::to_string(frames) +
                            "' (line " + std::to_string(frames_line) + ") promised more");
        doc.frames = done;
    }

    std::string_view s_;
    std::string source_;
    std::size_t pos_ = 0;
    std::size_t line_ = 1;
    std::size_t tok_line_ = 1;
    std::vector<std::size_t> joint_lines_;  // the line of every joint added, for messages
};

}  // namespace detail

/// Parses BVH text into a document (skeleton + raw channel values).
/// `source` names the text in error messages (a file name).
template <class T = double>
bvh_document<T> parse_bvh_document(std::string_view text, std::string source = "<bvh>") {
    return detail::bvh_parser(text, std::move(source)).parse<T>();
}

/// Reads a BVH file into a document. Throws anima::io_error when the file
/// cannot be read (missing, a folder, larger than 1 GiB) and anima::parse_error (file:line: message) when it is malformed.
template <class T = double>
bvh_document<T> read_bvh_document(const std::string& path) {
    return parse_bvh_document<T>(read_file(path), path);
}

/// Parses BVH text into a clip.
template <class T = double>
clip<T> parse_bvh(std::string_view text, std::string source = "<bvh>") {
    return to_clip(parse_bvh_document<T>(text, std::move(source)));
}

/// Reads a BVH file into a clip.
template <class T = double>
clip<T> read_bvh(const std::string& path) {
    return to_clip(read_bvh_document<T>(path));
}

}  // namespace anima
