// Everything in anima. Include the capability headers (anima/rotation.hpp,
// anima/motion.hpp, anima/bvh.hpp...) or single concept headers to compile less.
#pragma once

#include <anima/bvh.hpp>
#include <anima/core/constants.hpp>
#include <anima/core/error.hpp>
#include <anima/core/flush_denormals.hpp>
#include <anima/core/random.hpp>
#include <anima/core/version.hpp>
#include <anima/flight.hpp>
#include <anima/ik.hpp>
#include <anima/maxflow.hpp>
#include <anima/motion.hpp>
#include <anima/optimize.hpp>
#include <anima/poisson.hpp>
#include <anima/rotation.hpp>
#include <anima/sadm.hpp>
#include <anima/symmetry.hpp>
#include <anima/texture.hpp>
#include <anima/transition.hpp>
