// Joint torques on a fixed-base chain of revolute joints agree with KDL's
// recursive Newton-Euler solver (ChainIdSolver_RNE), an independent
// implementation; KDL is a test peer only. Each revolute joint is one of
// anima's ball joints turning about a single axis, and the torque about
// that axis is compared.
#include "flight_test_support.hpp"

#include <anima/flight/inverse_dynamics.hpp>

#include <doctest/doctest.h>

#ifdef ANIMA_HAVE_KDL
#include <kdl/chain.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/rigidbodyinertia.hpp>
#include <kdl/rotationalinertia.hpp>
#include <kdl/segment.hpp>
#endif

#include <random>
#include <vector>

namespace {

using namespace flight_test;

#ifdef ANIMA_HAVE_KDL

TEST_CASE_TEMPLATE("fixed-base chain: joint torques agree with KDL's recursive Newton-Euler", T, float, double) {
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const KDL::Joint::JointType types[] = {KDL::Joint::RotZ, KDL::Joint::RotY, KDL::Joint::RotX};
    const vec3<T> axes[] = {vec3<T>::UnitZ(), vec3<T>::UnitY(), vec3<T>::UnitX()};
    const T tol = tolerance<T>(1e-9, 1e-3);
    for (int trial = 0; trial < 10; ++trial) {
        const std::size_t joints = 2 + static_cast<std::size_t>(trial % 5);
        const auto model = random_model<T>(rng, joints + 1);
        // Turn the random tree into a chain: body j hangs from body j-1.
        anima::rigid_body_model<T> chain_model;
        for (std::size_t j = 0; j <= joints; ++j)
            chain_model.add_body(model.names[j], static_cast<int>(j) - 1, model.offsets[j], model.masses[j],
                                 model.coms[j], model.inertias[j]);
        const vec3<T> g(T(0.5), T(-1), T(-9.81));
        KDL::Chain chain;
        const auto to_kdl = [](const vec3<T>& v) {
            return KDL::Vector(static_cast<double>(v[0]), static_cast<double>(v[1]), static_cast<double>(v[2]));
        };
        const auto tip = [&](std::size_t j) { return j + 1 <= joints ? to_kdl(chain_model.offsets[j + 1]) : KDL::Vector::Zero(); };
        chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), KDL::Frame(tip(0))));
        auto motion = anima::body_motion<T>::at_rest(joints + 1);
        KDL::JntArray q(static_cast<unsigned>(joints)), qd(static_cast<unsigned>(joints)), qdd(static_cast<unsigned>(joints));
        for (std::size_t j = 1; j <= joints; ++j) {
            const auto& I = chain_model.inertias[j];
            const KDL::RotationalInertia ri(static_cast<double>(I(0, 0)), static_cast<double>(I(1, 1)),
                                            static_cast<double>(I(2, 2)), static_cast<double>(I(0, 1)),
                                            static_cast<double>(I(0, 2)), static_cast<double>(I(1, 2)));
            // KDL expresses a segment's inertia in its tip frame (here the
            // joint frame moved by the pure translation to the next joint).
            const KDL::RigidBodyInertia rb(static_cast<double>(chain_model.masses[j]),
                                           to_kdl(chain_model.coms[j]) - tip(j), ri);
            chain.addSegment(KDL::Segment(KDL::Joint(types[j % 3]), KDL::Frame(tip(j)), rb));
            const auto J = static_cast<unsigned>(j - 1);
            q(J) = 2 * u(rng);
            qd(J) = 3 * u(rng);
            qdd(J) = 5 * u(rng);
            const vec3<T>& a = axes[j % 3];
            motion.rotations[j] = Eigen::AngleAxis<T>(T(q(J)), a).toRotationMatrix();
            motion.angular_velocities[j] = a * T(qd(J));
            motion.angular_accelerations[j] = a * T(qdd(J));
        }
        KDL::ChainIdSolver_RNE solver(chain, to_kdl(g));
        KDL::JntArray torques(static_cast<unsigned>(joints));
        KDL::Wrenches external(chain.getNrOfSegments(), KDL::Wrench::Zero());
        REQUIRE(solver.CartToJnt(q, qd, qdd, external, torques) >= 0);
        const auto r = anima::inverse_dynamics(chain_model, motion, g);
        for (std::size_t j = 1; j <= joints; ++j) {
            const T mine = axes[j % 3].dot(r.joint_torques[j]);
            const double theirs = torques(static_cast<unsigned>(j - 1));
            CHECK(std::abs(static_cast<double>(mine) - theirs) < static_cast<double>(tol) * (1.0 + std::abs(theirs)));
        }
    }
}

#else

TEST_CASE("fixed-base chain against KDL") { MESSAGE("skipped: KDL (orocos-kdl) was not found"); }

#endif

}  // namespace
