// Shared by the optimiser tests and benchmark: Eigen's MINPACK port (the
// reference Levenberg-Marquardt, whose headers are not -Wpedantic clean)
// and the monotonicity check every solver's history must pass.
#pragma once

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#endif
#include <unsupported/Eigen/NonLinearOptimization>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <vector>

namespace anima_test {

/// True when no value in `history` exceeds the one before it (or `start`).
template <class T>
bool non_increasing(const std::vector<T>& history, T start) {
    T previous = start;
    for (T v : history) {
        if (v > previous) return false;
        previous = v;
    }
    return true;
}

}  // namespace anima_test
