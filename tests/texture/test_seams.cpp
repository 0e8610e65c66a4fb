// The parts of a seam: the C1 fade weight (Eq 12 as the spec reads it),
// the Eq 8-9 costs and their capacity policies, the overlap search against
// a brute-force triple loop and a planted best offset, and the (row x
// frame) min-cut against exhaustive enumeration of every labelling of
// small lattices.
#include "texture_test_support.hpp"

#include <anima/core/error.hpp>
#include <anima/core/random.hpp>
#include <anima/maxflow/capacity.hpp>
#include <anima/motion/frame_distance.hpp>
#include <anima/texture/overlap_search.hpp>
#include <anima/texture/seam_blend.hpp>
#include <anima/texture/seam_cost.hpp>
#include <anima/texture/seam_cut.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace texture_test;

template <class T>
matrix<T> random_matrix(anima::random_source& rng, Eigen::Index rows, Eigen::Index cols, double scale = 1) {
    matrix<T> m(rows, cols);
    for (Eigen::Index c = 0; c < cols; ++c)
        for (Eigen::Index r = 0; r < rows; ++r) m(r, c) = static_cast<T>(scale * (2 * rng.uniform() - 1));
    return m;
}

// ---------------------------------------------------------------------------
// alpha(p)
// ---------------------------------------------------------------------------

TEST_CASE_TEMPLATE("blend weight: the spec's values at every integer p", T, float, double) {
    for (std::size_t k = 1; k <= 12; ++k) {
        const T kk = static_cast<T>(k);
        for (int p = -5; p < static_cast<int>(k) + 5; ++p) {
            T expected;
            if (p <= -1) expected = T(1);
            else if (p >= static_cast<int>(k)) expected = T(0);
            else {
                const T x = (static_cast<T>(p) + T(1)) / kk;
                expected = T(2) * x * x * x - T(3) * x * x + T(1);
            }
            CHECK(anima::blend_weight(static_cast<T>(p), k) == doctest::Approx(expected).epsilon(tolerance<T>(1e-14, 1e-6)));
        }
        CHECK(anima::blend_weight(T(k) - T(1), k) == T(0));  // the last fade frame is all M1
    }
}

TEST_CASE_TEMPLATE("blend weight: monotone, C1 at both ends of the fade, symmetric", T, float, double) {
    for (std::size_t k : {1u, 2u, 5u, 25u}) {
        const T kk = static_cast<T>(k);
        T previous = T(1);
        for (int i = -200; i <= 200 * static_cast<int>(k); ++i) {
            const T p = T(-2) + static_cast<T>(i) * (kk + T(2)) / (T(200) * kk);
            const T a = anima::blend_weight(p, k);
            CHECK(a >= T(0));
            CHECK(a <= T(1));
            CHECK(a <= previous + tolerance<T>(1e-15, 1e-7));
            previous = a;
        }
        // One-sided difference quotients: 0 on both sides of p = -1 and p = k - 1.
        const double h = std::is_same_v<T, double> ? 1e-6 : 1e-2;
        const double slope_tol = std::is_same_v<T, double> ? 1e-5 : 5e-2;
        for (const T end : {T(-1), kk - T(1)}) {
            const T left = (anima::blend_weight(end, k) - anima::blend_weight(end - T(h), k)) / T(h);
            const T right = (anima::blend_weight(end + T(h), k) - anima::blend_weight(end, k)) / T(h);
            CHECK(std::abs(static_cast<double>(left)) < slope_tol * static_cast<double>(kk));
            CHECK(std::abs(static_cast<double>(right)) < slope_tol * static_cast<double>(kk));
        }
        // The derivative is continuous inside too: 6x(x-1)/k at x = 1/2 from both sides.
        const T mid = kk / T(2) - T(1);
        const T d = (anima::blend_weight(mid + T(h), k) - anima::blend_weight(mid - T(h), k)) / T(2 * h);
        CHECK(static_cast<double>(d) == doctest::Approx(-1.5 / static_cast<double>(k)).epsilon(slope_tol * 10));
        // alpha(p) + alpha(k - 2 - p) = 1: M2 fades out as M1 fades in.
        for (int p = -1; p < static_cast<int>(k); ++p)
            CHECK(anima::blend_weight(static_cast<T>(p), k) + anima::blend_weight(kk - T(2) - static_cast<T>(p), k) ==
                  doctest::Approx(1).epsilon(tolerance<T>(1e-14, 1e-6)));
    }
    CHECK(anima::blend_weight(std::numeric_limits<T>::quiet_NaN(), 4) == T(0));
    CHECK(contains(invalid_argument_message([] { (void)anima::blend_weight(T(0), 0); }), "at least one frame"));
}

TEST_CASE("blend windows: centred on the seam, inside the overlap") {
    CHECK(anima::blend_window_start(20, 10, 50) == 15);
    CHECK(anima::blend_window_start(1, 10, 50) == 0);
    CHECK(anima::blend_window_start(49, 10, 50) == 40);
    CHECK(anima::blend_window_start(5, 50, 50) == 0);
    CHECK(contains(invalid_argument_message([] { (void)anima::blend_window_start(5, 51, 50); }), "does not fit"));
    anima::seam_blend_params p;
    CHECK(anima::blend_frames(p, 50) == 25);
    CHECK(anima::blend_frames(p, 3) == 2);
    p.frames = 80;
    CHECK(anima::blend_frames(p, 50) == 50);
    p.enabled = false;
    CHECK(anima::blend_frames(p, 50) == 0);

    const auto w = anima::blend_weights<double>({3, 7}, 10, 4);
    REQUIRE(w.rows() == 2);
    REQUIRE(w.cols() == 10);
    // Row 0: window 1..4; before it all M2, from its last frame on all M1.
    CHECK(w(0, 0) == 1);
    CHECK(w(0, 1) == doctest::Approx(anima::blend_weight(0.0, 4)));
    CHECK(w(0, 4) == 0);
    CHECK(w(0, 9) == 0);
    CHECK(w(1, 4) == 1);
    CHECK(w(1, 8) == 0);
    const auto hard = anima::blend_weights<double>({3}, 10, 0);
    for (int t = 0; t < 10; ++t) CHECK(hard(0, t) == (t < 3 ? 1.0 : 0.0));
    CHECK(contains(invalid_argument_message([] { (void)anima::blend_weights<double>({0}, 10, 4); }), "outside 1..9"));
    CHECK(contains(invalid_argument_message([] { (void)anima::blend_weights<double>({10}, 10, 4); }), "outside 1..9"));
    CHECK(contains(invalid_argument_message([] { (void)anima::blend_weights<double>({3}, 10, 11); }), "does not fit"));
}

// ---------------------------------------------------------------------------
// Eq 8-9
// ---------------------------------------------------------------------------

TEST_CASE_TEMPLATE("seam cost: Eq 8 and Eq 9 by hand, every capacity policy", T, float, double) {
    // One column, 4 frames.
    matrix<T> a(4, 1), b(4, 1);
    a << 0, 1, 3, 6;
    b << 1, 1, 2, 2;
    anima::seam_cost_params<T> p;
    const anima::seam_cost<T> cost(a, b, 1, {}, p);
    REQUIRE(cost.rows() == 1);
    REQUIRE(cost.frames() == 4);
    const T mismatch[] = {1, 0, 1, 4};
    // Central differences inside, one-sided at the ends: A 1, 1.5, 2.5, 3; B 0, 0.5, 0.5, 0.
    const T gradient[] = {1, 2, 3, 3};
    for (std::size_t t = 0; t < 4; ++t) {
        CHECK(cost.mismatch(0, t) == doctest::Approx(mismatch[t]));
        CHECK(cost.gradient(0, t) == doctest::Approx(gradient[t]));
    }
    CHECK(cost.epsilon() == doctest::Approx(p.epsilon * T(9) / T(4)));
    const T eps = cost.epsilon();
    CHECK(cost.edge(0, 1, 0, 2) == doctest::Approx((0 + 1) / (2 + 3 + eps)));  // M / (grad + eps)
    CHECK(cost.edge(0, 2, 0, 1) == cost.edge(0, 1, 0, 2));

    p.capacity = anima::seam_capacity::plain;
    CHECK(anima::seam_cost<T>(a, b, 1, {}, p).edge(0, 2, 0, 3) == doctest::Approx(5));
    p.capacity = anima::seam_capacity::exponential;
    CHECK(anima::seam_cost<T>(a, b, 1, {}, p).edge(0, 2, 0, 3) == doctest::Approx(1 - std::exp(-5 / (6 + eps))));

    // Every policy grows with the mismatch at a fixed gradient; Eq 7 as
    // printed, exp(-M / grad), would fall.
    for (auto policy : {anima::seam_capacity::normalized, anima::seam_capacity::exponential, anima::seam_capacity::plain}) {
        p.capacity = policy;
        const anima::seam_cost<T> c(a, b, 1, {}, p);
        T previous = c.capacity(T(0), T(2));
        CHECK(previous == T(0));
        for (int i = 1; i <= 20; ++i) {
            const T value = c.capacity(T(i) / T(4), T(2));
            CHECK(value > previous);
            CHECK(std::isfinite(value));
            previous = value;
        }
        CHECK(anima::parse_seam_capacity(anima::to_string(policy)) == policy);
    }
}

TEST_CASE_TEMPLATE("seam cost: rows are weighted norms over blocks of columns", T, float, double) {
    anima::random_source rng(3);
    const matrix<T> a = random_matrix<T>(rng, 6, 6), b = random_matrix<T>(rng, 6, 6);
    Eigen::Matrix<T, Eigen::Dynamic, 1> w(6);
    w << 1, 2, 0.5, 3, 0, 1;
    const anima::seam_cost<T> cost(a, b, 3, w);
    REQUIRE(cost.rows() == 2);
    for (std::size_t r = 0; r < 2; ++r)
        for (std::size_t t = 0; t < 6; ++t) {
            T sum = 0;
            for (Eigen::Index c = 0; c < 3; ++c) {
                const Eigen::Index col = static_cast<Eigen::Index>(3 * r) + c;
                const T d = a(static_cast<Eigen::Index>(t), col) - b(static_cast<Eigen::Index>(t), col);
                sum += w[col] * d * d;
            }
            CHECK(cost.mismatch(r, t) == doctest::Approx(std::sqrt(sum)).epsilon(tolerance<T>(1e-12, 1e-5)));
        }
    // A motion that does not move still gets finite capacities.
    const matrix<T> still = matrix<T>::Constant(5, 3, T(1));
    const anima::seam_cost<T> frozen(still, still + matrix<T>::Constant(5, 3, T(0.5)), 3);
    CHECK(std::isfinite(frozen.edge(0, 0, 0, 1)));
    CHECK(frozen.edge(0, 0, 0, 1) < anima::max_flow_infinity<T>());
}

TEST_CASE_TEMPLATE("seam cost: a node out of range is refused by the accessors", T, float, double) {
    const matrix<T> a = matrix<T>::Ones(6, 6);
    const anima::seam_cost<T> cost(a, a + matrix<T>::Constant(6, 6, T(0.5)), 3);
    CHECK(invalid_argument_message([&] { (void)cost.mismatch(99, 0); }) ==
          "anima::seam_cost::mismatch: row must be less than the 2 rows, got 99");
    CHECK(invalid_argument_message([&] { (void)cost.mismatch(1, 6); }) ==
          "anima::seam_cost::mismatch: frame must be less than the 6 frames, got 6");
    CHECK(invalid_argument_message([&] { (void)cost.gradient(2, 0); }) ==
          "anima::seam_cost::gradient: row must be less than the 2 rows, got 2");
    CHECK(invalid_argument_message([&] { (void)cost.edge(0, 5, 0, 6); }) ==
          "anima::seam_cost::edge: frame must be less than the 6 frames, got 6");
    CHECK(invalid_argument_message([&] { (void)cost.edge(5, 0, 0, 0); }) ==
          "anima::seam_cost::edge: row must be less than the 2 rows, got 5");
    CHECK(cost.edge(1, 5, 0, 4) == cost.capacity(cost.mismatch(1, 5) + cost.mismatch(0, 4),
                                                 cost.gradient(1, 5) + cost.gradient(0, 4)));
}

TEST_CASE("seam cost: errors name what is wrong") {
    const matrix<double> a = matrix<double>::Zero(5, 6);
    CHECK(contains(invalid_argument_message([&] { anima::seam_cost<double>(a, matrix<double>::Zero(4, 6), 3); }), "5 x 6 and 4 x 6"));
    CHECK(contains(invalid_argument_message([&] { anima::seam_cost<double>(a.topRows(1), a.topRows(1), 3); }), "at least 2 frames"));
    CHECK(contains(invalid_argument_message([&] { anima::seam_cost<double>(a, a, 4); }), "does not divide"));
    Eigen::VectorXd w = Eigen::VectorXd::Ones(6);
    w[2] = -1;
    CHECK(contains(invalid_argument_message([&] { anima::seam_cost<double>(a, a, 3, w); }), "weight 2"));
    CHECK(contains(invalid_argument_message([&] { anima::seam_cost<double>(a, a, 3, Eigen::VectorXd::Ones(5)); }), "5 weights"));
    matrix<double> bad = a;
    bad(2, 2) = std::nan("");
    CHECK(contains(invalid_argument_message([&] { anima::seam_cost<double>(a, bad, 3); }), "non-finite"));
    anima::seam_cost_params<double> p;
    p.epsilon = 0;
    CHECK(contains(invalid_argument_message([&] { anima::seam_cost<double>(a, a, 3, {}, p); }), "epsilon"));
    CHECK(contains(invalid_argument_message([] { (void)anima::parse_seam_capacity("exp"); }), "normalized, exponential or plain"));
}

// ---------------------------------------------------------------------------
// The (i, j) loop
// ---------------------------------------------------------------------------

TEST_CASE_TEMPLATE("overlap search: equal to the triple loop on random costs", T, float, double) {
    anima::random_source rng(11);
    for (int trial = 0; trial < 30; ++trial) {
        const auto na = static_cast<Eigen::Index>(2 + rng.below(30)), nb = static_cast<Eigen::Index>(2 + rng.below(30));
        const std::size_t n = 1 + rng.below(static_cast<std::uint64_t>(std::min(na, nb)));
        matrix<T> p = random_matrix<T>(rng, na, nb).cwiseAbs();
        const auto r = anima::search_overlap(p, n);
        const auto nn = static_cast<Eigen::Index>(n);
        REQUIRE(r.costs.rows() == na - nn + 1);
        REQUIRE(r.costs.cols() == nb - nn + 1);
        double best = 1e300;
        Eigen::Index bi = 0, bj = 0;
        for (Eigen::Index i = 0; i + nn <= na; ++i)
            for (Eigen::Index j = 0; j + nn <= nb; ++j) {
                double sum = 0;
                for (Eigen::Index t = 0; t < nn; ++t) sum += static_cast<double>(p(i + t, j + t));
                CHECK(static_cast<double>(r.costs(i, j)) == doctest::Approx(sum).epsilon(tolerance<T>(1e-12, 1e-5)));
                if (sum < best) {
                    best = sum;
                    bi = i;
                    bj = j;
                }
            }
        CHECK(static_cast<double>(r.cost) == doctest::Approx(best).epsilon(tolerance<T>(1e-12, 1e-5)));
        if constexpr (std::is_same_v<T, double>) {
            CHECK(r.first_a == static_cast<std::size_t>(bi));
            CHECK(r.first_b == static_cast<std::size_t>(bj));
        }
        // Only the windows with i - j >= shift, for a shift some window meets.
        const auto shift = static_cast<std::ptrdiff_t>(rng.below(static_cast<std::uint64_t>(na + nb - 2 * nn + 1))) -
                           static_cast<std::ptrdiff_t>(nb - nn);
        const auto rs = anima::search_overlap(p, n, shift);
        CHECK(static_cast<std::ptrdiff_t>(rs.first_a) - static_cast<std::ptrdiff_t>(rs.first_b) >= shift);
        double best_shifted = 1e300;
        for (Eigen::Index i = 0; i + nn <= na; ++i)
            for (Eigen::Index j = 0; j + nn <= nb && i - j >= shift; ++j)
                best_shifted = std::min(best_shifted, static_cast<double>(r.costs(i, j)));
        CHECK(static_cast<double>(rs.cost) == doctest::Approx(best_shifted).epsilon(tolerance<T>(1e-12, 1e-5)));
        CHECK(rs.cost >= r.cost);
    }
}

TEST_CASE_TEMPLATE("overlap search finds a planted best offset", T, float, double) {
    anima::random_source rng(5);
    for (const auto& [i0, j0] : {std::pair<std::size_t, std::size_t>{0, 0}, {37, 4}, {9, 50}, {50, 50}, {13, 13}}) {
        const Eigen::Index m = 100, n = 50, dofs = 12;
        const matrix<T> a = random_matrix<T>(rng, m, dofs);
        matrix<T> b = random_matrix<T>(rng, m, dofs);
        // B's frames j0 .. j0+n-1 repeat A's frames i0 .. i0+n-1 up to noise.
        b.middleRows(static_cast<Eigen::Index>(j0), n) =
            a.middleRows(static_cast<Eigen::Index>(i0), n) + random_matrix<T>(rng, n, dofs, 1e-3);
        for (const auto metric : {anima::frame_metric::mahalanobis, anima::frame_metric::l2}) {
            anima::frame_distance_params<T> dp;
            dp.metric = metric;
            matrix<T> both(2 * m, dofs);
            both << a, b;
            const auto distance = anima::make_frame_distance(both, T(1) / T(30), dp);
            const matrix<T> pairs = anima::frame_pair_costs(a, b, distance);
            for (Eigen::Index i = 0; i < m; i += 17)
                for (Eigen::Index j = 0; j < m; j += 13)
                    CHECK(pairs(i, j) == doctest::Approx(distance(a.row(i).transpose(), b.row(j).transpose())));
            const auto r = anima::search_overlap(pairs, static_cast<std::size_t>(n));
            CHECK(r.first_a == i0);
            CHECK(r.first_b == j0);
            CHECK(r.cost < T(1e-2) * r.costs.mean());
        }
    }
}

TEST_CASE_TEMPLATE("overlap search: an overlap past the index range or sums past the scalar's are refused", T, float, double) {
    const matrix<T> p = matrix<T>::Ones(5, 5);
    for (const std::size_t huge : {std::numeric_limits<std::size_t>::max(), std::size_t(1) << 63}) {
        const std::string message = invalid_argument_message([&] { (void)anima::search_overlap(p, huge); });
        CHECK(contains(message, "anima::search_overlap: an overlap of " + std::to_string(huge) + " frames does not fit"));
    }
    const matrix<T> largest = matrix<T>::Constant(5, 5, std::numeric_limits<T>::max());
    CHECK(contains(invalid_argument_message([&] { (void)anima::search_overlap(largest, 3); }),
                   "anima::search_overlap: the summed costs of 3 frames overflow the scalar type; scale the DOFs down"));
}

TEST_CASE("overlap search: errors") {
    const matrix<double> p = matrix<double>::Ones(10, 8);
    CHECK(contains(invalid_argument_message([&] { (void)anima::search_overlap(p, 0); }), "does not fit"));
    CHECK(contains(invalid_argument_message([&] { (void)anima::search_overlap(p, 9); }), "does not fit"));
    matrix<double> bad = p;
    bad(3, 4) = -1;
    CHECK(contains(invalid_argument_message([&] { (void)anima::search_overlap(bad, 2); }), "(3, 4)"));
    anima::frame_distance<double> d;
    d.precision = Eigen::VectorXd::Ones(3);
    CHECK(contains(invalid_argument_message([&] { (void)anima::frame_pair_costs(p, matrix<double>::Ones(3, 7), d); }),
                   "8 and 7 DOFs"));
    CHECK(contains(invalid_argument_message([&] { (void)anima::frame_pair_costs(p, p, d); }), "3 DOF weights"));
    const auto one = anima::search_overlap(p, 8);
    CHECK(one.costs.rows() == 3);
    CHECK(one.costs.cols() == 1);
    // Windows start at i = 0..8: i - j >= 8 leaves (8, 0), 9 none.
    const auto last = anima::search_overlap(p, 2, 8);
    CHECK(last.first_a == 8);
    CHECK(last.first_b == 0);
    CHECK(contains(invalid_argument_message([&] { (void)anima::search_overlap(p, 2, 9); }), "no window has i - j >= 9"));
}

// ---------------------------------------------------------------------------
// The min-cut
// ---------------------------------------------------------------------------

// Capacity of the cut a labelling of the lattice makes in the graph
// cut_seams builds (rows x frames, true = B / sink side), infinite when a
// hard constraint is cut.
template <class T>
double labelling_cost(const anima::seam_cost<T>& cost, const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                      T weight, const std::vector<bool>& on_b) {
    const std::size_t rows = cost.rows(), frames = cost.frames();
    const auto b = [&](std::size_t r, std::size_t t) { return on_b[r * frames + t]; };
    double sum = 0;
    for (std::size_t r = 0; r < rows; ++r) {
        if (b(r, 0) || !b(r, frames - 1)) return 1e300;
        for (std::size_t t = 0; t + 1 < frames; ++t) {
            if (!b(r, t) && b(r, t + 1)) sum += static_cast<double>(cost.edge(r, t, r, t + 1));
            if (b(r, t) && !b(r, t + 1)) return 1e300;
        }
    }
    for (const auto& [r1, r2] : pairs)
        for (std::size_t t = 0; t < frames; ++t)
            if (b(r1, t) != b(r2, t)) sum += static_cast<double>(weight * cost.edge(r1, t, r2, t));
    return sum;
}

TEST_CASE_TEMPLATE("seam cut: the flow equals the cheapest of every labelling", T, float, double) {
    anima::random_source rng(17);
    for (int trial = 0; trial < 40; ++trial) {
        const std::size_t rows = 1 + rng.below(3), frames = 2 + rng.below(4);  // at most 3 x 5 = 2^15 labellings
        const matrix<T> a = random_matrix<T>(rng, static_cast<Eigen::Index>(frames), static_cast<Eigen::Index>(3 * rows));
        const matrix<T> b = random_matrix<T>(rng, static_cast<Eigen::Index>(frames), static_cast<Eigen::Index>(3 * rows));
        anima::seam_cost_params<T> p;
        p.capacity = static_cast<anima::seam_capacity>(rng.below(3));
        const anima::seam_cost<T> cost(a, b, 3, {}, p);
        std::vector<std::pair<std::size_t, std::size_t>> pairs;
        for (std::size_t r = 1; r < rows; ++r) pairs.emplace_back(rng.below(r), r);
        const T weight = static_cast<T>(rng.uniform() * 2);
        const auto cut = anima::cut_seams(cost, pairs, weight);
        double best = 1e300;
        const std::size_t nodes = rows * frames;
        for (std::uint64_t bits = 0; bits < (std::uint64_t(1) << nodes); ++bits) {
            std::vector<bool> on_b(nodes);
            for (std::size_t i = 0; i < nodes; ++i) on_b[i] = (bits >> i) & 1u;
            best = std::min(best, labelling_cost(cost, pairs, weight, on_b));
        }
        const double tol = std::is_same_v<T, double> ? 1e-9 : 1e-4;
        CHECK(static_cast<double>(cut.flow) == doctest::Approx(best).epsilon(tol));
        CHECK(static_cast<double>(cut.cost) == doctest::Approx(best).epsilon(tol));
        // The seams found make a labelling of that cost.
        std::vector<bool> found(nodes);
        T rows_sum = 0;
        for (std::size_t r = 0; r < rows; ++r) {
            REQUIRE(cut.seam[r] >= 1);
            REQUIRE(cut.seam[r] <= frames - 1);
            for (std::size_t t = 0; t < frames; ++t) found[r * frames + t] = t >= cut.seam[r];
            CHECK(cut.row_cost[r] == doctest::Approx(cost.edge(r, cut.seam[r] - 1, r, cut.seam[r])));
            rows_sum += cut.row_cost[r];
        }
        CHECK(static_cast<double>(rows_sum + cut.neighbour_cost) == doctest::Approx(static_cast<double>(cut.cost)));
        CHECK(labelling_cost(cost, pairs, weight, found) == doctest::Approx(best).epsilon(tol));
    }
}

TEST_CASE("seam cut: independent rows cut at their cheapest edge, strong ties cut together") {
    anima::random_source rng(23);
    const Eigen::Index frames = 30;
    const matrix<double> a = random_matrix<double>(rng, frames, 12), b = random_matrix<double>(rng, frames, 12);
    const anima::seam_cost<double> cost(a, b, 3);
    const std::vector<std::pair<std::size_t, std::size_t>> chain{{0, 1}, {1, 2}, {2, 3}};
    const auto free = anima::cut_seams(cost, chain, 0.0);
    for (std::size_t r = 0; r < 4; ++r) {
        std::size_t best = 1;
        for (std::size_t s = 2; s < static_cast<std::size_t>(frames); ++s)
            if (cost.edge(r, s - 1, r, s) < cost.edge(r, best - 1, r, best)) best = s;
        CHECK(free.seam[r] == best);
    }
    CHECK(free.neighbour_cost == 0);
    const auto tied = anima::cut_seams(cost, chain, 1e6);
    for (std::size_t r = 1; r < 4; ++r) CHECK(tied.seam[r] == tied.seam[0]);
    CHECK(tied.neighbour_cost == 0);
    CHECK(tied.cost >= free.cost);

    CHECK(contains(invalid_argument_message([&] { (void)anima::cut_seams(cost, {{1, 1}}, 0.5); }), "(1, 1)"));
    CHECK(contains(invalid_argument_message([&] { (void)anima::cut_seams(cost, {{0, 4}}, 0.5); }), "(0, 4)"));
    CHECK(contains(invalid_argument_message([&] { (void)anima::cut_seams(cost, chain, -1.0); }), "neighbour weight"));
}

}  // namespace
