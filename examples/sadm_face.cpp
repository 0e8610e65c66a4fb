// Shape-appearance dependence mapping on the bundled FGNet frames: train on
// 27 frames, synthesise the 9 held-out ones from their landmarks alone, and
// report the paper's measures (NCC per grey parameter, PSNR per frame with
// and without noise on the landmarks). Writes the first held-out frame's
// synthesis as sadm_face.pgm. Exits with 1 if a result is off.
#include <anima/image.hpp>
#include <anima/sadm.hpp>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
    const std::string dir = argc > 1 ? argv[1] : ANIMA_EXAMPLE_DATA_DIR "/face";
    try {
        // Every 4th frame is held out: it is synthesised from its landmarks only.
        const auto split = anima::parse_frame_split("every:4");
        const auto train = anima::load_frame_folder<double>(dir, split, anima::frame_selection::training);
        const auto test = anima::load_frame_folder<double>(dir, split, anima::frame_selection::test);
        const auto& train_images = train.images;
        const auto& train_points = train.landmarks;
        const auto& test_images = test.images;
        const auto& test_points = test.landmarks;
        const auto model = anima::sadm_model<double>::train(train_images, train_points);
        std::printf("trained on %zu frames: %td shape and %td grey parameters over %zu face pixels\n",
                    train_images.size(), model.shape().size(), model.grey().size(), model.grey().raster().size());
        const auto exact = anima::evaluate_sadm(model, test_images, test_points);
        std::printf("held-out frames: NCC of b_g 1-3: %.3f %.3f %.3f\n", exact.ncc[0], exact.ncc[1], exact.ncc[2]);
        bool ok = exact.ncc[0] > 0.5;
        double previous = exact.psnr_mean;
        std::printf("noise 0 px: PSNR %.2f dB (grey model alone %.2f dB)\n", exact.psnr_mean, exact.psnr_model_mean);
        for (double noise : {1.0, 2.0, 3.0}) {
            anima::sadm_evaluation_options<double> options;
            options.noise = noise;
            const double p = anima::evaluate_sadm(model, test_images, test_points, options).psnr_mean;
            std::printf("noise %.0f px: PSNR %.2f dB\n", noise, p);
            ok = ok && p < previous + 0.5;
            previous = p;
        }
        ok = ok && exact.psnr_mean > 25 && previous < exact.psnr_mean;
        const auto face = model.synthesize(test_points[0], test_images[0]);
        anima::write_pgm("sadm_face.pgm", face);
        std::printf("wrote sadm_face.pgm (PSNR against the real frame %.2f dB over the whole image)\n",
                    anima::psnr(face, test_images[0]));
        if (!ok) std::fprintf(stderr, "sadm_face: a check failed\n");
        return ok ? 0 : 1;
    } catch (const anima::error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
