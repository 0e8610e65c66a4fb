// The shared optimisers on two small problems: Levenberg-Marquardt fits the
// decay of a joint's swing amplitude (y = a exp(-b t) + c, noisy samples),
// and L-BFGS minimises a smooth function with a NaN region, from which the
// line search backs off. Exits 1 if either does not converge.
#include <anima/optimize.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

int main() {
    using vec = anima::vector_x<double>;
    using mat = anima::matrix_x<double>;

    // Samples of 1.7 exp(-0.8 t) + 0.3 with a deterministic wobble as noise.
    std::vector<double> t, y;
    for (int i = 0; i < 60; ++i) {
        t.push_back(0.05 * i);
        y.push_back(1.7 * std::exp(-0.8 * t.back()) + 0.3 + 0.01 * std::sin(7.0 * i));
    }
    auto residuals = [&](const vec& p, vec& r, mat* jacobian) {
        r.resize(static_cast<Eigen::Index>(t.size()));
        if (jacobian) jacobian->resize(r.size(), 3);
        for (Eigen::Index i = 0; i < r.size(); ++i) {
            const double e = std::exp(-p[1] * t[static_cast<std::size_t>(i)]);
            r[i] = p[0] * e + p[2] - y[static_cast<std::size_t>(i)];
            if (jacobian) jacobian->row(i) << e, -p[0] * t[static_cast<std::size_t>(i)] * e, 1.0;
        }
    };
    vec start(3);
    start << 1.0, 0.1, 0.0;
    const auto fit = anima::levenberg_marquardt<double>(residuals, start);
    std::printf("fit: a = %.4f, b = %.4f, c = %.4f after %d steps (%s), 0.5|r|^2 = %.3g\n", fit.x[0], fit.x[1],
                fit.x[2], fit.iterations, std::string(anima::to_string(fit.status)).c_str(), fit.value);

    // sum (x_i - log x_i) is NaN for x_i < 0; its minimum is x = 1.
    auto f = [](const vec& x, vec& g) {
        double v = 0;
        for (Eigen::Index i = 0; i < x.size(); ++i) {
            v += x[i] - std::log(x[i]);
            g[i] = 1.0 - 1.0 / x[i];
        }
        return v;
    };
    anima::bfgs_params<double> params;
    params.memory = 5;
    const auto min = anima::bfgs_minimize<double>(f, vec::LinSpaced(20, 0.2, 10.0), params);
    std::printf("minimum: f = %.6f (20 at x = 1) after %d iterations, %d evaluations (%s)\n", min.value,
                min.iterations, min.evaluations, std::string(anima::to_string(min.status)).c_str());
    return fit.converged() && min.converged() ? 0 : 1;
}
