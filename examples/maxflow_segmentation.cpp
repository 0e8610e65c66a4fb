// Binary segmentation of a noisy synthetic image by a minimum cut: each pixel
// pays for the label that does not fit its intensity (terminal weights), and
// neighbouring pixels pay for disagreeing (edge weights), so the cut finds a
// clean shape where thresholding the pixels one by one leaves speckle.
// Checks its own result: the grid layout and the general graph agree, and
// the cut makes far fewer mistakes than the threshold.
#include <anima/core/random.hpp>
#include <anima/maxflow.hpp>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

int main() {
    constexpr std::size_t rows = 24, cols = 60;
    constexpr double background = 0.25, foreground = 0.75;
    constexpr int scale = 1000;     // capacities are integers: costs in thousandths
    constexpr int smoothness = 90;  // cost of a label change between 4-neighbours

    // A disk and a bar, bright on dark, with strong uniform noise.
    anima::random_source rng(7);
    std::vector<bool> truth(rows * cols);
    std::vector<double> image(rows * cols);
    for (std::size_t r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < cols; ++c) {
            const double dr = double(r) - 11.5, dc = double(c) - 18.0;
            const bool inside = dr * dr + dc * dc < 81.0 || (r >= 6 && r < 18 && c >= 34 && c < 52);
            truth[r * cols + c] = inside;
            image[r * cols + c] = (inside ? foreground : background) + 0.9 * (rng.uniform() - 0.5);
        }

    // Source side = foreground. Cutting a pixel's source edge labels it
    // background, so that edge carries the cost of the background label.
    auto cost = [&](double value, double label) {
        return static_cast<int>(std::lround(scale * (value - label) * (value - label)));
    };
    anima::grid_flow_graph<int> grid(rows, cols);
    anima::flow_graph<int> graph(rows * cols, 2 * rows * cols);
    for (std::size_t r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < cols; ++c) {
            const std::size_t i = r * cols + c;
            const int to_background = cost(image[i], background), to_foreground = cost(image[i], foreground);
            grid.set_tweights(r, c, to_background, to_foreground);
            graph.add_tweights(i, to_background, to_foreground);
            if (c + 1 < cols) {
                grid.set_right(r, c, smoothness, smoothness);
                graph.add_edge(i, i + 1, smoothness, smoothness);
            }
            if (r + 1 < rows) {
                grid.set_down(r, c, smoothness, smoothness);
                graph.add_edge(i, i + cols, smoothness, smoothness);
            }
        }

    const auto cut = grid.min_cut();
    const auto check = graph.min_cut();
    std::size_t cut_errors = 0, threshold_errors = 0;
    std::string picture;
    for (std::size_t r = 0; r < rows; ++r) {
        for (std::size_t c = 0; c < cols; ++c) {
            const std::size_t i = r * cols + c;
            const bool fg = cut.side[i] == anima::cut_side::source;
            cut_errors += fg != truth[i];
            threshold_errors += (image[i] > 0.5) != truth[i];
            picture += fg ? (truth[i] ? '#' : '+') : (truth[i] ? '-' : '.');
        }
        picture += '\n';
    }
    std::printf("%s", picture.c_str());
    std::printf("('#' foreground, '.' background, '+' / '-' wrongly foreground / background)\n");
    std::printf("energy (max flow) %lld; mislabelled pixels: %zu by the cut, %zu by thresholding at 0.5\n", cut.flow,
                cut_errors, threshold_errors);

    if (check.flow != cut.flow) {
        std::fprintf(stderr, "error: the general graph's flow %lld differs from the grid's %lld\n", check.flow, cut.flow);
        return 1;
    }
    if (3 * cut_errors >= threshold_errors || cut_errors > rows * cols / 25) {
        std::fprintf(stderr, "error: the cut should make far fewer mistakes than the threshold\n");
        return 1;
    }
    return 0;
}
