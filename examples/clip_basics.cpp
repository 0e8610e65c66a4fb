// Read a real motion-capture clip, inspect it, run forward kinematics, look at
// it as a frames x DOF matrix, and write it back out.
#include <anima/bvh.hpp>
#include <anima/motion.hpp>
#include <anima/rotation/slerp.hpp>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

int main(int argc, char** argv) {
    const std::string path = argc > 1 ? argv[1] : ANIMA_EXAMPLE_DATA_DIR "/walk_cmu31_02_01.bvh";
    try {
        const anima::clip<double> walk = anima::read_bvh(path);
        const auto up = anima::guess_up_axis(walk.skeleton());
        const auto units = anima::guess_units(walk.skeleton(), up.up);
        std::printf("%s: %zu frames at %.1f Hz, %zu joints, up %s, units %s\n", path.c_str(), walk.frames(),
                    walk.frame_rate(), walk.joints(), anima::to_string(up.up).c_str(), units.name.c_str());

        // Where is the head halfway through?
        const std::size_t head = walk.skeleton().find("Head").value_or(walk.joints() - 1);
        const auto pose = anima::forward_kinematics(walk, walk.frames() / 2);
        const auto& p = pose.positions[head];
        std::printf("%s at frame %zu: (%.2f, %.2f, %.2f)\n", walk.skeleton()[head].name.c_str(), walk.frames() / 2,
                    p.x(), p.y(), p.z());

        // The numerical modules see the clip as a matrix.
        const auto layout = anima::make_dof_layout(walk);
        const auto m = anima::to_dof_matrix(walk, layout);
        std::printf("DOF matrix: %td x %td; column 0 is %s\n", m.rows(), m.cols(), layout.name(walk.skeleton(), 0).c_str());

        // Hold the head's rotation of the first frame through the first
        // tenth of a second, blended back out over it: one joint through
        // many frames, stored at once (already unit: not normalised again).
        anima::clip<double> held = walk;
        const std::size_t span = std::min<std::size_t>(walk.frames(), 12);
        std::vector<Eigen::Quaterniond> column(span);
        for (std::size_t f = 0; f < span; ++f)
            column[f] = anima::slerp(walk.rotation(0, head), walk.rotation(f, head),
                                     static_cast<double>(f) / static_cast<double>(span));
        held.set_joint_rotations(head, 0, column.data(), span);
        std::printf("head held for %zu frames\n", span);

        // Z-up, metres, XYZ channels, written to a string.
        auto zup = anima::change_up_axis(walk, up.up, anima::signed_axis{anima::axis::z, 1});
        zup = anima::scale_clip(zup, units.metres_per_unit);
        zup = anima::with_rotation_order(zup, anima::euler_order::xyz);
        const std::string text = anima::format_bvh(zup);
        std::printf("re-oriented clip written as %zu bytes of BVH\n", text.size());
    } catch (const anima::error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
