// The clip as a frames x DOF matrix for the numerical modules (symmetry
// metrics, Poisson smoothing, graph-cut seams, IK training).
//
// Each joint with position channels contributes 3 translation DOFs (its local
// translation); each joint with rotation channels contributes 3 rotation DOFs:
// the rotation vector (exponential map) of its local rotation *relative to a
// per-joint reference rotation*, v = log(ref^-1 q) * 2, so q = ref exp(v / 2).
// Near the reference the map is close to linear and free of gimbal lock; it
// is unique up to |v| = pi, which a mean reference keeps rare. Rotation DOFs
// are in radians, translation DOFs in the clip's length units.
#pragma once

#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/rotation/exp_log.hpp>
#include <anima/rotation/quaternion.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace anima {

/// What the rotation DOFs are measured from.
enum class dof_reference : unsigned char {
    identity,     ///< the joint's rest orientation
    first_frame,  ///< the clip's first frame
    mean          ///< the per-joint mean rotation over the clip (default)
};

/// One column of the DOF matrix.
struct dof {
    enum class kind : unsigned char { translation, rotation };
    std::size_t joint;
    kind type;
    int component;  ///< 0, 1, 2: x, y, z of the translation or rotation vector
};

/// Which columns exist and the reference rotations they are measured from.
template <class T>
struct dof_layout {
    std::vector<dof> dofs;
    std::vector<Eigen::Quaternion<T>> reference;  ///< per joint
    std::size_t size() const noexcept { return dofs.size(); }
    /// "hip.tx", "rShldr.ry"...
    template <class Skeleton>
    std::string name(const Skeleton& sk, std::size_t column) const {
        const auto& d = dofs.at(column);
        return sk[d.joint].name + (d.type == dof::kind::translation ? ".t" : ".r") + static_cast<char>('x' + d.component);
    }
};

namespace detail {
/// make_dof_layout over the frames of several clips of one skeleton: the
/// mean reference is taken over all of them (each rotation moved to the
/// hemisphere of the first clip's first frame), the first-frame reference
/// is the first clip's.
template <class T>
dof_layout<T> dof_layout_of(const std::vector<const clip<T>*>& clips, dof_reference ref) {
    using quat = Eigen::Quaternion<T>;
    const auto& sk = clips.front()->skeleton();
    std::size_t frames = 0;
    for (const clip<T>* c : clips) frames += c->frames();
    dof_layout<T> layout;
    layout.reference.assign(sk.size(), quat::Identity());
    for (std::size_t j = 0; j < sk.size(); ++j) {
        if (sk.translation_slot(j) >= 0)
            for (int k = 0; k < 3; ++k) layout.dofs.push_back({j, dof::kind::translation, k});
        if (sk.has_rotation_channels(j))
            for (int k = 0; k < 3; ++k) layout.dofs.push_back({j, dof::kind::rotation, k});
        if (clips.front()->empty() || ref == dof_reference::identity) continue;
        const quat first = clips.front()->rotation(0, j);
        if (ref == dof_reference::first_frame) {
            layout.reference[j] = first;
            continue;
        }
        Eigen::Matrix<T, 4, 1> sum = Eigen::Matrix<T, 4, 1>::Zero();
        for (const clip<T>* c : clips)
            for (std::size_t f = 0; f < c->frames(); ++f) sum += align_hemisphere(c->rotation(f, j), first).coeffs();
        const T n = sum.norm();
        // The sum cancels only for rotations spread evenly over the sphere;
        // fall back to the first frame rather than divide by ~0.
        layout.reference[j] = n > T(1e-6) * static_cast<T>(frames) ? quat(sum / n) : first;
    }
    return layout;
}
}  // namespace detail

/// The DOF layout of a clip's skeleton with the chosen rotation reference.
/// For dof_reference::mean the reference of a joint is its normalised sum of
/// rotations (each moved to the first frame's hemisphere): the chordal mean.
/// An empty clip has identity references.
template <class T>
dof_layout<T> make_dof_layout(const clip<T>& c, dof_reference ref = dof_reference::mean) {
    return detail::dof_layout_of(std::vector<const clip<T>*>{&c}, ref);
}

/// The frames x DOF matrix of a clip.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> to_dof_matrix(const clip<T>& c, const dof_layout<T>& layout) {
    if (layout.reference.size() != c.joints())
        throw invalid_argument("anima::to_dof_matrix: the layout was made for a skeleton with " +
                               std::to_string(layout.reference.size()) + " joints, the clip has " +
                               std::to_string(c.joints()));
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> m(static_cast<Eigen::Index>(c.frames()),
                                                       static_cast<Eigen::Index>(layout.size()));
    for (std::size_t f = 0; f < c.frames(); ++f) {
        std::size_t col = 0;
        while (col < layout.size()) {
            const dof& d = layout.dofs[col];
            const Eigen::Matrix<T, 3, 1> v =
                d.type == dof::kind::translation
                    ? c.translation(f, d.joint)
                    : Eigen::Matrix<T, 3, 1>(to_rotation_vector(Eigen::Quaternion<T>(layout.reference[d.joint].conjugate() *
                                                                                      c.rotation(f, d.joint))));
            for (int k = 0; k < 3; ++k)
                m(static_cast<Eigen::Index>(f), static_cast<Eigen::Index>(col + static_cast<std::size_t>(k))) = v[k];
            col += 3;
        }
    }
    return m;
}

/// The largest change of any rotation DOF (radians) and of any translation
/// DOF (the clip's units) between two frames x DOF matrices.
template <class T>
struct dof_change {
    T rotation = T(0), translation = T(0);
};

/// The largest |after - before| over the frames, for the rotation and the
/// translation DOFs of `layout`. Throws anima::invalid_argument when the
/// matrices' sizes differ or do not match the layout.
template <class A, class B>
dof_change<typename A::Scalar> largest_dof_change(const Eigen::MatrixBase<A>& before, const Eigen::MatrixBase<B>& after,
                                                  const dof_layout<typename A::Scalar>& layout) {
    if (before.rows() != after.rows() || before.cols() != after.cols() ||
        static_cast<std::size_t>(before.cols()) != layout.size())
        throw invalid_argument("anima::largest_dof_change: " + std::to_string(before.rows()) + " x " +
                               std::to_string(before.cols()) + " and " + std::to_string(after.rows()) + " x " +
                               std::to_string(after.cols()) + " matrices for a layout of " +
                               std::to_string(layout.size()) + " DOFs");
    dof_change<typename A::Scalar> out;
    for (Eigen::Index d = 0; d < before.cols() && before.rows() > 0; ++d) {
        const auto change = (after.col(d) - before.col(d)).cwiseAbs().maxCoeff();
        auto& largest = layout.dofs[static_cast<std::size_t>(d)].type == dof::kind::rotation ? out.rotation : out.translation;
        largest = std::max(largest, change);
    }
    return out;
}

/// Writes a frames x DOF matrix back into a clip with the same skeleton,
/// resizing it to the matrix's row count. Throws anima::invalid_argument on a
/// column-count mismatch or a non-finite entry (naming its row and DOF).
template <class T, class Derived>
void from_dof_matrix(const Eigen::MatrixBase<Derived>& m, const dof_layout<T>& layout, clip<T>& c) {
    if (static_cast<std::size_t>(m.cols()) != layout.size() || layout.reference.size() != c.joints())
        throw invalid_argument("anima::from_dof_matrix: matrix has " + std::to_string(m.cols()) +
                               " columns, the layout " + std::to_string(layout.size()) + " DOFs for " +
                               std::to_string(layout.reference.size()) + " joints; the clip has " +
                               std::to_string(c.joints()) + " joints");
    for (Eigen::Index r = 0; r < m.rows(); ++r)
        for (Eigen::Index k = 0; k < m.cols(); ++k)
            if (!std::isfinite(static_cast<double>(m(r, k))))
                throw invalid_argument("anima::from_dof_matrix: non-finite value at frame " + std::to_string(r) +
                                       ", DOF " + layout.name(c.skeleton(), static_cast<std::size_t>(k)));
    c.resize(static_cast<std::size_t>(m.rows()));
    for (std::size_t f = 0; f < c.frames(); ++f) {
        for (std::size_t col = 0; col < layout.size(); col += 3) {
            const dof& d = layout.dofs[col];
            const auto fr = static_cast<Eigen::Index>(f);
            const auto cl = static_cast<Eigen::Index>(col);
            const Eigen::Matrix<T, 3, 1> v(T(m(fr, cl)), T(m(fr, cl + 1)), T(m(fr, cl + 2)));
            if (d.type == dof::kind::translation)
                c.set_translation(f, d.joint, v);
            else
                c.set_rotation(f, d.joint, layout.reference[d.joint] * from_rotation_vector<Eigen::Quaternion<T>>(v));
        }
    }
}

}  // namespace anima
