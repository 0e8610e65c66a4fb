// epsilon-SVR: the SMO solution against an independent projected-gradient
// QP on the same dual run to high accuracy, the KKT conditions on every
// training point, a planted smooth non-linear relation recovered within
// epsilon, degenerate data, determinism and save/load.
#include "regress_test_support.hpp"

#include <anima/core/error.hpp>
#include <anima/sadm/regressor.hpp>
#include <anima/sadm/svr_regressor.hpp>

#include <doctest/doctest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using namespace regress_test;
using vec_d = Eigen::VectorXd;
using mat_d = Eigen::MatrixXd;

/// Columns shifted to mean 0 and scaled to population standard deviation 1.
mat_d standardised(const mat_d& m) {
    mat_d s = m.rowwise() - m.colwise().mean();
    for (Eigen::Index c = 0; c < s.cols(); ++c) {
        const double sd = std::sqrt(s.col(c).squaredNorm() / static_cast<double>(s.rows()));
        if (sd > 0) s.col(c) /= sd;
    }
    return s;
}

mat_d rbf(const mat_d& a, const mat_d& b, double gamma) {
    mat_d k(a.rows(), b.rows());
    for (Eigen::Index i = 0; i < a.rows(); ++i)
        for (Eigen::Index j = 0; j < b.rows(); ++j) k(i, j) = std::exp(-gamma * (a.row(i) - b.row(j)).squaredNorm());
    return k;
}

/// The projection onto {0 <= a <= C, sum_{t<n} a_t = sum_{t>=n} a_t}: a =
/// clip(v - mu y) with mu found by bisection (the constraint falls with mu).
vec_d project(const vec_d& v, double c) {
    const Eigen::Index n = v.size() / 2;
    const auto clipped = [&](double mu) {
        vec_d a(v.size());
        for (Eigen::Index t = 0; t < v.size(); ++t) a(t) = std::clamp(v(t) - mu * (t < n ? 1.0 : -1.0), 0.0, c);
        return a;
    };
    const auto balance = [&](double mu) {
        const vec_d a = clipped(mu);
        return a.head(n).sum() - a.tail(n).sum();
    };
    double lo = -v.cwiseAbs().maxCoeff() - c - 1, hi = -lo;
    for (int it = 0; it < 100; ++it) {
        const double mid = (lo + hi) / 2;
        (balance(mid) > 0 ? lo : hi) = mid;
    }
    return clipped((lo + hi) / 2);
}

/// beta of the epsilon-SVR dual by accelerated projected gradient (FISTA),
/// an independent route, run until the iterate stops moving.
vec_d reference_beta(const mat_d& k, const vec_d& z, double c, double epsilon) {
    const Eigen::Index n = z.size();
    mat_d q(2 * n, 2 * n);
    q << k, -k, -k, k;
    vec_d p(2 * n);
    p << epsilon - z.array(), epsilon + z.array();
    const double step = 1.0 / (2.0 * k.selfadjointView<Eigen::Lower>().eigenvalues().maxCoeff());
    vec_d a = vec_d::Zero(2 * n), w = a;
    double t = 1;
    for (int it = 0; it < 100000; ++it) {
        const vec_d next = project(w - step * (q * w + p), c);
        const double t_next = (1 + std::sqrt(1 + 4 * t * t)) / 2;
        w = next + ((t - 1) / t_next) * (next - a);
        const bool still = (next - a).cwiseAbs().maxCoeff() < 1e-15;
        a = next;
        t = t_next;
        if (still) break;
    }
    return a.head(n) - a.tail(n);
}

template <class T>
anima::svr_regressor<T> svr(double c, double epsilon, double gamma, double tolerance, int max_iterations = 100000) {
    typename anima::regressor_options<T>::svr_params p;
    p.c = static_cast<T>(c);
    p.epsilon = static_cast<T>(epsilon);
    p.gamma = static_cast<T>(gamma);
    p.tolerance = static_cast<T>(tolerance);
    p.max_iterations = max_iterations;
    return anima::svr_regressor<T>(p);
}

/// beta per training row (zeros for the rows that are not support vectors).
template <class T>
mat_d full_beta(const anima::svr_regressor<T>& r, Eigen::Index n) {
    mat_d beta = mat_d::Zero(n, r.output_size());
    for (std::size_t s = 0; s < r.support_indices().size(); ++s)
        beta.row(r.support_indices()[s]) = r.coefficients().row(static_cast<Eigen::Index>(s)).template cast<double>();
    return beta;
}

/// Checks the epsilon-SVR KKT conditions of a fit on every training point,
/// in standardised output units: beta = 0 inside the tube, free beta on its
/// edge (the side given by the sign), bounded beta outside, sum beta = 0.
template <class T>
void check_kkt(const anima::svr_regressor<T>& r, const matrix<T>& x, const matrix<T>& y, double slack) {
    const mat_d yd = y.template cast<double>();
    const mat_d z = standardised(yd);
    const mat_d beta = full_beta(r, x.rows());
    const mat_d pred = r.predict(x).template cast<double>();
    const double c = static_cast<double>(r.parameters().c), eps = static_cast<double>(r.parameters().epsilon);
    for (Eigen::Index k = 0; k < y.cols(); ++k) {
        const double sd = std::sqrt((yd.col(k).array() - yd.col(k).mean()).square().mean());
        CHECK(std::abs(beta.col(k).sum()) < 1e-9 * c * static_cast<double>(x.rows()) + slack);
        for (Eigen::Index i = 0; i < x.rows(); ++i) {
            CAPTURE(i);
            const double b = beta(i, k), res = (pred(i, k) - yd(i, k)) / sd - 0 * z(i, k);
            CHECK(std::abs(b) <= c * (1 + 1e-6));
            if (b == 0) CHECK(std::abs(res) <= eps + slack);
            else if (b >= c) CHECK(res <= -eps + slack);
            else if (b <= -c) CHECK(res >= eps - slack);
            else if (b > 0) CHECK(std::abs(res + eps) <= slack);
            else CHECK(std::abs(res - eps) <= slack);
        }
    }
}

TEST_CASE_TEMPLATE("svr: SMO finds the dual optimum an independent projected-gradient QP finds", T, float, double) {
    anima::random_source rng(41);
    const matrix<T> x = random_matrix<T>(rng, 7, 2, 2);
    const matrix<T> y = random_matrix<T>(rng, 7, 2, 3);
    const double c = 2, eps = 0.1, gamma = 0.7;
    auto r = svr<T>(c, eps, gamma, tolerance<T>(1e-11, 1e-5));
    r.fit(x, y);
    CHECK(r.converged());
    CHECK(static_cast<double>(r.gamma()) == doctest::Approx(gamma).epsilon(1e-7));
    const mat_d xs = standardised(x.template cast<double>()), zs = standardised(y.template cast<double>());
    const mat_d k = rbf(xs, xs, gamma);
    const mat_d beta = full_beta(r, 7);
    for (Eigen::Index col = 0; col < 2; ++col) {
        const vec_d reference = reference_beta(k, zs.col(col), c, eps);
        CAPTURE(col);
        CHECK((beta.col(col) - reference).cwiseAbs().maxCoeff() < tolerance<T>(1e-7, 2e-3));
        // The bias from a free support vector of the reference solution.
        for (Eigen::Index i = 0; i < 7; ++i) {
            const double b = reference(i);
            if (std::abs(b) > 1e-4 && std::abs(b) < c - 1e-4) {
                const double bias = zs(i, col) - (k.row(i) * reference)(0) - (b > 0 ? eps : -eps);
                CHECK(static_cast<double>(r.bias()(col)) == doctest::Approx(bias).epsilon(tolerance<T>(1e-6, 2e-3)));
                break;
            }
        }
    }
    check_kkt(r, x, y, tolerance<T>(1e-9, 1e-3));
}

TEST_CASE_TEMPLATE("svr: KKT conditions hold at every training point of a noisy problem", T, float, double) {
    anima::random_source rng(42);
    const matrix<T> x = random_matrix<T>(rng, 90, 4, 3, true);
    matrix<T> y(90, 3);
    for (Eigen::Index i = 0; i < 90; ++i) {
        y(i, 0) = std::sin(x(i, 0)) + static_cast<T>(0.3 * (rng.uniform() - 0.5));
        y(i, 1) = x(i, 1) * x(i, 2) + static_cast<T>(0.3 * (rng.uniform() - 0.5));
        y(i, 2) = static_cast<T>(rng.uniform());  // no relation at all: many bounded multipliers
    }
    for (double c : {0.5, 10.0}) {
        CAPTURE(c);
        const double tol = tolerance<T>(1e-6, 1e-3);
        auto r = svr<T>(c, 0.1, 0, tol);
        r.fit(x, y);
        CHECK(r.converged());
        check_kkt(r, x, y, tol * 1.01 + tolerance<T>(1e-12, 1e-5));
        // Only rows with a non-zero multiplier are kept.
        CHECK(r.support_vectors().rows() == static_cast<Eigen::Index>(r.support_indices().size()));
        CHECK(r.support_vectors().rows() < 90 * 1 + 1);
    }
}

TEST_CASE_TEMPLATE("svr: a planted smooth relation is recovered within epsilon", T, float, double) {
    anima::random_source rng(43);
    const auto truth = [](const matrix<T>& in) {
        matrix<T> out(in.rows(), 2);
        for (Eigen::Index i = 0; i < in.rows(); ++i) {
            out(i, 0) = std::sin(T(2) * in(i, 0)) + T(0.5) * in(i, 1) * in(i, 1);
            out(i, 1) = T(3) - in(i, 0) * in(i, 2) + T(0.2) * in(i, 1);
        }
        return out;
    };
    const matrix<T> x = random_matrix<T>(rng, 160, 3);
    const matrix<T> y = truth(x);
    const double eps = 0.02, tol = tolerance<T>(1e-4, 1e-3);
    auto r = svr<T>(1000, eps, 0, tol);
    r.fit(x, y);
    CHECK(r.converged());
    CHECK(static_cast<double>(r.gamma()) == doctest::Approx(1.0 / 3).epsilon(1e-5));  // 1 / (d * 1)
    // Unbounded multipliers everywhere: every training point lies within the tube.
    CHECK(r.coefficients().cwiseAbs().maxCoeff() < T(1000));
    const mat_d yd = y.template cast<double>();
    const mat_d residual = (r.predict(x).template cast<double>() - yd);
    for (Eigen::Index k = 0; k < 2; ++k) {
        const double sd = std::sqrt((yd.col(k).array() - yd.col(k).mean()).square().mean());
        CHECK(residual.col(k).cwiseAbs().maxCoeff() <= (eps + 1.01 * tol) * sd + tolerance<T>(1e-12, 1e-5));
    }
    // Unseen points inside the training box: close, and far better than linear.
    const matrix<T> fresh = random_matrix<T>(rng, 60, 3, 0.9);
    auto l = anima::linear_regressor<T>();
    l.fit(x, y);
    const double svr_error = relative_difference<T>(r.predict(fresh), truth(fresh));
    CHECK(svr_error < 0.05);
    CHECK(svr_error * 5 < relative_difference<T>(l.predict(fresh), truth(fresh)));
}

TEST_CASE_TEMPLATE("svr: degenerate data", T, float, double) {
    anima::random_source rng(44);
    // One sample, constant outputs, a wide tube: the mean is predicted.
    auto one = svr<T>(1, 0.1, 0, 1e-3);
    one.fit(matrix<T>::Constant(1, 2, T(3)), matrix<T>::Constant(1, 2, T(-4)));
    CHECK(one.support_vectors().rows() == 0);
    CHECK(one.predict(random_matrix<T>(rng, 3, 2)).isApprox(matrix<T>::Constant(3, 2, T(-4))));

    const matrix<T> x = random_matrix<T>(rng, 20, 3);
    auto flat = svr<T>(1, 0.1, 0, 1e-3);
    flat.fit(x, matrix<T>::Constant(20, 1, T(2.5)));
    CHECK(flat.predict(x).isApprox(matrix<T>::Constant(20, 1, T(2.5))));

    // Every input constant or duplicated, outputs conflicting: finite, between the outputs.
    matrix<T> same = matrix<T>::Constant(6, 2, T(1));
    const matrix<T> y = (matrix<T>(6, 1) << 0, 1, 0, 1, 0, 1).finished();
    auto dup = svr<T>(10, 0.01, 0, 1e-4);
    dup.fit(same, y);
    const matrix<T> p = dup.predict(same);
    CHECK(p.allFinite());
    CHECK(p(0, 0) == doctest::Approx(0.5).epsilon(1e-3));

    // A tube wider than the data: no support vector, every point inside.
    auto wide = svr<T>(1, 5, 0, 1e-3);
    const matrix<T> yr = random_matrix<T>(rng, 20, 1);
    wide.fit(x, yr);
    CHECK(wide.support_vectors().rows() == 0);
    CHECK(wide.predict(x).allFinite());
    const T sd = std::sqrt((yr.array() - yr.mean()).square().mean());
    CHECK(static_cast<double>((wide.predict(x) - yr).cwiseAbs().maxCoeff()) <= 5 * static_cast<double>(sd) + 1e-5);

    // An iteration limit stops early, says so, and still predicts finitely.
    auto limited = svr<T>(1000, 0.001, 0, 1e-6, 3);
    limited.fit(x, random_matrix<T>(rng, 20, 1));
    CHECK_FALSE(limited.converged());
    CHECK(limited.iterations().at(0) == 3);
    CHECK(limited.predict(x).allFinite());
}

TEST_CASE_TEMPLATE("svr: bad options are refused, fits are deterministic, save/load is bit-exact", T, float, double) {
    const auto message = [](double c, double eps, double gamma, double tol, int it) {
        return invalid_argument_message([&] { svr<T>(c, eps, gamma, tol, it); });
    };
    CHECK(contains(message(0, 0.1, 0, 1e-3, 10), "anima::svr_regressor: c 0"));
    CHECK(contains(message(1, -0.1, 0, 1e-3, 10), "epsilon -0.1"));
    CHECK(contains(message(1, 0.1, std::numeric_limits<double>::infinity(), 1e-3, 10), "gamma inf"));
    CHECK(contains(message(1, 0.1, 0, 0, 10), "tolerance 0"));
    CHECK(contains(message(1, 0.1, 0, 1e-3, 0), "max_iterations 0"));

    anima::random_source rng(45);
    const matrix<T> x = random_matrix<T>(rng, 50, 5, 4, true), y = random_matrix<T>(rng, 50, 3, 100);
    anima::regressor_options<T> options;
    std::vector<int> reported;
    options.progress = [&](const std::string& stage, int done, int total) {
        CHECK(stage == "svr");
        CHECK(total == 3);
        reported.push_back(done);
    };
    auto a = anima::make_regressor<T>(anima::regressor_kind::svr, options);
    auto b = anima::make_regressor<T>(anima::regressor_kind::svr, options);
    a->fit(x, y);
    b->fit(x, y);
    CHECK(reported == std::vector<int>{1, 2, 3, 1, 2, 3});
    const matrix<T> fresh = random_matrix<T>(rng, 8, 5, 4, true);
    CHECK(a->predict(fresh) == b->predict(fresh));

    std::string text;
    auto back = round_trip(*a, &text);
    CHECK(text.rfind("anima-regressor svr 1\n", 0) == 0);
    CHECK(back->kind() == anima::regressor_kind::svr);
    CHECK(back->predict(fresh) == a->predict(fresh));
    std::string cut = text.substr(0, text.size() / 2);
    CHECK(contains(load_error<T>(cut.substr(0, cut.rfind('\n') + 1)), "file ends"));
    std::string bad_gamma = text;
    bad_gamma.replace(bad_gamma.find("gamma "), 6, "gamma -");
    CHECK(contains(load_error<T>(bad_gamma), "model.txt:5: c and gamma must be > 0"));
}

}  // namespace

TEST_CASE_TEMPLATE("svr and mlp: outputs whose squares overflow are standardised and predicted finitely", T, float,
                   double) {
    anima::random_source rng(45);
    const matrix<T> x = random_matrix<T>(rng, 12, 3);
    const matrix<T> unit = random_matrix<T>(rng, 12, 2);
    // Squared deviations of 1e19 overflow float, of 1e155 double.
    const T big = static_cast<T>(std::is_same_v<T, float> ? 1e19 : 1e155);
    const matrix<T> y = unit * big;
    for (const auto kind : {anima::regressor_kind::svr, anima::regressor_kind::mlp}) {
        CAPTURE(anima::to_string(kind));
        auto scaled = anima::make_regressor<T>(kind);
        scaled->fit(x, y);
        const matrix<T> p = scaled->predict(x);
        REQUIRE(p.allFinite());
        // Standardisation makes the fit scale-free: as the one on unit outputs, times big.
        auto plain = anima::make_regressor<T>(kind);
        plain->fit(x, unit);
        CHECK(relative_difference<T>(matrix<T>(p / big), plain->predict(x)) < 1e-2);
        // A column of the type's largest values but one at the other end:
        // its mean is near the largest, and centring the odd one overflows.
        matrix<T> wide = x;
        wide.col(1).setConstant(std::numeric_limits<T>::max());
        wide(0, 1) = -std::numeric_limits<T>::max();
        CHECK(contains(invalid_argument_message([&] { scaled->fit(wide, y); }),
                       "fit: inputs column 1 spans more than the scalar type holds once centred"));
    }
}
