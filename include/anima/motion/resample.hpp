// Resampling a clip to another frame time: rotations by slerp and
// translations linearly between the two nearest source frames.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/core/nondeduced.hpp>
#include <anima/motion/clip.hpp>
#include <anima/rotation/slerp.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

namespace anima {

namespace detail {
/// The frame of a resampled clip r at the time of frame f of its source,
/// whose frame time was source_frame_time.
template <class T>
std::size_t resampled_frame(std::size_t f, T source_frame_time, const clip<T>& r) {
    if (r.frames() == 0) return 0;
    const auto g = static_cast<std::size_t>(std::lround(static_cast<T>(f) * source_frame_time / r.frame_time()));
    return std::min(g, r.frames() - 1);
}
}  // namespace detail

/// The clip sampled every frame_time seconds over the same duration (the last
/// output frame is the last whole step that fits). An empty or one-frame clip
/// keeps its frames. Throws anima::invalid_argument when the output would take
/// more than max_memory bytes (1 GiB by default; 0 lifts the limit), e.g. two
/// frames a second apart resampled every nanosecond.
template <class T>
clip<T> resample(const clip<T>& c, nondeduced_t<T> frame_time, double max_memory = 1024.0 * 1024.0 * 1024.0) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    check_positive("anima::resample", "frame time", frame_time);
    if (c.frames() < 2) {
        clip<T> out = c;
        out.set_frame_time(frame_time);
        return out;
    }
    // Tolerate rounding so that e.g. 1/120 -> 1/120 keeps the last frame.
    const double steps = std::floor(static_cast<double>(c.duration() / frame_time) + 1e-6);
    const double bytes = (steps + 1) * clip_frame_bytes(c.skeleton());
    if (!(steps < 1e18) || (max_memory > 0 && !(bytes <= max_memory)))
        throw invalid_argument("anima::resample: frame time " + detail::argument_text(frame_time) + " over " +
                               detail::argument_text(c.duration()) + " s makes " + detail::argument_text(steps + 1) +
                               " frames, about " + detail::argument_text(std::ceil(bytes / 1048576.0)) +
                               " MiB, more than max_memory (" + detail::argument_text(max_memory / 1048576.0) +
                               " MiB)");
    const auto n = static_cast<std::size_t>(steps) + 1;
    clip<T> out(c.skeleton(), n, frame_time);
    for (std::size_t f = 0; f < n; ++f) {
        const T s = std::min(static_cast<T>(f) * frame_time / c.frame_time(), static_cast<T>(c.frames() - 1));
        const auto i = std::min(static_cast<std::size_t>(s), c.frames() - 2);
        const T u = s - static_cast<T>(i);
        for (std::size_t j = 0; j < c.joints(); ++j) {
            out.set_rotation(f, j, slerp(c.rotation(i, j), c.rotation(i + 1, j), u));
            if (c.skeleton().translation_slot(j) >= 0)
                out.set_translation(f, j, (T(1) - u) * c.translation(i, j) + u * c.translation(i + 1, j));
        }
    }
    return out;
}

}  // namespace anima
