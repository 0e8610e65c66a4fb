// Spacetime flight: a de Leva rigid-body model of a skeleton, recursive
// Newton-Euler inverse dynamics with momentum, spline motions through keys,
// the T^-1 integral of sum F_i^2 objective and its models (1) and (2), and
// the paper's somersault as a key set.
#pragma once

#include <anima/flight/anthropometry.hpp>
#include <anima/flight/body_model.hpp>
#include <anima/flight/clip_keys.hpp>
#include <anima/flight/cubic_spline.hpp>
#include <anima/flight/flight_clip.hpp>
#include <anima/flight/flight_objective.hpp>
#include <anima/flight/instances.hpp>
#include <anima/flight/inverse_dynamics.hpp>
#include <anima/flight/key_set.hpp>
#include <anima/flight/key_trajectory.hpp>
#include <anima/flight/optimize_flight.hpp>
#include <anima/flight/somersault.hpp>
