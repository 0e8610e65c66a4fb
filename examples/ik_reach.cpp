// Inverse kinematics on real motion, evaluated on held-out blocks: each clip
// is cut into four contiguous blocks; each block in turn is held out, the
// rest of the clip (minus a quarter second on both sides of the block)
// trains the learned Jacobian inverse, and on the block's frames the hands,
// feet and head are sent to their true positions with the root placed as
// recorded. Every solver starts from the same pose: the rest pose, or its
// own solution of the previous evaluated frame. Reported per solver: success
// (every target within 1e-3 of the body height), the RMS joint-rotation
// distance of the solution to the real pose (rad), the distance to the
// nearest training pose (rad) and time. Usage: example_ik_reach [BVH...]
// (CMU clips, either skeleton layout); without arguments the bundled walk
// and run.
#include <anima/bvh.hpp>
#include <anima/ik.hpp>
#include <anima/ik/evaluation.hpp>
#include <anima/motion.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace anima;

constexpr int solvers = 4;
const char* const solver_names[solvers] = {"pseudo-inverse", "DLS (adaptive)", "nearest pose + DLS",
                                           "learned J+ (goal-blended)"};

struct totals {
    ik_evaluation<double> by[2][solvers];  // [start mode][solver]
};

std::vector<ik_effector<double>> effectors_for(const skeleton<double>& sk) {
    const bool cmu = sk.find("LeftHand").has_value();
    const std::vector<std::string> names = cmu ? std::vector<std::string>{"LeftHand", "RightHand", "LeftFoot", "RightFoot", "Head"}
                                               : std::vector<std::string>{"lHand", "rHand", "lFoot", "rFoot", "head"};
    std::vector<ik_effector<double>> out;
    for (const auto& n : names) out.push_back({n, Eigen::Vector3d::Zero()});
    return out;
}

double body_height(const kinematic_tree<double>& tree) {
    ik_state<double> s;
    tree.forward(ik_vector<double>::Zero(tree.dofs()), s);
    double lo = 1e300, hi = -1e300;
    for (const auto& p : s.positions) lo = std::min(lo, p.y()), hi = std::max(hi, p.y());
    return hi - lo;
}

ik_evaluation<double> run(int solver, const kinematic_tree<double>& tree, const clip<double>& c,
                          const std::vector<std::size_t>& test, const std::vector<ik_effector<double>>& eff,
                          const ik_matrix<double>& poses, const learned_ik_model<double>& model,
                          const nearest_pose_by_effectors<double>& nearest, ik_start mode, double height) {
    ik_params<double> prm;
    prm.tolerance = 1e-4 * height;
    prm.max_iterations = 200;
    damped_least_squares<double>::params d;
    d.adaptive = true;
    const ik_vector<double> rest = ik_vector<double>::Zero(tree.dofs());
    const auto solve = [&](const kinematic_tree<double>& t, const std::vector<ik_goal<double>>& goals,
                           const ik_vector<double>& q0) -> ik_result<double> {
        switch (solver) {
            case 0: return solve_ik(t, goals, q0, pseudo_inverse<double>{}, prm);
            case 1: return solve_ik(t, goals, q0, damped_least_squares<double>(d), prm);
            case 2: return solve_ik(t, goals, nearest(t, goals), damped_least_squares<double>(d), prm);
            default: {
                learned_solve_params<double> l;
                l.ik = prm;
                return solve_ik_learned(t, model, goals, l);
            }
        }
    };
    return evaluate_ik_on_frames<double>(tree, c, test, eff, poses, rest, mode, 1e-3 * height, solve);
}

void add(ik_evaluation<double>& to, const ik_evaluation<double>& e) {
    to.solves += e.solves;
    to.successes += e.successes;
    to.to_real += e.to_real;
    to.to_training += e.to_training;
    to.seconds += e.seconds;
    to.iterations += e.iterations;
}

void evaluate_clip(const std::string& path, totals& all) {
    const auto c = read_bvh<double>(path);
    kinematic_tree<double> tree(c.skeleton());
    tree.set_fixed(0);
    const auto eff = effectors_for(c.skeleton());
    const double height = body_height(tree);
    // Daz-layout clips start with a converter's T-pose frame: not motion.
    const std::size_t first = c.skeleton().find("LeftHand") ? 0 : 1, n = c.frames() - first;
    const std::size_t gap = static_cast<std::size_t>(0.25 / c.frame_time()), stride = std::max<std::size_t>(1, n / 160);
    totals clip_totals;
    for (int b = 0; b < 4; ++b) {
        const std::size_t lo = first + n * static_cast<std::size_t>(b) / 4, hi = first + n * static_cast<std::size_t>(b + 1) / 4;
        std::vector<std::size_t> train, test;
        for (std::size_t f = first; f < c.frames(); ++f) {
            if (f >= lo && f < hi) {
                if ((f - lo) % stride == 0) test.push_back(f);
            } else if (f + gap < lo || f >= hi + gap) {
                train.push_back(f);
            }
        }
        ik_matrix<double> poses(tree.dofs(), static_cast<Eigen::Index>(train.size()));
        for (std::size_t i = 0; i < train.size(); ++i) poses.col(static_cast<Eigen::Index>(i)) = tree.pose_of(c, train[i]);
        const auto model = learned_ik_model<double>::train(tree, eff, poses);
        const nearest_pose_by_effectors<double> nearest(tree, eff, poses);
        for (int m = 0; m < 2; ++m)
            for (int s = 0; s < solvers; ++s)
                add(clip_totals.by[m][s], run(s, tree, c, test, eff, poses, model, nearest,
                                              m ? ik_start::previous : ik_start::fixed, height));
    }
    const auto name = std::filesystem::path(path).filename().string();
    for (int m = 0; m < 2; ++m) {
        const double best = std::min(clip_totals.by[m][0].mean_to_real(), clip_totals.by[m][1].mean_to_real());
        for (int s = 0; s < solvers; ++s) {
            const auto& e = clip_totals.by[m][s];
            std::printf("| %s | %s | %s | %.1f%% | %.4f | %.2f | %.4f | %.2f |\n", name.c_str(), m ? "previous" : "rest pose",
                        solver_names[s], 100 * e.success_rate(), e.mean_to_real(), e.mean_to_real() / best,
                        e.mean_to_training(), e.ms_per_solve());
            add(all.by[m][s], e);
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) files.emplace_back(argv[i]);
    if (files.empty()) {
        files = {std::string(ANIMA_EXAMPLE_DATA_DIR) + "/walk_cmu31_02_01.bvh",
                 std::string(ANIMA_EXAMPLE_DATA_DIR) + "/run_cmu_09_01.bvh"};
    }
    std::printf("| clip | start | solver | success | to real pose (rad) | / best of pinv, DLS | to training (rad) | ms |\n");
    std::printf("| --- | --- | --- | ---: | ---: | ---: | ---: | ---: |\n");
    totals all;
    for (const auto& f : files) evaluate_clip(f, all);
    for (int m = 0; m < 2; ++m) {
        const double best = std::min(all.by[m][0].mean_to_real(), all.by[m][1].mean_to_real());
        for (int s = 0; s < solvers; ++s) {
            const auto& e = all.by[m][s];
            std::printf("| all | %s | %s | %.1f%% | %.4f | %.2f | %.4f | %.2f |\n", m ? "previous" : "rest pose",
                        solver_names[s], 100 * e.success_rate(), e.mean_to_real(), e.mean_to_real() / best,
                        e.mean_to_training(), e.ms_per_solve());
        }
    }
    return 0;
}
