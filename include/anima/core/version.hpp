// Library version, kept in step with project(VERSION) in CMakeLists.txt.
#pragma once

#define ANIMA_VERSION_MAJOR 0
#define ANIMA_VERSION_MINOR 1
#define ANIMA_VERSION_PATCH 0

namespace anima {
inline constexpr int version_major = ANIMA_VERSION_MAJOR;
inline constexpr int version_minor = ANIMA_VERSION_MINOR;
inline constexpr int version_patch = ANIMA_VERSION_PATCH;
}  // namespace anima
