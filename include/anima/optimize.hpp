// Numerical optimisation shared by the modules that fit or solve something:
// BFGS / L-BFGS with a strong-Wolfe line search, Levenberg-Marquardt for
// least squares, and central finite differences.
#pragma once

#include <anima/optimize/bfgs.hpp>
#include <anima/optimize/levenberg_marquardt.hpp>
#include <anima/optimize/line_search.hpp>
#include <anima/optimize/numeric_derivatives.hpp>
#include <anima/optimize/result.hpp>
