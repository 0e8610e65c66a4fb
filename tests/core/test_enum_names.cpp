// anima::enum_names: every named enum's values have a name, names and values
// round-trip, aliases and case are accepted, and a bad name lists the
// choices. The enums are those of the modules below.
#include <anima/bvh/document.hpp>
#include <anima/core/enum_names.hpp>
#include <anima/flight/anthropometry.hpp>
#include <anima/ik/solve.hpp>
#include <anima/ik/solve_with.hpp>
#include <anima/motion/body_sides.hpp>
#include <anima/motion/frame_distance.hpp>
#include <anima/motion/joint_roles.hpp>
#include <anima/motion/resequence.hpp>
#include <anima/optimize/result.hpp>
#include <anima/poisson/cg_poisson.hpp>
#include <anima/poisson/grid.hpp>
#include <anima/poisson/multigrid_poisson.hpp>
#include <anima/sadm/regressor_base.hpp>
#include <anima/texture/motion_smoothing.hpp>
#include <anima/texture/seam_cost.hpp>
#include <anima/transition/classify.hpp>
#include <anima/transition/timing.hpp>
#include <anima/transition/variable_timing_transition.hpp>

#include <doctest/doctest.h>

#include <set>
#include <string>
#include <vector>

namespace {

/// Values 0..count-1 of E all have a name, distinct from each other; each
/// name parses back to its value, in upper case too.
template <class E>
void check_names(int count, const std::vector<std::string>& expected) {
    std::set<std::string> seen;
    for (int k = 0; k < count; ++k) {
        const E value = static_cast<E>(k);
        const std::string name = anima::to_string(value);
        CAPTURE(name);
        CHECK(name != "unknown");
        CHECK(seen.insert(name).second);
        CHECK(anima::parse_enum<E>(name) == value);
        std::string upper = name;
        for (char& c : upper) c = static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
        CHECK(anima::parse_enum<E>(upper) == value);
    }
    CHECK(std::string(anima::to_string(static_cast<E>(count))) == "unknown");
    CHECK(anima::enum_name_list<E>() == expected);
}

std::string parse_message(const std::string& name) {
    try {
        (void)anima::parse_enum<anima::root_path>(name);
    } catch (const anima::invalid_argument& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("every named enum has one name per value, and they round-trip") {
    using namespace anima;
    check_names<root_path>(4, {"recorded", "in_place", "accumulated", "keep_direction"});
    check_names<boundary>(2, {"dirichlet", "neumann"});
    check_names<multigrid_cycle>(2, {"v", "w"});
    check_names<frame_metric>(2, {"mahalanobis", "l2"});
    check_names<seam_capacity>(3, {"normalized", "exponential", "plain"});
    check_names<seam_smoothing_form>(2, {"1d", "2d"});
    check_names<poisson_method>(2, {"multigrid", "dst"});
    check_names<regressor_kind>(4, {"linear", "poly2", "mlp", "svr"});
    check_names<ik_solver>(5, {"pinv", "dls", "ccd", "bfgs", "lm"});
    check_names<ik_status>(4, {"converged", "unreachable_closest", "max_iterations", "singular"});
    check_names<body_side>(3, {"centre", "left", "right"});
    check_names<cg_preconditioner>(2, {"diagonal", "incomplete_cholesky"});
    check_names<optimize_status>(4, {"converged", "max_iterations", "stalled", "stopped"});
    check_names<joint_role>(5, {"root", "leg", "foot", "finger", "other"});
    check_names<motion_class>(3, {"on_the_spot", "plane_motion", "space_flight"});
    check_names<interpolation>(4, {"automatic", "lerp", "slerp", "squad"});
    check_names<timing_model>(2, {"velocity", "acceleration"});
    check_names<easing>(2, {"linear", "ease_in_out"});
    check_names<euler_angles>(2, {"continuous", "principal"});
    check_names<segment_kind>(10, {"head", "upper_trunk", "middle_trunk", "lower_trunk", "upper_arm", "forearm",
                                   "hand", "thigh", "shank", "foot"});
}

TEST_CASE("aliases parse but are not listed; the parse_* wrappers agree") {
    using namespace anima;
    CHECK(parse_enum<seam_smoothing_form>("temporal") == seam_smoothing_form::temporal);
    CHECK(parse_enum<seam_smoothing_form>("Image") == seam_smoothing_form::image);
    CHECK(std::string(to_string(seam_smoothing_form::image)) == "2d");
    CHECK(parse_seam_smoothing_form("2D") == seam_smoothing_form::image);
    CHECK(parse_root_path("in_place") == root_path::in_place);
    CHECK(parse_ik_solver("LM") == ik_solver::levenberg_marquardt);
    CHECK(parse_frame_metric("L2") == frame_metric::l2);
    CHECK(parse_multigrid_cycle("W") == multigrid_cycle::w);
    CHECK(parse_boundary("neumann") == boundary::neumann);
    CHECK(parse_regressor_kind("svr") == regressor_kind::svr);
    CHECK(parse_seam_capacity("plain") == seam_capacity::plain);
    CHECK(parse_poisson_method("dst") == poisson_method::dst);
    CHECK(parse_enum<timing_model>("constant_acceleration") == timing_model::constant_acceleration);
    CHECK(parse_segment_kind("Shank") == segment_kind::shank);
    CHECK(enum_choices<root_path>() == "recorded, in_place, accumulated or keep_direction");
    CHECK(enum_choices<frame_metric>() == "mahalanobis or l2");
}

TEST_CASE("a name that is not a value is an error naming it and the choices") {
    CHECK(parse_message("teleport") ==
          "anima::parse_enum: 'teleport' is not a root path: use recorded, in_place, accumulated or keep_direction");
    CHECK(parse_message("") ==
          "anima::parse_enum: '' is not a root path: use recorded, in_place, accumulated or keep_direction");
    CHECK(parse_message("recorded ").find("'recorded '") != std::string::npos);  // no trimming
    CHECK(parse_message(std::string("in\0place", 8)).find("'in\\x00place'") != std::string::npos);
    CHECK_THROWS_AS(anima::parse_boundary("periodic"), anima::invalid_argument);
    CHECK_THROWS_WITH(anima::parse_enum<anima::ik_solver>("newton"),
                      "anima::parse_enum: 'newton' is not an IK solver: use pinv, dls, ccd, bfgs or lm");
    // The named parsers say who they are.
    try {
        anima::parse_regressor_kind("cubic");
        FAIL("no exception");
    } catch (const anima::invalid_argument& e) {
        CHECK(std::string(e.what()) == "anima::parse_regressor_kind: 'cubic' is not a regressor: use linear, poly2, mlp or svr");
    }
}
