// The DOFs of a frames x DOF matrix that move: those whose range over the
// frames is more than a threshold (one for rotations, one for
// translations), with that range. Uncaptured joints (fingers that only
// carry rounding noise) and the root's ground position (which a long
// motion makes grow without bound) are left out: what a plot or a check of
// a clip's DOFs wants to look at.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/dof_view.hpp>
#include <anima/motion/figure.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace anima {

/// A column of a frames x DOF matrix and its smallest and largest value.
template <class T>
struct dof_range {
    Eigen::Index column = 0;
    T lo = T(0), hi = T(0);
};

/// The columns of `m` (frames x DOF, as to_dof_matrix makes it for
/// `layout`) whose range hi - lo is more than `min_rotation` (radians) for
/// a rotation DOF or `min_translation` (the clip's units) for a translation
/// DOF, in column order. The root's (joint 0's) translation along the axes
/// other than `up` is left out. Throws anima::invalid_argument when the
/// matrix's columns do not match the layout or a threshold is negative or
/// not finite.
template <class Derived>
std::vector<dof_range<typename Derived::Scalar>> moving_dofs(const Eigen::MatrixBase<Derived>& m,
                                                             const dof_layout<typename Derived::Scalar>& layout,
                                                             signed_axis up, typename Derived::Scalar min_rotation,
                                                             typename Derived::Scalar min_translation) {
    using T = typename Derived::Scalar;
    if (static_cast<std::size_t>(m.cols()) != layout.size())
        throw invalid_argument("anima::moving_dofs: a matrix of " + std::to_string(m.cols()) +
                               " columns for a layout of " + std::to_string(layout.size()) + " DOFs");
    check_non_negative("anima::moving_dofs", "min_rotation", min_rotation);
    check_non_negative("anima::moving_dofs", "min_translation", min_translation);
    std::vector<dof_range<T>> out;
    if (m.rows() == 0) return out;
    for (Eigen::Index c = 0; c < m.cols(); ++c) {
        const dof& d = layout.dofs[static_cast<std::size_t>(c)];
        const bool rotation = d.type == dof::kind::rotation;
        if (!rotation && d.joint == 0 && d.component != static_cast<int>(up.axis)) continue;
        const T lo = m.col(c).minCoeff(), hi = m.col(c).maxCoeff();
        if (hi - lo > (rotation ? min_rotation : min_translation)) out.push_back({c, lo, hi});
    }
    return out;
}

}  // namespace anima
