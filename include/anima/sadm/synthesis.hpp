// Steps 4-5 of the paper's synthesis and the final paste: grey levels g of
// the reference face are warped onto given landmarks in an output image,
// then pasted into a neutral frame, the seam removed by Poisson blending
// (inside the face the result keeps the patch's Laplacian, at the face's
// edge it meets the frame).
#pragma once

#include <anima/core/error.hpp>
#include <anima/image/bilinear.hpp>
#include <anima/image/image.hpp>
#include <anima/poisson/grid.hpp>
#include <anima/poisson/laplacian.hpp>
#include <anima/poisson/multigrid_poisson.hpp>
#include <anima/poisson/problem.hpp>
#include <anima/sadm/appearance_model.hpp>
#include <anima/sadm/landmarks.hpp>
#include <anima/sadm/piecewise_affine_warp.hpp>

#include <Eigen/Core>

#include <string>

namespace anima {

/// A face rendered into an output raster: grey levels where `mask` is true.
template <class T>
struct face_patch {
    grey_image<T> values;  ///< rows x cols; 0 outside the mask
    poisson_mask mask;     ///< the pixels inside the landmarks' triangles
};

/// Step 5: g (the grey levels of the model's reference face) warped so that
/// its landmarks land on `landmarks`, on a rows x cols raster. Throws
/// anima::invalid_argument for a g or landmark set of the wrong size, a
/// non-finite landmark or an empty raster.
template <class T>
face_patch<T> render_face(const grey_model<T>& model, const Eigen::Matrix<T, Eigen::Dynamic, 1>& g,
                          const landmark_set<T>& landmarks, Eigen::Index rows, Eigen::Index cols) {
    const std::string who = "anima::render_face";
    if (landmarks.rows() != model.reference().rows())
        throw invalid_argument(who + ": the landmark set has " + std::to_string(landmarks.rows()) +
                               " points, the model " + std::to_string(model.reference().rows()));
    check_finite_landmarks(landmarks, who);
    const grey_image<T> texture = model.texture(g);
    const triangle_raster<T> raster = rasterize_triangles(landmarks, model.triangles(), rows, cols);
    const landmark_set<T> at = map_raster(raster, model.triangles(), model.reference());
    face_patch<T> out;
    out.values = grey_image<T>::Zero(rows, cols);
    out.mask = poisson_mask::Constant(rows, cols, false);
    for (std::size_t k = 0; k < raster.size(); ++k) {
        const auto i = static_cast<Eigen::Index>(k);
        out.values(raster.y(k), raster.x(k)) = sample_bilinear(texture, at(i, 0), at(i, 1));
        out.mask(raster.y(k), raster.x(k)) = true;
    }
    return out;
}

/// The frame with the patch copied over it where the mask is set.
template <class T>
grey_image<T> paste_face(const grey_image<T>& frame, const face_patch<T>& patch) {
    if (frame.rows() != patch.values.rows() || frame.cols() != patch.values.cols() ||
        patch.mask.rows() != frame.rows() || patch.mask.cols() != frame.cols())
        throw invalid_argument("anima::paste_face: the frame is " + std::to_string(frame.rows()) + " x " +
                               std::to_string(frame.cols()) + ", the patch " + std::to_string(patch.values.rows()) +
                               " x " + std::to_string(patch.values.cols()));
    return patch.mask.select(patch.values, frame);
}

/// Poisson blending of the patch into the frame: the pixels strictly inside
/// the mask (all four neighbours in it, none on the image border) are solved
/// for with the patch's Laplacian as right-hand side and the frame's values
/// around them (multigrid_poisson with a mask). Everything else is the
/// frame. Throws anima::invalid_argument for sizes that differ or
/// non-finite values.
template <class T>
grey_image<T> blend_face(const grey_image<T>& frame, const face_patch<T>& patch,
                         const typename multigrid_poisson<T>::params& solver = {}) {
    const grey_image<T> pasted = paste_face(frame, patch);
    const Eigen::Index rows = frame.rows(), cols = frame.cols();
    poisson_grid<T> grid = make_poisson_grid<T>(rows, cols, boundary::neumann);
    grid.mask = poisson_mask::Constant(rows, cols, false);
    for (Eigen::Index y = 1; y + 1 < rows; ++y)
        for (Eigen::Index x = 1; x + 1 < cols; ++x)
            grid.mask(y, x) = patch.mask(y, x) && patch.mask(y - 1, x) && patch.mask(y + 1, x) && patch.mask(y, x - 1) &&
                              patch.mask(y, x + 1);
    if (grid.unknowns() == 0) return frame;
    poisson_problem<T> problem;
    problem.rhs = laplacian(grid, pasted);  // read on unknowns only, whose neighbours are all patch pixels
    problem.grid = grid;
    problem.fixed = frame;
    multigrid_poisson<T> mg(grid, solver);
    return mg.solve(problem).u;
}

}  // namespace anima
