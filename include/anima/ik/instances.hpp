// The IK module's heavy instantiations for double, for builds that
// compile them once: ANIMA_EXTERN_TEMPLATES makes them explicit
// instantiation declarations, ANIMA_INSTANTIATE_IK (in one unit) their
// definitions; neither, and nothing changes. See flight/instances.hpp and
// docs/building.md.
#pragma once

#include <anima/ik/learned_inverse.hpp>
#include <anima/ik/plant_feet.hpp>
#include <anima/ik/solve_with.hpp>
#include <anima/motion/instances.hpp>  // plant_feet finds contacts: compiled with the motion module

#if defined(ANIMA_INSTANTIATE_IK)
#define ANIMA_IK_INSTANCE template
#elif defined(ANIMA_EXTERN_TEMPLATES)
#define ANIMA_IK_INSTANCE extern template
#endif

#ifdef ANIMA_IK_INSTANCE
namespace anima {
// clang-format off
ANIMA_IK_INSTANCE plant_feet_result<double> plant_feet(const clip<double>&, const contact_set<double>&, const plant_feet_params<double>&);
ANIMA_IK_INSTANCE plant_feet_result<double> plant_feet(const clip<double>&, const plant_feet_params<double>&);
ANIMA_IK_INSTANCE ik_result<double> solve_ik<double, pseudo_inverse<double>>(const kinematic_tree<double>&, const std::vector<ik_goal<double>>&, const ik_vector_arg<double>&, const pseudo_inverse<double>&, const ik_params<double>&);
ANIMA_IK_INSTANCE void solve_ik_into<double, pseudo_inverse<double>>(const kinematic_tree<double>&, const std::vector<ik_goal<double>>&, const ik_vector_arg<double>&, const pseudo_inverse<double>&, const ik_params<double>&, ik_result<double>&, ik_workspace<double>&);
ANIMA_IK_INSTANCE ik_result<double> solve_ik<double, damped_least_squares<double>>(const kinematic_tree<double>&, const std::vector<ik_goal<double>>&, const ik_vector_arg<double>&, const damped_least_squares<double>&, const ik_params<double>&);
ANIMA_IK_INSTANCE void solve_ik_into<double, damped_least_squares<double>>(const kinematic_tree<double>&, const std::vector<ik_goal<double>>&, const ik_vector_arg<double>&, const damped_least_squares<double>&, const ik_params<double>&, ik_result<double>&, ik_workspace<double>&);
ANIMA_IK_INSTANCE ik_result<double> solve_ik_ccd<double>(const kinematic_tree<double>&, std::vector<ik_goal<double>>, const ik_vector_arg<double>&, const ik_params<double>&);
ANIMA_IK_INSTANCE ik_result<double> solve_ik_bfgs<double>(const kinematic_tree<double>&, std::vector<ik_goal<double>>, const ik_vector_arg<double>&, const bfgs_ik_params<double>&);
ANIMA_IK_INSTANCE ik_result<double> solve_ik_levenberg_marquardt<double>(const kinematic_tree<double>&, std::vector<ik_goal<double>>, const ik_vector_arg<double>&, const levenberg_marquardt_ik_params<double>&);
ANIMA_IK_INSTANCE learned_ik_model<double> learned_ik_model<double>::train(const kinematic_tree<double>&, std::vector<ik_effector<double>>, const ik_matrix<double>&, const learned_ik_params<double>&);
ANIMA_IK_INSTANCE learned_ik_result<double> solve_ik_learned<double>(const kinematic_tree<double>&, const learned_ik_model<double>&, std::vector<ik_goal<double>>, const learned_solve_params<double>&);
ANIMA_IK_INSTANCE ik_result<double> solve_ik_with<double>(ik_solver, const kinematic_tree<double>&, const std::vector<ik_goal<double>>&, const ik_vector_arg<double>&, const ik_params<double>&);
// clang-format on
}  // namespace anima
#undef ANIMA_IK_INSTANCE
#endif
