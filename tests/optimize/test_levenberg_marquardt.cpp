// Levenberg-Marquardt against independent solutions: Eigen's QR least
// squares on linear problems, planted parameters of a noise-free curve fit,
// and Eigen's own (MINPACK) Levenberg-Marquardt on a noisy one.
#include <anima/optimize.hpp>

#include <doctest/doctest.h>

#include <Eigen/QR>
#include <cmath>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "../test_support.hpp"
#include "optimize_test_support.hpp"

using anima::matrix_x;
using anima::vector_x;
using anima_test::non_increasing;
using anima_test::tolerance;

namespace {

// y = a exp(-b t) + c sampled at 40 times, optionally with noise.
struct decay_data {
    Eigen::VectorXd t, y;
    decay_data(double a, double b, double c, double noise, unsigned seed) : t(40), y(40) {
        std::mt19937 gen(seed);
        std::normal_distribution<double> normal(0.0, 1.0);
        for (int i = 0; i < 40; ++i) {
            t[i] = 0.1 * i;
            y[i] = a * std::exp(-b * t[i]) + c + noise * normal(gen);
        }
    }
};

template <class T>
auto decay_residuals(const decay_data& data) {
    return [&data](const vector_x<T>& p, vector_x<T>& r, matrix_x<T>* j) {
        const Eigen::Index m = data.t.size();
        r.resize(m);
        if (j) j->resize(m, 3);
        for (Eigen::Index i = 0; i < m; ++i) {
            const T t = T(data.t[i]);
            const T e = std::exp(-p[1] * t);
            r[i] = p[0] * e + p[2] - T(data.y[i]);
            if (j) {
                (*j)(i, 0) = e;
                (*j)(i, 1) = -p[0] * t * e;
                (*j)(i, 2) = T(1);
            }
        }
    };
}

// The same model for Eigen's MINPACK port (double only).
struct eigen_decay_functor {
    using Scalar = double;
    using InputType = Eigen::VectorXd;
    using ValueType = Eigen::VectorXd;
    using JacobianType = Eigen::MatrixXd;
    enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
    const decay_data* data;
    int inputs() const { return 3; }
    int values() const { return int(data->t.size()); }
    int operator()(const Eigen::VectorXd& p, Eigen::VectorXd& r) const {
        for (Eigen::Index i = 0; i < data->t.size(); ++i) {
            r[i] = p[0] * std::exp(-p[1] * data->t[i]) + p[2] - data->y[i];
        }
        return 0;
    }
    int df(const Eigen::VectorXd& p, Eigen::MatrixXd& j) const {
        for (Eigen::Index i = 0; i < data->t.size(); ++i) {
            const double e = std::exp(-p[1] * data->t[i]);
            j(i, 0) = e;
            j(i, 1) = -p[0] * data->t[i] * e;
            j(i, 2) = 1.0;
        }
        return 0;
    }
};

}  // namespace

TEST_CASE_TEMPLATE("levenberg_marquardt solves linear least squares like Eigen's QR", T, float, double) {
    std::mt19937 gen(11);
    std::normal_distribution<double> normal;
    Eigen::MatrixXd a(30, 6);
    Eigen::VectorXd b(30);
    for (int i = 0; i < 30; ++i) {
        b[i] = normal(gen);
        for (int k = 0; k < 6; ++k) a(i, k) = normal(gen);
    }
    const Eigen::VectorXd exact = a.colPivHouseholderQr().solve(b);
    const matrix_x<T> at = a.cast<T>();
    const vector_x<T> bt = b.cast<T>();
    auto residuals = [&](const vector_x<T>& x, vector_x<T>& r, matrix_x<T>* j) {
        r = at * x - bt;
        if (j) *j = at;
    };
    const auto result = anima::levenberg_marquardt<T>(residuals, vector_x<T>::Zero(6));
    CHECK(result.converged());
    CHECK((result.x.template cast<double>() - exact).norm() <= tolerance<T>(1e-9, 1e-4) * exact.norm());
    CHECK(non_increasing(result.history, bt.squaredNorm() / T(2)));
}

TEST_CASE_TEMPLATE("levenberg_marquardt recovers planted curve parameters", T, float, double) {
    const decay_data data(2.5, 1.3, -0.4, 0.0, 1u);
    vector_x<T> x0(3);
    x0 << T(1), T(0.2), T(0);
    const auto result = anima::levenberg_marquardt<T>(decay_residuals<T>(data), x0);
    CHECK(result.converged());
    CHECK(double(result.x[0]) == doctest::Approx(2.5).epsilon(double(tolerance<T>(1e-8, 1e-3))));
    CHECK(double(result.x[1]) == doctest::Approx(1.3).epsilon(double(tolerance<T>(1e-8, 1e-3))));
    CHECK(double(result.x[2]) == doctest::Approx(-0.4).epsilon(double(tolerance<T>(1e-8, 2e-3))));
    // Stopped by the gradient test (|J'r| <= 1e-8 in double): a value of
    // about 1e-18 is where that test holds, parameters exact to 1e-8.
    CHECK(result.value <= tolerance<T>(1e-16, 1e-8));
}

TEST_CASE("levenberg_marquardt agrees with Eigen's MINPACK Levenberg-Marquardt on noisy data") {
    for (unsigned seed = 1; seed <= 5; ++seed) {
        CAPTURE(seed);
        const decay_data data(1.7, 0.8, 0.3, 0.05, seed);
        Eigen::VectorXd x0(3);
        x0 << 1.0, 0.3, 0.0;

        Eigen::VectorXd reference = x0;
        eigen_decay_functor functor{&data};
        Eigen::LevenbergMarquardt<eigen_decay_functor> eigen_lm(functor);
        eigen_lm.parameters.xtol = 1e-14;
        eigen_lm.parameters.ftol = 1e-14;
        eigen_lm.minimize(reference);

        const auto result = anima::levenberg_marquardt<double>(decay_residuals<double>(data), x0);
        CHECK(result.converged());
        CHECK((result.x - reference).norm() <= 1e-7 * reference.norm());
        CHECK(non_increasing(result.history, 1e300));
    }
}

TEST_CASE_TEMPLATE("levenberg_marquardt handles rank deficiency, rejected steps and bad input", T, float, double) {
    SUBCASE("a variable the residuals ignore keeps its value") {
        auto residuals = [](const vector_x<T>& x, vector_x<T>& r, matrix_x<T>* j) {
            r.resize(2);
            r << x[0] - T(3), T(2) * x[0] + T(1);
            if (j) {
                j->setZero(2, 2);
                (*j)(0, 0) = T(1);
                (*j)(1, 0) = T(2);
            }
        };
        vector_x<T> x0(2);
        x0 << T(0), T(5);
        const auto result = anima::levenberg_marquardt<T>(residuals, x0);
        CHECK(result.converged());
        CHECK(double(result.x[0]) == doctest::Approx(0.2).epsilon(double(tolerance<T>(1e-9, 1e-4))));
        CHECK(result.x[1] == T(5));
    }
    SUBCASE("NaN at trial points is a rejected step") {
        // r = log(x) - 1 is NaN for x < 0, where the first Gauss-Newton step from x = 20 lands.
        auto residuals = [](const vector_x<T>& x, vector_x<T>& r, matrix_x<T>* j) {
            r.resize(1);
            r[0] = std::log(x[0]) - T(1);
            if (j) {
                j->resize(1, 1);
                (*j)(0, 0) = T(1) / x[0];
            }
        };
        const auto result = anima::levenberg_marquardt<T>(residuals, vector_x<T>::Constant(1, T(20)));
        CHECK(result.converged());
        // The gradient test (|r / x| <= 1e-8, 1e-4 in float) holds within
        // x^2 times that of e: 7.4e-8 (7.4e-4), 2.7e-8 (2.7e-4) relative.
        CHECK(double(result.x[0]) == doctest::Approx(std::exp(1.0)).epsilon(double(tolerance<T>(3e-8, 3e-4))));
    }
    SUBCASE("zero residual at the start") {
        auto residuals = [](const vector_x<T>& x, vector_x<T>& r, matrix_x<T>* j) {
            r = x;
            if (j) *j = matrix_x<T>::Identity(x.size(), x.size());
        };
        const auto result = anima::levenberg_marquardt<T>(residuals, vector_x<T>::Zero(4));
        CHECK(result.converged());
        CHECK(result.iterations == 0);
    }
    SUBCASE("bad input") {
        auto wrong_jacobian = [](const vector_x<T>&, vector_x<T>& r, matrix_x<T>* j) {
            r = vector_x<T>::Ones(3);
            if (j) j->setZero(2, 2);
        };
        CHECK_THROWS_AS(anima::levenberg_marquardt<T>(wrong_jacobian, vector_x<T>::Zero(2)), anima::error);
        auto nan_residuals = [](const vector_x<T>& x, vector_x<T>& r, matrix_x<T>* j) {
            r = vector_x<T>::Constant(1, std::numeric_limits<T>::quiet_NaN());
            if (j) j->setZero(1, x.size());
        };
        CHECK_THROWS_AS(anima::levenberg_marquardt<T>(nan_residuals, vector_x<T>::Zero(2)), anima::error);
        CHECK_THROWS_WITH_AS(anima::levenberg_marquardt<T>(nan_residuals, vector_x<T>()),
                             "anima::levenberg_marquardt: the start point is empty", anima::invalid_argument);
        anima::levenberg_marquardt_params<T> params;
        params.initial_damping = T(0);
        auto fine = [](const vector_x<T>& x, vector_x<T>& r, matrix_x<T>* j) {
            r = x;
            if (j) *j = matrix_x<T>::Identity(x.size(), x.size());
        };
        CHECK_THROWS_AS(anima::levenberg_marquardt<T>(fine, vector_x<T>::Ones(2), params), anima::invalid_argument);
    }
}

TEST_CASE_TEMPLATE("Levenberg-Marquardt takes the same steps whatever the residuals' scale", T, float, double) {
    // r = c (x - 1): one Gauss-Newton step from anywhere. The damping is
    // relative to J'J's diagonal, so c = 1e5 (float) or 1e8 (double) must
    // converge as c = 1 does; scaled twice, the first step was 1e-7 of the
    // way and the solve ended "converged" at the start.
    const T big = static_cast<T>(std::is_same_v<T, float> ? 1e5 : 1e8);
    for (const T c : {T(1), T(1000), big}) {
        CAPTURE(c);
        const auto r = [c](const vector_x<T>& x, vector_x<T>& res, matrix_x<T>* j) {
            res = c * (x.array() - T(1)).matrix();
            if (j) *j = c * matrix_x<T>::Identity(x.size(), x.size());
        };
        const auto out = anima::levenberg_marquardt<T>(r, vector_x<T>::Constant(2, T(2)));
        CHECK(out.status == anima::optimize_status::converged);
        CHECK((out.x.array() - T(1)).abs().maxCoeff() <= tolerance<T>(1e-9, 1e-4));
        // A few damped Gauss-Newton steps at every scale (the gradient test's
        // floor of 1 on |r|^2 / 2 lets the count differ by one or two);
        // scaled twice, c = 1e7 took 32.
        CHECK(out.iterations <= 6);
    }
}

TEST_CASE_TEMPLATE("Levenberg-Marquardt refuses residuals whose square overflows at the start", T, float, double) {
    // Finite residuals, |r|^2 = inf: the gradient test compared infinities
    // and reported "converged" with the value inf.
    const T huge = static_cast<T>(std::is_same_v<T, float> ? 1e20 : 1e155);
    const auto r = [huge](const vector_x<T>& x, vector_x<T>& res, matrix_x<T>* j) {
        res.resize(2);
        res << huge, x[0];
        if (j) {
            j->setZero(2, 1);
            (*j)(1, 0) = T(1);
        }
    };
    bool threw = false;
    try {
        (void)anima::levenberg_marquardt<T>(r, vector_x<T>::Constant(1, T(2)));
    } catch (const anima::error& e) {
        threw = true;
        CHECK(std::string(e.what()).find("overflow at the start point") != std::string::npos);
    }
    CHECK(threw);
}
