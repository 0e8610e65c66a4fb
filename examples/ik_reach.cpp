// Inverse kinematics on a real walk: every tenth frame is held out, the
// others train a learned Jacobian inverse; on held-out frames the hands and
// feet are sent to their true positions from a pose half a gait cycle away,
// and three solvers are compared: the minimum-norm pseudo-inverse, damped
// least squares pulled toward the mean training pose in the null space, and
// the learned inverse. Naturalness = RMS joint angle to the nearest
// training pose (radians; smaller is more natural).
#include <anima/bvh.hpp>
#include <anima/ik.hpp>
#include <anima/motion.hpp>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

int main() {
    using namespace anima;
    const auto walk = read_bvh<double>(std::string(ANIMA_EXAMPLE_DATA_DIR) + "/walk_cmu31_02_01.bvh");
    const auto& sk = walk.skeleton();
    kinematic_tree<double> tree(sk);
    tree.set_fixed(0);  // the root is placed as in the held-out frame; everything else is solved
    std::vector<std::size_t> train, test;
    for (std::size_t f = 0; f < walk.frames(); ++f) (f % 10 == 5 ? test : train).push_back(f);
    ik_matrix<double> poses(tree.dofs(), static_cast<Eigen::Index>(train.size()));
    for (std::size_t i = 0; i < train.size(); ++i) poses.col(static_cast<Eigen::Index>(i)) = tree.pose_of(walk, train[i]);
    const std::vector<std::string> names{"LeftHand", "RightHand", "LeftFoot", "RightFoot"};
    std::vector<ik_effector<double>> effectors;
    for (const auto& n : names) effectors.push_back({n, Eigen::Vector3d::Zero()});
    const auto model = learned_ik_model<double>::train(tree, effectors, poses);
    const ik_vector<double> mean = poses.rowwise().mean();

    ik_params<double> prm;
    prm.tolerance = 1e-5 * 30;  // 1e-5 of the body height (about 30 units)
    prm.max_iterations = 200;
    struct row {
        const char* name;
        int ok = 0, iterations = 0;
        double error = 0, natural = 0, seconds = 0;
    } rows[3] = {{"minimum-norm pseudo-inverse"}, {"DLS + null space to mean pose"}, {"learned J+ (SOM 6x6) + DLS polish"}};
    for (std::size_t f : test) {
        tree.set_base(walk, f);
        const auto truth = forward_kinematics(walk, f);
        std::vector<ik_goal<double>> goals;
        for (const auto& n : names) goals.push_back(position_goal<double>(sk.index_of(n), truth.positions[sk.index_of(n)]));
        const ik_vector<double> start = tree.pose_of(walk, (f + 170) % walk.frames());
        for (int s = 0; s < 3; ++s) {
            const auto t0 = std::chrono::steady_clock::now();
            ik_result<double> r;
            if (s == 0) {
                r = solve_ik(tree, goals, start, pseudo_inverse<double>{}, prm);
            } else if (s == 1) {
                auto p = prm;
                p.null_space.gain = 0.1;
                p.null_space.reference = mean;
                damped_least_squares<double>::params d;
                d.adaptive = true;
                r = solve_ik(tree, goals, start, damped_least_squares<double>(d), p);
            } else {
                learned_solve_params<double> l;
                l.ik = prm;
                r = solve_ik_learned(tree, model, goals, l);
            }
            rows[s].seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            rows[s].ok += r.converged();
            rows[s].iterations += r.iterations;
            rows[s].error += r.max_position_error;
            rows[s].natural += distance_to_nearest_pose<double>(tree, r.q, poses);
        }
    }
    const double n = static_cast<double>(test.size());
    std::printf("%zu held-out frames, %zu training poses, targets: both hands and feet\n", test.size(), train.size());
    std::printf("| solver | success | mean error | mean iterations | ms per solve | naturalness (rad) |\n");
    std::printf("| --- | ---: | ---: | ---: | ---: | ---: |\n");
    for (const auto& r : rows)
        std::printf("| %s | %.0f%% | %.2e | %.1f | %.2f | %.4f |\n", r.name, 100.0 * r.ok / n, r.error / n,
                    r.iterations / n, 1e3 * r.seconds / n, r.natural / n);
    return rows[0].ok > 0 && rows[2].ok > 0 ? 0 : 1;
}
