// A folder of face frames with landmarks, the layout SADM trains and
// evaluates on (as ../shared/data/face and examples/data/face):
//   FOLDER/points/NAME.pts   the frame's landmarks (FGNet/IBUG .pts)
//   FOLDER/images/NAME.ext   the frame (.jpg, .png, .pgm, .ppm, .jpeg, .pnm)
// Frames are taken in name order, so numbered names give the video's order
// and a hold-out split (every:N, last:N) means the same frames every time.
// The library decodes only PGM/PPM; JPEG, PNG or anything else is read by a
// decoder the caller passes in, so the library depends on no image codec.
#pragma once

#include <anima/core/error.hpp>
#include <anima/core/text.hpp>
#include <anima/image/image.hpp>
#include <anima/image/pnm.hpp>
#include <anima/sadm/landmarks.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace anima {

// ---------------------------------------------------------------------------
// Hold-out splits
// ---------------------------------------------------------------------------

/// Which frames of a sequence are held out to test a model on frames it was
/// not trained on. every:N holds out frames N-1, 2N-1, ... (test frames spread
/// over the sequence, each next to training frames); last:N holds out the last
/// N (a contiguous block: expressions the training frames may not show, the
/// harder and more honest test).
struct frame_split {
    enum class rule { none, every, last };
    rule kind = rule::none;
    std::size_t count = 0;  ///< the N of every:N and last:N (at least 1)
};

/// Parses "every:N" or "last:N" (N >= 1, decimal digits); "" is no split.
/// Throws anima::invalid_argument naming the spec for anything else.
inline frame_split parse_frame_split(std::string_view spec) {
    if (spec.empty()) return {};
    const std::string who = "anima::parse_frame_split: '" + escape_for_message(spec, 200) + "'";
    const std::size_t colon = spec.find(':');
    const std::string_view kind = spec.substr(0, colon);
    const std::string_view digits = colon == std::string_view::npos ? std::string_view() : spec.substr(colon + 1);
    bool ok = (kind == "every" || kind == "last") && !digits.empty();
    constexpr std::size_t top = std::numeric_limits<std::size_t>::max();
    std::size_t n = 0;
    for (const char c : digits) {
        if (c < '0' || c > '9') ok = false;
        if (!ok) break;
        const auto digit = static_cast<std::size_t>(c - '0');
        if (n > (top - digit) / 10) throw invalid_argument(who + ": N is larger than " + std::to_string(top));
        n = n * 10 + digit;
    }
    if (!ok || n == 0)
        throw invalid_argument(who + " is not a hold-out rule: use every:N (every Nth frame) or last:N (the last N "
                                     "frames), N >= 1");
    return {kind == "every" ? frame_split::rule::every : frame_split::rule::last, n};
}

/// The spec parse_frame_split reads back: "every:N", "last:N", "" for none.
inline std::string to_string(const frame_split& split) {
    switch (split.kind) {
        case frame_split::rule::every: return "every:" + std::to_string(split.count);
        case frame_split::rule::last: return "last:" + std::to_string(split.count);
        case frame_split::rule::none: break;
    }
    return {};
}

/// Whether each of `count` frames (in name order) is held out under the split;
/// none holds out no frame. Throws anima::invalid_argument for every:0 or last:0.
inline std::vector<bool> held_out(const frame_split& split, std::size_t count) {
    std::vector<bool> out(count, false);
    if (split.kind == frame_split::rule::none) return out;
    if (split.count == 0)
        throw invalid_argument("anima::held_out: '" + to_string(split) + "' holds out nothing: N must be at least 1");
    for (std::size_t k = 0; k < count; ++k)
        out[k] = split.kind == frame_split::rule::every ? (k + 1) % split.count == 0 : count - k <= split.count;
    return out;
}

// ---------------------------------------------------------------------------
// Listing
// ---------------------------------------------------------------------------

/// The image extensions a frame folder's images/ may use, in the order they
/// are looked for when a name has more than one image.
inline constexpr std::array<std::string_view, 6> frame_image_extensions{".jpg", ".png",  ".pgm",
                                                                        ".ppm", ".jpeg", ".pnm"};

/// The frames of a folder as paths. Listing decodes nothing, so a folder of
/// thousands of frames is checked (every .pts has its image) before any work.
struct frame_files {
    std::string folder;                       ///< as given to list_frame_folder
    std::vector<std::string> names;           ///< NAME of each frame, in name order
    std::vector<std::string> image_paths;     ///< FOLDER/images/NAME.ext
    std::vector<std::string> landmark_paths;  ///< FOLDER/points/NAME.pts

    std::size_t size() const noexcept { return names.size(); }
};

namespace detail {

/// "NAME.jpg, .png, ... and .pnm": the image files looked for.
inline std::string frame_image_candidates(const std::string& name) {
    std::string out = name;
    for (std::size_t k = 0; k < frame_image_extensions.size(); ++k) {
        if (k > 0) out += k + 1 == frame_image_extensions.size() ? " and " : ", ";
        out += frame_image_extensions[k];
    }
    return out;
}

inline std::string frame_folder_layout() {
    return "a frame folder holds points/NAME.pts and images/" + frame_image_candidates("NAME");
}

/// Throws anima::io_error naming `path` unless it is a folder.
inline void require_folder(const std::filesystem::path& path) {
    std::error_code ec;
    const std::filesystem::file_status s = std::filesystem::status(path, ec);
    if (s.type() == std::filesystem::file_type::not_found)
        throw io_error("'" + path.string() + "' does not exist: " + frame_folder_layout());
    if (ec) throw io_error("cannot read '" + path.string() + "': " + ec.message());
    if (s.type() != std::filesystem::file_type::directory)
        throw io_error("'" + path.string() + "' is not a folder: " + frame_folder_layout());
}

}  // namespace detail

/// The frames of `folder`: every points/NAME.pts in name order, each with its
/// images/NAME.ext (see frame_image_extensions). Throws anima::io_error naming
/// the folder when it, points/ or images/ is missing, when points/ holds no
/// .pts file or cannot be read, and naming the .pts file when its image is
/// missing.
inline frame_files list_frame_folder(const std::string& folder) {
    namespace fs = std::filesystem;
    detail::require_folder(folder);
    const fs::path points = fs::path(folder) / "points", images = fs::path(folder) / "images";
    detail::require_folder(points);
    detail::require_folder(images);
    frame_files out;
    out.folder = folder;
    std::error_code ec;
    fs::directory_iterator it(points, ec), end;
    for (; !ec && it != end; it.increment(ec))
        if (it->path().extension() == ".pts") out.names.push_back(it->path().stem().string());
    if (ec) throw io_error("cannot list '" + points.string() + "': " + ec.message());
    if (out.names.empty())
        throw io_error("'" + points.string() + "' holds no .pts file: " + detail::frame_folder_layout());
    std::sort(out.names.begin(), out.names.end());
    for (const std::string& name : out.names) {
        std::string image;
        for (const std::string_view ext : frame_image_extensions) {
            const fs::path candidate = images / (name + std::string(ext));
            if (fs::exists(candidate, ec)) {
                image = candidate.string();
                break;
            }
        }
        if (image.empty())
            throw io_error("no image for '" + name + ".pts' in '" + images.string() + "': looked for " +
                           detail::frame_image_candidates(name));
        out.image_paths.push_back(image);
        out.landmark_paths.push_back((points / (name + ".pts")).string());
    }
    return out;
}

/// Which frames of a split a caller wants: all of them, the training frames
/// (those the split does not hold out) or the test frames (those it does).
enum class frame_selection { all, training, test };

/// The frames of `files` that `which` picks under `split`, in order.
inline frame_files select_frames(const frame_files& files, const frame_split& split, frame_selection which) {
    if (which == frame_selection::all) return files;
    const std::vector<bool> held = held_out(split, files.size());
    frame_files out;
    out.folder = files.folder;
    for (std::size_t k = 0; k < files.size(); ++k) {
        if (held[k] != (which == frame_selection::test)) continue;
        out.names.push_back(files.names[k]);
        out.image_paths.push_back(files.image_paths[k]);
        out.landmark_paths.push_back(files.landmark_paths[k]);
    }
    return out;
}

// ---------------------------------------------------------------------------
// Loading
// ---------------------------------------------------------------------------

/// Frames with their paths, decoded images (grey levels 0-255) and landmarks.
template <class T>
struct frame_set : frame_files {
    std::vector<grey_image<T>> images;
    std::vector<landmark_set<T>> landmarks;
};

/// Decodes one image file into grey levels 0-255.
template <class T>
using frame_decoder = std::function<grey_image<T>(const std::string& path)>;

/// The default decoder: PGM/PPM (.pgm, .ppm, .pnm) with read_grey_pnm. Throws
/// anima::io_error for any other extension, saying which types it reads and
/// that a decoder can be passed for the others.
template <class T>
grey_image<T> read_frame_image(const std::string& path) {
    const std::string ext = ascii_lower(std::filesystem::path(path).extension().string());
    if (ext == ".pgm" || ext == ".ppm" || ext == ".pnm") return read_grey_pnm<T>(path);
    throw io_error("cannot read '" + path + "': anima::read_frame_image reads PGM/PPM images (.pgm, .ppm, .pnm); " +
                   "pass a decoder (frame_load_options::decode) for other types");
}

/// How load_frames decodes images and reports progress.
template <class T>
struct frame_load_options {
    frame_decoder<T> decode;  ///< empty: read_frame_image<T> (PGM/PPM only)
    /// Called after each frame: (frames loaded, frames to load).
    std::function<void(std::size_t loaded, std::size_t total)> progress;
};

/// Reads every frame of `files`: its landmarks, then its image. Frames must
/// agree for a model to be built from them, so this throws
/// anima::invalid_argument for fewer than 2 frames (naming the folder), for a
/// landmark count that differs from the first frame's (naming both .pts
/// files) and for a landmark outside its image (naming the .pts file, the
/// point and the image); errors of read_pts and the decoder (anima::io_error,
/// anima::parse_error, naming the file) pass through.
template <class T>
frame_set<T> load_frames(const frame_files& files, const frame_load_options<T>& options = {}) {
    const std::size_t n = files.size();
    if (files.image_paths.size() != n || files.landmark_paths.size() != n)
        throw invalid_argument("anima::load_frames: " + std::to_string(n) + " names, " +
                               std::to_string(files.image_paths.size()) + " image paths and " +
                               std::to_string(files.landmark_paths.size()) + " landmark paths");
    if (n < 2)
        throw invalid_argument("'" + files.folder + "': " + std::to_string(n) + (n == 1 ? " frame" : " frames") +
                               " to load, at least 2 are needed");
    const frame_decoder<T> decode = options.decode ? options.decode : frame_decoder<T>(&read_frame_image<T>);
    frame_set<T> out;
    static_cast<frame_files&>(out) = files;
    out.images.reserve(n);
    out.landmarks.reserve(n);
    for (std::size_t k = 0; k < n; ++k) {
        const std::string& pts = files.landmark_paths[k];
        const std::string& image_path = files.image_paths[k];
        landmark_set<T> lm = read_pts<T>(pts);
        if (k > 0 && lm.rows() != out.landmarks.front().rows())
            throw invalid_argument("'" + pts + "' has " + std::to_string(lm.rows()) + " points, '" +
                                   files.landmark_paths.front() + "' has " +
                                   std::to_string(out.landmarks.front().rows()) +
                                   ": every frame needs the same landmarks");
        grey_image<T> image = decode(image_path);
        if (image.size() == 0) throw invalid_argument("'" + image_path + "' was decoded to an empty image");
        try {
            check_landmarks_inside(lm, image.cols(), image.rows(), "'" + pts + "'");
        } catch (const invalid_argument& e) {
            throw invalid_argument(std::string(e.what()) + " '" + image_path + "'");
        }
        out.landmarks.push_back(std::move(lm));
        out.images.push_back(std::move(image));
        if (options.progress) options.progress(k + 1, n);
    }
    return out;
}

/// list_frame_folder, select_frames and load_frames in one call: the frames
/// of `folder` that `which` picks under `split`, decoded. Throws as those do;
/// when fewer than 2 frames are picked, the message names the folder, the
/// split and the folder's frame count.
template <class T>
frame_set<T> load_frame_folder(const std::string& folder, const frame_split& split = {},
                               frame_selection which = frame_selection::all,
                               const frame_load_options<T>& options = {}) {
    const frame_files all = list_frame_folder(folder);
    const frame_files picked = select_frames(all, split, which);
    if (picked.size() < 2) {
        const std::string frames = std::to_string(all.size()) + (all.size() == 1 ? " frame" : " frames");
        if (which == frame_selection::all)
            throw invalid_argument("'" + folder + "' has " + frames + ", at least 2 are needed");
        throw invalid_argument("'" + folder + "': " + std::to_string(picked.size()) + " of its " + frames +
                               (picked.size() == 1 ? " is " : " are ") +
                               (which == frame_selection::test ? "held out" : "left for training") +
                               (split.kind == frame_split::rule::none ? " (no hold-out rule given)"
                                                                      : " by " + to_string(split)) +
                               ", at least 2 are needed");
    }
    return load_frames(picked, options);
}

}  // namespace anima
