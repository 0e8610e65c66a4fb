// Wall-clock timing of the stages of a pipeline (steady clock).
#pragma once

#include <chrono>

namespace anima {

class stopwatch {
public:
    /// Seconds since the start or the last lap, and starts the next lap.
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(now - start_).count();
        start_ = now;
        return s;
    }
    /// Seconds since the start or the last lap.
    double elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

private:
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace anima
