// Play a real walk forwards and backwards: find the frames where it can be
// reversed without a seam (symmetry scores and turning candidates, Eq 3-5),
// generate a long frame stream that turns there with adaptive probabilities
// (Eq 6), compare it with fixed probabilities, and write the new motion,
// feet held where it turns (anima::render_stream), as BVH
// (symmetry_playback.bvh in the working directory).
//
//   example_symmetry_playback [CLIP.bvh [FIRST_FRAME]]
//
// FIRST_FRAME leaves out a rest pose at the start (5 for the Daz-layout CMU
// clips, which start with a T-pose and swing out of it over frames 1-5).
#include <anima/bvh.hpp>
#include <anima/symmetry.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

int failures = 0;

void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "check failed: %s\n", what);
        ++failures;
    }
}

}  // namespace

int main(int argc, char** argv) {
    const std::string path = argc > 1 ? argv[1] : ANIMA_EXAMPLE_DATA_DIR "/walk_cmu31_02_01.bvh";
    const std::size_t first = argc > 2 ? static_cast<std::size_t>(std::strtoul(argv[2], nullptr, 10)) : 0;
    try {
        anima::clip<double> clip = anima::read_bvh(path);
        clip = clip.slice(first, clip.frames());

        // 1. Symmetry of every frame: the frames i-r and i+r around a good
        //    turning point look alike (r = 1..10, Mahalanobis distance).
        const Eigen::MatrixXd features = anima::frame_features(clip);  // root's ground position zeroed
        anima::symmetry_params<double> params;
        params.radius = 10;
        const auto sym = anima::symmetry_scores(features, clip.frame_time(), params);
        std::printf("%s: %zu frames, %zu turning candidates; the best:\n", path.c_str(), clip.frames(),
                    sym.candidates.size());
        for (std::size_t k = 0; k < sym.candidates.size() && k < 5; ++k) {
            const auto& c = sym.candidates[k];
            std::printf("  frame %4zu  score %.3f  P(turn) %.3f  (%d pairs)\n", first + c.frame, c.score, c.probability,
                        sym.pairs[c.frame]);
        }
        check(sym.candidates.size() >= 2, "at least two turning candidates");
        check(sym.score.allFinite() && sym.score.minCoeff() >= 0 && sym.score.maxCoeff() <= 1, "scores in [0, 1]");

        // 2. A stream of frame indices that reverses at the candidates, with
        //    adaptive probabilities (Eq 6) and, for comparison, fixed ones.
        const std::size_t length = 3000;
        std::vector<std::size_t> streams[2], turns[2];
        for (const bool adaptive : {true, false}) {
            anima::playback_params<double> pp;
            pp.adaptive = adaptive;
            pp.seed = 7;
            anima::symmetric_playback<double> playback(clip.frames(), sym.candidates, pp);
            std::vector<std::size_t>& stream = streams[adaptive ? 0 : 1];
            stream = playback.take(length);
            turns[adaptive ? 0 : 1] = playback.turns();
            const auto cov = anima::coverage(stream, clip.frames());
            std::printf("%s playback, %zu frames: %zu turns, %.1f%% of the clip shown, evenness %.3f\n",
                        adaptive ? "adaptive" : "fixed   ", length, playback.turns().size(), 100 * cov.visited,
                        cov.evenness);

            // The stream only ever steps to a neighbouring frame, and reverses
            // only at candidates.
            bool steps = true, turns_at_candidates = true;
            for (std::size_t k = 1; k < stream.size(); ++k)
                steps = steps && (stream[k] == stream[k - 1] + 1 || stream[k] + 1 == stream[k - 1]);
            for (const std::size_t t : playback.turns())
                turns_at_candidates = turns_at_candidates && playback.probability(stream[t]) > 0;
            check(steps, "playback moves one frame at a time");
            check(turns_at_candidates, "playback turns only at candidates");
            check(!playback.turns().empty(), "playback turns");
        }

        // 3. The new motion: rotations from the source frames, the root's
        //    recorded steps added up, and the feet that are on the ground
        //    where playback turns held in place (the legs reverse there).
        const auto played = anima::render_stream(clip, streams[0], turns[0]);
        std::printf("feet held through the turns: %zu contact runs\n", played.planted_runs);
        anima::write_bvh(played.motion, "symmetry_playback.bvh");
        const anima::clip<double> back = anima::read_bvh("symmetry_playback.bvh");
        std::printf("wrote symmetry_playback.bvh: %zu frames (%.1f s)\n", back.frames(), back.duration());
        check(back.frames() == length, "the written clip has every frame");
    } catch (const anima::error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return failures == 0 ? 0 : 1;
}
