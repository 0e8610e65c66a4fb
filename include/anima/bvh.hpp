// BVH input and output.
#pragma once

#include <anima/bvh/document.hpp>
#include <anima/bvh/reader.hpp>
#include <anima/bvh/value_decimals.hpp>
#include <anima/bvh/writer.hpp>
