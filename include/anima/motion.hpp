// The skeleton and clip model: hierarchy, clips, forward kinematics,
// velocities, the frames x DOF view and its moving DOFs, figure guesses,
// reorientation, and stick-figure projection.
#pragma once

#include <anima/motion/body_sides.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/contacts.hpp>
#include <anima/motion/dof_view.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/finite_difference.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/frame_distance.hpp>
#include <anima/motion/frame_features.hpp>
#include <anima/motion/instances.hpp>
#include <anima/motion/joint_roles.hpp>
#include <anima/motion/moving_dofs.hpp>
#include <anima/motion/reorient.hpp>
#include <anima/motion/resample.hpp>
#include <anima/motion/resequence.hpp>
#include <anima/motion/rest_pose.hpp>
#include <anima/motion/skeleton.hpp>
#include <anima/motion/speed_limits.hpp>
#include <anima/motion/stick_figure.hpp>
#include <anima/motion/velocities.hpp>
