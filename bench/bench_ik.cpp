// Inverse kinematics: anima's solvers next to KDL's ChainIkSolverPos_LMA and
// ChainIkSolverPos_NR_JL (with ChainIkSolverVel_pinv and
// ChainFkSolverPos_recursive) on the same 1,000 reachable 6-D targets (tip
// position and orientation from forward kinematics of random joint vectors
// within limits, fixed seed), from the same start poses.
//
//   BM_ik<solver>/arm7   7-DOF arm (hinges z y z y z y z, reach 1.2)
//   BM_ik<solver>/cmu    CMU walk's left arm, LeftArm..LeftHand (three ball
//                        joints; KDL gets three revolute joints X, Y, Z per ball)
//
// One benchmark iteration solves all 1,000 targets; items_per_second is
// solves per second and the `success` counter the fraction solved to
// position error <= 1e-5 x reach and orientation error <= 1e-5 rad within the
// iteration cap (100 per attempt; anima: up to 5 random restarts). For KDL,
// `success_within_limits` also requires the joints within the chain's limits
// (LMA does not know them; anima's solvers and NR_JL never leave them).
// CCD only takes position goals and is timed on the positions alone.
//
//   BM_ik_anima_dls_adaptive_into   the adaptive DLS row through solve_ik_into,
//                        one result and workspace for all targets (the
//                        game-loop form: no allocation per solve)
//   BM_clip_ik<whole clip | per frame, into>
//                        clip-level IK on the bundled CMU walk (31 joints,
//                        whole-body tree, 90 DOFs): the left hand moved
//                        11 cm up over frames 10-89, adaptive DLS, warm
//                        starts; solve_clip_ik on the clip against
//                        solve_clip_frame_into frame by frame (items: frames)
//   BM_plant_feet<own contacts | contacts given>
//                        plant_feet on the first 240 frames of the walk:
//                        finding the contacts itself (the feet measured once
//                        for both), and with find_contacts' result passed in
//                        (items: frames)

#include "../tests/ik/ik_test_support.hpp"

#include <anima/bvh.hpp>
#include <anima/ik.hpp>
#include <anima/motion.hpp>

#include <benchmark/benchmark.h>

#ifdef ANIMA_HAVE_KDL
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>
#endif

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace {

using vec3 = Eigen::Vector3d;
using quat = Eigen::Quaterniond;
constexpr int target_count = 1000;

struct problem {
    explicit problem(anima::kinematic_tree<double> t, std::size_t e, const vec3& t_ip, double r)
        : tree(std::move(t)), effector(e), tip(t_ip), reach(r) {}
    anima::kinematic_tree<double> tree;
    std::size_t effector = 0;
    vec3 tip = vec3::Zero();
    double reach = 1;
    std::vector<vec3> positions;   // world frame
    std::vector<quat> orientations;
    std::vector<anima::ik_vector<double>> starts;
#ifdef ANIMA_HAVE_KDL
    KDL::Chain chain;
    KDL::Frame base = KDL::Frame::Identity();  // world pose of the chain's base
    KDL::JntArray lower, upper;
    std::vector<KDL::JntArray> kdl_starts;
#endif
};

void make_targets(problem& p) {
    anima::random_source rng(2024);
    for (int i = 0; i < target_count; ++i) {
        const auto q = anima_ik_test::random_q(p.tree, rng);
        anima::ik_state<double> s;
        p.tree.forward(q, s);
        p.positions.push_back(s.positions[p.effector] + s.orientations[p.effector] * p.tip);
        p.orientations.push_back(s.orientations[p.effector]);
        p.starts.push_back(anima_ik_test::random_q(p.tree, rng));
    }
}

#ifdef ANIMA_HAVE_KDL
KDL::Vector kv(const vec3& v) { return KDL::Vector(v.x(), v.y(), v.z()); }
#endif

const problem& arm7() {
    static const problem p = [] {
        problem a(anima_ik_test::seven_dof_arm<double>(), 6, anima_ik_test::arm_tip<double>(), 1.2);
        make_targets(a);
#ifdef ANIMA_HAVE_KDL
        const auto offsets = anima_ik_test::arm_offsets<double>();
        a.chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), KDL::Frame(kv(offsets[0]))));
        a.lower.resize(7);
        a.upper.resize(7);
        for (int i = 0; i < 7; ++i) {
            const vec3 next = i < 6 ? offsets[static_cast<std::size_t>(i + 1)] : a.tip;
            a.chain.addSegment(KDL::Segment(KDL::Joint(anima_ik_test::arm_axis(i) == 2 ? KDL::Joint::RotZ : KDL::Joint::RotY),
                                            KDL::Frame(kv(next))));
            a.lower(static_cast<unsigned>(i)) = -anima_ik_test::arm_limit<double>(i);
            a.upper(static_cast<unsigned>(i)) = anima_ik_test::arm_limit<double>(i);
        }
        for (const auto& s : a.starts) {
            KDL::JntArray k(7);
            for (int i = 0; i < 7; ++i) k(static_cast<unsigned>(i)) = s[i];
            a.kdl_starts.push_back(k);
        }
#endif
        return a;
    }();
    return p;
}

const problem& cmu_arm() {
    static const problem p = [] {
        const auto walk = anima::read_bvh<double>(std::string(ANIMA_BENCH_DATA_DIR) + "/walk_cmu31_02_01.bvh");
        const auto& sk = walk.skeleton();
        const std::size_t hand = sk.index_of("LeftHand");
        const vec3 tip = sk[sk.index_of("LeftFingerBase")].offset;
        problem a(anima_ik_test::cmu_left_arm(walk), hand, tip,
                  anima_ik_test::chain_length(sk, sk.index_of("LeftArm"), hand, tip));
        make_targets(a);
        for (auto& s : a.starts) s.setZero();  // rest pose start for both libraries
#ifdef ANIMA_HAVE_KDL
        anima::ik_state<double> st;
        a.tree.forward(anima::ik_vector<double>::Zero(a.tree.dofs()), st);
        const std::size_t shoulder = sk.index_of("LeftShoulder");
        const quat r = st.orientations[shoulder];
        a.base = KDL::Frame(KDL::Rotation::Quaternion(r.x(), r.y(), r.z(), r.w()), kv(st.positions[shoulder]));
        const char* names[] = {"LeftArm", "LeftForeArm", "LeftHand"};
        a.chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), KDL::Frame(kv(sk[sk.index_of(names[0])].offset))));
        for (int b = 0; b < 3; ++b) {
            const vec3 next = b < 2 ? sk[sk.index_of(names[b + 1])].offset : tip;
            a.chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotX)));
            a.chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotY)));
            a.chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ), KDL::Frame(kv(next))));
        }
        a.lower.resize(9);
        a.upper.resize(9);
        for (unsigned i = 0; i < 9; ++i) {
            a.lower(i) = -2.5;
            a.upper(i) = 2.5;
        }
        for (std::size_t i = 0; i < a.starts.size(); ++i) a.kdl_starts.emplace_back(9);  // zeros
#endif
        return a;
    }();
    return p;
}

const problem& problem_of(const benchmark::State& state) { return state.range(0) == 0 ? arm7() : cmu_arm(); }

anima::ik_params<double> params_for(const problem& p) {
    anima::ik_params<double> prm;
    prm.tolerance = 1e-5 * p.reach;
    prm.angle_tolerance = 1e-5;
    prm.max_iterations = 100;
    prm.restarts = 5;
    return prm;
}

std::vector<anima::ik_goal<double>> goals_for(const problem& p, int i, bool pose) {
    if (!pose) return {anima::position_goal<double>(p.effector, p.positions[static_cast<std::size_t>(i)], p.tip)};
    auto g = anima::pose_goal(p.effector, p.positions[static_cast<std::size_t>(i)],
                              p.orientations[static_cast<std::size_t>(i)], p.reach);
    g.offset = p.tip;
    return {g};
}

template <class Solve>
void run_anima(benchmark::State& state, bool pose, Solve&& solve) {
    const problem& p = problem_of(state);
    int ok = 0, solves = 0;
    for (auto _ : state) {
        ok = 0;
        for (int i = 0; i < target_count; ++i) {
            const auto& r = solve(p, goals_for(p, i, pose), p.starts[static_cast<std::size_t>(i)]);
            ok += r.converged();
            benchmark::DoNotOptimize(r.q.data());
        }
        solves += target_count;
    }
    state.SetItemsProcessed(solves);
    state.counters["success"] = static_cast<double>(ok) / target_count;
}

void BM_ik_anima_pinv(benchmark::State& state) {
    run_anima(state, true, [](const problem& p, const auto& g, const auto& q0) {
        return anima::solve_ik(p.tree, g, q0, anima::pseudo_inverse<double>{}, params_for(p));
    });
}
void BM_ik_anima_dls_adaptive(benchmark::State& state) {
    run_anima(state, true, [](const problem& p, const auto& g, const auto& q0) {
        anima::damped_least_squares<double>::params d;
        d.adaptive = true;
        d.threshold = 0.1 * p.reach;
        d.damping = 0.05 * p.reach;
        return anima::solve_ik(p.tree, g, q0, anima::damped_least_squares<double>(d), params_for(p));
    });
}
void BM_ik_anima_dls_adaptive_into(benchmark::State& state) {
    anima::ik_result<double> out;
    anima::ik_workspace<double> ws;
    run_anima(state, true, [&](const problem& p, const auto& g, const auto& q0) -> const anima::ik_result<double>& {
        anima::damped_least_squares<double>::params d;
        d.adaptive = true;
        d.threshold = 0.1 * p.reach;
        d.damping = 0.05 * p.reach;
        anima::solve_ik_into(p.tree, g, q0, anima::damped_least_squares<double>(d), params_for(p), out, ws);
        return out;
    });
}
void BM_ik_anima_bfgs(benchmark::State& state) {
    run_anima(state, true, [](const problem& p, const auto& g, const auto& q0) {
        anima::bfgs_ik_params<double> b;
        b.ik = params_for(p);
        return anima::solve_ik_bfgs(p.tree, g, q0, b);
    });
}
void BM_ik_anima_levenberg_marquardt(benchmark::State& state) {
    run_anima(state, true, [](const problem& p, const auto& g, const auto& q0) {
        anima::levenberg_marquardt_ik_params<double> l;
        l.ik = params_for(p);
        return anima::solve_ik_levenberg_marquardt(p.tree, g, q0, l);
    });
}
void BM_ik_anima_levenberg_marquardt_limits_in_step(benchmark::State& state) {
    run_anima(state, true, [](const problem& p, const auto& g, const auto& q0) {
        anima::levenberg_marquardt_ik_params<double> l;
        l.ik = params_for(p);
        l.limits_in_step = true;
        return anima::solve_ik_levenberg_marquardt(p.tree, g, q0, l);
    });
}
void BM_ik_anima_ccd_position_only(benchmark::State& state) {
    run_anima(state, false, [](const problem& p, const auto& g, const auto& q0) {
        auto prm = params_for(p);
        prm.max_iterations = 300;
        return anima::solve_ik_ccd(p.tree, g, q0, prm);
    });
}

// Clip-level IK: the walk's left hand 11 cm (2 units) up over frames 10-89.
struct clip_edit {
    anima::clip<double> walk;
    std::vector<anima::frame_goals<double>> goals;
    anima::clip_ik_params<double> params;
    anima::damped_least_squares<double> rule;
};

const clip_edit& hand_edit() {
    static const clip_edit e = [] {
        clip_edit c{anima::read_bvh<double>(std::string(ANIMA_BENCH_DATA_DIR) + "/walk_cmu31_02_01.bvh"), {}, {}, {}};
        const std::size_t hand = c.walk.skeleton().index_of("LeftHand");
        for (std::size_t f = 10; f < 90; ++f)
            c.goals.push_back({f,
                               {anima::position_goal<double>(
                                   hand, anima::forward_kinematics(c.walk, f).positions[hand] + vec3(0, 2, 0))}});
        c.params.ik.tolerance = 1e-4;
        anima::damped_least_squares<double>::params d;
        d.adaptive = true;
        c.rule = anima::damped_least_squares<double>(d);
        return c;
    }();
    return e;
}

void BM_clip_ik_whole(benchmark::State& state) {
    const clip_edit& e = hand_edit();
    const anima::kinematic_tree<double> tree(e.walk.skeleton());
    const auto solve = [&](const anima::kinematic_tree<double>& t, const std::vector<anima::ik_goal<double>>& g,
                           const anima::ik_vector<double>& start, const anima::ik_params<double>& prm) {
        return anima::solve_ik(t, g, start, e.rule, prm);
    };
    std::size_t converged = 0;
    for (auto _ : state) {
        const auto r = anima::solve_clip_ik(tree, e.walk, e.goals, solve, e.params);
        converged = r.converged_frames;
        benchmark::DoNotOptimize(r.edited.rotations().data());
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * e.goals.size()));
    state.counters["converged"] = static_cast<double>(converged) / static_cast<double>(e.goals.size());
}

const anima::clip<double>& walk_240() {
    static const anima::clip<double> c =
        anima::read_bvh<double>(std::string(ANIMA_BENCH_DATA_DIR) + "/walk_cmu31_02_01.bvh").slice(0, 240);
    return c;
}

void BM_plant_feet_own_contacts(benchmark::State& state) {
    for (auto _ : state) {
        const auto r = anima::plant_feet(walk_240());
        benchmark::DoNotOptimize(r.planted.rotations().data());
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * walk_240().frames()));
}

void BM_plant_feet_contacts_given(benchmark::State& state) {
    const auto contacts = anima::find_contacts(walk_240());
    for (auto _ : state) {
        const auto r = anima::plant_feet(walk_240(), contacts, {});
        benchmark::DoNotOptimize(r.planted.rotations().data());
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * walk_240().frames()));
}

void BM_clip_ik_frame_into(benchmark::State& state) {
    const clip_edit& e = hand_edit();
    anima::kinematic_tree<double> tree(e.walk.skeleton());
    anima::clip<double> edited = e.walk;
    anima::ik_result<double> out;
    anima::clip_ik_workspace<double> ws;
    std::size_t converged = 0;
    for (auto _ : state) {
        ws.reset();
        converged = 0;
        for (const auto& frame : e.goals) {
            anima::solve_clip_frame_into(tree, e.walk, frame.frame, frame.goals, e.rule, e.params, out, ws);
            tree.write_pose(out.q, edited, frame.frame);
            converged += out.converged();
        }
        benchmark::DoNotOptimize(edited.rotations().data());
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * e.goals.size()));
    state.counters["converged"] = static_cast<double>(converged) / static_cast<double>(e.goals.size());
}

#ifdef ANIMA_HAVE_KDL
KDL::Frame kdl_target(const problem& p, int i) {
    const auto& q = p.orientations[static_cast<std::size_t>(i)];
    const KDL::Frame world(KDL::Rotation::Quaternion(q.x(), q.y(), q.z(), q.w()), kv(p.positions[static_cast<std::size_t>(i)]));
    return p.base.Inverse() * world;
}

bool kdl_success(const problem& p, KDL::ChainFkSolverPos_recursive& fk, const KDL::JntArray& q, const KDL::Frame& target) {
    KDL::Frame f;
    if (fk.JntToCart(q, f) < 0) return false;
    const KDL::Twist d = KDL::diff(f, target);
    return d.vel.Norm() <= 1e-5 * p.reach && d.rot.Norm() <= 1e-5;
}

template <class MakeSolver>
void run_kdl(benchmark::State& state, MakeSolver&& make) {
    const problem& p = problem_of(state);
    KDL::ChainFkSolverPos_recursive fk(p.chain);
    KDL::ChainIkSolverVel_pinv vel(p.chain);
    auto solver = make(p, fk, vel);
    KDL::JntArray out(p.chain.getNrOfJoints());
    std::vector<KDL::Frame> targets;
    for (int i = 0; i < target_count; ++i) targets.push_back(kdl_target(p, i));
    int ok = 0, ok_within = 0, solves = 0;
    for (auto _ : state) {
        ok = ok_within = 0;
        for (int i = 0; i < target_count; ++i) {
            const int rc = solver->CartToJnt(p.kdl_starts[static_cast<std::size_t>(i)], targets[static_cast<std::size_t>(i)], out);
            state.PauseTiming();
            const bool success = rc >= 0 && kdl_success(p, fk, out, targets[static_cast<std::size_t>(i)]);
            ok += success;
            // LMA ignores joint limits; anima's solvers never leave them.
            bool within = true;
            for (unsigned k = 0; k < out.rows(); ++k) within = within && out(k) >= p.lower(k) && out(k) <= p.upper(k);
            ok_within += success && within;
            state.ResumeTiming();
        }
        solves += target_count;
    }
    state.SetItemsProcessed(solves);
    state.counters["success"] = static_cast<double>(ok) / target_count;
    state.counters["success_within_limits"] = static_cast<double>(ok_within) / target_count;
}

void BM_ik_kdl_lma(benchmark::State& state) {
    run_kdl(state, [](const problem& p, auto&, auto&) {
        // Orientation rows weighted by the reach, so that eps bounds both
        // errors as the success test does (the default weights are 0.01).
        Eigen::Matrix<double, 6, 1> weights;
        weights << 1, 1, 1, p.reach, p.reach, p.reach;
        return std::make_unique<KDL::ChainIkSolverPos_LMA>(p.chain, weights, 1e-5 * p.reach, 500);
    });
}
void BM_ik_kdl_nr_jl(benchmark::State& state) {
    run_kdl(state, [](const problem& p, auto& fk, auto& vel) {
        return std::make_unique<KDL::ChainIkSolverPos_NR_JL>(p.chain, p.lower, p.upper, fk, vel, 100, 1e-5 * p.reach);
    });
}
BENCHMARK(BM_ik_kdl_lma)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ik_kdl_nr_jl)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond);
#endif

BENCHMARK(BM_ik_anima_pinv)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ik_anima_dls_adaptive)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ik_anima_dls_adaptive_into)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ik_anima_bfgs)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ik_anima_levenberg_marquardt)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ik_anima_levenberg_marquardt_limits_in_step)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ik_anima_ccd_position_only)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_clip_ik_whole)->Name("BM_clip_ik<whole clip>")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_clip_ik_frame_into)->Name("BM_clip_ik<per frame, into>")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_plant_feet_own_contacts)->Name("BM_plant_feet<own contacts>")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_plant_feet_contacts_given)->Name("BM_plant_feet<contacts given>")->Unit(benchmark::kMillisecond);

}  // namespace
