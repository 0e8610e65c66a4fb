// Shared pieces of every transition: checking two clips can be joined, the
// root's velocity and acceleration at a frame, and placing the next clip in
// world space with its heading turned to match.
#pragma once

#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/figure.hpp>
#include <anima/rotation/swing_twist.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/QR>

#include <algorithm>
#include <cstddef>
#include <string>

namespace anima {

/// Velocity and acceleration of a point.
template <class T>
struct point_motion {
    Eigen::Matrix<T, 3, 1> velocity = Eigen::Matrix<T, 3, 1>::Zero();
    Eigen::Matrix<T, 3, 1> acceleration = Eigen::Matrix<T, 3, 1>::Zero();
};

namespace detail {

/// Root fits over at most this many frames (0.53 s at 120 Hz) run in
/// fixed-size storage, with no heap allocation: the same algorithm as on
/// dynamic matrices (bit for bit the same results with Eigen 3.4).
inline constexpr int root_fit_rows = 64;

/// root_motion_at's factorisation of its design matrix, kept from call to
/// call: the matrix depends only on the number of frames and the frame time.
template <class T>
struct root_fit {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, 3, Eigen::ColMajor, root_fit_rows, 3>;
    Eigen::ColPivHouseholderQR<matrix> qr;
    Eigen::Index rows = 0;  ///< frames of the factorised design matrix (0: none yet)
    T frame_time = 0;
};

template <class T>
point_motion<T> root_motion_at(const clip<T>& c, std::size_t frame, std::size_t window, root_fit<T>& fit) {
    if (frame >= c.frames())
        throw invalid_argument("anima::root_motion_at: frame " + std::to_string(frame) + " out of range (" +
                               std::to_string(c.frames()) + " frames)");
    point_motion<T> out;
    const std::size_t count = std::min(std::max<std::size_t>(window, 3), frame + 1);
    if (count < 2) return out;
    const T dt = c.frame_time();
    if (count == 2) {
        out.velocity = (c.root_position(frame) - c.root_position(frame - 1)) / dt;
        return out;
    }
    // p(s) = c0 + c1 s + c2 s^2 with s = time relative to `frame` (s <= 0).
    const auto rows = static_cast<Eigen::Index>(count);
    const auto design = [&](auto& a) {
        a.resize(rows, 3);
        for (Eigen::Index i = 0; i < rows; ++i) {
            const T s = -static_cast<T>(i) * dt;
            a.row(i) << T(1), s, s * s;
        }
    };
    const auto positions = [&](auto& y) {
        y.resize(rows, 3);
        for (std::size_t i = 0; i < count; ++i)
            y.row(static_cast<Eigen::Index>(i)) = c.root_position(frame - i).transpose();
    };
    Eigen::Matrix<T, 3, 3> coef;
    if (rows <= root_fit_rows) {
        if (fit.rows != rows || fit.frame_time != dt) {
            typename root_fit<T>::matrix a;
            design(a);
            fit.qr.compute(a);
            fit.rows = rows;
            fit.frame_time = dt;
        }
        typename root_fit<T>::matrix y;
        positions(y);
        coef = fit.qr.solve(y);
    } else {
        Eigen::Matrix<T, Eigen::Dynamic, 3> a, y;
        design(a);
        positions(y);
        coef = a.colPivHouseholderQr().solve(y);
    }
    out.velocity = coef.row(1).transpose();
    out.acceleration = T(2) * coef.row(2).transpose();
    return out;
}

}  // namespace detail

/// Root velocity and acceleration at `frame` from the frames up to it: a
/// least-squares quadratic through the last `window` frames (at least 3),
/// which tames the noise that plain second differences amplify at 120 Hz.
/// With two frames only the velocity is estimated, with one neither.
template <class T>
point_motion<T> root_motion_at(const clip<T>& c, std::size_t frame, std::size_t window = 7) {
    detail::root_fit<T> fit;
    return detail::root_motion_at(c, frame, window, fit);
}

/// The turn about `up` that takes the heading of orientation `from` to that
/// of `to` (headings are the twists about the up axis).
template <class T>
Eigen::Quaternion<T> heading_change(const Eigen::Quaternion<T>& from, const Eigen::Quaternion<T>& to, signed_axis up) {
    const auto u = axis_vector<T>(up);
    return swing_twist(to, u).second * swing_twist(from, u).second.conjugate();
}

/// Where place_clip puts a clip: its frames from `first` on, turned by `turn`
/// about the vertical through its root at `first` (`pivot`) and moved so that
/// that root lands on `start`. A game can play the clip through it instead of
/// placing a copy.
template <class T>
struct clip_placement {
    std::size_t first = 0;
    Eigen::Quaternion<T> turn = Eigen::Quaternion<T>::Identity();
    Eigen::Matrix<T, 3, 1> pivot = Eigen::Matrix<T, 3, 1>::Zero();
    Eigen::Matrix<T, 3, 1> start = Eigen::Matrix<T, 3, 1>::Zero();

    /// The placed rotation of a root rotation, as place_clip stores it (normalised as clip::set_rotation does).
    Eigen::Quaternion<T> rotation(const Eigen::Quaternion<T>& root) const {
        const Eigen::Quaternion<T> q = turn * root;
        return Eigen::Quaternion<T>(q.coeffs() / q.norm());
    }
    /// The placed position of a root position (roots with position channels; others keep their offset).
    Eigen::Matrix<T, 3, 1> position(const Eigen::Matrix<T, 3, 1>& root) const { return turn * (root - pivot) + start; }
};

/// Frames [first, end) of c, turned by `turn` about the vertical through the
/// root at `first` and moved so that that root lands on `start`.
template <class T>
clip<T> place_clip(const clip<T>& c, std::size_t first, const Eigen::Quaternion<T>& turn,
                   const Eigen::Matrix<T, 3, 1>& start) {
    if (first >= c.frames())
        throw invalid_argument("anima::place_clip: frame " + std::to_string(first) + " out of range (" +
                               std::to_string(c.frames()) + " frames)");
    clip<T> out = c.slice(first, c.frames());
    const Eigen::Matrix<T, 3, 1> pivot = out.root_position(0);
    const bool translated = out.skeleton().translation_slot(0) >= 0;
    for (std::size_t f = 0; f < out.frames(); ++f) {
        out.set_rotation(f, 0, turn * out.rotation(f, 0));
        if (translated) out.set_root_position(f, turn * (out.root_position(f) - pivot) + start);
    }
    return out;
}

}  // namespace anima
