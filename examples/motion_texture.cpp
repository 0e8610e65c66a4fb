// Turn a short run into a long one with graph-cut motion textures: lay the
// clip's end over its beginning where they overlap best, let every joint
// switch at its own frame (a min-cut), fade, patch the textons end to end
// and smooth the seams with Poisson. Then check the seams against the
// clip's own joint and root speeds (anima::measure_texture, with the feet's
// skate), next to a plain cut-and-paste loop, and write the result (motion_texture.bvh in the working directory).
// Last, the clip's two halves as two clips: one loop through both, with a
// seam from each half into the other.
//
//   example_motion_texture [CLIP.bvh [FIRST_FRAME [FRAMES]]]
//
// FIRST_FRAME leaves out a rest pose at the start (default 6, for the
// bundled Daz-layout run, which starts with a T-pose and swings out of it).
#include <anima/bvh.hpp>
#include <anima/texture.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace {

int failures = 0;

void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "check failed: %s\n", what);
        ++failures;
    }
}

double worst(const std::vector<anima::seam_speed<double>>& s, bool root) {
    const auto w = anima::worst_seam_speed(s);
    return root ? w.root_ratio : w.joint_ratio;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string path = argc > 1 ? argv[1] : ANIMA_EXAMPLE_DATA_DIR "/run_cmu_09_01.bvh";
    const std::size_t first = argc > 2 ? static_cast<std::size_t>(std::strtoul(argv[2], nullptr, 10)) : 6;
    const std::size_t frames = argc > 3 ? static_cast<std::size_t>(std::strtoul(argv[3], nullptr, 10)) : 1200;
    try {
        anima::clip<double> clip = anima::read_bvh(path);
        clip = clip.slice(first, clip.frames());

        // m = 100 and an overlap of 50 as in the paper, shrunk for a short clip.
        anima::motion_texture_params<double> params;
        params.texton = anima::fit_texton_lengths(params.texton, clip.frames());
        const auto texture = anima::make_motion_texture(clip, frames, params);
        const auto& texton = texture.texton;
        std::printf("%s: %zu frames -> %zu frames (%.1f s)\n", path.c_str(), clip.frames(), texture.motion.frames(),
                    static_cast<double>(texture.motion.frames()) * clip.frame_time());
        std::printf("texton: M2 frame %zu over M1 frame %zu (m = %zu, overlap %zu), %zu frames, heading turn %.1f deg\n",
                    texton.offset_m2, texton.offset_m1, texton.m, texton.overlap, texton.motion.frames(),
                    anima::degrees(texton.heading_turn));
        const auto [lo, hi] = std::minmax_element(texton.cut.seam.begin(), texton.cut.seam.end());
        std::printf("seams: %zu rows switch at overlap frames %zu..%zu, cut cost %.3f\n", texton.rows(), *lo, *hi,
                    texton.cut.cost);
        std::printf("stages (ms): search %.2f, cut %.2f, fades %.2f, patch %.2f, Poisson %.2f\n",
                    1e3 * texture.timings.search, 1e3 * texture.timings.cut, 1e3 * texture.timings.blend,
                    1e3 * texture.timings.patch, 1e3 * texture.timings.smoothing);

        check(texture.motion.frames() == frames, "exactly the frames asked for");
        bool unit = true;
        for (std::size_t f = 0; f < texture.motion.frames(); ++f)
            for (std::size_t j = 0; j < texture.motion.joints(); ++j)
                unit = unit && std::abs(texture.motion.rotation(f, j).norm() - 1) < 1e-9 &&
                       texture.motion.translation(f, j).allFinite();
        check(unit, "unit quaternions and finite translations");

        // Seams: each joint's speed and the root's against the clip's own
        // fastest (and a cut-and-paste loop's), and the feet's skate.
        const auto quality = anima::measure_texture(clip, texture);
        const auto& seams = quality.seams;
        const auto limits = anima::clip_speed_limits(clip);
        std::vector<std::pair<std::size_t, std::size_t>> jumps;
        std::vector<std::size_t> stream;
        for (std::size_t k = 0; k < frames; ++k) {
            stream.push_back((texton.m + k) % clip.frames());
            if (k > 0 && stream[k] == 0) jumps.emplace_back(k - 1, k);
        }
        const auto naive = anima::seam_speeds(anima::resequence(clip, stream), jumps, limits);
        std::printf("fastest joint at the %zu seams: %.3f x the clip's own (cut-and-paste loop: %.3f x), root %.3f x\n",
                    seams.size(), worst(seams, false), worst(naive, false), worst(seams, true));
        if (quality.input_skate.median > 0)
            std::printf("foot skate: %.3f body heights/s, %.2f x the clip's own\n", quality.skate.median,
                        quality.skate.median / quality.input_skate.median);
        check(!seams.empty(), "the texture passes through seams");
        check(worst(seams, false) <= 1.02 && worst(seams, true) <= 1.02, "seams within the clip's own speeds");
        check(worst(naive, false) > 1.5, "a cut-and-paste loop is not");

        anima::write_bvh(texture.motion, "motion_texture.bvh");
        std::printf("wrote motion_texture.bvh\n");

        // Several clips of one skeleton: here the two halves of the clip.
        const std::size_t half = clip.frames() / 2;
        const std::vector<anima::clip<double>> halves{clip.slice(0, half), clip.slice(half, clip.frames())};
        anima::motion_texture_params<double> two = params;
        two.texton = anima::fit_texton_lengths(anima::texton_params<double>{}, half);
        const auto joined = anima::make_motion_texture(halves, frames, two);
        for (const auto& seam : joined.texton.seams())
            std::printf("halves: seam %zu -> %zu at offsets (a, b) = (%zu, %zu) of M2 and M1 (m = %zu), turn %.1f deg\n",
                        seam.from, seam.to, seam.offset_a, seam.offset_b, joined.texton.m,
                        anima::degrees(seam.heading_turn));
        const auto joined_seams = anima::seam_speeds(joined.motion, joined.overlap_spans, limits);
        std::printf("halves: %zu-frame loop, fastest joint at the %zu seams %.3f x the clip's own\n",
                    joined.texton.motion.frames(), joined_seams.size(), worst(joined_seams, false));
        check(joined.texton.seams().size() == 2, "two clips, two seams");
        check(worst(joined_seams, false) <= 1.02, "the seams between the halves within the clip's own speeds");
    } catch (const anima::error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    if (failures) std::fprintf(stderr, "%d check(s) failed\n", failures);
    return failures ? 1 : 0;
}
