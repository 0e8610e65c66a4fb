// The interface (kinds, argument checks, save/load) and the two least-squares
// mappings: Eq 5 with its ridge against Eigen's QR and SVD least squares on
// the same data (also with fewer samples than inputs and collinear inputs),
// and the second-order polynomial recovering a planted quadratic.
#include "regress_test_support.hpp"

#include <anima/core/error.hpp>
#include <anima/sadm/linear_regressor.hpp>
#include <anima/sadm/polynomial_regressor.hpp>
#include <anima/sadm/regressor.hpp>

#include <doctest/doctest.h>

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>

namespace {

using namespace regress_test;

/// Reference ridge solution: least squares on [Xc; sqrt(lambda) I] W = [Yc; 0]
/// by column-pivoting QR, with lambda as the regressor defines it.
template <class T>
matrix<T> augmented_ridge(const matrix<T>& x, const matrix<T>& y, T ridge) {
    const matrix<T> xc = x.rowwise() - x.colwise().mean();
    const matrix<T> yc = y.rowwise() - y.colwise().mean();
    const T lambda = ridge * xc.squaredNorm() / static_cast<T>(x.cols());
    matrix<T> a(x.rows() + x.cols(), x.cols());
    a << xc, std::sqrt(lambda) * matrix<T>::Identity(x.cols(), x.cols());
    matrix<T> b(x.rows() + x.cols(), y.cols());
    b << yc, matrix<T>::Zero(x.cols(), y.cols());
    return a.colPivHouseholderQr().solve(b);
}

/// Reference minimum-norm least squares: Jacobi SVD in double (independent of
/// the orthogonal decomposition the regressor uses). Float data are solved in
/// double too, with singular values below 1e-5 of the largest taken as zero,
/// as rank decisions on float data should be.
template <class T>
matrix<T> min_norm_solution(const matrix<T>& xc, const matrix<T>& yc) {
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(xc.template cast<double>(), Eigen::ComputeThinU | Eigen::ComputeThinV);
    if (std::is_same_v<T, float>) svd.setThreshold(1e-5);
    return svd.solve(yc.template cast<double>()).template cast<T>();
}

template <class T>
anima::linear_regressor<T> linear(T ridge) {
    typename anima::regressor_options<T>::linear_params p;
    p.ridge = ridge;
    return anima::linear_regressor<T>(p);
}

template <class T>
anima::polynomial_regressor<T> poly2(T ridge) {
    typename anima::regressor_options<T>::poly2_params p;
    p.ridge = ridge;
    return anima::polynomial_regressor<T>(p);
}

// ---------------------------------------------------------------------------
// Kinds and the factory
// ---------------------------------------------------------------------------

TEST_CASE("regressor kinds: names round-trip, unknown names are refused") {
    for (auto k : {anima::regressor_kind::linear, anima::regressor_kind::poly2, anima::regressor_kind::mlp,
                   anima::regressor_kind::svr})
        CHECK(anima::parse_regressor_kind(anima::to_string(k)) == k);
    const std::string message = invalid_argument_message([] { anima::parse_regressor_kind("cubic"); });
    CHECK(contains(message, "parse_regressor_kind"));
    CHECK(contains(message, "'cubic'"));
}

TEST_CASE_TEMPLATE("make_regressor: the kind asked for, options passed on, bad options refused", T, float, double) {
    anima::regressor_options<T> options;
    options.linear.ridge = T(0.25);
    auto r = anima::make_regressor<T>(anima::regressor_kind::linear, options);
    CHECK(r->kind() == anima::regressor_kind::linear);
    CHECK(dynamic_cast<anima::linear_regressor<T>&>(*r).parameters().ridge == T(0.25));
    CHECK(anima::make_regressor<T>(anima::regressor_kind::poly2)->kind() == anima::regressor_kind::poly2);
    CHECK(r->input_size() == 0);
    CHECK(r->output_size() == 0);

    options.linear.ridge = T(-1);
    CHECK(contains(invalid_argument_message([&] { anima::make_regressor<T>(anima::regressor_kind::linear, options); }),
                   "ridge -1"));
    options.poly2.ridge = std::numeric_limits<T>::quiet_NaN();
    CHECK(contains(invalid_argument_message([&] { anima::make_regressor<T>(anima::regressor_kind::poly2, options); }),
                   "ridge"));
}

TEST_CASE_TEMPLATE("fit and predict refuse bad arguments and leave the model as it was", T, float, double) {
    anima::random_source rng(3);
    const matrix<T> x = random_matrix<T>(rng, 10, 3), y = random_matrix<T>(rng, 10, 2);
    for (auto kind : {anima::regressor_kind::linear, anima::regressor_kind::poly2}) {
        CAPTURE(anima::to_string(kind));
        auto r = anima::make_regressor<T>(kind);
        try {
            r->predict(x);
            FAIL("predict before fit did not throw");
        } catch (const anima::invalid_argument&) {
            FAIL("predict before fit is a state error, not a bad argument");
        } catch (const anima::error& e) {
            CHECK(contains(e.what(), "not been fitted"));
        }
        std::ostringstream unsaved;
        CHECK_THROWS_AS(r->save(unsaved), anima::error);

        CHECK(contains(invalid_argument_message([&] { r->fit(matrix<T>(0, 3), matrix<T>(0, 2)); }), "no samples"));
        CHECK(contains(invalid_argument_message([&] { r->fit(x, y.topRows(9)); }), "10 rows but outputs has 9"));
        CHECK(contains(invalid_argument_message([&] { r->fit(x, matrix<T>(10, 0)); }), "outputs has 0 columns"));
        CHECK(contains(invalid_argument_message([&] { r->fit(matrix<T>(10, 0), y); }), "inputs has 0 columns"));
        matrix<T> bad = x;
        bad(4, 1) = std::numeric_limits<T>::infinity();
        CHECK(contains(invalid_argument_message([&] { r->fit(bad, y); }), "inputs(4, 1) is not finite"));
        matrix<T> bad_y = y;
        bad_y(2, 0) = std::numeric_limits<T>::quiet_NaN();
        CHECK(contains(invalid_argument_message([&] { r->fit(x, bad_y); }), "outputs(2, 0) is not finite"));
        CHECK_FALSE(r->fitted());

        r->fit(x, y);
        const matrix<T> before = r->predict(x);
        CHECK_THROWS_AS(r->fit(bad, y), anima::invalid_argument);
        CHECK(r->predict(x) == before);
        CHECK(r->input_size() == 3);
        CHECK(r->output_size() == 2);
        CHECK(contains(invalid_argument_message([&] { r->predict(x.leftCols(2)); }), "2 columns, the model takes 3"));
        CHECK(contains(invalid_argument_message([&] { r->predict(bad); }), "not finite"));
        CHECK(r->predict(matrix<T>(0, 3)).rows() == 0);
    }
}

// ---------------------------------------------------------------------------
// Linear (Eq 5)
// ---------------------------------------------------------------------------

TEST_CASE_TEMPLATE("linear: a planted affine relation is recovered exactly", T, float, double) {
    anima::random_source rng(11);
    const matrix<T> x = random_matrix<T>(rng, 60, 6, 10, true);
    const matrix<T> a = random_matrix<T>(rng, 6, 4, 2);
    const Eigen::Matrix<T, 1, Eigen::Dynamic> b = random_matrix<T>(rng, 1, 4, 5);
    const matrix<T> y = (x * a).rowwise() + b;
    for (T ridge : {T(0), T(1e-12)}) {
        auto r = linear(ridge);
        r.fit(x, y);
        CHECK(relative_difference<T>(r.coefficients(), a) < tolerance<T>(1e-9, 2e-3));
        CHECK(relative_difference<T>(r.intercept(), b) < tolerance<T>(1e-9, 2e-3));
        const matrix<T> fresh = random_matrix<T>(rng, 7, 6, 10);
        CHECK(relative_difference<T>(r.predict(fresh), (fresh * a).rowwise() + b) < tolerance<T>(1e-9, 2e-3));
    }
}

TEST_CASE_TEMPLATE("linear: Eq 5 without ridge equals Eigen's QR least squares with an intercept column", T, float,
                   double) {
    anima::random_source rng(12);
    const matrix<T> x = random_matrix<T>(rng, 80, 8, 3, true);
    const matrix<T> y = random_matrix<T>(rng, 80, 5, 2);  // no relation: pure least squares
    matrix<T> design(80, 9);
    design << matrix<T>::Ones(80, 1), x;
    const matrix<T> reference = design.colPivHouseholderQr().solve(y);
    auto r = linear(T(0));
    r.fit(x, y);
    CHECK(relative_difference<T>(r.intercept(), reference.topRows(1)) < tolerance<T>(1e-10, 1e-3));
    CHECK(relative_difference<T>(r.coefficients(), reference.bottomRows(8)) < tolerance<T>(1e-10, 1e-3));
    // The residual is orthogonal to every column of the design (normal equations).
    const matrix<T> residual = y - r.predict(x);
    CHECK(static_cast<double>((design.transpose() * residual).cwiseAbs().maxCoeff()) < tolerance<T>(1e-10, 2e-3));
}

TEST_CASE_TEMPLATE("linear: the ridge solution equals an augmented QR least squares", T, float, double) {
    anima::random_source rng(13);
    const matrix<T> x = random_matrix<T>(rng, 50, 7, 4, true);
    const matrix<T> y = random_matrix<T>(rng, 50, 3, 1);
    for (T ridge : {T(1e-3), T(0.1), T(10)}) {
        CAPTURE(ridge);
        auto r = linear(ridge);
        r.fit(x, y);
        CHECK(relative_difference<T>(r.coefficients(), augmented_ridge<T>(x, y, ridge)) < tolerance<T>(1e-10, 1e-3));
        // The intercept is not penalised: mean prediction equals mean output.
        CHECK(relative_difference<T>(r.predict(x).colwise().mean(), y.colwise().mean()) < tolerance<T>(1e-12, 1e-5));
    }
    // A larger ridge shrinks the coefficients.
    auto small = linear(T(1e-3)), large = linear(T(10));
    small.fit(x, y);
    large.fit(x, y);
    CHECK(large.coefficients().norm() < small.coefficients().norm());
}

TEST_CASE_TEMPLATE("linear: fewer samples than inputs, minimum norm without ridge, defined with ridge", T, float,
                   double) {
    anima::random_source rng(14);
    const matrix<T> x = random_matrix<T>(rng, 6, 15);
    const matrix<T> y = random_matrix<T>(rng, 6, 4);
    const matrix<T> xc = x.rowwise() - x.colwise().mean();
    const matrix<T> yc = y.rowwise() - y.colwise().mean();
    const matrix<T> min_norm = min_norm_solution<T>(xc, yc);

    auto exact = linear(T(0));
    exact.fit(x, y);
    CHECK(relative_difference<T>(exact.coefficients(), min_norm) < tolerance<T>(1e-9, 2e-3));
    CHECK(relative_difference<T>(exact.predict(x), y) < tolerance<T>(1e-9, 2e-3));  // interpolates

    auto ridged = linear(T(1e-2));
    ridged.fit(x, y);
    CHECK(ridged.coefficients().allFinite());
    CHECK(relative_difference<T>(ridged.coefficients(), augmented_ridge<T>(x, y, T(1e-2))) <
          tolerance<T>(1e-9, 2e-3));
    // As the ridge vanishes the solution tends to the minimum-norm one (in
    // float, down to the rounding of the normal equations, near 1e-6).
    auto tiny = linear(tolerance<T>(1e-9, 1e-5));
    tiny.fit(x, y);
    CHECK(relative_difference<T>(tiny.coefficients(), min_norm) < tolerance<T>(1e-6, 5e-2));
}

TEST_CASE_TEMPLATE("linear: collinear and constant inputs", T, float, double) {
    anima::random_source rng(15);
    matrix<T> x = random_matrix<T>(rng, 40, 5);
    x.col(3) = T(2) * x.col(0) - x.col(1);  // collinear
    x.col(4).setConstant(T(7));             // constant
    const matrix<T> a = random_matrix<T>(rng, 5, 2);
    const matrix<T> y = x * a;
    const matrix<T> xc = x.rowwise() - x.colwise().mean();
    const matrix<T> yc = y.rowwise() - y.colwise().mean();
    const matrix<T> min_norm = min_norm_solution<T>(xc, yc);

    auto exact = linear(T(0));
    exact.fit(x, y);
    CHECK(relative_difference<T>(exact.predict(x), y) < tolerance<T>(1e-10, 1e-4));
    CHECK(relative_difference<T>(exact.coefficients(), min_norm) < tolerance<T>(1e-9, 1e-3));
    CHECK(std::abs(static_cast<double>(exact.coefficients().row(4).cwiseAbs().maxCoeff())) <
          tolerance<T>(1e-12, 1e-5));  // no weight on a constant column

    auto ridged = linear(T(1e-6));
    ridged.fit(x, y);
    CHECK(relative_difference<T>(ridged.predict(x), y) < tolerance<T>(1e-5, 2e-3));
    CHECK(ridged.coefficients().allFinite());

    // Every input constant: the fit is the output mean.
    const matrix<T> flat = matrix<T>::Constant(10, 3, T(2));
    const matrix<T> out = random_matrix<T>(rng, 10, 2);
    for (T ridge : {T(0), T(1)}) {
        auto r = linear(ridge);
        r.fit(flat, out);
        CHECK(relative_difference<T>(r.predict(flat.topRows(1)), out.colwise().mean()) < tolerance<T>(1e-14, 1e-6));
    }
    // One sample: predicts it everywhere.
    auto one = linear(T(0));
    one.fit(x.topRows(1), y.topRows(1));
    CHECK(relative_difference<T>(one.predict(x.bottomRows(3)), y.topRows(1).replicate(3, 1)) <
          tolerance<T>(1e-14, 1e-6));
}

// ---------------------------------------------------------------------------
// Second-order polynomial
// ---------------------------------------------------------------------------

TEST_CASE_TEMPLATE("poly2: the monomials in their documented order", T, float, double) {
    matrix<T> x(2, 3);
    x << 1, 2, 3, -1, 0.5, 4;
    const matrix<T> f = anima::poly2_features<T>(x);
    REQUIRE(f.cols() == anima::poly2_feature_count(3));
    REQUIRE(f.cols() == 9);
    for (Eigen::Index r = 0; r < 2; ++r) {
        Eigen::Index k = 0;
        for (Eigen::Index i = 0; i < 3; ++i) CHECK(f(r, k++) == x(r, i));
        for (Eigen::Index i = 0; i < 3; ++i)
            for (Eigen::Index j = i; j < 3; ++j) CHECK(f(r, k++) == x(r, i) * x(r, j));
    }
}

TEST_CASE_TEMPLATE("poly2: a planted quadratic is recovered on unseen inputs", T, float, double) {
    anima::random_source rng(21);
    const Eigen::Index d = 5, m = 3;
    const matrix<T> x = random_matrix<T>(rng, 120, d, 6, true);
    const matrix<T> lin = random_matrix<T>(rng, d, m);
    const matrix<T> c = random_matrix<T>(rng, 1, m, 3);
    std::vector<matrix<T>> quad;
    for (Eigen::Index k = 0; k < m; ++k) quad.push_back(random_matrix<T>(rng, d, d));
    const auto truth = [&](const matrix<T>& in) {
        matrix<T> out = (in * lin).rowwise() + Eigen::Matrix<T, 1, Eigen::Dynamic>(c);
        for (Eigen::Index k = 0; k < m; ++k)
            out.col(k) += ((in * quad[static_cast<std::size_t>(k)]).cwiseProduct(in)).rowwise().sum();
        return out;
    };
    const matrix<T> y = truth(x);
    auto r = poly2(T(0));
    r.fit(x, y);
    const matrix<T> fresh = random_matrix<T>(rng, 30, d, 6, true);
    CHECK(relative_difference<T>(r.predict(fresh), truth(fresh)) < tolerance<T>(1e-8, 2e-3));
    CHECK(relative_difference<T>(r.predict(x), y) < tolerance<T>(1e-8, 2e-3));

    // The linear mapping cannot represent it: its training error is far larger.
    auto l = linear(T(0));
    l.fit(x, y);
    CHECK(relative_difference<T>(l.predict(x), y) > 100 * relative_difference<T>(r.predict(x), y));

    // A tiny ridge changes little, a strong one shrinks towards the mean.
    auto ridged = poly2(T(1e-10));
    ridged.fit(x, y);
    CHECK(relative_difference<T>(ridged.predict(fresh), truth(fresh)) < tolerance<T>(1e-5, 5e-3));
}

TEST_CASE_TEMPLATE("poly2: equals the linear least squares on explicit monomials of the standardised inputs", T,
                   float, double) {
    anima::random_source rng(22);
    const matrix<T> x = random_matrix<T>(rng, 70, 4, 5, true);
    const matrix<T> y = random_matrix<T>(rng, 70, 2);
    const matrix<T> z = (x.rowwise() - x.colwise().mean()).array().rowwise() /
                        ((x.rowwise() - x.colwise().mean()).colwise().norm().array() / std::sqrt(T(70)));
    const T ridge = T(0.05);
    const matrix<T> reference = augmented_ridge<T>(anima::poly2_features<T>(z), y, ridge);
    auto r = poly2(ridge);
    r.fit(x, y);
    CHECK(relative_difference<T>(r.coefficients(), reference) < tolerance<T>(1e-10, 1e-3));
}

TEST_CASE_TEMPLATE("poly2: more monomials than samples and a constant input stay finite", T, float, double) {
    anima::random_source rng(23);
    matrix<T> x = random_matrix<T>(rng, 12, 6);  // 27 monomials, 12 samples
    x.col(2).setConstant(T(-3));
    const matrix<T> y = random_matrix<T>(rng, 12, 2);
    auto exact = poly2(T(0));
    exact.fit(x, y);
    CHECK(exact.coefficients().allFinite());
    CHECK(relative_difference<T>(exact.predict(x), y) < tolerance<T>(1e-9, 2e-3));  // interpolates
    auto ridged = poly2(T(1e-4));
    ridged.fit(x, y);
    CHECK(ridged.coefficients().allFinite());
    CHECK(relative_difference<T>(ridged.predict(x), y) < 1e-2);
    CHECK(relative_difference<T>(ridged.predict(x), y) > relative_difference<T>(exact.predict(x), y));
}

// ---------------------------------------------------------------------------
// Save and load
// ---------------------------------------------------------------------------

TEST_CASE_TEMPLATE("save/load: linear and poly2 predict bit for bit after a round trip", T, float, double) {
    anima::random_source rng(31);
    const matrix<T> x = random_matrix<T>(rng, 40, 4, 3, true), y = random_matrix<T>(rng, 40, 3, 1e3);
    const matrix<T> fresh = random_matrix<T>(rng, 9, 4, 3, true);
    for (auto kind : {anima::regressor_kind::linear, anima::regressor_kind::poly2}) {
        CAPTURE(anima::to_string(kind));
        auto r = anima::make_regressor<T>(kind);
        r->fit(x, y);
        std::string text;
        auto back = round_trip(*r, &text);
        CHECK(text.rfind("anima-regressor " + std::string(anima::to_string(kind)) + " 1\n", 0) == 0);
        CHECK(back->kind() == kind);
        CHECK(back->input_size() == 4);
        CHECK(back->output_size() == 3);
        CHECK(back->predict(fresh) == r->predict(fresh));
        // Saving again gives the same text.
        std::ostringstream again;
        back->save(again);
        CHECK(again.str() == text);
    }
}

TEST_CASE_TEMPLATE("load: errors name the line", T, float, double) {
    anima::random_source rng(32);
    auto r = anima::make_regressor<T>(anima::regressor_kind::linear);
    r->fit(random_matrix<T>(rng, 10, 2), random_matrix<T>(rng, 10, 2));
    std::string text;
    round_trip(*r, &text);
    // text: 1 header, 2 sizes, 3 ridge, 4 intercept, 5 "coefficients 2 2", 6-7 rows
    CHECK(load_error<T>("") == "model.txt:1: file ends where 'anima-regressor' was expected");
    CHECK(contains(load_error<T>("hello\n"), "model.txt:1: not a saved regressor"));
    CHECK(contains(load_error<T>("anima-regressor cubic 1\n"), "model.txt:1: unknown regressor kind 'cubic'"));
    CHECK(contains(load_error<T>("anima-regressor linear 2\n"), "model.txt:1: unsupported regressor format"));
    CHECK(contains(load_error<T>(text.substr(0, text.rfind('\n', text.size() - 2) + 1)),
                   "model.txt:7: file ends"));
    std::string bad_number = text;
    bad_number.replace(bad_number.find("intercept ") + 10, 1, "x");
    CHECK(contains(load_error<T>(bad_number), "model.txt:4: bad intercept value"));
    std::string nan_value = text;
    nan_value.replace(nan_value.find("ridge "), nan_value.find('\n', nan_value.find("ridge ")) - nan_value.find("ridge "),
                      "ridge nan");
    CHECK(contains(load_error<T>(nan_value), "model.txt:3: bad ridge value 'nan'"));
    std::string wrong_shape = text;
    wrong_shape.replace(wrong_shape.find("coefficients 2 2"), 16, "coefficients 3 2");
    CHECK(contains(load_error<T>(wrong_shape), "model.txt:5: 'coefficients' is 3 x 2, expected 2 x 2"));
    std::string wrong_key = text;
    wrong_key.replace(wrong_key.find("sizes"), 5, "sises");
    CHECK(contains(load_error<T>(wrong_key), "model.txt:2: expected 'sizes', found 'sises'"));
    CHECK(contains(load_error<T>("anima-regressor linear 1\nsizes 0 2\n"), "model.txt:2: 'sizes' must be positive"));
}

}  // namespace
