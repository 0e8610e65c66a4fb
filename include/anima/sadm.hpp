// Shape-appearance dependence mapping (SADM): PCA for few samples of many
// dimensions, Procrustes alignment, Delaunay triangulation and
// piecewise-affine warps, the shape (Eq 1) and grey-level (Eq 2) models,
// regressors from shape to grey parameters, synthesis with Poisson pasting,
// the model file, the paper's evaluation (NCC, PSNR) and the reader of a
// folder of frames with landmarks.
#pragma once

#include <anima/image.hpp>
#include <anima/sadm/appearance_model.hpp>
#include <anima/sadm/delaunay.hpp>
#include <anima/sadm/evaluate_model.hpp>
#include <anima/sadm/evaluation.hpp>
#include <anima/sadm/frame_folder.hpp>
#include <anima/sadm/instances.hpp>
#include <anima/sadm/landmarks.hpp>
#include <anima/sadm/pca.hpp>
#include <anima/sadm/piecewise_affine_warp.hpp>
#include <anima/sadm/procrustes.hpp>
#include <anima/sadm/regressor.hpp>
#include <anima/sadm/sadm_model.hpp>
#include <anima/sadm/shape_model.hpp>
#include <anima/sadm/synthesis.hpp>
