// Inverse kinematics: kinematic trees over a skeleton, goals and their
// analytic Jacobian, the Jacobian iteration of Table 1 with pluggable step
// rules (inverse, pseudo-inverse, damped least squares, weighted), null-space
// tasks and joint limits, quaternion CCD, BFGS on goal errors, the learned
// Jacobian inverse (SOM + per-cluster J+, Eq 3), clip IK, and per-frame
// position targets read from a file.
#pragma once

#include <anima/ik/bfgs_ik.hpp>
#include <anima/ik/ccd.hpp>
#include <anima/ik/clip_ik.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/instances.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/learned_inverse.hpp>
#include <anima/ik/levenberg_marquardt_ik.hpp>
#include <anima/ik/plant_feet.hpp>
#include <anima/ik/position_targets.hpp>
#include <anima/ik/pose_statistics.hpp>
#include <anima/ik/solve.hpp>
#include <anima/ik/solve_with.hpp>
#include <anima/ik/step_rules.hpp>
