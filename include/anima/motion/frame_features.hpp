// The per-frame feature vectors the symmetry metrics compare: a clip's DOF
// view (rotation vectors about each joint's mean rotation, translations),
// by default with the root's position on the ground plane zeroed. Where the
// figure stands says nothing about its pose, and for travelling motion it
// would make every frame far from every other; its height is kept. Zeroing
// rather than dropping keeps the DOF view's 3-column joint blocks.
#pragma once

#include <anima/core/flush_denormals.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/dof_view.hpp>
#include <anima/motion/figure.hpp>

#include <Eigen/Core>

#include <optional>

namespace anima {

struct frame_feature_params {
    /// Keep the root's two ground-plane translation DOFs.
    bool root_ground_translation = false;
    /// Up axis of the clip; guessed from the skeleton when empty.
    std::optional<signed_axis> up;
    dof_reference reference = dof_reference::mean;
};

/// frame_features in a given layout (params.reference unused): the
/// rotations measured from the layout's references, e.g. one layout for
/// several clips so that their features compare.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> frame_features(const clip<T>& c, const dof_layout<T>& layout,
                                                                const frame_feature_params& params = {}) {
    const flush_denormals guard;  // float mocap's tiny angles make subnormal numbers
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> m = to_dof_matrix(c, layout);
    if (params.root_ground_translation) return m;
    const signed_axis up = params.up ? *params.up : guess_up_axis(c.skeleton()).up;
    for (std::size_t k = 0; k < layout.size(); ++k) {
        const dof& d = layout.dofs[k];
        if (d.joint == 0 && d.type == dof::kind::translation && d.component != static_cast<int>(up.axis))
            m.col(static_cast<Eigen::Index>(k)).setZero();
    }
    return m;
}

/// frames x DOF matrix of a clip (columns as anima::make_dof_layout) for
/// anima::symmetry_scores and anima::make_frame_distance.
template <class T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> frame_features(const clip<T>& c, const frame_feature_params& params = {}) {
    return frame_features(c, make_dof_layout(c, params.reference), params);
}

}  // namespace anima
