// The rotation toolkit: every function works with glm::qua<T> and
// Eigen::Quaternion<T> (T = float or double) through anima::quat_traits.
#pragma once

#include <anima/rotation/angular_velocity.hpp>
#include <anima/rotation/axis_angle.hpp>
#include <anima/rotation/euler.hpp>
#include <anima/rotation/exp_log.hpp>
#include <anima/rotation/lerp.hpp>
#include <anima/rotation/quat_traits.hpp>
#include <anima/rotation/quaternion.hpp>
#include <anima/rotation/shortest_arc.hpp>
#include <anima/rotation/slerp.hpp>
#include <anima/rotation/slerp_batch.hpp>
#include <anima/rotation/squad.hpp>
#include <anima/rotation/swing_twist.hpp>
