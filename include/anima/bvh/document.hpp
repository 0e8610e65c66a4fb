// A BVH file as written: the skeleton with its channel layout, the frame time
// and the channel values (degrees and file units) of every frame. The reader
// produces one, the writer consumes one; to_clip / to_document convert to and
// from the clip model, where rotations are quaternions.
#pragma once

#include <anima/core/constants.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/skeleton.hpp>
#include <anima/rotation/detail/quat4.hpp>
#include <anima/rotation/euler.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace anima {
namespace detail {

/// Whether BVH text can carry a joint name so that it reads back the same:
/// not empty, no brace, no line break, no white space at either end.
inline bool bvh_writable_name(std::string_view name) {
    const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; };
    return !name.empty() && name.find_first_of("{}\r\n") == std::string_view::npos && !blank(name.front()) &&
           !blank(name.back());
}

}  // namespace detail

template <class T>
struct bvh_document {
    anima::skeleton<T> skeleton;  ///< joints in file (depth-first) order
    T frame_time = T(1) / T(30);
    std::size_t frames = 0;
    std::vector<T> values;  ///< frames x skeleton.channel_count(), frame-major

    std::size_t channels() const { return skeleton.channel_count(); }
    T value(std::size_t frame, std::size_t channel) const { return values[frame * channels() + channel]; }
};

/// The clip a document describes. A joint's local rotation is the product of
/// its rotation channels in file order (Zrotation Xrotation Yrotation is
/// Rz Rx Ry); its local translation is OFFSET plus its position channels.
template <class T>
clip<T> to_clip(const bvh_document<T>& doc) {
    const auto& sk = doc.skeleton;
    const std::size_t nc = sk.channel_count();
    if (doc.values.size() != doc.frames * nc)
        throw invalid_argument("anima::to_clip: document has " + std::to_string(doc.values.size()) +
                               " values for " + std::to_string(doc.frames) + " frames of " + std::to_string(nc) +
                               " channels");
    clip<T> c(sk, doc.frames, doc.frame_time);
    for (std::size_t f = 0; f < doc.frames; ++f) {
        const T* v = doc.values.data() + f * nc;
        for (std::size_t j = 0; j < sk.size(); ++j) {
            detail::quat4<T> q{T(1), T(0), T(0), T(0)};
            Eigen::Matrix<T, 3, 1> t = sk[j].offset;
            for (channel ch : sk[j].channels) {
                const T x = *v++;
                if (is_rotation(ch))
                    q = q * detail::axis_rotation(axis_of(ch), radians(x));
                else
                    t[static_cast<int>(axis_of(ch))] += x;
            }
            c.set_rotation(f, j, Eigen::Quaternion<T>(q.w, q.x, q.y, q.z));
            if (sk.translation_slot(j) >= 0) c.set_translation(f, j, t);
        }
    }
    return c;
}

namespace detail {

/// The value equal to v modulo 360 that is nearest to previous.
template <class T>
T unwrap_degrees(T v, T previous) {
    return v + T(360) * std::round((previous - v) / T(360));
}

/// Euler angles in degrees of q for the joint's rotation axes (1 to 3 distinct
/// axes), chosen to continue `previous` (the last frame's values; nullptr for
/// the first frame, which takes the principal solution). Throws when q has a
/// component the channels cannot express.
template <class T>
void encode_rotation(const quat4<T>& q, const std::vector<axis>& axes, const T* previous, bool continuous, T* out,
                     const std::string& joint, std::size_t frame) {
    const T tolerance = T(1e3) * std::numeric_limits<T>::epsilon();
    const auto fail = [&] {
        throw invalid_argument("anima::to_document: frame " + std::to_string(frame) + ", joint '" + joint +
                               "': its rotation cannot be written with its " + std::to_string(axes.size()) +
                               " rotation channel(s); give the joint three rotation channels "
                               "(anima::with_rotation_order)");
    };
    if (axes.empty()) {
        if (T(2) * std::atan2(vector_norm(q), std::abs(q.w)) > tolerance) fail();
        return;
    }
    if (axes.size() == 1) {
        const T s = axes[0] == axis::x ? q.x : axes[0] == axis::y ? q.y : q.z;
        // Any other vector component is rotation about another axis. Their
        // own length, not |q|^2 - w^2 - s^2: that difference leaves the
        // rounding of the squares, whose square root (1e-8 in double) would
        // refuse every rotation about the channel's own axis.
        const T other0 = axes[0] == axis::x ? q.y : q.x, other1 = axes[0] == axis::z ? q.y : q.z;
        if (std::hypot(other0, other1) > tolerance) fail();
        T a = degrees(T(2) * std::atan2(s, q.w));
        a = std::remainder(a, T(360));
        out[0] = previous && continuous ? unwrap_degrees(a, previous[0]) : a;
        return;
    }
    // Two or three axes: decompose with the full Tait-Bryan order; with two
    // channels the third angle must come out as zero.
    axis third = axes.size() == 3 ? axes[2] : static_cast<axis>(3 - static_cast<int>(axes[0]) - static_cast<int>(axes[1]));
    const euler_order order = euler_order_of(axes[0], axes[1], third);
    const auto e = matrix_to_euler(to_matrix(q), order);
    std::array<T, 3> sol[2] = {{degrees(e[0]), degrees(e[1]), degrees(e[2])},
                               {degrees(e[0]) + T(180), T(180) - degrees(e[1]), degrees(e[2]) + T(180)}};
    const std::size_t n = axes.size();
    int best = 0;
    T best_cost = std::numeric_limits<T>::infinity();
    for (int s = 0; s < 2; ++s) {
        T cost = 0;
        if (n == 2) {
            cost = std::abs(std::remainder(sol[s][2], T(360)));
        } else if (previous && continuous) {
            for (std::size_t k = 0; k < 3; ++k) cost += std::abs(unwrap_degrees(sol[s][k], previous[k]) - previous[k]);
        } else {
            cost = T(s);  // first frame: the principal solution
        }
        if (cost < best_cost) {
            best_cost = cost;
            best = s;
        }
    }
    if (n == 2 && radians(best_cost) > T(1e-4)) fail();
    for (std::size_t k = 0; k < n; ++k) {
        const T a = std::remainder(sol[best][k], T(360));
        out[k] = previous && continuous ? unwrap_degrees(a, previous[k]) : a;
    }
}

}  // namespace detail

/// How rotations become Euler angles when a clip is written.
enum class euler_angles : unsigned char {
    /// Each frame continues the previous one: no 360 degree jumps, and of the
    /// two equivalent Tait-Bryan triples the nearer one. Smooth channel curves.
    continuous,
    /// Each frame independently: outer angles in (-180, 180], middle angle in
    /// [-90, 90]. Jumps where a joint passes the middle axis's +-90 degrees.
    principal
};

template <>
struct enum_names<euler_angles> {
    static constexpr const char* what = "Euler angle policy";
    static constexpr enum_entry<euler_angles> entries[] = {{euler_angles::continuous, "continuous"},
                                                           {euler_angles::principal, "principal"}};
};

/// The BVH document of a clip: channel values in degrees and the clip's
/// units, laid out as the skeleton's channels. The first frame takes the
/// principal solution; later ones follow `angles`. A clip stores rotations,
/// not angles, so a file that spelled a rotation with the other equivalent
/// triple (or 360 degrees away) is written with other numbers for the same
/// motion; write the bvh_document itself to keep a file's numbers.
/// Throws anima::invalid_argument when a joint's rotation has a component its
/// channels cannot express (e.g. a twist on a joint with one rotation channel).
template <class T>
bvh_document<T> to_document(const clip<T>& c, euler_angles angles_policy = euler_angles::continuous) {
    bvh_document<T> doc;
    doc.skeleton = c.skeleton();
    doc.frame_time = c.frame_time();
    doc.frames = c.frames();
    const auto& sk = doc.skeleton;
    const std::size_t nc = sk.channel_count();
    doc.values.resize(doc.frames * nc);
    std::vector<std::vector<axis>> axes(sk.size());
    for (std::size_t j = 0; j < sk.size(); ++j) axes[j] = sk.rotation_axes(j);
    for (std::size_t f = 0; f < doc.frames; ++f) {
        T* v = doc.values.data() + f * nc;
        const T* prev = f ? v - nc : nullptr;
        for (std::size_t j = 0; j < sk.size(); ++j) {
            const auto& q = c.rotation(f, j);
            const auto& t = c.translation(f, j);
            T angles[3] = {};
            T prev_angles[3] = {};
            std::size_t r = 0;
            const std::size_t start = static_cast<std::size_t>(v - (doc.values.data() + f * nc));
            for (std::size_t k = 0; k < sk[j].channels.size(); ++k)
                if (prev && is_rotation(sk[j].channels[k])) prev_angles[r++] = prev[start + k];
            detail::encode_rotation(detail::quat4<T>{q.w(), q.x(), q.y(), q.z()}, axes[j], prev ? prev_angles : nullptr,
                                    angles_policy == euler_angles::continuous, angles, sk[j].name, f);
            r = 0;
            for (channel ch : sk[j].channels) {
                if (is_rotation(ch))
                    *v++ = angles[r++];
                else
                    *v++ = t[static_cast<int>(axis_of(ch))] - sk[j].offset[static_cast<int>(axis_of(ch))];
            }
        }
    }
    return doc;
}

}  // namespace anima
