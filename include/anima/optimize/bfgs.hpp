// Quasi-Newton minimisation: BFGS with a dense inverse-Hessian estimate, or
// L-BFGS (limited memory, two-loop recursion) for many variables. Both use
// the strong-Wolfe line search, so every accepted step lowers the objective.
#pragma once

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <string>

#include <anima/core/check_argument.hpp>
#include <anima/optimize/line_search.hpp>
#include <anima/optimize/result.hpp>

namespace anima {

template <class T>
struct bfgs_params {
    int max_iterations = 200;
    /// Stop when |gradient|_inf <= gradient_tolerance * max(1, |f(x0)|): relative
    /// to the start's value, which (unlike the current one) cannot drift away.
    T gradient_tolerance = detail::default_gradient_tolerance<T>();
    /// Stop when an iteration lowers f by less than value_tolerance * max(1, |f|).
    T value_tolerance = detail::default_value_tolerance<T>();
    /// 0: dense BFGS (n x n memory, best for up to a few hundred variables);
    /// m > 0: L-BFGS keeping the last m steps (O(m n) memory and work).
    int memory = 0;
    wolfe_line_search_params<T> line_search{};
    /// Called after each iteration with its number and f; return false to stop.
    std::function<bool(int iteration, T value)> on_iteration;
};

namespace detail {

// The quasi-Newton direction -H g with H from the stored step pairs
// (Nocedal & Wright, algorithm 7.4), scaled by gamma = s'y / y'y.
template <class T>
struct lbfgs_memory {
    std::deque<vector_x<T>> s, y;
    std::deque<T> rho;
    std::size_t capacity;

    void clear() {
        s.clear();
        y.clear();
        rho.clear();
    }
    void push(vector_x<T> step, vector_x<T> change, T curvature) {
        if (s.size() == capacity) {
            s.pop_front();
            y.pop_front();
            rho.pop_front();
        }
        rho.push_back(T(1) / curvature);
        s.push_back(std::move(step));
        y.push_back(std::move(change));
    }
    vector_x<T> direction(const vector_x<T>& gradient) const {
        vector_x<T> q = -gradient;
        std::vector<T> alpha(s.size());
        for (std::size_t i = s.size(); i-- > 0;) {
            alpha[i] = rho[i] * s[i].dot(q);
            q -= alpha[i] * y[i];
        }
        if (!s.empty()) q *= s.back().dot(y.back()) / y.back().squaredNorm();
        for (std::size_t i = 0; i < s.size(); ++i) {
            const T beta = rho[i] * y[i].dot(q);
            q += (alpha[i] - beta) * s[i];
        }
        return q;
    }
};

}  // namespace detail

namespace detail {

/// The gradient at an iterate whose squared norm overflows (|g| = 1e200 in
/// double) makes every slope and curvature infinite: the line search finds
/// no step and BFGS stalls. `scale`: the power of two the objective was
/// divided by.
template <class T>
void check_gradient_norm(const vector_x<T>& gradient, int iterate, int scale) {
    if (std::isfinite(gradient.squaredNorm())) return;
    const double largest = std::ldexp(static_cast<double>(gradient.template lpNorm<Eigen::Infinity>()), scale);
    throw error("anima::bfgs_minimize: at iterate " + std::to_string(iterate) +
                " the gradient's squared norm overflows the scalar type (largest component " +
                argument_text(largest) + "); scale the objective down");
}

/// The power of two bfgs_minimize divides the objective by: 0 unless the
/// start's gradient has a squared norm past max / 2^16 (huge but finite,
/// where the old iteration stalled), else the exponent of its largest
/// component, which brings that into [0.5, 1). Exact, and no change for a
/// gradient of ordinary size.
template <class T>
int bfgs_scale(const vector_x<T>& gradient) {
    if (gradient.squaredNorm() < std::ldexp(std::numeric_limits<T>::max(), -16)) return 0;
    int e = 0;
    std::frexp(gradient.template lpNorm<Eigen::Infinity>(), &e);
    return e;
}

/// The iterations of bfgs_minimize from the evaluated start in `result`
/// and `gradient` (of the objective divided by 2^scale).
template <class T, class F>
void bfgs_iterate(F&& f, optimize_result<T>& result, vector_x<T>& gradient, const bfgs_params<T>& params, int scale) {
    const Eigen::Index n = gradient.size();
    const bool dense = params.memory == 0;
    matrix_x<T> inverse_hessian;
    detail::lbfgs_memory<T> memory{{}, {}, {}, static_cast<std::size_t>(params.memory)};
    bool identity = true;  // H is still the (scaled) identity
    auto reset = [&] {
        if (dense) inverse_hessian.setIdentity(n, n);
        memory.clear();
        identity = true;
    };
    reset();

    const T gradient_scale = std::max(T(1), std::abs(result.value));
    auto gradient_small = [&] {
        return gradient.template lpNorm<Eigen::Infinity>() <= params.gradient_tolerance * gradient_scale;
    };
    if (gradient_small()) {
        result.status = optimize_status::converged;
        return;
    }

    result.status = optimize_status::max_iterations;
    while (result.iterations < params.max_iterations) {
        vector_x<T> direction = dense ? vector_x<T>(-(inverse_hessian * gradient)) : memory.direction(gradient);
        if (!(gradient.dot(direction) < T(0)) || !direction.allFinite()) {
            reset();
            direction = -gradient;
        }
        // The first step of a steepest-descent direction has no scale yet:
        // move at most one unit along the largest component.
        T step = T(1);
        if (identity) step = std::min(T(1), T(1) / direction.template lpNorm<Eigen::Infinity>());

        auto point = wolfe_line_search(f, result.x, result.value, gradient, direction, step, params.line_search);
        result.evaluations += point.evaluations;
        if (!point.found && !identity) {
            // A stale Hessian estimate can point badly: retry downhill.
            reset();
            direction = -gradient;
            step = std::min(T(1), T(1) / direction.template lpNorm<Eigen::Infinity>());
            point = wolfe_line_search(f, result.x, result.value, gradient, direction, step, params.line_search);
            result.evaluations += point.evaluations;
        }
        ++result.iterations;
        if (!point.found) {
            result.status = optimize_status::stalled;
            break;
        }

        vector_x<T> s = point.x - result.x;
        vector_x<T> y = point.gradient - gradient;
        const T previous = result.value;
        result.x = std::move(point.x);
        result.value = point.value;
        gradient = std::move(point.gradient);
        result.history.push_back(result.value);
        check_gradient_norm(gradient, result.iterations, scale);

        // Update only with positive curvature, which keeps H positive definite.
        const T sy = s.dot(y);
        if (sy > std::numeric_limits<T>::epsilon() * s.norm() * y.norm()) {
            if (dense) {
                if (identity) inverse_hessian *= sy / y.squaredNorm();  // Nocedal & Wright (6.20)
                const T rho = T(1) / sy;
                const vector_x<T> hy = inverse_hessian * y;
                const T yhy = y.dot(hy);
                // H+ = (I - rho s y') H (I - rho y s') + rho s s', expanded.
                inverse_hessian += (rho * rho * yhy + rho) * (s * s.transpose()) -
                                   rho * (hy * s.transpose() + s * hy.transpose());
            } else {
                memory.push(std::move(s), std::move(y), sy);
            }
            identity = false;
        }

        if (params.on_iteration && !params.on_iteration(result.iterations, result.value)) {
            result.status = optimize_status::stopped;
            break;
        }
        if (gradient_small() ||
            previous - result.value <= params.value_tolerance * std::max(T(1), std::abs(result.value))) {
            result.status = optimize_status::converged;
            break;
        }
    }
}

}  // namespace detail

/// Minimises f from x0. F: T(const vector_x<T>& x, vector_x<T>& gradient)
/// returns f(x) and writes its gradient (already sized like x).
/// Throws invalid_argument for an empty or non-finite x0 or bad parameters,
/// anima::error if f or its gradient is not finite at x0. A huge but finite
/// gradient (its squared norm near or past the scalar type's largest) is
/// handled by minimising f / 2^k (exact; the values returned and passed to
/// on_iteration are f's own, the tolerances apply to f / 2^k); one whose
/// squared norm overflows at a later iterate throws anima::error naming
/// the iterate, where the iteration would otherwise stall.
template <class T, class F>
optimize_result<T> bfgs_minimize(F&& f, vector_x<T> x0, const bfgs_params<T>& params = {}) {
    detail::check_start(x0, "anima::bfgs_minimize");
    if (params.max_iterations < 0 || params.memory < 0 || !(params.gradient_tolerance >= T(0)) ||
        !(params.value_tolerance >= T(0))) {
        throw invalid_argument("bfgs_minimize: max_iterations, memory and tolerances must not be negative");
    }
    const Eigen::Index n = x0.size();
    optimize_result<T> result;
    result.x = std::move(x0);
    vector_x<T> gradient(n);
    result.value = f(static_cast<const vector_x<T>&>(result.x), gradient);
    result.evaluations = 1;
    if (!std::isfinite(result.value) || gradient.size() != n || !gradient.allFinite()) {
        throw error("bfgs_minimize: the objective or its gradient is not finite at the start point");
    }
    const int scale = detail::bfgs_scale(gradient);
    if (scale == 0) {
        detail::bfgs_iterate(f, result, gradient, params, 0);
        return result;
    }
    const auto down = [scale](T v) { return std::ldexp(v, -scale); };
    const auto up = [scale](T v) { return std::ldexp(v, scale); };
    result.value = down(result.value);
    gradient = gradient.unaryExpr(down);
    auto scaled = [&](const vector_x<T>& x, vector_x<T>& g) {
        const T value = f(x, g);
        g = g.unaryExpr(down);
        return down(value);
    };
    bfgs_params<T> scaled_params = params;
    if (params.on_iteration)
        scaled_params.on_iteration = [&](int iteration, T value) { return params.on_iteration(iteration, up(value)); };
    detail::bfgs_iterate(scaled, result, gradient, scaled_params, scale);
    result.value = up(result.value);
    for (T& v : result.history) v = up(v);
    return result;
}

}  // namespace anima
