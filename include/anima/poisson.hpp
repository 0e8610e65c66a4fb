// Poisson solvers on regular grids: the problem description, the 5-point
// Laplacian and its residual, gradient fields and their divergence, full
// multigrid (O(n)), the sine/cosine-transform fast solver (O(n log n)) with
// its FFT, the seam smoothing of stitched motion (Eq 14), and grids as CSV text.
#pragma once

#include <anima/poisson/cg_poisson.hpp>
#include <anima/poisson/dst_poisson.hpp>
#include <anima/poisson/fft.hpp>
#include <anima/poisson/gradient_field.hpp>
#include <anima/poisson/grid_csv.hpp>
#include <anima/poisson/grid.hpp>
#include <anima/poisson/instances.hpp>
#include <anima/poisson/laplacian.hpp>
#include <anima/poisson/multigrid_poisson.hpp>
#include <anima/poisson/problem.hpp>
#include <anima/poisson/real_transforms.hpp>
