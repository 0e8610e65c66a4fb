// The texture module's heavy instantiations for double, for builds
// that compile them once: ANIMA_EXTERN_TEMPLATES makes them explicit
// instantiation declarations, ANIMA_INSTANTIATE_TEXTURE (in one unit) their
// definitions; neither, and nothing changes. See flight/instances.hpp and
// docs/building.md.
#pragma once

#include <anima/ik/instances.hpp>  // texture plants feet: its instances are compiled there
#include <anima/motion/instances.hpp>
#include <anima/poisson/instances.hpp>  // seam smoothing solves with multigrid: compiled there
#include <anima/texture/motion_texture.hpp>
#include <anima/texture/texton.hpp>

#if defined(ANIMA_INSTANTIATE_TEXTURE)
#define ANIMA_TEXTURE_INSTANCE template
#elif defined(ANIMA_EXTERN_TEMPLATES)
#define ANIMA_TEXTURE_INSTANCE extern template
#endif

#ifdef ANIMA_TEXTURE_INSTANCE
namespace anima {
// clang-format off
ANIMA_TEXTURE_INSTANCE motion_texton<double> make_texton(const clip<double>&, const texton_params<double>&);
ANIMA_TEXTURE_INSTANCE motion_texton<double> make_texton(const std::vector<clip<double>>&, const texton_params<double>&);
ANIMA_TEXTURE_INSTANCE motion_texture<double> patch_texton(const motion_texton<double>&, std::size_t, const motion_texture_params<double>&);
ANIMA_TEXTURE_INSTANCE motion_texture<double> make_motion_texture(const clip<double>&, std::size_t, const motion_texture_params<double>&);
ANIMA_TEXTURE_INSTANCE motion_texture<double> make_motion_texture(const std::vector<clip<double>>&, std::size_t, const motion_texture_params<double>&);
// clang-format on
}  // namespace anima
#undef ANIMA_TEXTURE_INSTANCE
#endif
