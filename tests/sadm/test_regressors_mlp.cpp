// The neural-network mapping: back-propagation against central differences,
// planted linear and quadratic relations recovered on unseen inputs, a
// monotone training history, seeded determinism, options and save/load.
#include "regress_test_support.hpp"

#include <anima/core/error.hpp>
#include <anima/optimize/numeric_derivatives.hpp>
#include <anima/sadm/detail/regress_mlp_network.hpp>
#include <anima/sadm/mlp_regressor.hpp>
#include <anima/sadm/regressor.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace regress_test;

template <class T>
anima::mlp_regressor<T> mlp(std::vector<int> hidden, double decay, int iterations, std::uint64_t seed = 1) {
    typename anima::regressor_options<T>::mlp_params p;
    p.hidden = std::move(hidden);
    p.weight_decay = static_cast<T>(decay);
    p.max_iterations = iterations;
    p.seed = seed;
    return anima::mlp_regressor<T>(p);
}

TEST_CASE_TEMPLATE("mlp: back-propagation agrees with central differences", T, float, double) {
    anima::random_source rng(51);
    const matrix<T> x = random_matrix<T>(rng, 9, 3), y = random_matrix<T>(rng, 9, 2);
    for (const std::vector<int>& sizes : {std::vector<int>{3, 5, 2}, std::vector<int>{3, 4, 3, 2}}) {
        CAPTURE(sizes.size());
        auto net = anima::detail::mlp_network<T>::initial(sizes, 7);
        anima::vector_x<T> theta = net.pack();
        for (Eigen::Index i = 0; i < theta.size(); ++i) theta(i) += static_cast<T>(0.3 * (rng.uniform() - 0.5));
        anima::detail::mlp_objective<T> objective(net, x, y, T(0.01));
        anima::vector_x<T> gradient(theta.size());
        const T value = objective(theta, gradient);
        CHECK(value == doctest::Approx(static_cast<double>(objective.value(theta))));
        const anima::vector_x<T> numeric =
            anima::numeric_gradient<T>([&](const anima::vector_x<T>& t) { return objective.value(t); }, theta);
        CHECK(static_cast<double>((gradient - numeric).cwiseAbs().maxCoeff()) <
              tolerance<T>(1e-8, 2e-3) * std::max(1.0, static_cast<double>(numeric.cwiseAbs().maxCoeff())));
        // pack and unpack are inverse.
        net.unpack(theta);
        CHECK(net.pack() == theta);
    }
}

TEST_CASE_TEMPLATE("mlp: the objective's value is the documented one", T, float, double) {
    // One hidden unit, fixed weights: f(x) = w2 tanh(w1 x + b1) + b2.
    auto net = anima::detail::mlp_network<T>::initial({1, 1, 1}, 1);
    net.weights[0](0, 0) = T(0.5);
    net.biases[0](0) = T(0.1);
    net.weights[1](0, 0) = T(2);
    net.biases[1](0) = T(-1);
    const matrix<T> x = (matrix<T>(2, 1) << 1, -2).finished(), y = (matrix<T>(2, 1) << 0, 1).finished();
    anima::detail::mlp_objective<T> objective(net, x, y, T(0.1));
    double expected = 0;
    for (int i = 0; i < 2; ++i) {
        const double f = 2 * std::tanh(0.5 * static_cast<double>(x(i, 0)) + 0.1) - 1;
        expected += (f - static_cast<double>(y(i, 0))) * (f - static_cast<double>(y(i, 0))) / 4;
    }
    expected += 0.05 * (0.25 + 4);
    CHECK(static_cast<double>(objective.value(net.pack())) == doctest::Approx(expected).epsilon(1e-6));
    CHECK(net.evaluate(x)(1, 0) == doctest::Approx(2 * std::tanh(-0.9) - 1).epsilon(1e-6));
}

TEST_CASE_TEMPLATE("mlp: planted linear and quadratic relations are recovered on unseen inputs", T, float, double) {
    anima::random_source rng(52);
    const matrix<T> x = random_matrix<T>(rng, 200, 3);
    const matrix<T> fresh = random_matrix<T>(rng, 50, 3, 0.9);
    const matrix<T> a = random_matrix<T>(rng, 3, 2, 2);
    const auto linear_truth = [&](const matrix<T>& in) { return matrix<T>((in * a).array() + T(1)); };
    const auto quadratic_truth = [](const matrix<T>& in) {
        matrix<T> out(in.rows(), 2);
        out.col(0) = in.col(0).cwiseProduct(in.col(1)) + in.col(2);
        out.col(1) = in.col(0).array().square() - T(0.5) * in.col(1).array() + T(2);
        return out;
    };
    // Under the sanitizers every path runs with a tenth of the iterations and
    // the accuracy, which needs them all, is left to the optimised build.
    const bool fit_fully = !anima_test::sanitized_build;
    const int steps = fit_fully ? 10 : 1;
    auto lin = mlp<T>({8}, 0, 40 * steps);
    lin.fit(x, linear_truth(x));
    if (fit_fully) CHECK(relative_difference<T>(lin.predict(fresh), linear_truth(fresh)) < tolerance<T>(5e-3, 2e-2));

    auto quad = mlp<T>({16}, 0, 150 * steps);
    const matrix<T> y = quadratic_truth(x);
    quad.fit(x, y);
    if (fit_fully) CHECK(relative_difference<T>(quad.predict(fresh), quadratic_truth(fresh)) < tolerance<T>(2e-2, 5e-2));
    // The linear mapping cannot represent the quadratic: the network is far closer.
    anima::linear_regressor<T> l;
    l.fit(x, y);
    if (fit_fully) CHECK(5 * relative_difference<T>(quad.predict(fresh), quadratic_truth(fresh)) <
          relative_difference<T>(l.predict(fresh), quadratic_truth(fresh)));

    // Two hidden layers also fit it.
    auto deep = mlp<T>({10, 10}, 0, 150 * steps);
    deep.fit(x, y);
    if (fit_fully) CHECK(relative_difference<T>(deep.predict(fresh), quadratic_truth(fresh)) < tolerance<T>(3e-2, 6e-2));
}

TEST_CASE_TEMPLATE("mlp: training lowers the loss, weight decay shrinks, progress is reported", T, float, double) {
    anima::random_source rng(53);
    const matrix<T> x = random_matrix<T>(rng, 60, 4, 5, true), y = random_matrix<T>(rng, 60, 3, 2);
    const matrix<T> xs = (x.rowwise() - x.colwise().mean());
    auto start = anima::detail::mlp_network<T>::initial({4, 6, 3}, 1);
    std::vector<int> seen;
    anima::regressor_options<T> options;
    options.mlp.hidden = {6};
    options.mlp.max_iterations = 30;
    options.progress = [&](const std::string& stage, int done, int total) {
        CHECK(stage == "mlp");
        CHECK(total == 30);
        seen.push_back(done);
    };
    auto r = anima::make_regressor<T>(anima::regressor_kind::mlp, options);
    r->fit(x, y);
    const auto& fitted = dynamic_cast<const anima::mlp_regressor<T>&>(*r);
    REQUIRE_FALSE(seen.empty());
    CHECK(seen.front() == 1);
    CHECK(static_cast<int>(seen.size()) == fitted.iterations());
    CHECK(fitted.iterations() <= 30);
    // The loss at the seeded start is higher than after training.
    const matrix<T> z = (y.rowwise() - y.colwise().mean());
    CHECK(fitted.training_loss() < T(0.5) * z.squaredNorm() / T(60));

    auto loose = mlp<T>({6}, 0, 200), tight = mlp<T>({6}, 1, 200);
    loose.fit(x, y);
    tight.fit(x, y);
    CHECK(loose.training_loss() < tight.training_loss());
    const matrix<T> xf = random_matrix<T>(rng, 10, 4, 5, true);
    // Strong decay pulls the output towards the mean.
    CHECK((tight.predict(xf).rowwise() - y.colwise().mean()).norm() <
          (loose.predict(xf).rowwise() - y.colwise().mean()).norm());
}

TEST_CASE_TEMPLATE("mlp: deterministic by seed, options checked, degenerate data, save/load", T, float, double) {
    anima::random_source rng(54);
    const matrix<T> x = random_matrix<T>(rng, 40, 3), y = random_matrix<T>(rng, 40, 2, 10);
    const matrix<T> fresh = random_matrix<T>(rng, 6, 3);
    auto a = mlp<T>({5}, 1e-3, 50, 9), b = mlp<T>({5}, 1e-3, 50, 9), c = mlp<T>({5}, 1e-3, 50, 10);
    a.fit(x, y);
    b.fit(x, y);
    c.fit(x, y);
    CHECK(a.predict(fresh) == b.predict(fresh));
    CHECK(a.predict(fresh) != c.predict(fresh));

    CHECK(contains(invalid_argument_message([] { mlp<T>({}, 0, 10); }), "hidden has 0 layers"));
    CHECK(contains(invalid_argument_message([] { mlp<T>({3, 3, 3}, 0, 10); }), "hidden has 3 layers"));
    CHECK(contains(invalid_argument_message([] { mlp<T>({0}, 0, 10); }), "hidden layer size 0"));
    CHECK(contains(invalid_argument_message([] { mlp<T>({3}, -1, 10); }), "weight_decay -1"));
    CHECK(contains(invalid_argument_message([] { mlp<T>({3}, 0, 0); }), "max_iterations 0"));

    // Constant outputs: the mean is predicted; one sample: that sample.
    auto flat = mlp<T>({4}, 1e-3, 50);
    flat.fit(x, matrix<T>::Constant(40, 2, T(-3)));
    CHECK(relative_difference<T>(flat.predict(fresh), matrix<T>::Constant(6, 2, T(-3))) < 1e-5);
    auto one = mlp<T>({4}, 1e-3, 50);
    one.fit(x.topRows(1), y.topRows(1));
    CHECK(relative_difference<T>(one.predict(fresh), y.topRows(1).replicate(6, 1)) < 1e-5);

    auto deep = mlp<T>({4, 3}, 1e-3, 20);
    deep.fit(x, y);
    for (const anima::mlp_regressor<T>* r : {&a, &deep}) {
        std::string text;
        auto back = round_trip(*r, &text);
        CHECK(text.rfind("anima-regressor mlp 1\n", 0) == 0);
        CHECK(back->kind() == anima::regressor_kind::mlp);
        CHECK(back->predict(fresh) == r->predict(fresh));
    }
    std::string text;
    round_trip(a, &text);
    std::string bad = text;
    bad.replace(bad.find("hidden 5"), 8, "hidden 0");
    CHECK(contains(load_error<T>(bad), "model.txt:3: a hidden layer size must be positive"));
    std::string wrong = text;
    wrong.replace(wrong.find("weights 5 3"), 11, "weights 4 3");
    CHECK(contains(load_error<T>(wrong), "'weights' is 4 x 3, expected 5 x 3"));
}

}  // namespace
