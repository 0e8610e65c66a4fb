// Clip IK one frame at a time, as a game loop runs it: while the walk plays,
// each foot in ground contact is held where it touched down, solved per
// frame into storage kept from frame to frame (solve_clip_frame_into), with
// no allocation per frame. Prints how far the ankles drift over their
// contacts before and after, and the time per frame.
#include <anima/bvh.hpp>
#include <anima/ik.hpp>
#include <anima/motion.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

int main(int argc, char** argv) {
    const std::string path = argc > 1 ? argv[1] : ANIMA_EXAMPLE_DATA_DIR "/walk_cmu31_02_01.bvh";
    try {
        const anima::clip<double> walk = anima::read_bvh(path);
        const anima::contact_set<double> contacts = anima::find_contacts(walk);

        // Kept from frame to frame: the tree, the goals, the result and the workspace.
        anima::kinematic_tree<double> tree(walk.skeleton());
        anima::clip_ik_params<double> params;
        params.ik.tolerance = 1e-3 * contacts.body_height;
        anima::damped_least_squares<double>::params d;
        d.adaptive = true;
        const anima::damped_least_squares<double> rule(d);
        anima::ik_result<double> out;
        anima::clip_ik_workspace<double> ws;
        std::vector<anima::ik_goal<double>> goals;
        anima::global_pose<double> recorded;
        anima::clip<double> played = walk;  // what the player shows

        std::vector<double> before, after;  // per held foot and frame: distance from its anchor
        std::size_t frames = 0, converged = 0;
        std::vector<Eigen::Vector3d> anchor(contacts.feet.size());
        const auto start = std::chrono::steady_clock::now();
        for (std::size_t f = 0; f < walk.frames(); ++f) {
            // This frame's goals: every foot in contact stays where its contact began.
            goals.clear();
            anima::forward_kinematics(walk, f, recorded);  // into storage kept between frames
            for (std::size_t i = 0; i < contacts.feet.size(); ++i) {
                const auto& foot = contacts.feet[i];
                if (!foot.in_contact[f]) continue;
                if (f == 0 || !foot.in_contact[f - 1]) anchor[i] = recorded.positions[foot.joint];
                before.push_back((recorded.positions[foot.joint] - anchor[i]).norm());
                goals.push_back(anima::position_goal<double>(foot.joint, anchor[i]));
            }
            if (goals.empty()) {
                ws.reset();  // a new run of solved frames starts cold
                continue;
            }
            anima::solve_clip_frame_into(tree, walk, f, goals, rule, params, out, ws);
            tree.write_pose(out.q, played, f);
            ++frames;
            converged += out.converged();
            for (const auto& e : out.errors) after.push_back(e.position);
        }
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

        const double cm = 100 * anima::guess_units(walk.skeleton(), contacts.up).metres_per_unit;
        std::printf("%s: %zu of %zu frames have a foot in contact; solved to tolerance in %zu\n", path.c_str(), frames,
                    walk.frames(), converged);
        const auto median_and_max = [cm](std::vector<double> v) {
            std::sort(v.begin(), v.end());
            return v.empty() ? std::pair<double, double>{0, 0} : std::pair{v[v.size() / 2] * cm, v.back() * cm};
        };
        const auto [recorded_median, recorded_max] = median_and_max(before);
        const auto [held_median, held_max] = median_and_max(after);
        std::printf("ankle drift from where its contact began, median / largest: %.2f / %.2f cm recorded, "
                    "%.3f / %.2f cm held\n",
                    recorded_median, recorded_max, held_median, held_max);
        std::printf("%.1f us per frame (forward kinematics of the recording included)\n",
                    frames ? 1e6 * seconds / static_cast<double>(walk.frames()) : 0.0);
        for (const auto& q : played.rotations())
            if (!q.coeffs().allFinite()) return 1;
    } catch (const anima::error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
