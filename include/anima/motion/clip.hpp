// A clip: a skeleton and, per frame, every joint's local rotation (a unit
// quaternion relative to the parent) and the local translation of the joints
// that carry position channels (the root, usually).
// Every value a clip holds is finite: its setters refuse non-finite ones,
// so code that reads a clip need not check.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/skeleton.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace anima {

namespace detail {
struct clip_storage;
}

template <class T>
class clip {
public:
    using scalar = T;
    using vector3 = Eigen::Matrix<T, 3, 1>;
    using quaternion = Eigen::Quaternion<T>;

    clip() = default;

    /// A clip of `frames` frames of the rest pose (identity rotations, rest
    /// offsets), sampled every frame_time seconds (> 0 and finite).
    clip(anima::skeleton<T> skel, std::size_t frames, T frame_time) : skeleton_(std::move(skel)) {
        set_frame_time(frame_time);
        resize(frames);
    }

    const anima::skeleton<T>& skeleton() const noexcept { return skeleton_; }
    std::size_t frames() const noexcept { return frames_; }
    std::size_t joints() const noexcept { return skeleton_.size(); }
    bool empty() const noexcept { return frames_ == 0; }
    T frame_time() const noexcept { return frame_time_; }
    T frame_rate() const noexcept { return T(1) / frame_time_; }
    /// Time from the first to the last frame.
    T duration() const noexcept { return frames_ > 1 ? frame_time_ * static_cast<T>(frames_ - 1) : T(0); }

    /// A normal positive number, so that the frame rate 1 / frame_time is finite.
    void set_frame_time(T frame_time) {
        using std::isfinite;
        check_argument(frame_time >= std::numeric_limits<T>::min() && isfinite(frame_time), "anima::clip",
                       "frame time", "positive, normal and finite", frame_time);
        frame_time_ = frame_time;
    }

    /// Changes the number of frames; new frames repeat the last frame (or the
    /// rest pose for an empty clip).
    void resize(std::size_t frames) {
        const std::size_t nj = skeleton_.size(), nt = skeleton_.translated_joint_count();
        if (frames_ == 0) {
            rotations_.assign(frames * nj, quaternion::Identity());
            translations_.clear();
            for (std::size_t f = 0; f < frames; ++f)
                for (std::size_t j = 0; j < nj; ++j)
                    if (skeleton_.translation_slot(j) >= 0) translations_.push_back(skeleton_[j].offset);
        } else {
            rotations_.reserve(frames * nj);
            translations_.reserve(frames * nt);
            for (std::size_t f = frames_; f < frames; ++f) {
                for (std::size_t j = 0; j < nj; ++j) rotations_.push_back(rotations_[(frames_ - 1) * nj + j]);
                for (std::size_t k = 0; k < nt; ++k) translations_.push_back(translations_[(frames_ - 1) * nt + k]);
            }
            rotations_.resize(frames * nj);
            translations_.resize(frames * nt);
        }
        frames_ = frames;
    }

    /// Local rotation of joint j at frame f (relative to the parent's frame).
    const quaternion& rotation(std::size_t f, std::size_t j) const { return rotations_[index(f, j)]; }
    /// Sets a local rotation; q is normalised, and a zero or non-finite q is refused.
    void set_rotation(std::size_t f, std::size_t j, const quaternion& q) {
        const T n = q.norm();
        if (!(n > T(0)) || !std::isfinite(n))
            throw invalid_argument("anima::clip::set_rotation: frame " + std::to_string(f) + ", joint '" +
                                   skeleton_.at(j).name + "': zero or non-finite quaternion");
        rotations_[index(f, j)] = quaternion(q.coeffs() / n);
    }
    /// Sets joint j's rotation at frames first, first + 1, ..., first + n - 1
    /// to q[0], ..., q[n - 1]: one joint's blended rotations through many
    /// frames at once. A q already of unit length to rounding (|q|^2 within
    /// 16 epsilon of 1, as slerp, squad and nlerp return them) is stored as it
    /// is, without set_rotation's square root and division; any other is
    /// normalised as set_rotation does, and a zero or non-finite one refused.
    void set_joint_rotations(std::size_t j, std::size_t first, const quaternion* q, std::size_t n) {
        if (n == 0) return;
        if (n > frames_ || first > frames_ - n)
            throw invalid_argument("anima::clip::set_joint_rotations: frames [" + std::to_string(first) + ", " +
                                   std::to_string(first) + " + " + std::to_string(n) + ") out of range (" +
                                   std::to_string(frames_) + " frames)");
        const std::size_t nj = skeleton_.size();
        quaternion* out = rotations_.data() + index(first, j);
        constexpr T tolerance = 16 * std::numeric_limits<T>::epsilon();
        for (std::size_t k = 0; k < n; ++k, out += nj) {
            if (std::abs(q[k].squaredNorm() - T(1)) <= tolerance) *out = q[k];  // NaN fails the test
            else set_rotation(first + k, j, q[k]);
        }
    }

    /// Local translation of joint j at frame f: the animated value for joints
    /// with position channels, the rest offset otherwise.
    const vector3& translation(std::size_t f, std::size_t j) const {
        check_frame(f, "anima::clip::translation");
        (void)skeleton_.at(j);  // range check
        const int s = skeleton_.translation_slot(j);
        return s < 0 ? skeleton_[j].offset
                     : translations_[f * skeleton_.translated_joint_count() + static_cast<std::size_t>(s)];
    }
    /// Sets the local translation of a joint that has position channels;
    /// throws for a joint without them (its translation is the rest offset).
    void set_translation(std::size_t f, std::size_t j, const vector3& t) {
        check_frame(f, "anima::clip::set_translation");
        if (j >= skeleton_.size() || skeleton_.translation_slot(j) < 0)
            throw invalid_argument("anima::clip::set_translation: joint " + std::to_string(j) +
                                   " has no position channels");
        if (!t.allFinite())
            throw invalid_argument("anima::clip::set_translation: frame " + std::to_string(f) + ", joint '" +
                                   skeleton_[j].name + "': non-finite translation");
        translations_[f * skeleton_.translated_joint_count() + static_cast<std::size_t>(skeleton_.translation_slot(j))] = t;
    }

    /// Translation of the first joint (the root) at frame f.
    const vector3& root_position(std::size_t f) const { return translation(f, 0); }
    void set_root_position(std::size_t f, const vector3& t) { set_translation(f, 0, t); }

    /// Frames [first, last) as a new clip with the same skeleton.
    clip slice(std::size_t first, std::size_t last) const {
        if (first > last || last > frames_)
            throw invalid_argument("anima::clip::slice: range [" + std::to_string(first) + ", " +
                                   std::to_string(last) + ") is not within 0.." + std::to_string(frames_));
        clip out(skeleton_, 0, frame_time_);
        const std::size_t nj = skeleton_.size(), nt = skeleton_.translated_joint_count();
        out.rotations_.assign(rotations_.begin() + static_cast<std::ptrdiff_t>(first * nj),
                              rotations_.begin() + static_cast<std::ptrdiff_t>(last * nj));
        out.translations_.assign(translations_.begin() + static_cast<std::ptrdiff_t>(first * nt),
                                 translations_.begin() + static_cast<std::ptrdiff_t>(last * nt));
        out.frames_ = last - first;
        return out;
    }

    /// Appends the frames of another clip with an equal skeleton.
    void append(const clip& other) {
        if (other.skeleton_ != skeleton_)
            throw invalid_argument("anima::clip::append: the clips have different skeletons");
        rotations_.insert(rotations_.end(), other.rotations_.begin(), other.rotations_.end());
        translations_.insert(translations_.end(), other.translations_.begin(), other.translations_.end());
        frames_ += other.frames_;
    }

    /// Raw storage, frame-major: rotations()[f * joints() + j] and
    /// translations()[f * skeleton().translated_joint_count() + slot].
    const std::vector<quaternion>& rotations() const noexcept { return rotations_; }
    const std::vector<vector3>& translations() const noexcept { return translations_; }

private:
    friend struct detail::clip_storage;

    std::size_t index(std::size_t f, std::size_t j) const {
        check_frame(f, "anima::clip");
        if (j >= skeleton_.size())
            throw invalid_argument("anima::clip: joint index " + std::to_string(j) + " out of range (" +
                                   std::to_string(skeleton_.size()) + " joints)");
        return f * skeleton_.size() + j;
    }
    void check_frame(std::size_t f, const char* who) const {
        if (f >= frames_)
            throw invalid_argument(std::string(who) + ": frame " + std::to_string(f) + " out of range (" +
                                   std::to_string(frames_) + " frames)");
    }

    anima::skeleton<T> skeleton_;
    std::size_t frames_ = 0;
    T frame_time_ = T(1) / T(30);
    std::vector<quaternion> rotations_;
    std::vector<vector3> translations_;
};

namespace detail {

/// The library's own write access to a clip's rotations, for blends that
/// give unit quaternions by construction (slerp, squad, normalised lerps)
/// and write a joint's frames in place, at stride joints(), without
/// set_rotation's check of each one.
struct clip_storage {
    template <class T>
    static Eigen::Quaternion<T>* rotations(clip<T>& c) noexcept {
        return c.rotations_.data();
    }
};

}  // namespace detail

/// The bytes one frame of a clip of skeleton sk stores: a rotation per
/// joint and a translation per translated joint. What the library's
/// max_memory limits count a clip by.
template <class T>
double clip_frame_bytes(const skeleton<T>& sk) {
    return static_cast<double>(4 * sizeof(T) * sk.size() + 3 * sizeof(T) * sk.translated_joint_count());
}

}  // namespace anima
