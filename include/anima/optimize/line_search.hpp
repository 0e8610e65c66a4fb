// A line search for the strong Wolfe conditions (Nocedal & Wright,
// Numerical Optimization, 2nd ed., algorithms 3.5 and 3.6): bracket a step,
// then shrink the bracket by safeguarded cubic interpolation. Quasi-Newton
// methods need the curvature condition to keep their Hessian estimate
// positive definite; a backtracking search alone does not give it.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include <anima/optimize/result.hpp>

namespace anima {

template <class T>
struct wolfe_line_search_params {
    T sufficient_decrease = T(1e-4);  ///< c1 of the Armijo condition
    T curvature = T(0.9);             ///< c2: 0.9 suits quasi-Newton directions
    int max_evaluations = 40;
    T max_step = T(1e10);
};

/// Where a line search ended: the accepted point with its value and gradient.
template <class T>
struct line_search_point {
    T step = T(0);
    T value{};
    vector_x<T> x;
    vector_x<T> gradient;
    int evaluations = 0;
    bool found = false;  ///< a point with sufficient decrease was found
    bool wolfe = false;  ///< it also meets the curvature condition
};

/// Searches along `direction` from `x` (value `value`, gradient `gradient`)
/// starting with `step`. F: T(const vector_x<T>& x, vector_x<T>& gradient).
/// A non-finite value at a trial point counts as "too far".
template <class T, class F>
line_search_point<T> wolfe_line_search(F& f, const vector_x<T>& x, T value, const vector_x<T>& gradient,
                                       const vector_x<T>& direction, T step,
                                       const wolfe_line_search_params<T>& params = {}) {
    line_search_point<T> best;
    const T slope0 = gradient.dot(direction);
    if (!(slope0 < T(0)) || !(step > T(0))) {
        return best;  // not a descent direction: nothing to find
    }

    struct sample {
        T step, value, slope;
        bool finite;
    };
    vector_x<T> trial_x(x.size()), trial_g(x.size());
    int evaluations = 0;
    auto evaluate = [&](T a) {
        trial_x = x + a * direction;
        trial_g.resize(x.size());
        const T v = f(static_cast<const vector_x<T>&>(trial_x), trial_g);
        ++evaluations;
        const bool finite = std::isfinite(v) && trial_g.allFinite();
        return sample{a, v, finite ? trial_g.dot(direction) : T(0), finite};
    };
    auto armijo = [&](const sample& s) {
        // Strictly lower too: near the rounding floor the Armijo bound
        // rounds to `value` itself and would accept standing still.
        return s.finite && s.value < value && s.value <= value + params.sufficient_decrease * s.step * slope0;
    };
    auto keep = [&](const sample& s, bool wolfe) {
        // Remember the lowest Armijo point seen: the fallback if the
        // curvature condition is never met within the budget.
        if (armijo(s) && (!best.found || s.value < best.value || wolfe)) {
            best.step = s.step;
            best.value = s.value;
            best.x = trial_x;
            best.gradient = trial_g;
            best.found = true;
            best.wolfe = wolfe;
        }
    };
    auto curvature_ok = [&](const sample& s) { return std::abs(s.slope) <= -params.curvature * slope0; };

    // Zoom into [lo, hi]: lo satisfies Armijo and has the lowest value so far.
    auto zoom = [&](sample lo, sample hi) {
        while (evaluations < params.max_evaluations) {
            const T width = hi.step - lo.step;
            T a = lo.step + width / T(2);
            if (hi.finite) {
                // Minimiser of the cubic through both ends' values and slopes.
                const T d1 = lo.slope + hi.slope - T(3) * (lo.value - hi.value) / (lo.step - hi.step);
                const T radicand = d1 * d1 - lo.slope * hi.slope;
                if (radicand >= T(0)) {
                    const T d2 = std::copysign(std::sqrt(radicand), hi.step - lo.step);
                    const T cubic =
                        hi.step - (hi.step - lo.step) * (hi.slope + d2 - d1) / (hi.slope - lo.slope + T(2) * d2);
                    const T lo_edge = std::min(lo.step, hi.step) + T(0.1) * std::abs(width);
                    const T hi_edge = std::max(lo.step, hi.step) - T(0.1) * std::abs(width);
                    if (std::isfinite(cubic) && cubic >= lo_edge && cubic <= hi_edge) a = cubic;
                }
            }
            if (!(std::abs(a - lo.step) > std::numeric_limits<T>::epsilon() * std::max(T(1), std::abs(lo.step)))) {
                return;  // the bracket has collapsed
            }
            const sample s = evaluate(a);
            if (!armijo(s) || s.value >= lo.value) {
                hi = s;
            } else {
                if (curvature_ok(s)) {
                    keep(s, true);
                    return;
                }
                keep(s, false);
                if (s.slope * (hi.step - lo.step) >= T(0)) hi = lo;
                lo = s;
            }
        }
    };

    sample previous{T(0), value, slope0, true};
    T a = std::min(step, params.max_step);
    while (evaluations < params.max_evaluations) {
        const sample s = evaluate(a);
        if (!armijo(s) || (evaluations > 1 && s.value >= previous.value)) {
            zoom(previous, s);
            break;
        }
        if (curvature_ok(s)) {
            keep(s, true);
            break;
        }
        keep(s, false);
        if (s.slope >= T(0)) {
            zoom(s, previous);
            break;
        }
        previous = s;
        if (a >= params.max_step) break;
        a = std::min(T(4) * a, params.max_step);
    }
    best.evaluations = evaluations;
    return best;
}

}  // namespace anima
