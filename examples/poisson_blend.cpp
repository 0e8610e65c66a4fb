// Gradient-domain editing with anima's Poisson solvers: paste a patch into an
// image so that the seam disappears (Poisson image blending: inside a mask
// the result has the patch's Laplacian, outside it is the image), then
// smooth the seams of a clip stitched from two pieces of a CMU walk.
// Checks its own results and exits with 1 if one is off.
#include <anima/bvh.hpp>
#include <anima/motion.hpp>
#include <anima/poisson.hpp>
#include <anima/texture/motion_smoothing.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

int main(int argc, char** argv) {
    const std::string path = argc > 1 ? argv[1] : ANIMA_EXAMPLE_DATA_DIR "/walk_cmu31_02_01.bvh";
    bool ok = true;
    try {
        // An image (a slanted ramp) and a patch (ripples at another level).
        const Eigen::Index rows = 120, cols = 160;
        Eigen::MatrixXd image(rows, cols), patch(rows, cols);
        for (Eigen::Index j = 0; j < cols; ++j)
            for (Eigen::Index i = 0; i < rows; ++i) {
                image(i, j) = 0.01 * static_cast<double>(i) + 0.004 * static_cast<double>(j);
                patch(i, j) = 5.0 + 0.3 * std::sin(0.3 * static_cast<double>(i)) * std::cos(0.2 * static_cast<double>(j));
            }
        // Paste inside a disc: the unknowns. Everything else keeps the image.
        anima::poisson_grid<double> grid = anima::make_poisson_grid<double>(rows, cols, anima::boundary::neumann);
        grid.mask.resize(rows, cols);
        for (Eigen::Index j = 0; j < cols; ++j)
            for (Eigen::Index i = 0; i < rows; ++i) {
                const double y = static_cast<double>(i) - 60, x = static_cast<double>(j) - 70;
                grid.mask(i, j) = x * x + y * y < 40.0 * 40.0;
            }
        anima::poisson_problem<double> blend;
        blend.grid = grid;
        blend.rhs = anima::laplacian(grid, patch);  // keep the patch's detail
        blend.fixed = image;                        // and meet the image at the seam
        anima::multigrid_poisson<double> mg(grid);
        const auto r = mg.solve(blend);
        std::printf("blend: %td unknowns, %zu levels, %d cycles, relative residual %.1e\n", grid.unknowns(),
                    mg.levels(), r.iterations, r.relative_residual);
        // The pasted patch is shifted to the image's level: 5 units of offset gone.
        const double centre = r.u(60, 70) - image(60, 70), copied = patch(60, 70) - image(60, 70);
        std::printf("at the disc's centre the result is %.3f above the image (a plain copy: %.3f)\n", centre, copied);
        ok = ok && r.converged && std::abs(centre) < 0.5 && anima::relative_residual(blend, r.u) < 1e-7;

        // The sine-transform solver on the whole rectangle gives the same as multigrid.
        anima::poisson_problem<double> whole = anima::make_poisson_problem(
            anima::make_poisson_grid<double>(rows, cols), anima::laplacian(anima::make_poisson_grid<double>(rows, cols), patch));
        const auto a = anima::solve_poisson_dst(whole);
        const auto b = anima::solve_poisson_multigrid(whole);
        const double diff = (a.u - b.u).norm() / a.u.norm();
        std::printf("rectangle: DST and multigrid differ by %.1e (relative)\n", diff);
        ok = ok && diff < 1e-6;

        // Motion: frames 0-149 of the walk followed by frames 200-342, smoothed at the seam.
        const anima::clip<double> walk = anima::read_bvh(path);
        anima::clip<double> stitched = walk.slice(0, 150);
        stitched.append(walk.slice(200, walk.frames()));
        const auto smoothed = anima::smooth_seams(stitched, {150});
        const auto layout = anima::make_dof_layout(stitched);
        const Eigen::MatrixXd before = anima::to_dof_matrix(stitched, layout);
        const Eigen::MatrixXd after = anima::to_dof_matrix(smoothed.motion, layout);
        const auto excess = [&](const Eigen::MatrixXd& m) {  // over every DOF, whatever its unit
            const auto jump = anima::measure_seam_jump(m, 150, layout);
            return std::max(jump.rotation, jump.translation);
        };
        std::printf("motion: %zu frames, %zu DOFs; largest jump at the seam beyond the trend %.3f -> %.2e\n",
                    stitched.frames(), layout.size(), excess(before), excess(after));
        ok = ok && smoothed.stats.converged && excess(after) < 1e-6 && excess(before) > 0.1;
    } catch (const anima::error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    if (!ok) std::fprintf(stderr, "poisson_blend: a check failed\n");
    return ok ? 0 : 1;
}
