// Forward kinematics: local rotations and translations to global joint
// positions and orientations.
#pragma once

#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/motion/clip.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace anima {

/// Global (world-space) position and orientation of every joint at one frame.
template <class T>
struct global_pose {
    std::vector<Eigen::Matrix<T, 3, 1>> positions;
    std::vector<Eigen::Quaternion<T>> orientations;
};

/// Global pose of frame f, written into `out` (reusing its storage: no
/// allocation once it has the right size, so it can run every game frame).
template <class T>
void forward_kinematics(const clip<T>& c, std::size_t f, global_pose<T>& out) {
    if (f >= c.frames())
        throw invalid_argument("anima::forward_kinematics: frame " + std::to_string(f) + " out of range (" +
                               std::to_string(c.frames()) + " frames)");
    const auto& sk = c.skeleton();
    const std::size_t n = sk.size(), nt = sk.translated_joint_count();
    out.positions.resize(n);
    out.orientations.resize(n);
    const auto* rot = c.rotations().data() + f * n;
    const auto* tra = nt ? c.translations().data() + f * nt : nullptr;
    for (std::size_t j = 0; j < n; ++j) {
        const auto& jt = sk[j];
        const int slot = sk.translation_slot(j);
        const auto& local_t = slot < 0 ? jt.offset : tra[slot];
        if (jt.parent < 0) {
            out.positions[j] = local_t;
            out.orientations[j] = rot[j];
        } else {
            const auto p = static_cast<std::size_t>(jt.parent);
            out.positions[j] = out.positions[p] + out.orientations[p] * local_t;
            out.orientations[j] = out.orientations[p] * rot[j];
        }
    }
}

/// Global pose of frame f.
template <class T>
global_pose<T> forward_kinematics(const clip<T>& c, std::size_t f) {
    global_pose<T> out;
    forward_kinematics(c, f, out);
    return out;
}

/// Global position of every joint's End Site (joints without one get their
/// own position), for drawing and for effector targets at finger and toe tips.
template <class T>
std::vector<Eigen::Matrix<T, 3, 1>> end_site_positions(const skeleton<T>& sk, const global_pose<T>& pose) {
    std::vector<Eigen::Matrix<T, 3, 1>> out(sk.size());
    for (std::size_t j = 0; j < sk.size(); ++j)
        out[j] = sk[j].end_site ? Eigen::Matrix<T, 3, 1>(pose.positions[j] + pose.orientations[j] * *sk[j].end_site)
                                : pose.positions[j];
    return out;
}

/// The lowest point a clip's figure reaches along `direction` (a unit
/// vector, e.g. up): the least dot product of `direction` with any joint or
/// End Site position in any frame; +infinity for a clip without frames or
/// without joints (there is no point to be lowest).
template <class T>
T lowest_along(const clip<T>& c, const Eigen::Matrix<T, 3, 1>& direction) {
    T lowest = std::numeric_limits<T>::infinity();
    global_pose<T> pose;
    for (std::size_t f = 0; f < c.frames(); ++f) {
        forward_kinematics(c, f, pose);
        for (const auto& p : pose.positions) lowest = std::min(lowest, p.dot(direction));
        for (const auto& p : end_site_positions(c.skeleton(), pose)) lowest = std::min(lowest, p.dot(direction));
    }
    return lowest;
}

/// The length of the diagonal of the box the joints of frame `f` span (End
/// Sites not included): a measure of the pose's size for relative
/// tolerances. 0 for a single joint. Throws anima::invalid_argument for a
/// frame outside the clip.
template <class T>
T pose_diagonal(const clip<T>& c, std::size_t f) {
    const global_pose<T> pose = forward_kinematics(c, f);
    Eigen::AlignedBox<T, 3> box;
    for (const auto& p : pose.positions) box.extend(p);
    return pose.positions.empty() ? T(0) : box.diagonal().norm();
}

/// Global joint positions over the whole clip: a frames x (3 * joints) matrix,
/// row f = (x0, y0, z0, x1, y1, z1, ...) of frame f.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> global_positions(const clip<T>& c) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    const std::size_t n = c.joints();
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> out(static_cast<Eigen::Index>(c.frames()),
                                                         static_cast<Eigen::Index>(3 * n));
    global_pose<T> pose;
    for (std::size_t f = 0; f < c.frames(); ++f) {
        forward_kinematics(c, f, pose);
        for (std::size_t j = 0; j < n; ++j)
            out.row(static_cast<Eigen::Index>(f)).template segment<3>(static_cast<Eigen::Index>(3 * j)) =
                pose.positions[j].transpose();
    }
    return out;
}

/// Every joint and End Site position of every frame, in one array: what a
/// viewer that animates the whole clip draws (bones to End Sites included),
/// computed once. Frame f's points are points[f * per_frame ...]: the joints
/// in order, then the End Sites in their joints' order.
template <class T>
struct clip_points {
    static constexpr std::size_t npos = static_cast<std::size_t>(-1);
    std::vector<std::size_t> end_site_point;  ///< per joint: its End Site's index within a frame, or npos
    std::size_t per_frame = 0;                ///< joints + End Sites
    std::vector<Eigen::Matrix<T, 3, 1>> points;
};

/// The clip_points of `c`: forward_kinematics and end_site_positions of
/// every frame. A clip without frames has no points (per_frame is still set).
template <class T>
clip_points<T> global_points(const clip<T>& c) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    const skeleton<T>& sk = c.skeleton();
    clip_points<T> out;
    out.end_site_point.assign(sk.size(), clip_points<T>::npos);
    out.per_frame = sk.size();
    for (std::size_t j = 0; j < sk.size(); ++j)
        if (sk[j].end_site) out.end_site_point[j] = out.per_frame++;
    out.points.reserve(out.per_frame * c.frames());
    global_pose<T> pose;
    for (std::size_t f = 0; f < c.frames(); ++f) {
        forward_kinematics(c, f, pose);
        const std::vector<Eigen::Matrix<T, 3, 1>> ends = end_site_positions(sk, pose);
        out.points.insert(out.points.end(), pose.positions.begin(), pose.positions.end());
        for (std::size_t j = 0; j < sk.size(); ++j)
            if (sk[j].end_site) out.points.push_back(ends[j]);
    }
    return out;
}

/// lowest_along on positions already computed (the same points, so the same
/// value): a viewer that has its clip_points need not run the clip's
/// forward kinematics again. +infinity when there are no points.
template <class T>
T lowest_along(const clip_points<T>& pts, const Eigen::Matrix<T, 3, 1>& direction) {
    T lowest = std::numeric_limits<T>::infinity();
    for (const auto& p : pts.points) lowest = std::min(lowest, p.dot(direction));
    return lowest;
}

/// Positions of the skeleton in its rest pose (identity rotations, offsets
/// only), plus the End Sites in the second vector.
template <class T>
std::pair<std::vector<Eigen::Matrix<T, 3, 1>>, std::vector<Eigen::Matrix<T, 3, 1>>> rest_positions(
    const skeleton<T>& sk) {
    std::vector<Eigen::Matrix<T, 3, 1>> joints(sk.size()), ends;
    for (std::size_t j = 0; j < sk.size(); ++j) {
        joints[j] = sk[j].parent < 0 ? sk[j].offset : Eigen::Matrix<T, 3, 1>(joints[static_cast<std::size_t>(sk[j].parent)] + sk[j].offset);
        if (sk[j].end_site) ends.push_back(joints[j] + *sk[j].end_site);
    }
    return {joints, ends};
}

}  // namespace anima
