// Spacetime flight on the CMU 31-joint skeleton (de Leva body, 70 kg):
//
//   BM_inverse_dynamics<double|float>    one Newton-Euler pass over the 31 bodies
//   BM_objective                         the model (2) residuals of the somersault
//                                        (11 intervals x 4 Gauss points x 6)
//   BM_objective_jacobian                the same residuals and their exact
//                                        Jacobian (AutoDiff, 10 parameters)
//   BM_model2_somersault                 a whole model (2) optimisation from
//                                        evenly spaced key times
//   BM_chain_rne<anima|kdl>/<joints>     a fixed-base revolute chain, anima's
//                                        recursive Newton-Euler next to KDL's
//                                        ChainIdSolver_RNE on the same chain
//
// Before anything is timed, the chain torques of anima and KDL are compared
// once; the program aborts if they differ.

#include <anima/bvh/reader.hpp>
#include <anima/flight.hpp>

#include <benchmark/benchmark.h>

#ifdef ANIMA_HAVE_KDL
#include <kdl/chain.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#endif

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

namespace {

template <class T>
const anima::skeleton<T>& cmu31() {
    static const auto sk = anima::read_bvh<T>(ANIMA_BENCH_DATA_DIR "/walk_cmu31_02_01.bvh").skeleton();
    return sk;
}

template <class T>
void BM_inverse_dynamics(benchmark::State& state) {
    const auto model = anima::make_body_model(cmu31<T>(), {});
    const auto keys = anima::somersault_keys(cmu31<T>());
    const auto traj = anima::key_trajectory<T>::from_keys(keys);
    const auto motion = traj.at(T(0.5));
    const Eigen::Matrix<T, 3, 1> g(T(0), T(-9.81), T(0));
    for (auto _ : state) benchmark::DoNotOptimize(anima::inverse_dynamics(model, motion, g));
}
BENCHMARK_TEMPLATE(BM_inverse_dynamics, double);
BENCHMARK_TEMPLATE(BM_inverse_dynamics, float);

const anima::flight_problem<double>& somersault() {
    static const anima::flight_problem<double> p(anima::make_body_model(cmu31<double>(), {}),
                                                 anima::somersault_keys(cmu31<double>()),
                                                 anima::somersault_settings<double>());
    return p;
}

void BM_objective(benchmark::State& state) {
    const auto& p = somersault();
    const auto x = p.timing_parameters(p.keys().times);
    anima::vector_x<double> r;
    for (auto _ : state) {
        p.timing_residuals(x, r, nullptr);
        benchmark::DoNotOptimize(r.data());
    }
}
BENCHMARK(BM_objective)->Unit(benchmark::kMicrosecond);

void BM_objective_jacobian(benchmark::State& state) {
    const auto& p = somersault();
    const auto x = p.timing_parameters(p.keys().times);
    anima::vector_x<double> r;
    anima::matrix_x<double> J;
    for (auto _ : state) {
        p.timing_residuals(x, r, &J);
        benchmark::DoNotOptimize(J.data());
    }
}
BENCHMARK(BM_objective_jacobian)->Unit(benchmark::kMicrosecond);

void BM_model2_somersault(benchmark::State& state) {
    const auto& p = somersault();
    anima::flight_optimization_params<double> params;
    params.momentum_samples = 2;
    for (auto _ : state) benchmark::DoNotOptimize(anima::optimize_flight(p, params).objective_final);
}
BENCHMARK(BM_model2_somersault)->Unit(benchmark::kMillisecond);

// ---------------------------------------------------------------------------
// A fixed-base chain: joint j turns about Z, Y, X in turn.
// ---------------------------------------------------------------------------

struct chain_case {
    anima::rigid_body_model<double> model;
    anima::body_motion<double> motion;
    std::vector<double> q, qd, qdd;
    Eigen::Vector3d gravity{0.0, 0.0, -9.81};
};

const Eigen::Vector3d& chain_axis(std::size_t j) {
    static const Eigen::Vector3d axes[] = {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX()};
    return axes[j % 3];
}

chain_case make_chain(std::size_t joints) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    chain_case c;
    c.model.add_body("base", -1, Eigen::Vector3d::Zero(), 1.0, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity());
    for (std::size_t j = 1; j <= joints; ++j) {
        const Eigen::Vector3d d(0.1 + 0.05 * u(rng), 0.1 * u(rng), 0.3);
        c.model.add_body("link" + std::to_string(j), static_cast<int>(j) - 1, j == 1 ? Eigen::Vector3d::Zero() : d,
                         1.0 + 0.5 * u(rng), Eigen::Vector3d(0.05, 0.02 * u(rng), 0.15),
                         Eigen::Vector3d(0.02, 0.03, 0.01).asDiagonal().toDenseMatrix());
    }
    c.motion = anima::body_motion<double>::at_rest(joints + 1);
    for (std::size_t j = 1; j <= joints; ++j) {
        c.q.push_back(u(rng));
        c.qd.push_back(2 * u(rng));
        c.qdd.push_back(4 * u(rng));
        c.motion.rotations[j] = Eigen::AngleAxisd(c.q.back(), chain_axis(j)).toRotationMatrix();
        c.motion.angular_velocities[j] = chain_axis(j) * c.qd.back();
        c.motion.angular_accelerations[j] = chain_axis(j) * c.qdd.back();
    }
    return c;
}

std::vector<double> anima_chain_torques(const chain_case& c) {
    const auto r = anima::inverse_dynamics(c.model, c.motion, c.gravity);
    std::vector<double> out;
    for (std::size_t j = 1; j < c.model.size(); ++j) out.push_back(chain_axis(j).dot(r.joint_torques[j]));
    return out;
}

void BM_chain_rne_anima(benchmark::State& state) {
    const auto c = make_chain(static_cast<std::size_t>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(anima::inverse_dynamics(c.model, c.motion, c.gravity));
}
BENCHMARK(BM_chain_rne_anima)->Name("BM_chain_rne<anima>")->Arg(7)->Arg(30);

#ifdef ANIMA_HAVE_KDL
KDL::Chain kdl_chain(const chain_case& c) {
    const KDL::Joint::JointType types[] = {KDL::Joint::RotZ, KDL::Joint::RotY, KDL::Joint::RotX};
    const auto v = [](const Eigen::Vector3d& x) { return KDL::Vector(x[0], x[1], x[2]); };
    const std::size_t n = c.model.size();
    const auto tip = [&](std::size_t j) { return j + 1 < n ? v(c.model.offsets[j + 1]) : KDL::Vector::Zero(); };
    KDL::Chain chain;
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), KDL::Frame(tip(0))));
    for (std::size_t j = 1; j < n; ++j) {
        const auto& I = c.model.inertias[j];
        // KDL holds a segment's inertia in its tip frame.
        chain.addSegment(KDL::Segment(KDL::Joint(types[j % 3]), KDL::Frame(tip(j)),
                                      KDL::RigidBodyInertia(c.model.masses[j], v(c.model.coms[j]) - tip(j),
                                                            KDL::RotationalInertia(I(0, 0), I(1, 1), I(2, 2), I(0, 1),
                                                                                   I(0, 2), I(1, 2)))));
    }
    return chain;
}

struct kdl_case {
    KDL::Chain chain;
    KDL::JntArray q, qd, qdd, torques;
    KDL::Wrenches external;
    explicit kdl_case(const chain_case& c) : chain(kdl_chain(c)) {
        const unsigned n = chain.getNrOfJoints();
        q.resize(n);
        qd.resize(n);
        qdd.resize(n);
        torques.resize(n);
        for (unsigned j = 0; j < n; ++j) {
            q(j) = c.q[j];
            qd(j) = c.qd[j];
            qdd(j) = c.qdd[j];
        }
        external.assign(chain.getNrOfSegments(), KDL::Wrench::Zero());
    }
};

void BM_chain_rne_kdl(benchmark::State& state) {
    const auto c = make_chain(static_cast<std::size_t>(state.range(0)));
    kdl_case k(c);
    KDL::ChainIdSolver_RNE solver(k.chain, KDL::Vector(c.gravity[0], c.gravity[1], c.gravity[2]));
    for (auto _ : state) {
        solver.CartToJnt(k.q, k.qd, k.qdd, k.external, k.torques);
        benchmark::DoNotOptimize(k.torques.data.data());
    }
}
BENCHMARK(BM_chain_rne_kdl)->Name("BM_chain_rne<kdl>")->Arg(7)->Arg(30);

// Both solvers must agree before their times mean anything.
const bool chains_agree = [] {
    for (std::size_t n : {7u, 30u}) {
        const auto c = make_chain(n);
        kdl_case k(c);
        KDL::ChainIdSolver_RNE solver(k.chain, KDL::Vector(c.gravity[0], c.gravity[1], c.gravity[2]));
        solver.CartToJnt(k.q, k.qd, k.qdd, k.external, k.torques);
        const auto mine = anima_chain_torques(c);
        for (std::size_t j = 0; j < mine.size(); ++j)
            if (std::abs(mine[j] - k.torques(static_cast<unsigned>(j))) > 1e-8 * (1 + std::abs(mine[j]))) {
                std::fprintf(stderr, "bench_flight: anima and KDL torques differ at joint %zu of %zu\n", j, n);
                std::abort();
            }
    }
    return true;
}();
#endif

}  // namespace
