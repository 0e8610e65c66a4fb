// Learned Jacobian inverse (SOM + Eq 3), Komura's weights from mocap
// variance, the naturalness measure, and the model's file format.
#include "ik_test_support.hpp"
#include "../test_support.hpp"

#include <anima/bvh.hpp>
#include <anima/ik.hpp>
#include <anima/ik/evaluation.hpp>
#include <anima/motion.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>

using namespace anima;
using anima_test::bundled;
using anima_test::tolerance;

namespace {

template <class T>
struct walk_setup {
    clip<T> walk = read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    kinematic_tree<T> tree{walk.skeleton()};
    std::vector<ik_effector<T>> effectors{{"LeftHand", Eigen::Matrix<T, 3, 1>::Zero()},
                                          {"RightHand", Eigen::Matrix<T, 3, 1>::Zero()},
                                          {"LeftFoot", Eigen::Matrix<T, 3, 1>::Zero()},
                                          {"RightFoot", Eigen::Matrix<T, 3, 1>::Zero()}};
    ik_matrix<T> training;
    std::vector<std::size_t> held_out;
    walk_setup() {
        tree.set_fixed(0);
        std::vector<std::size_t> train;
        for (std::size_t f = 0; f < walk.frames(); ++f) (f % 10 == 5 ? held_out : train).push_back(f);
        training.resize(tree.dofs(), static_cast<Eigen::Index>(train.size()));
        for (std::size_t i = 0; i < train.size(); ++i) training.col(static_cast<Eigen::Index>(i)) = tree.pose_of(walk, train[i]);
    }
    std::vector<ik_goal<T>> goals_of(std::size_t f) const {
        const auto truth = forward_kinematics(walk, f);
        std::vector<ik_goal<T>> g;
        for (const auto& e : effectors) {
            const auto j = walk.skeleton().index_of(e.joint);
            g.push_back(position_goal<T>(j, truth.positions[j], e.offset));
        }
        return g;
    }
};

}  // namespace

TEST_CASE_TEMPLATE("learned J+ of a cluster is Eq 3's least-squares fit of its members", T, double, float) {
    walk_setup<T> w;
    learned_ik_params<T> prm;
    prm.rows = prm.cols = 3;
    prm.epochs = 10;
    prm.ridge = T(1e-9);
    const auto model = learned_ik_model<T>::train(w.tree, w.effectors, w.training, prm);
    REQUIRE(model.clusters() == 9);
    const auto joints = model.resolve(w.tree, "test");
    // Rebuild one well-populated cluster's (dq, dg) pairs and solve Eq 3 with
    // an SVD least-squares solve, independently of the model's normal equations.
    std::vector<std::vector<Eigen::Index>> members(9);
    for (Eigen::Index s = 0; s < w.training.cols(); ++s) {
        Eigen::Index best = 0;
        (model.centres().colwise() - w.training.col(s)).colwise().squaredNorm().minCoeff(&best);
        members[static_cast<std::size_t>(best)].push_back(s);
    }
    int checked = 0;
    for (Eigen::Index c = 0; c < 9; ++c) {
        const auto& mem = members[static_cast<std::size_t>(c)];
        if (mem.size() < 20) continue;
        REQUIRE(model.inverse(c).rows() == w.tree.dofs());
        ik_matrix<double> dq(w.tree.dofs(), static_cast<Eigen::Index>(mem.size())), dg(12, dq.cols());
        for (std::size_t i = 0; i < mem.size(); ++i) {
            dq.col(static_cast<Eigen::Index>(i)) = (w.training.col(mem[i]) - model.centres().col(c)).template cast<double>();
            dg.col(static_cast<Eigen::Index>(i)) =
                (model.effectors_of(w.tree, joints, w.training.col(mem[i])) - model.centre_effectors().col(c)).template cast<double>();
        }
        const ik_matrix<double> ref = dg.transpose().jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(dq.transpose()).transpose();
        const ik_matrix<double> got = model.inverse(c).template cast<double>();
        const double fit_ref = (dq - ref * dg).norm(), fit_got = (dq - got * dg).norm();
        CHECK(fit_got <= fit_ref * tolerance<T>(1.0001, 1.1) + 1e-9);  // as good as the least-squares optimum
        CHECK(fit_got < dq.norm());                                     // and better than no model
        ++checked;
    }
    CHECK(checked >= 2);
}

TEST_CASE_TEMPLATE("learned inverse on a held-out block of the walk: nearer the real pose than pinv and DLS from the "
                   "same start, by the 0.65 margin", T, double, float) {
    // Train on frames [0, 228), hold out the contiguous block [258, 343)
    // (a quarter second of gap), targets for both hands, both feet and the
    // head; every solver starts from the rest pose.
    const auto walk = read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    kinematic_tree<T> tree(walk.skeleton());
    tree.set_fixed(0);
    std::vector<ik_effector<T>> effectors;
    for (const char* n : {"LeftHand", "RightHand", "LeftFoot", "RightFoot", "Head"})
        effectors.push_back({n, Eigen::Matrix<T, 3, 1>::Zero()});
    const ik_matrix<T> training = clip_poses(tree, walk, 0, 228);
    std::vector<std::size_t> block;
    for (std::size_t f = 258; f < walk.frames(); f += 4) block.push_back(f);
    const auto model = learned_ik_model<T>::train(tree, effectors, training);
    const T height = T(30);  // the figure is about 26.5 units tall, with the hands raised about 30
    ik_params<T> p;
    p.tolerance = T(1e-4) * height;
    p.max_iterations = 200;
    typename damped_least_squares<T>::params d;
    d.adaptive = true;
    const ik_vector<T> rest = ik_vector<T>::Zero(tree.dofs());
    const auto evaluate = [&](auto solve) {
        return evaluate_ik_on_frames<T>(tree, walk, block, effectors, training, rest, ik_start::fixed, T(1e-3) * height, solve);
    };
    const auto pinv = evaluate([&](const kinematic_tree<T>& t, const std::vector<ik_goal<T>>& g, const ik_vector<T>& q0) {
        return solve_ik(t, g, q0, pseudo_inverse<T>{}, p);
    });
    const auto dls = evaluate([&](const kinematic_tree<T>& t, const std::vector<ik_goal<T>>& g, const ik_vector<T>& q0) {
        return solve_ik(t, g, q0, damped_least_squares<T>(d), p);
    });
    learned_solve_params<T> lp;
    lp.ik = p;
    const auto learned = evaluate([&](const kinematic_tree<T>& t, const std::vector<ik_goal<T>>& g, const ik_vector<T>&) {
        return solve_ik_learned(t, model, g, lp);
    });
    const int n = static_cast<int>(block.size());
    CHECK(pinv.successes == n);
    CHECK(dls.successes == n);
    CHECK(learned.successes == n);
    const double best = std::min(pinv.mean_to_real(), dls.mean_to_real());
    MESSAGE("distance to the real pose (rad): learned " << learned.mean_to_real() << ", pinv " << pinv.mean_to_real()
                                                        << ", DLS " << dls.mean_to_real());
    CHECK(learned.mean_to_real() <= 0.65 * best);
    CHECK(learned.mean_to_training() < pinv.mean_to_training());
}

TEST_CASE_TEMPLATE("learned inverse: the pose comes from the goal, blended over the nearest clusters", T, double, float) {
    walk_setup<T> w;
    learned_ik_params<T> prm;
    prm.rows = prm.cols = 4;
    prm.epochs = 8;
    const auto model = learned_ik_model<T>::train(w.tree, w.effectors, w.training, prm);
    // On a reference pose's own effectors the blend is that cluster alone
    // and the prediction is its centre.
    const auto b = model.nearest_to_goal(model.centre_effectors().col(5), 4);
    REQUIRE(b.clusters.size() == 4);
    CHECK(b.clusters.front() == 5);
    CHECK(b.weights.front() > T(0.999));
    CHECK((model.predict(model.centre_effectors().col(5), b) - model.centres().col(5)).norm() <
          tolerance<T>(1e-6, 1e-2));
    // Weights are positive, sum to one and fall with the distance.
    const ik_vector<T> between = (model.centre_effectors().col(0) + model.centre_effectors().col(15)) / T(2);
    const auto m = model.nearest_to_goal(between, 3);
    T sum = 0;
    for (std::size_t i = 0; i < m.weights.size(); ++i) {
        CHECK(m.weights[i] > T(0));
        if (i) CHECK(m.weights[i] <= m.weights[i - 1] * T(1.0001));
        sum += m.weights[i];
    }
    CHECK(sum == doctest::Approx(1.0).epsilon(1e-5));
    // The solve reports the clusters it used.
    w.tree.set_base(w.walk, 5);
    learned_solve_params<T> sp;
    sp.blend = 2;
    const auto r = solve_ik_learned(w.tree, model, w.goals_of(5), sp);
    CHECK(r.blended.size() == 2);
    CHECK(r.cluster == r.blended.front());
    CHECK(r.q.allFinite());
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)model.nearest_to_goal(between.head(3), 2); }),
                               "target of 3 values"));
    sp.blend = 0;
    CHECK(anima_test::contains(
        anima_test::invalid_argument_message([&] { (void)solve_ik_learned(w.tree, model, w.goals_of(5), sp); }), "blend"));
}

TEST_CASE_TEMPLATE("learned inverse: a target whose squared distances overflow is refused, not blended into NaN", T,
                   double, float) {
    walk_setup<T> w;
    learned_ik_params<T> prm;
    prm.rows = prm.cols = 3;
    prm.epochs = 4;
    const auto model = learned_ik_model<T>::train(w.tree, w.effectors, w.training, prm);
    const auto rows = model.centre_effectors().rows();
    // Finite, but its squares are not: 1e20 in float, 1e160 in double.
    const T far = static_cast<T>(std::is_same_v<T, float> ? 1e20 : 1e160);
    const ik_vector<T> target = ik_vector<T>::Constant(rows, far);
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)model.nearest_to_goal(target, 3); }),
                               "anima::learned_ik_model::nearest_to_goal: target too far out (largest coordinate " +
                                   anima::detail::argument_text(far) + ")"));
    // A blend built elsewhere does not turn the far target into NaN either.
    const ik_vector<T> near = ik_vector<T>::Constant(rows, T(1e3));
    const auto b = model.nearest_to_goal(near, 3);
    const ik_vector<T> overflowing = ik_vector<T>::Constant(rows, std::numeric_limits<T>::max());
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)model.predict(overflowing, b); }),
                               "anima::learned_ik_model::predict: target too far out"));
    // The largest target solve_ik_learned accepts still blends finitely.
    const T largest = static_cast<T>(std::is_same_v<T, float> ? 1e18 : 1e150);
    const auto fb = model.nearest_to_goal(ik_vector<T>::Constant(rows, largest), 3);
    for (const T wt : fb.weights) CHECK(std::isfinite(wt));
    CHECK(model.predict(ik_vector<T>::Constant(rows, largest), fb).allFinite());
    // Clusters at the floor (a duplicated target) keep weights that sum to one.
    const auto on = model.nearest_to_goal(model.centre_effectors().col(0), 9);
    T sum = T(0);
    for (const T wt : on.weights) sum += wt;
    CHECK(sum == doctest::Approx(1.0).epsilon(1e-5));
}

TEST_CASE_TEMPLATE("learned model: save and load round trip, file errors with line numbers", T, double, float) {
    walk_setup<T> w;
    learned_ik_params<T> prm;
    prm.rows = 2;
    prm.cols = 3;
    prm.epochs = 3;
    const auto model = learned_ik_model<T>::train(w.tree, w.effectors, w.training, prm);
    std::ostringstream out;
    model.save(out);
    std::istringstream in(out.str());
    const auto back = learned_ik_model<T>::load(in, "model.txt");
    CHECK(back.centres() == model.centres());
    CHECK(back.centre_effectors() == model.centre_effectors());
    for (Eigen::Index c = 0; c < model.clusters(); ++c) CHECK(back.inverse(c) == model.inverse(c));
    std::ostringstream again;
    back.save(again);
    CHECK(again.str() == out.str());
    w.tree.set_base(w.walk, 5);
    const auto a = solve_ik_learned(w.tree, model, w.goals_of(5));
    const auto b = solve_ik_learned(w.tree, back, w.goals_of(5));
    CHECK(a.q == b.q);

    const auto parse_message = [](const std::string& text) -> std::string {
        std::istringstream s(text);
        try {
            (void)learned_ik_model<T>::load(s, "m.txt");
        } catch (const parse_error& e) {
            return e.what();
        }
        return "";
    };
    CHECK(parse_message("anima-learned-ik 2\n") == "m.txt:1: unsupported version (this build reads version 1)");
    CHECK(anima_test::contains(parse_message("anima-learned-ik 1\ndofs 3\n"), "m.txt:3: file ends"));
    // Counts past the format's limit are refused where they stand; counts
    // within it are not trusted to size memory: the file ends first.
    CHECK(anima_test::contains(parse_message("anima-learned-ik 1\ndofs 2000000000\n"),
                               "m.txt:2: expected a count between 0 and 1000000"));
    CHECK(anima_test::contains(parse_message("anima-learned-ik 1\ndofs 1000000\neffectors 1\neffector Hand 0 0 0\n"
                                             "clusters 1000000\ncentre 1 2\n"),
                               "m.txt:6: line ends"));
    CHECK(anima_test::contains(parse_message("anima-learned-ik 1\ndofs 2\neffectors 1\neffector Hand 0 0 0\n"
                                             "clusters 1000000\ncentre 1 2\nreach 1 2 3\ninverse 1 1 2 3\n"),
                               "m.txt:8: line ends"));
    std::string text = out.str();
    const auto pos = text.find("centre ");
    text.replace(text.find(' ', pos + 7) + 1, 1, "x");
    const auto line = static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(pos), '\n') + 1);
    CHECK(anima_test::contains(parse_message(text), "m.txt:" + std::to_string(line) + ": '"));
    // A model for another tree is refused by name.
    kinematic_tree<T> other = kinematic_tree<T>::chain(w.walk.skeleton(), "LeftArm", "LeftHand");
    CHECK(anima_test::contains(
        anima_test::invalid_argument_message([&] { (void)solve_ik_learned(other, model, w.goals_of(5)); }), "DOFs"));
    kinematic_tree<T> free_root(w.walk.skeleton());
    CHECK(anima_test::contains(
        anima_test::invalid_argument_message([&] { (void)learned_ik_model<T>::train(free_root, w.effectors, w.training); }),
        "must be fixed"));
}

TEST_CASE_TEMPLATE("Komura weights from variance; the weighted inverse is the W-norm minimum", T, double, float) {
    ik_matrix<T> poses(3, 4);
    poses << 0, 2, 0, 2,   // variance 4/3
        0, 0, 0, 0,        // never moves: floored
        1, 2, 1, 2;        // variance 1/3
    const auto w = dof_weights_from_poses<T>(poses, T(0.1));
    const T mean = (T(4) / 3 + T(1) / 3) / 3;
    CHECK(w[0] == doctest::Approx(static_cast<double>(mean / (T(4) / 3))));
    CHECK(w[1] == doctest::Approx(10.0));  // floor 0.1 of the mean
    CHECK(w[2] == doctest::Approx(static_cast<double>(mean / (T(1) / 3))));
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] { (void)dof_weights_from_poses<T>(poses.leftCols(1)); }),
                               "at least 2 poses"));

    const auto arm = anima_ik_test::seven_dof_arm<T>();
    ik_vector<T> qg = ik_vector<T>::Zero(7);
    qg << T(0.4), T(0.5), T(0.3), T(0.6), T(0.2), T(0.4), T(0);
    std::vector<ik_goal<T>> goals{
        position_goal<T>(6, anima_ik_test::point_at(arm, qg, 6, anima_ik_test::arm_tip<T>()), anima_ik_test::arm_tip<T>())};
    ik_params<T> p;
    p.tolerance = tolerance<T>(1e-8, 2e-5);
    const ik_vector<T> q0 = T(0.1) * ik_vector<T>::Ones(7);
    ik_vector<T> heavy = ik_vector<T>::Ones(7);
    heavy[1] = T(100);  // the shoulder is expensive
    const auto weighted = solve_ik(arm, goals, q0, weighted_rule<T, pseudo_inverse<T>>(heavy), p);
    CHECK(weighted.converged());
    // One step is the W-weighted minimum-norm solution of J dq = e: compare
    // with the closed form W^-1 J^T (J W^-1 J^T)^-1 e.
    const auto jac = goal_jacobian(arm, q0, goals);
    const ik_vector<T> e = goals[0].position - anima_ik_test::point_at(arm, q0, 6, anima_ik_test::arm_tip<T>());
    ik_vector<T> dq;
    ik_step_info<T> info;
    const weighted_rule<T, pseudo_inverse<T>> rule(heavy);
    rule(jac, e, dq, info);
    const ik_vector<T> winv = heavy.cwiseInverse();
    const ik_matrix<T> a = jac * winv.asDiagonal() * jac.transpose();
    const ik_vector<T> ref = winv.asDiagonal() * jac.transpose() * a.ldlt().solve(e);
    CHECK((dq - ref).norm() < tolerance<T>(1e-9, 1e-3) * ref.norm());
    ik_vector<T> plain;
    pseudo_inverse<T>{}(jac, e, plain, info);
    // Each is the minimum of its own norm among the exact solutions.
    const auto wnorm = [&](const ik_vector<T>& v) { return v.dot(heavy.cwiseProduct(v)); };
    CHECK(wnorm(dq) <= wnorm(plain) * T(1.0001));
    CHECK(plain.norm() <= dq.norm() * T(1.0001));
    CHECK(wnorm(dq) < T(0.5) * wnorm(plain));  // the weighting matters here
}

TEST_CASE_TEMPLATE("pose_distance: zero on itself, symmetric, the joint angle for one joint", T, double, float) {
    const auto walk = read_bvh<T>(bundled("walk_cmu31_02_01.bvh"));
    auto arm = kinematic_tree<T>::chain(walk.skeleton(), "LeftArm", "LeftHand");
    const auto a = arm.pose_of(walk, 10), b = arm.pose_of(walk, 200);
    CHECK(pose_distance<T>(arm, a, a) < tolerance<T>(1e-7, 1e-3));
    CHECK(pose_distance<T>(arm, a, b) == doctest::Approx(static_cast<double>(pose_distance<T>(arm, b, a))).epsilon(1e-4));
    ik_vector<T> c = a;
    const Eigen::Quaternion<T> turned =
        arm.local_rotation(a, walk.skeleton().index_of("LeftArm")) * Eigen::Quaternion<T>(Eigen::AngleAxis<T>(T(0.3), Eigen::Matrix<T, 3, 1>::UnitY()));
    c.template head<3>() = to_rotation_vector(turned);
    // One of three joints turned by 0.3: RMS = 0.3 / sqrt(3).
    CHECK(pose_distance<T>(arm, a, c) == doctest::Approx(0.3 / std::sqrt(3.0)).epsilon(tolerance<T>(1e-6, 1e-3)));
    ik_matrix<T> poses(9, 2);
    poses << b, c;
    CHECK(distance_to_nearest_pose<T>(arm, a, poses) == doctest::Approx(static_cast<double>(pose_distance<T>(arm, a, c))));
}

TEST_CASE_TEMPLATE("learned_ik_solver and ik_solver_call: solve_clip_ik's solver shape, the same results", T, double,
                   float) {
    walk_setup<T> w;
    learned_ik_params<T> prm;
    prm.rows = prm.cols = 4;
    prm.epochs = 8;
    const auto model = learned_ik_model<T>::train(w.tree, w.effectors, w.training, prm);
    std::vector<frame_goals<T>> goals;
    for (std::size_t i = 0; i < 4; ++i) goals.push_back({w.held_out[i], w.goals_of(w.held_out[i])});
    clip_ik_params<T> cp;  // no pull and no warm start: each frame's params are cp.ik as they are
    cp.pose_pull = T(0);
    cp.warm_start = false;
    cp.ik.tolerance = tolerance<T>(1e-4, 1e-3);
    learned_solve_params<T> sp;
    sp.blend = 2;
    std::vector<Eigen::Index> clusters;
    const auto solved = solve_clip_ik(w.tree, w.walk, goals, learned_ik_solver<T>{&model, sp, &clusters}, cp);
    const auto library = solve_clip_ik(w.tree, w.walk, goals, ik_solver_call<T>{ik_solver::levenberg_marquardt}, cp);
    REQUIRE(clusters.size() == goals.size());
    for (std::size_t i = 0; i < goals.size(); ++i) {
        auto tree = w.tree;
        tree.set_base(w.walk, goals[i].frame);
        learned_solve_params<T> own = sp;
        own.ik = cp.ik;
        const auto alone = solve_ik_learned(tree, model, goals[i].goals, own);
        CHECK(solved.results[i].q == alone.q);
        CHECK(solved.results[i].iterations == alone.iterations);
        CHECK(clusters[i] == alone.cluster);
        const auto lm = solve_ik_with(ik_solver::levenberg_marquardt, tree, goals[i].goals, tree.pose_of(w.walk, goals[i].frame), cp.ik);
        CHECK(library.results[i].q == lm.q);
    }
    CHECK(solved.converged_frames == goals.size());
    CHECK(anima_test::contains(anima_test::invalid_argument_message([&] {
                                   (void)solve_clip_ik(w.tree, w.walk, goals, learned_ik_solver<T>{}, cp);
                               }),
                               "no model"));
}
