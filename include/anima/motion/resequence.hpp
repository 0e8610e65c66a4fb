// A new clip from a stream of frame indices into an existing one: symmetric
// (reversing) playback, video-texture jumps and motion textures all produce
// such streams. Rotations are copied; the root's path on the ground plane
// needs a policy, because a reversed or jumped-over stream has no recorded
// path of its own. The root's height always comes from the source frame.
#pragma once

#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/figure.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace anima {

/// What the root does on the ground plane in a resequenced clip.
enum class root_path : unsigned char {
    /// The source frame's position: reversed playback walks back over the
    /// recorded path (feet stay planted), jumps teleport.
    recorded,
    /// The first output frame's ground position throughout: motion in place.
    in_place,
    /// The source's steps added up: equal to `recorded` for a contiguous
    /// stream, but a jump continues from where the figure is, moving by the
    /// step the source made into the frame jumped to (no teleport).
    accumulated,
    /// As `accumulated`, with reversed steps negated: the figure keeps
    /// travelling the way it went while its limbs play backwards.
    keep_direction
};

template <>
struct enum_names<root_path> {
    static constexpr const char* what = "root path";
    static constexpr enum_entry<root_path> entries[] = {{root_path::recorded, "recorded"},
                                                        {root_path::in_place, "in_place"},
                                                        {root_path::accumulated, "accumulated"},
                                                        {root_path::keep_direction, "keep_direction"}};
};

/// "recorded", "in_place", "accumulated" or "keep_direction" (any case); throws anima::invalid_argument otherwise.
inline root_path parse_root_path(std::string_view name) {
    return parse_enum<root_path>(name, "anima::parse_root_path");
}

struct resequence_params {
    root_path root = root_path::accumulated;
    /// Up axis of the clip; guessed from the skeleton when empty.
    std::optional<signed_axis> up;
};

/// The clip whose frame k is frame indices[k] of `source`. Throws
/// anima::invalid_argument for an index outside the source (naming it).
template <class T>
clip<T> resequence(const clip<T>& source, const std::vector<std::size_t>& indices, const resequence_params& params = {}) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    for (std::size_t k = 0; k < indices.size(); ++k)
        if (indices[k] >= source.frames())
            throw invalid_argument("anima::resequence: index " + std::to_string(k) + " is frame " +
                                   std::to_string(indices[k]) + ", the clip has " + std::to_string(source.frames()) +
                                   " frames");
    clip<T> out(source.skeleton(), indices.size(), source.frame_time());
    const auto& sk = source.skeleton();
    for (std::size_t k = 0; k < indices.size(); ++k)
        for (std::size_t j = 0; j < sk.size(); ++j) {
            out.set_rotation(k, j, source.rotation(indices[k], j));
            if (sk.translation_slot(j) >= 0) out.set_translation(k, j, source.translation(indices[k], j));
        }
    if (indices.empty() || sk.empty() || sk.translation_slot(0) < 0 || params.root == root_path::recorded) return out;

    using vec3 = Eigen::Matrix<T, 3, 1>;
    const int up = static_cast<int>((params.up ? *params.up : guess_up_axis(sk).up).axis);
    const auto ground = [up](vec3 v) {
        v[up] = T(0);
        return v;
    };
    const auto at = [&](std::size_t f) -> const vec3& { return source.root_position(f); };
    vec3 position = ground(at(indices[0]));
    for (std::size_t k = 0; k < indices.size(); ++k) {
        const std::size_t f = indices[k];
        if (k > 0 && params.root != root_path::in_place) {
            const std::size_t prev = indices[k - 1];
            vec3 step = vec3::Zero();
            if (f == prev + 1 || prev == f + 1) {
                step = ground(at(f) - at(prev));
                if (params.root == root_path::keep_direction && prev == f + 1) step = -step;
            } else if (f != prev) {
                // A jump: move as the source moved into frame f.
                step = f > 0 ? ground(at(f) - at(f - 1)) : (source.frames() > 1 ? ground(at(1) - at(0)) : vec3::Zero());
            }
            position += step;
            if (!position.allFinite())
                throw invalid_argument("anima::resequence: the accumulated root path overflows the scalar type at "
                                       "output frame " + std::to_string(k) + "; scale the clip down (scale_clip)");
        }
        vec3 p = position;
        p[up] = at(f)[up];
        out.set_root_position(k, p);
    }
    return out;
}

}  // namespace anima
