// The SADM module's heavy instantiations for double, for builds that
// compile them once: ANIMA_EXTERN_TEMPLATES makes them explicit
// instantiation declarations, ANIMA_INSTANTIATE_SADM (in one unit) their
// definitions; neither, and nothing changes. See flight/instances.hpp and
// docs/building.md.
#pragma once

#include <anima/image/image.hpp>
#include <anima/sadm/regressor.hpp>
#include <anima/sadm/sadm_model.hpp>

#if defined(ANIMA_INSTANTIATE_SADM)
#define ANIMA_SADM_INSTANCE template
#elif defined(ANIMA_EXTERN_TEMPLATES)
#define ANIMA_SADM_INSTANCE extern template
#endif

#ifdef ANIMA_SADM_INSTANCE
namespace anima {
// clang-format off
ANIMA_SADM_INSTANCE std::unique_ptr<regressor<double>> make_regressor(regressor_kind, const regressor_options<double>&);
ANIMA_SADM_INSTANCE std::unique_ptr<regressor<double>> load_regressor(std::istream&, const std::string&);
ANIMA_SADM_INSTANCE sadm_model<double> sadm_model<double>::train(const std::vector<grey_image<double>>&, const std::vector<landmark_set<double>>&, const sadm_options<double>&);
ANIMA_SADM_INSTANCE sadm_model<double> sadm_model<double>::load(std::istream&, const std::string&);
// clang-format on
}  // namespace anima
#undef ANIMA_SADM_INSTANCE
#endif
