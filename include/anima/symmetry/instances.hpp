// The symmetry module's heavy instantiations for double, for builds that
// compile them once: ANIMA_EXTERN_TEMPLATES makes them explicit
// instantiation declarations, ANIMA_INSTANTIATE_SYMMETRY (in one unit)
// their definitions; neither, and nothing changes. See flight/instances.hpp
// and docs/building.md.
#pragma once

#include <anima/symmetry/symmetry_scores.hpp>

#include <Eigen/Core>

#if defined(ANIMA_INSTANTIATE_SYMMETRY)
#define ANIMA_SYMMETRY_INSTANCE template
#elif defined(ANIMA_EXTERN_TEMPLATES)
#define ANIMA_SYMMETRY_INSTANCE extern template
#endif

#ifdef ANIMA_SYMMETRY_INSTANCE
namespace anima {
// clang-format off
ANIMA_SYMMETRY_INSTANCE symmetry_result<double> symmetry_scores<Eigen::MatrixXd>(const Eigen::MatrixBase<Eigen::MatrixXd>&, double, const symmetry_params<double>&);
ANIMA_SYMMETRY_INSTANCE symmetry_result<double> symmetry_scores<double>(const clip<double>&, const symmetry_params<double>&, const frame_feature_params&);
// clang-format on
}  // namespace anima
#undef ANIMA_SYMMETRY_INSTANCE
#endif
