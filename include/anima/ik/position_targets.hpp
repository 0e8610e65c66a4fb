// Per-frame position goals for clip IK from a text file, one goal a line:
//
//   # frame,effector,x,y,z
//   120,LeftHand,0.31,1.02,0.15
//   121,LeftHand,0.31,1.03,0.15
//
// what `anima ik --targets` reads: a hand moved along a path, a foot held
// where it is, each target in the clip's world units. And the goals of an
// offset edit: a joint moved by a fixed offset over a range of frames.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/file_io.hpp>
#include <anima/core/text.hpp>
#include <anima/ik/clip_ik.hpp>
#include <anima/ik/goal.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/skeleton.hpp>

#include <Eigen/Core>

#include <charconv>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace anima {

namespace detail {

/// The fields of a comma-separated line, blanks around each trimmed.
inline std::vector<std::string_view> trimmed_fields(std::string_view line) {
    std::vector<std::string_view> fields;
    for (std::size_t start = 0;;) {
        const std::size_t comma = std::min(line.find(',', start), line.size());
        std::string_view cell = line.substr(start, comma - start);
        const std::size_t b = cell.find_first_not_of(" \t"), e = cell.find_last_not_of(" \t");
        fields.push_back(b == std::string_view::npos ? std::string_view() : cell.substr(b, e - b + 1));
        if (comma == line.size()) return fields;
        start = comma + 1;
    }
}

}  // namespace detail

/// Position goals per frame from "frame,effector,x,y,z" lines: a frame
/// number (digits only), a joint of `sk` by name, and the target's world
/// position. '#' starts a comment; blank lines are skipped (line ends and a
/// byte order mark as text_lines reads them). The result has one
/// frame_goals per frame named, in increasing frame order, its goals
/// (position_goal on the joint's origin) in the order of the lines: what
/// solve_clip_ik takes. Throws anima::parse_error ("path:line: message") for
/// a line without five fields, a frame that is not a number or not below
/// `frames`, an effector `sk` does not have (naming a joint that differs
/// only in case), a
/// target that is not three finite numbers, and text with no goal at all.
template <class T>
std::vector<frame_goals<T>> parse_position_targets(std::string_view text, const std::string& path,
                                                   const skeleton<T>& sk, std::size_t frames) {
    std::map<std::size_t, std::vector<ik_goal<T>>> by_frame;
    const std::vector<std::string> lines = text_lines(text);
    for (std::size_t number = 1; number <= lines.size(); ++number) {
        std::string_view line = lines[number - 1];
        line = line.substr(0, line.find('#'));
        if (line.find_first_not_of(" \t") == std::string_view::npos) continue;
        const auto fail = [&](const std::string& message) { throw parse_error(path, number, message); };
        const std::vector<std::string_view> f = detail::trimmed_fields(line);
        if (f.size() != 5)
            fail("expected frame,effector,x,y,z (5 fields), got " + std::to_string(f.size()));
        unsigned long long frame = 0;
        const auto read = std::from_chars(f[0].data(), f[0].data() + f[0].size(), frame);
        if (f[0].empty() || f[0].find_first_not_of("0123456789") != std::string_view::npos || read.ec != std::errc())
            fail("'" + std::string(f[0]) + "' is not a frame number");
        Eigen::Matrix<T, 3, 1> p;
        for (int k = 0; k < 3; ++k) {
            const std::optional<double> v = whole_number(f[2 + static_cast<std::size_t>(k)]);
            if (!v) fail("expected three numbers x,y,z, got '" + std::string(line) + "'");
            p[k] = static_cast<T>(*v);
        }
        if (!p.allFinite()) fail("the target is not finite");
        if (f[1].empty()) fail("the effector name is empty");
        if (frame >= frames)
            fail("frame " + std::to_string(frame) + " is outside the clip (" +
                 (frames == 0 ? std::string("it has no frames") : "0.." + std::to_string(frames - 1)) + ")");
        const auto joint = sk.find(f[1]);
        if (!joint) fail("no joint named '" + std::string(f[1]) + "' in the clip" + sk.did_you_mean(f[1]));
        by_frame[static_cast<std::size_t>(frame)].push_back(position_goal<T>(*joint, p));
    }
    if (by_frame.empty()) throw parse_error(path, lines.size(), "no targets in the file");
    std::vector<frame_goals<T>> out;
    for (auto& [frame, goals] : by_frame) out.push_back({frame, std::move(goals)});
    return out;
}

/// parse_position_targets on the content of a file (read_file: its size
/// checked first). Throws anima::io_error when it cannot be read.
template <class T>
std::vector<frame_goals<T>> read_position_targets(const std::string& path, const skeleton<T>& sk, std::size_t frames) {
    return parse_position_targets(read_file(path), path, sk, frames);
}

/// An offset edit as goals for solve_clip_ik: joint `joint` of c moved by
/// `offset` (world units) from where the recording has it, in every frame
/// first..last ("the left hand 10 cm higher over frames 20-80"). Each frame's
/// goal is a position goal at its recorded global position plus the offset.
/// Throws anima::invalid_argument for a joint outside the skeleton, a
/// reversed range or one outside the clip, or a non-finite offset.
template <class T>
std::vector<frame_goals<T>> offset_goals(const clip<T>& c, std::size_t joint, const Eigen::Matrix<T, 3, 1>& offset,
                                         std::size_t first, std::size_t last) {
    constexpr const char* who = "anima::offset_goals";
    check_argument(joint < c.joints(), who, "joint", "a joint of the clip's " + std::to_string(c.joints()), joint);
    check_argument(first <= last, who, "first", "at most last (" + std::to_string(last) + ")", first);
    check_argument(last < c.frames(), who, "last", "a frame of the clip's " + std::to_string(c.frames()), last);
    for (int k = 0; k < 3; ++k) check_finite(who, "offset", offset[k]);
    std::vector<frame_goals<T>> out;
    out.reserve(last - first + 1);
    global_pose<T> pose;
    for (std::size_t f = first; f <= last; ++f) {
        forward_kinematics(c, f, pose);
        out.push_back({f, {position_goal<T>(joint, pose.positions[joint] + offset)}});
    }
    return out;
}

/// offset_goals with a GLM offset.
template <class T, glm::qualifier P>
std::vector<frame_goals<T>> offset_goals(const clip<T>& c, std::size_t joint, const glm::vec<3, T, P>& offset,
                                         std::size_t first, std::size_t last) {
    return offset_goals(c, joint, detail::eigen_vector(offset), first, last);
}

}  // namespace anima
