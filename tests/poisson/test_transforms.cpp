// The FFT and the real-to-real transforms of the fast Poisson solver,
// against the defining sums evaluated directly in long double: every path
// (radix 2/3/4/5, a generic prime radix, Bluestein) and both column
// packings, in float and double.
#include "../test_support.hpp"

#include <anima/core/error.hpp>
#include <anima/poisson/fft.hpp>
#include <anima/poisson/real_transforms.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <cmath>
#include <complex>
#include <cstddef>
#include <random>
#include <vector>

namespace {

constexpr long double pi_l = 3.141592653589793238462643383279502884L;

template <class T>
std::vector<std::complex<T>> random_complex(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<std::complex<T>> x(n);
    for (auto& z : x) z = std::complex<T>(static_cast<T>(u(rng)), static_cast<T>(u(rng)));
    return x;
}

template <class T>
std::vector<std::complex<long double>> naive_dft(const std::vector<std::complex<T>>& x, int sign) {
    const std::size_t n = x.size();
    std::vector<std::complex<long double>> root(n), y(n);
    for (std::size_t m = 0; m < n; ++m) {
        const long double a = sign * 2 * pi_l * static_cast<long double>(m) / static_cast<long double>(n);
        root[m] = {std::cos(a), std::sin(a)};
    }
    for (std::size_t k = 0; k < n; ++k) {
        std::complex<long double> s = 0;
        for (std::size_t j = 0; j < n; ++j) s += std::complex<long double>(x[j].real(), x[j].imag()) * root[(j * k) % n];
        y[k] = s;
    }
    return y;
}

template <class T>
double max_relative_error(const std::vector<std::complex<T>>& got, const std::vector<std::complex<long double>>& want) {
    long double err = 0, scale = 0;
    for (std::size_t k = 0; k < got.size(); ++k) {
        err = std::max(err, std::abs(std::complex<long double>(got[k].real(), got[k].imag()) - want[k]));
        scale = std::max(scale, std::abs(want[k]));
    }
    return static_cast<double>(err / (scale > 0 ? scale : 1));
}

// Direct evaluation of the FFTW-convention definitions.
template <class T>
Eigen::Matrix<long double, Eigen::Dynamic, 1> naive_r2r(anima::real_transform_kind kind,
                                                        const Eigen::Matrix<T, Eigen::Dynamic, 1>& x) {
    const auto n = x.size();
    Eigen::Matrix<long double, Eigen::Dynamic, 1> y(n);
    const long double N = static_cast<long double>(n);
    for (Eigen::Index k = 0; k < n; ++k) {
        long double s = 0;
        for (Eigen::Index j = 0; j < n; ++j) {
            const long double xj = x[j], jl = static_cast<long double>(j), kl = static_cast<long double>(k);
            switch (kind) {
                case anima::real_transform_kind::dst1: s += 2 * xj * std::sin(pi_l * (jl + 1) * (kl + 1) / (N + 1)); break;
                case anima::real_transform_kind::dct2: s += 2 * xj * std::cos(pi_l * (jl + 0.5L) * kl / N); break;
                case anima::real_transform_kind::dct3:
                    s += j == 0 ? xj : 2 * xj * std::cos(pi_l * jl * (kl + 0.5L) / N);
                    break;
            }
        }
        y[k] = s;
    }
    return y;
}

template <class T>
constexpr double tolerance() {
    return std::is_same<T, float>::value ? 2e-5 : 1e-13;
}

}  // namespace

TEST_CASE_TEMPLATE("fft_plan matches the direct DFT for every kind of length", T, float, double) {
    // Powers of two, 3/5-smooth, a generic prime radix (7, 11, 13, 41, 97),
    // and lengths with a prime factor above 97 (Bluestein: 101, 2 * 257).
    const std::size_t lengths[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 15, 16, 25, 30, 32, 41, 60,
                                   64, 97, 101, 128, 194, 243, 250, 256, 514, 1000, 1024, 4100};
    for (std::size_t n : lengths) {
        CAPTURE(n);
        const anima::fft_plan<T> plan(n);
        CHECK(plan.size() == n);
        CHECK(plan.uses_bluestein() == (n == 101 || n == 514));
        const auto x = random_complex<T>(n, static_cast<unsigned>(n));
        const double tol = tolerance<T>() * (1 + std::log2(static_cast<double>(n)));
        // The quadratic reference at n = 4100 is most of this test's time
        // under the sanitizers; there the round trip below runs its path.
        if (!anima_test::sanitized_build || n < 4096) {
            CHECK(max_relative_error(plan.forward(x), naive_dft(x, -1)) < tol);
            CHECK(max_relative_error(plan.inverse(x), naive_dft(x, +1)) < tol);
        }
        // inverse(forward(x)) = n x
        auto back = plan.inverse(plan.forward(x));
        for (auto& z : back) z /= static_cast<T>(n);
        std::vector<std::complex<long double>> xl(n);
        for (std::size_t k = 0; k < n; ++k) xl[k] = {x[k].real(), x[k].imag()};
        CHECK(max_relative_error(back, xl) < tol);
    }
}

TEST_CASE("fft_plan factors lengths into small radices") {
    CHECK(anima::fft_plan<double>(64).radices() == std::vector<std::size_t>{4, 4, 4});
    CHECK(anima::fft_plan<double>(8).radices() == std::vector<std::size_t>{4, 2});
    CHECK(anima::fft_plan<double>(4100).radices() == std::vector<std::size_t>{4, 5, 5, 41});
    CHECK(anima::fft_plan<double>(2 * 257).uses_bluestein());
}

TEST_CASE("fft_plan rejects bad lengths") {
    CHECK_THROWS_AS(anima::fft_plan<double>(0), anima::invalid_argument);
    const anima::fft_plan<double> plan(8);
    CHECK_THROWS_WITH_AS(plan.forward(std::vector<std::complex<double>>(7)), doctest::Contains("anima::fft_plan::forward"),
                         anima::invalid_argument);
}

TEST_CASE_TEMPLATE("real transforms match their definitions", T, float, double) {
    using anima::real_transform_kind;
    using vec = Eigen::Matrix<T, Eigen::Dynamic, 1>;
    using mat = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (auto kind : {real_transform_kind::dst1, real_transform_kind::dct2, real_transform_kind::dct3}) {
        for (Eigen::Index n : {1, 2, 3, 4, 5, 7, 8, 16, 17, 31, 50, 100, 101, 127, 256}) {
            CAPTURE(anima::to_string(kind));
            CAPTURE(n);
            const anima::real_transform<T> tr(kind, n);
            // Three columns: one packed pair and one column alone.
            mat m(n, 3);
            for (Eigen::Index j = 0; j < 3; ++j)
                for (Eigen::Index i = 0; i < n; ++i) m(i, j) = static_cast<T>(u(rng));
            mat y = m;
            tr.apply_columns(y);
            for (Eigen::Index j = 0; j < 3; ++j) {
                const auto want = naive_r2r<T>(kind, vec(m.col(j)));
                const long double scale = std::max(1.0L, want.cwiseAbs().maxCoeff());
                const long double err = (y.col(j).template cast<long double>() - want).cwiseAbs().maxCoeff();
                CHECK(static_cast<double>(err / scale) < tolerance<T>() * 4 * (1 + std::log2(static_cast<double>(n) + 1)));
            }
            // A single column goes through the unpacked path.
            const vec single = tr(vec(m.col(1)));
            CHECK((single - y.col(1)).cwiseAbs().maxCoeff() < T(tolerance<T>() * 100 * static_cast<double>(n)));
        }
    }
}

TEST_CASE("a small column keeps its accuracy next to a large one") {
    // Two columns share one FFT; the second is rescaled to the first's
    // magnitude first, or it would inherit the large one's rounding error.
    using anima::real_transform_kind;
    for (auto kind : {real_transform_kind::dst1, real_transform_kind::dct2, real_transform_kind::dct3}) {
        CAPTURE(anima::to_string(kind));
        const Eigen::Index n = 300;
        Eigen::MatrixXf m = Eigen::MatrixXf::Random(n, 2);
        m.col(0) *= 1e6f;
        m.col(1) *= 1e-3f;
        Eigen::MatrixXf y = m;
        anima::real_transform<float>(kind, n).apply_columns(y);
        Eigen::MatrixXd yd = m.cast<double>();
        anima::real_transform<double>(kind, n).apply_columns(yd);
        for (Eigen::Index j = 0; j < 2; ++j)
            CHECK((y.col(j).cast<double>() - yd.col(j)).norm() / yd.col(j).norm() < 1e-6);
    }
}

TEST_CASE("real transforms invert as documented") {
    using anima::real_transform_kind;
    for (Eigen::Index n : {1, 6, 63, 64, 65, 200}) {
        CAPTURE(n);
        const Eigen::MatrixXd x = Eigen::MatrixXd::Random(n, 5);
        Eigen::MatrixXd y = x;
        anima::real_transform<double> s(real_transform_kind::dst1, n);
        s.apply_columns(y);
        s.apply_columns(y);
        CHECK((y / (2.0 * static_cast<double>(n + 1)) - x).cwiseAbs().maxCoeff() < 1e-12);
        y = x;
        anima::real_transform<double>(real_transform_kind::dct2, n).apply_columns(y);
        anima::real_transform<double>(real_transform_kind::dct3, n).apply_columns(y);
        CHECK((y / (2.0 * static_cast<double>(n)) - x).cwiseAbs().maxCoeff() < 1e-12);
    }
}

TEST_CASE("real_transform rejects bad sizes") {
    CHECK_THROWS_AS(anima::real_transform<double>(anima::real_transform_kind::dst1, 0), anima::invalid_argument);
    const anima::real_transform<double> tr(anima::real_transform_kind::dct2, 8);
    Eigen::MatrixXd m(7, 2);
    CHECK_THROWS_WITH_AS(tr.apply_columns(m), doctest::Contains("has 7 rows"), anima::invalid_argument);
}
