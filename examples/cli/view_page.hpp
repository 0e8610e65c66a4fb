// The page `anima view` and the --view options write: one self-contained
// HTML file that plays clips in a browser (three.js compiled in, or a 2D
// canvas), with their foot contacts, timeline markers and IK targets. The
// CLI computes every joint's world position (forward kinematics) and writes
// them into the page; the player (examples/cli/view/player.js) only draws.
#pragma once

#include "common.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace anima_cli {

/// A clip to play, named on the page by `label` ("input", "texture", a file name).
struct view_clip {
    std::string label;
    clip_t motion;
};

/// An event on the timeline: frames first..last of clip `clip` (one frame
/// when last == first). `kind` picks its colour ("seam", "overlap",
/// "transition", "turn", "key", "target"); `label` is shown on hover.
struct view_marker {
    std::size_t clip = 0, first = 0, last = 0;
    std::string kind, label;
};

/// A point shown with clip `clip` at frame `frame` (an IK target), in the
/// clip's file coordinates.
struct view_target {
    std::size_t clip = 0, frame = 0;
    vec3 position = vec3::Zero();
    std::string label;
};

struct view_page {
    std::string title;
    std::vector<view_clip> clips;
    std::vector<view_marker> markers;
    std::vector<view_target> targets;
    bool overlay = false;                  ///< one place for all clips instead of side by side
    std::optional<anima::signed_axis> up;  ///< guessed per clip when empty
};

/// Whether this build embeds three.js (else pages draw with a 2D canvas).
bool view_has_three();

/// The page's HTML. Throws failure for a clip without frames, a marker or
/// target outside its clip, or a page that would need more than 1 GiB.
std::string make_view_page(const view_page& page);

/// Writes the page atomically to `path` and returns what to print: "PATH: 2
/// clips, 3 markers, 1.2 MB, WebGL (three.js 0.170.0) or 2D canvas".
std::string write_view_page(const std::string& path, const view_page& page);

/// One marker of `kind` on clip `clip` per run of consecutive frames in
/// `frames` (sorted or not, repeats allowed), labelled "LABEL (frame a)" or
/// "LABEL (frames a-b)".
std::vector<view_marker> frame_markers(std::size_t clip, const std::vector<std::size_t>& frames, const std::string& kind,
                                       const std::string& label);

/// Adds `--view PAGE.html` to a subcommand that makes motion.
CLI::Option* add_view_option(CLI::App& sub, std::string& path, const std::string& what);

}  // namespace anima_cli
