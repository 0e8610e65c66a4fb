// Frame distances (Eq 1-2), symmetry scores and turning candidates (Eq 3-5)
// against hand computations and a brute-force reference built from the full
// distance matrix; real clips played forwards and backwards; degenerate and
// invalid input; every clip of the shared data set when it is present.
#include "symmetry_test_support.hpp"

#include <anima/bvh/reader.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/dof_view.hpp>
#include <anima/motion/figure.hpp>
#include <anima/motion/resequence.hpp>
#include <anima/motion/frame_distance.hpp>
#include <anima/motion/frame_features.hpp>
#include <anima/symmetry/symmetric_playback.hpp>
#include <anima/symmetry/symmetry_scores.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace symmetry_test;
using anima::frame_metric;

// C(m, k) from Pascal's triangle: exact in 64 bits for the m used here.
std::uint64_t choose(int m, int k) {
    if (k < 0 || k > m) return 0;
    std::vector<std::uint64_t> row{1};
    for (int i = 1; i <= m; ++i) {
        std::vector<std::uint64_t> next(row.size() + 1, 1);
        for (std::size_t j = 1; j < row.size(); ++j) next[j] = row[j - 1] + row[j];
        row = next;
    }
    return row[static_cast<std::size_t>(k)];
}

struct reference_scores {
    std::vector<double> weighted;  // Eq 3 / weights used; unset (0) without pairs
    std::vector<double> score;     // Eq 4
    std::vector<int> pairs;
};

// Eq 3-4 straight from the full distance matrix, one frame at a time, with
// exact integer binomial weights; frames near the ends use the pairs they
// have and divide by those pairs' weights.
template <class M>
reference_scores brute_force(const M& distances, int radius, int smoothness) {
    const auto n = static_cast<int>(distances.rows());
    reference_scores out;
    out.weighted.assign(static_cast<std::size_t>(n), 0.0);
    out.score.assign(static_cast<std::size_t>(n), 0.0);
    out.pairs.assign(static_cast<std::size_t>(n), 0);
    std::vector<double> weight(static_cast<std::size_t>(radius) + 1);
    for (int r = 1; r <= radius; ++r)
        weight[static_cast<std::size_t>(r)] = static_cast<double>(choose(2 * (radius - smoothness), radius - r));
    double largest = 0;
    for (int i = 0; i < n; ++i) {
        double sum = 0, used = 0;
        int r = 1;
        for (; r <= radius && i - r >= 0 && i + r < n; ++r) {
            const double w = weight[static_cast<std::size_t>(r)];
            sum += w * static_cast<double>(distances(i - r, i + r));
            used += w;
        }
        out.pairs[static_cast<std::size_t>(i)] = r - 1;
        if (r > 1) {
            out.weighted[static_cast<std::size_t>(i)] = sum / used;
            largest = std::max(largest, sum / used);
        }
    }
    for (int i = 0; i < n; ++i)
        if (out.pairs[static_cast<std::size_t>(i)] > 0)
            out.score[static_cast<std::size_t>(i)] = largest > 0 ? 1 - out.weighted[static_cast<std::size_t>(i)] / largest : 1;
    return out;
}

// Eq 5 from the scores: a frame is a candidate when it is the first maximum
// of its window (std::max_element returns the first), has pairs and a
// positive score; ordered by score, earlier frame first on ties.
template <class T>
std::vector<std::size_t> reference_candidates(const vector<T>& score, const std::vector<int>& pairs, int window,
                                              int min_pairs = 1) {
    std::vector<std::size_t> out;
    const auto n = static_cast<int>(score.size());
    const T* s = score.data();
    for (int i = 0; i < n; ++i) {
        const auto eligible = [&](int k) { return pairs[static_cast<std::size_t>(k)] >= min_pairs; };
        if (!eligible(i) || !(s[i] > T(0))) continue;
        if ((i > 0 && s[i - 1] > s[i]) || (i + 1 < n && s[i + 1] > s[i])) continue;  // on a slope
        // i must be the first largest score among the eligible frames in the window.
        int first_best = -1;
        for (int k = std::max(0, i - window); k <= std::min(n - 1, i + window); ++k)
            if (eligible(k) && (first_best < 0 || s[k] > s[first_best])) first_best = k;
        if (first_best == i) out.push_back(static_cast<std::size_t>(i));
    }
    std::stable_sort(out.begin(), out.end(), [&](std::size_t a, std::size_t b) { return s[a] > s[b]; });
    return out;
}

template <class T>
matrix<T> features(const anima::clip<T>& c) {
    return anima::frame_features(c);
}

template <class T>
anima::symmetry_params<T> params_for(frame_metric metric, int radius = 10, int smoothness = 0) {
    anima::symmetry_params<T> p;
    p.distance.metric = metric;
    p.radius = radius;
    p.smoothness = smoothness;
    return p;
}

// Scores finite and in [0, 1], weighted distances finite and >= 0, every
// candidate a frame with pairs: what every result must satisfy.
template <class T>
void check_well_formed(const anima::symmetry_result<T>& r, Eigen::Index frames) {
    REQUIRE(r.score.size() == frames);
    REQUIRE(r.weighted_distance.size() == frames);
    REQUIRE(r.pairs.size() == static_cast<std::size_t>(frames));
    for (Eigen::Index i = 0; i < frames; ++i) {
        CHECK(std::isfinite(r.score[i]));
        CHECK(r.score[i] >= T(0));
        CHECK(r.score[i] <= T(1));
        CHECK(std::isfinite(r.weighted_distance[i]));
        CHECK(r.weighted_distance[i] >= T(0));
    }
    for (const auto& c : r.candidates) {
        REQUIRE(c.frame < static_cast<std::size_t>(frames));
        CHECK(r.pairs[c.frame] > 0);
        CHECK(c.score == r.score[static_cast<Eigen::Index>(c.frame)]);
        CHECK(c.probability == c.score / T(2));
    }
}

}  // namespace

// ---------------------------------------------------------------------------
// Eq 1 and Eq 2
// ---------------------------------------------------------------------------

TEST_CASE_TEMPLATE("Eq 1: the L2 distance sums the Euclidean norms of the joints' differences", T, float, double) {
    matrix<T> m(3, 6);
    m << 0, 0, 0, 1, 2, 2,   //
        3, 4, 0, 1, 2, 2,    // joint 0 moved by (3, 4, 0): 5
        1, 1, 1, -1, -1, 4;  // from row 0: sqrt(3) and |(-2, -3, 2)| = sqrt(17)
    anima::frame_distance_params<T> p;
    p.metric = frame_metric::l2;
    const auto d = anima::make_frame_distance(m, T(0.1), p);
    CHECK(d.metric == frame_metric::l2);
    CHECK(d(m.row(0), m.row(1)) == doctest::Approx(5.0));
    CHECK(d(m.row(0), m.row(2)) == doctest::Approx(std::sqrt(3.0) + std::sqrt(17.0)));
    // |(2, 3, 1)| + |(2, 3, -2)|
    CHECK(d(m.row(1), m.row(2)) == doctest::Approx(std::sqrt(14.0) + std::sqrt(17.0)));
    CHECK(d(m.row(2), m.row(2)) == T(0));

    const matrix<T> full = anima::distance_matrix(m, d);
    REQUIRE(full.rows() == 3);
    REQUIRE(full.cols() == 3);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            CHECK(full(i, j) == full(j, i));
            CHECK(full(i, j) == doctest::Approx(static_cast<double>(d(m.row(i), m.row(j)))));
        }

    // One DOF per block: the sum of absolute differences.
    p.block_size = 1;
    CHECK(anima::make_frame_distance(m, T(0.1), p)(m.row(0), m.row(2)) == doctest::Approx(1 + 1 + 1 + 2 + 3 + 2));
    p.block_size = 2;  // (0,0)-(1,1), (0,1)-(-1,-1), (2,2)-(-1,4): sqrt(2) + sqrt(5) + sqrt(13)
    CHECK(anima::make_frame_distance(m, T(0.1), p)(m.row(0), m.row(2)) ==
          doctest::Approx(std::sqrt(2.0) + std::sqrt(5.0) + std::sqrt(13.0)));
}

TEST_CASE_TEMPLATE("Eq 1: l2_similarity is exp(-d / sigma), 1 for equal frames, validated", T, float, double) {
    CHECK(anima::l2_similarity(T(0), T(2)) == T(1));
    CHECK(anima::l2_similarity(T(2), T(2)) == doctest::Approx(std::exp(-1.0)));
    CHECK(anima::l2_similarity(T(3), T(0.5)) == doctest::Approx(std::exp(-6.0)));
    CHECK(anima::l2_similarity(T(1), T(4)) > anima::l2_similarity(T(2), T(4)));
    CHECK(anima::l2_similarity(std::numeric_limits<T>::infinity(), T(1)) == T(0));
    CHECK(anima::l2_similarity(T(1e6), T(1e-3)) == T(0));  // underflows to 0, never NaN
    const T nan = std::numeric_limits<T>::quiet_NaN();
    for (T sigma : {T(0), T(-1), nan, std::numeric_limits<T>::infinity()})
        CHECK(contains(invalid_argument_message([&] { anima::l2_similarity(T(1), sigma); }), "sigma"));
    for (T d : {T(-1), nan}) CHECK(contains(invalid_argument_message([&] { anima::l2_similarity(d, T(1)); }), "distance"));
}

TEST_CASE_TEMPLATE("Eq 2: velocity_precision is 1 / var of the finite-difference velocity", T, float, double) {
    // Real motion, and two columns that never change speed: a frozen DOF and
    // a ramp (constant velocity, variance 0 in exact arithmetic).
    const matrix<T> real = features(walk<T>()).middleRows(40, 120);
    matrix<T> m(real.rows(), real.cols() + 2);
    m << real, matrix<T>::Constant(real.rows(), 1, T(0.75)), matrix<T>::Zero(real.rows(), 1);
    const T dt = walk<T>().frame_time();
    for (Eigen::Index f = 0; f < m.rows(); ++f) m(f, m.cols() - 1) = T(2) * static_cast<T>(f);

    // Independent reference in double: central differences inside,
    // one-sided at both ends (as anima::time_derivative documents).
    const Eigen::Index n = m.rows();
    Eigen::MatrixXd velocity(n, m.cols());
    const double h = static_cast<double>(dt);
    for (Eigen::Index f = 0; f < n; ++f)
        for (Eigen::Index d = 0; d < m.cols(); ++d) {
            const double next = static_cast<double>(m(std::min(f + 1, n - 1), d));
            const double prev = static_cast<double>(m(std::max<Eigen::Index>(f - 1, 0), d));
            const double span = (f == 0 || f == n - 1) ? h : 2 * h;
            velocity(f, d) = (next - prev) / span;
        }
    const Eigen::VectorXd mean = velocity.colwise().mean().transpose();
    Eigen::VectorXd variance(m.cols());
    for (Eigen::Index d = 0; d < m.cols(); ++d) {
        double sum = 0;
        for (Eigen::Index f = 0; f < n; ++f) sum += (velocity(f, d) - mean[d]) * (velocity(f, d) - mean[d]);
        variance[d] = sum / static_cast<double>(n);
    }
    const double largest = variance.maxCoeff();

    for (double regularization : {1e-3, 0.05, 1.0}) {
        CAPTURE(regularization);
        const vector<T> precision = anima::velocity_precision(m, dt, static_cast<T>(regularization));
        REQUIRE(precision.size() == m.cols());
        for (Eigen::Index d = 0; d < m.cols(); ++d) {
            CAPTURE(d);
            const double expected = 1 / std::max(variance[d], regularization * largest);
            CHECK(std::isfinite(precision[d]));
            CHECK(static_cast<double>(precision[d]) == doctest::Approx(expected).epsilon(tolerance<T>(1e-9, 1e-3)));
        }
        // The frozen DOF and the ramp get the regularised weight, the largest one.
        const double floor_weight = 1 / (regularization * largest);
        CHECK(static_cast<double>(precision[m.cols() - 2]) == doctest::Approx(floor_weight).epsilon(tolerance<T>(1e-9, 1e-3)));
        CHECK(static_cast<double>(precision[m.cols() - 1]) == doctest::Approx(floor_weight).epsilon(tolerance<T>(1e-9, 1e-3)));
        CHECK(precision.maxCoeff() <= static_cast<T>(floor_weight * (1 + tolerance<T>(1e-9, 1e-3))));
    }

    // The Mahalanobis distance is sum_d (a_d - b_d)^2 / var_d.
    const auto distance = anima::make_frame_distance(m, dt);
    CHECK(distance.metric == frame_metric::mahalanobis);
    const vector<T> precision = anima::velocity_precision(m, dt);
    for (auto [a, b] : {std::pair<int, int>{0, 1}, {3, 90}, {119, 7}}) {
        double expected = 0;
        for (Eigen::Index d = 0; d < m.cols(); ++d) {
            const double e = static_cast<double>(m(a, d)) - static_cast<double>(m(b, d));
            expected += e * e * static_cast<double>(precision[d]);
        }
        CHECK(static_cast<double>(distance(m.row(a), m.row(b))) == doctest::Approx(expected).epsilon(tolerance<T>(1e-12, 1e-4)));
    }
}

TEST_CASE_TEMPLATE("Eq 2 over several motions: velocity variances pooled, none across the joins", T, float, double) {
    // Two stretches of the walk far apart: stacked, the jump between them
    // would be one huge velocity; pooled, each stretch's velocities are its own.
    const matrix<T> all = features(walk<T>());
    const matrix<T> p0 = all.middleRows(20, 90), p1 = all.middleRows(200, 60);
    const T dt = walk<T>().frame_time();
    // One motion: the same distance as make_frame_distance of it.
    const auto one = anima::make_frame_distance(std::vector<matrix<T>>{p0}, dt);
    CHECK(one.precision == anima::make_frame_distance(p0, dt).precision);
    // Reference in double: each part's own finite differences, one variance over all.
    std::vector<Eigen::VectorXd> velocities(static_cast<std::size_t>(all.cols()));
    for (const matrix<T>* part : {&p0, &p1})
        for (Eigen::Index d = 0; d < all.cols(); ++d) {
            const Eigen::Index n = part->rows();
            Eigen::VectorXd& v = velocities[static_cast<std::size_t>(d)];
            v.conservativeResize(v.size() + n);
            for (Eigen::Index f = 0; f < n; ++f) {
                const double next = static_cast<double>((*part)(std::min(f + 1, n - 1), d));
                const double prev = static_cast<double>((*part)(std::max<Eigen::Index>(f - 1, 0), d));
                v[v.size() - n + f] = (next - prev) / ((f == 0 || f == n - 1) ? 1.0 : 2.0) / static_cast<double>(dt);
            }
        }
    Eigen::VectorXd variance(all.cols());
    for (Eigen::Index d = 0; d < all.cols(); ++d) {
        const Eigen::VectorXd& v = velocities[static_cast<std::size_t>(d)];
        variance[d] = (v.array() - v.mean()).square().mean();
    }
    const double floor = 1e-3 * variance.maxCoeff();
    const auto pooled = anima::make_frame_distance(std::vector<matrix<T>>{p0, p1}, dt);
    REQUIRE(pooled.precision.size() == all.cols());
    for (Eigen::Index d = 0; d < all.cols(); ++d)
        CHECK(static_cast<double>(pooled.precision[d]) ==
              doctest::Approx(1 / std::max(variance[d], floor)).epsilon(tolerance<T>(1e-9, 1e-3)));
    // Stacked into one motion, the join's jump inflates some variance.
    matrix<T> stacked(p0.rows() + p1.rows(), all.cols());
    stacked << p0, p1;
    CHECK((anima::make_frame_distance(stacked, dt).precision - pooled.precision).cwiseAbs().maxCoeff() >
          T(0.1) * pooled.precision.cwiseAbs().maxCoeff());
    // Refused: no motions, different widths (named), a non-finite value in a later motion.
    CHECK(contains(invalid_argument_message([&] { anima::make_frame_distance(std::vector<matrix<T>>{}, dt); }), "no motions"));
    const std::string wide = invalid_argument_message(
        [&] { anima::make_frame_distance(std::vector<matrix<T>>{p0, all.leftCols(all.cols() - 1)}, dt); });
    CHECK(contains(wide, "motion 1"));
    matrix<T> bad = p1;
    bad(3, 2) = std::numeric_limits<T>::quiet_NaN();
    CHECK(contains(invalid_argument_message([&] { anima::make_frame_distance(std::vector<matrix<T>>{p0, bad}, dt); }),
                   "frame 3"));
}

TEST_CASE_TEMPLATE("Eq 2: precision without motion, with one frame, and with bad input", T, float, double) {
    const matrix<T> frozen = matrix<T>::Constant(20, 6, T(1.5));
    CHECK(anima::velocity_precision(frozen, T(0.01)) == vector<T>::Ones(6));
    CHECK(anima::velocity_precision(matrix<T>(1, 6).setRandom().eval(), T(0.01)) == vector<T>::Ones(6));
    CHECK(anima::velocity_precision(matrix<T>(0, 6), T(0.01)) == vector<T>::Ones(6));
    CHECK(anima::velocity_precision(matrix<T>(10, 0), T(0.01)).size() == 0);
    // A frame time so short that the velocities' squares overflow: the
    // message names it as well as the DOFs' scale.
    const T instant = static_cast<T>(std::is_same_v<T, float> ? 1e-20 : 1e-160);
    matrix<T> saw(10, 2);
    for (Eigen::Index i = 0; i < saw.rows(); ++i) saw.row(i) << static_cast<T>(i % 3 * (i % 3)), T(0);  // 0, 1, 4, 0, ...
    CHECK(contains(invalid_argument_message([&] { (void)anima::velocity_precision(saw, instant); }),
                   "overflows the scalar type at a frame time of " + anima::detail::argument_text(instant) +
                       " s; scale the DOFs down or lengthen the frame time"));

    const matrix<T> m = features(walk<T>()).topRows(30);
    const T nan = std::numeric_limits<T>::quiet_NaN();
    for (T reg : {T(0), T(-1), T(1.5), nan})
        CHECK(contains(invalid_argument_message([&] { anima::velocity_precision(m, T(0.01), reg); }), "regularization"));
    for (T dt : {T(0), T(-0.01), nan, std::numeric_limits<T>::infinity()}) {
        CHECK(contains(invalid_argument_message([&] { anima::velocity_precision(m, dt); }), "frame time"));
        // Also with one frame, where the time step is never used.
        CHECK(contains(invalid_argument_message([&] { anima::velocity_precision(m.topRows(1), dt); }), "frame time"));
    }
    matrix<T> bad = m;
    bad(7, 4) = nan;
    const std::string message = invalid_argument_message([&] { anima::velocity_precision(bad, T(0.01)); });
    CHECK(contains(message, "frame 7"));
    CHECK(contains(message, "column 4"));
    bad(7, 4) = std::numeric_limits<T>::infinity();
    CHECK(contains(invalid_argument_message([&] { anima::velocity_precision(bad, T(0.01)); }), "non-finite"));

    // Finite values whose velocities overflow: an error, not a NaN weight.
    matrix<T> huge = matrix<T>::Zero(6, 1);
    huge(2, 0) = std::numeric_limits<T>::max();
    huge(4, 0) = -std::numeric_limits<T>::max();
    CHECK(contains(invalid_argument_message([&] { anima::velocity_precision(huge, T(1)); }), "overflow"));
}

TEST_CASE_TEMPLATE("frame distances: parameter and size errors name the problem", T, float, double) {
    const matrix<T> m = features(walk<T>()).topRows(30);
    anima::frame_distance_params<T> p;
    p.metric = frame_metric::l2;
    for (int block : {0, -3, 5, 7}) {  // the walk has 96 DOFs
        p.block_size = block;
        CHECK(contains(invalid_argument_message([&] { anima::make_frame_distance(m, T(0.01), p); }), "block size"));
    }
    p = {};
    p.regularization = T(0);
    CHECK(contains(invalid_argument_message([&] { anima::make_frame_distance(m, T(0.01), p); }), "regularization"));
    for (auto metric : {frame_metric::l2, frame_metric::mahalanobis}) {
        p = {};
        p.metric = metric;
        CHECK(contains(invalid_argument_message([&] { anima::make_frame_distance(m, T(0), p); }), "frame time"));
        CHECK(contains(invalid_argument_message([&] { anima::make_frame_distance(m.topRows(1), T(-1), p); }), "frame time"));
        matrix<T> bad = m;
        bad(29, 0) = std::numeric_limits<T>::quiet_NaN();
        CHECK(contains(invalid_argument_message([&] { anima::make_frame_distance(bad, T(0.01), p); }), "frame 29"));
    }

    // A hand-made distance that does not fit the matrix.
    anima::frame_distance<T> mismatched;
    mismatched.precision = vector<T>::Ones(m.cols() - 1);
    CHECK(contains(invalid_argument_message([&] { anima::distance_matrix(m, mismatched); }), "DOF weights"));
    anima::frame_distance<T> bad_blocks;
    bad_blocks.metric = frame_metric::l2;
    bad_blocks.block_size = 0;
    CHECK(contains(invalid_argument_message([&] { anima::distance_matrix(m, bad_blocks); }), "block size"));

    CHECK(anima::parse_frame_metric("l2") == frame_metric::l2);
    CHECK(anima::parse_frame_metric("mahalanobis") == frame_metric::mahalanobis);
    for (auto metric : {frame_metric::l2, frame_metric::mahalanobis})
        CHECK(anima::parse_frame_metric(anima::to_string(metric)) == metric);
    const std::string message = invalid_argument_message([] { anima::parse_frame_metric("L1"); });
    CHECK(contains(message, "'L1'"));
    CHECK(contains(message, "mahalanobis"));
}

TEST_CASE("frame_features: the root's ground position is zeroed, its height and every rotation kept") {
    const auto& c = walk<double>();
    const auto layout = anima::make_dof_layout(c);
    const matrix<double> all = anima::to_dof_matrix(c, layout);
    const matrix<double> f = anima::frame_features(c);
    REQUIRE(f.rows() == all.rows());
    REQUIRE(f.cols() == all.cols());
    const auto up = static_cast<int>(anima::guess_up_axis(c.skeleton()).up.axis);
    CHECK(up == 1);  // the CMU layout is Y-up
    int zeroed = 0;
    for (std::size_t k = 0; k < layout.size(); ++k) {
        const auto& d = layout.dofs[k];
        const auto col = static_cast<Eigen::Index>(k);
        if (d.joint == 0 && d.type == anima::dof::kind::translation && d.component != up) {
            CHECK(f.col(col).isZero());
            CHECK_FALSE(all.col(col).isZero());  // the walk does travel
            ++zeroed;
        } else {
            CHECK(f.col(col) == all.col(col));
        }
    }
    CHECK(zeroed == 2);
    anima::frame_feature_params keep;
    keep.root_ground_translation = true;
    CHECK(anima::frame_features(c, keep) == all);
    // An explicit up axis: Z up zeroes x and y instead.
    anima::frame_feature_params z_up;
    z_up.up = anima::signed_axis{anima::axis::z, 1};
    const matrix<double> fz = anima::frame_features(c, z_up);
    CHECK(fz.col(0).isZero());
    CHECK(fz.col(1).isZero());
    CHECK(fz.col(2) == all.col(2));
}

// ---------------------------------------------------------------------------
// Eq 3-5
// ---------------------------------------------------------------------------

TEST_CASE("Eq 3: binomial weights match exact integer binomials C(2(n-s), n-r)") {
    for (int n = 1; n <= 14; ++n)
        for (int s = 0; s <= (n + 1) / 2; ++s) {
            CAPTURE(n);
            CAPTURE(s);
            const auto w = anima::binomial_weights<double>(n, s);
            const auto wf = anima::binomial_weights<float>(n, s);
            REQUIRE(w.size() == static_cast<std::size_t>(n));
            REQUIRE(wf.size() == static_cast<std::size_t>(n));
            double total = 0;
            for (int r = 1; r <= n; ++r) total += static_cast<double>(choose(2 * (n - s), n - r));
            double sum = 0;
            for (int r = 1; r <= n; ++r) {
                const double expected = static_cast<double>(choose(2 * (n - s), n - r)) / total;
                CHECK(expected > 0);
                CHECK(w[static_cast<std::size_t>(r - 1)] == doctest::Approx(expected).epsilon(1e-12));
                CHECK(wf[static_cast<std::size_t>(r - 1)] == doctest::Approx(expected).epsilon(1e-6));
                sum += w[static_cast<std::size_t>(r - 1)];
            }
            CHECK(sum == doctest::Approx(1.0).epsilon(1e-12));
            // s = 0 weighs the nearest pair most; otherwise the peak is at r = s.
            const auto peak = static_cast<int>(std::max_element(w.begin(), w.end()) - w.begin()) + 1;
            CHECK(peak == std::max(s, 1));
        }
    // Wide windows: C(2n, n) is far beyond a double, the weights are not.
    for (int n : {600, 5000}) {
        const auto w = anima::binomial_weights<double>(n, 0);
        const auto wf = anima::binomial_weights<float>(n, n / 2);
        CHECK(std::all_of(w.begin(), w.end(), [](double x) { return std::isfinite(x) && x > 0; }));
        CHECK(std::all_of(wf.begin(), wf.end(), [](float x) { return std::isfinite(x) && x > 0; }));
        CHECK(w[0] / w[1] == doctest::Approx(static_cast<double>(n + 2) / (n - 1)));  // C(2n, n-1) / C(2n, n-2)
    }
    CHECK(contains(invalid_argument_message([] { anima::binomial_weights<double>(0, 0); }), "radius"));
    CHECK(contains(invalid_argument_message([] { anima::binomial_weights<double>(4, 3); }), "smoothness"));
    CHECK(contains(invalid_argument_message([] { anima::binomial_weights<double>(4, 3); }), "binomial_weights"));
}

TEST_CASE_TEMPLATE("Eq 3: binomial weights refuse a radius beyond max_binomial_radius", T, float, double) {
    for (const int radius : {std::numeric_limits<int>::max(), anima::max_binomial_radius + 1}) {
        CHECK(invalid_argument_message([&] { (void)anima::binomial_weights<T>(radius, 0); }) ==
              "anima::binomial_weights: radius (n of Eq 3) must be at most 10000000, got " + std::to_string(radius));
    }
    // symmetry_scores caps the radius at the clip's before it weighs pairs.
    anima::symmetry_params<T> p;
    p.radius = std::numeric_limits<int>::max();
    const auto r = anima::symmetry_scores(matrix<T>::Random(50, 3).eval(), T(1) / T(30), p);
    CHECK(r.score.allFinite());
}

TEST_CASE_TEMPLATE("Eq 3-5: banded symmetry equals the brute force over the full distance matrix", T, float, double) {
    struct source {
        const char* name;
        matrix<T> dofs;
        T dt;
    };
    const std::vector<source> sources{
        {"walk 100-260", features(walk<T>()).middleRows(100, 160), walk<T>().frame_time()},
        {"run 0-143", features(run<T>()), run<T>().frame_time()},
        {"walk 9 frames", features(walk<T>()).middleRows(50, 9), walk<T>().frame_time()},
    };
    for (const auto& src : sources)
        for (auto metric : {frame_metric::mahalanobis, frame_metric::l2}) {
            const auto distances =
                anima::distance_matrix(src.dofs, anima::make_frame_distance(src.dofs, src.dt, params_for<T>(metric).distance));
            for (int radius : {1, 2, 3, 7, 10, 16})
                for (int smoothness : {0, 1, (radius + 1) / 2}) {
                    if (smoothness == 1 && (radius + 1) / 2 == 1) continue;  // listed twice
                    CAPTURE(src.name);
                    CAPTURE(anima::to_string(metric));
                    CAPTURE(radius);
                    CAPTURE(smoothness);
                    auto p = params_for<T>(metric, radius, smoothness);
                    const auto result = anima::symmetry_scores(src.dofs, src.dt, p);
                    const auto ref = brute_force(distances, radius, smoothness);
                    check_well_formed(result, src.dofs.rows());
                    CHECK(result.pairs == ref.pairs);
                    const double largest = *std::max_element(ref.weighted.begin(), ref.weighted.end());
                    for (Eigen::Index i = 0; i < src.dofs.rows(); ++i) {
                        const auto k = static_cast<std::size_t>(i);
                        CAPTURE(i);
                        CHECK(static_cast<double>(result.score[i]) ==
                              doctest::Approx(ref.score[k]).epsilon(tolerance<T>(1e-10, 2e-4)));
                        // Frames without pairs report the largest weighted distance.
                        const double weighted = ref.pairs[k] ? ref.weighted[k] : largest;
                        CHECK(static_cast<double>(result.weighted_distance[i]) ==
                              doctest::Approx(weighted).epsilon(tolerance<T>(1e-10, 2e-4)));
                    }
                    for (int window : {0, 3, 25}) {
                        p.candidate_radius = window;
                        const auto with_window = window ? anima::symmetry_scores(src.dofs, src.dt, p) : result;
                        std::vector<std::size_t> frames;
                        for (const auto& c : with_window.candidates) frames.push_back(c.frame);
                        // Candidates need the fullest window the clip allows.
                        const int full = std::min(radius, static_cast<int>((src.dofs.rows() - 1) / 2));
                        CHECK(frames == reference_candidates(with_window.score, with_window.pairs, window ? window : radius, full));
                        CHECK(std::is_sorted(with_window.candidates.begin(), with_window.candidates.end(),
                                             [](const auto& a, const auto& b) { return a.score > b.score; }));
                    }
                }
        }
}

TEST_CASE_TEMPLATE("Eq 5: turning_candidates keeps first maxima of plateaus and validates its input", T, float, double) {
    vector<T> s(12);
    s << T(0), T(0.5), T(0.9), T(0.9), T(0.2), T(0.1), T(0.3), T(0.8), T(0.4), T(0.8), T(0.6), T(0);
    std::vector<int> pairs{0, 1, 2, 3, 4, 5, 5, 4, 3, 2, 1, 0};
    auto c = anima::turning_candidates(s, pairs, 1);
    std::vector<std::size_t> frames;
    for (const auto& x : c) frames.push_back(x.frame);
    // 2 (first of the 0.9 plateau), 7 and 9 (0.8 each, earlier first), 5 is not above 4.
    CHECK(frames == std::vector<std::size_t>{2, 7, 9});
    CHECK(c[0].probability == T(0.45));
    frames.clear();
    for (const auto& x : anima::turning_candidates(s, pairs, 2)) frames.push_back(x.frame);
    CHECK(frames == std::vector<std::size_t>{2, 7});
    // Frames without pairs never turn, however high their score, and do not
    // suppress their neighbours either.
    s[0] = T(1);
    frames.clear();
    for (const auto& x : anima::turning_candidates(s, pairs, 20)) frames.push_back(x.frame);
    CHECK(frames == std::vector<std::size_t>{2});
    s[0] = T(0);
    frames.clear();
    for (const auto& x : anima::turning_candidates(s, pairs, 20)) frames.push_back(x.frame);
    CHECK(frames == std::vector<std::size_t>{2});

    CHECK(contains(invalid_argument_message([&] { anima::turning_candidates(s, std::vector<int>(3, 1), 1); }), "pair counts"));
    CHECK(contains(invalid_argument_message([&] { anima::turning_candidates(s, pairs, 0); }), "window"));
    CHECK(contains(invalid_argument_message([&] { anima::turning_candidates(s, pairs, 1, 0); }), "min_pairs"));
    // The first eligible frame on a falling slope is no candidate, although
    // every eligible frame of its window scores lower.
    {
        vector<T> slope(9);
        slope << T(0), T(0.7), T(0.9), T(0.8), T(0.7), T(0.6), T(0.5), T(0.4), T(0);
        const std::vector<int> slope_pairs{0, 1, 2, 3, 4, 4, 3, 2, 1};
        CHECK(anima::turning_candidates(slope, slope_pairs, 3, 3).empty());
        CHECK(reference_candidates(slope, slope_pairs, 3, 3).empty());
        std::vector<std::size_t> loose;
        for (const auto& x : anima::turning_candidates(slope, slope_pairs, 3, 1)) loose.push_back(x.frame);
        CHECK(loose == std::vector<std::size_t>{2});
    }
    // Frames judged on fewer than min_pairs pairs drop out: 2 and 9 (3 and 2
    // pairs) go, 7 stays.
    frames.clear();
    for (const auto& x : anima::turning_candidates(s, pairs, 2, 4)) frames.push_back(x.frame);
    CHECK(frames == std::vector<std::size_t>{7});
}

TEST_CASE_TEMPLATE("Eq 5: by default a candidate has the full window of pairs, so clip ends do not win", T, float, double) {
    const matrix<T> m = features(walk<T>());
    auto p = params_for<T>(frame_metric::mahalanobis);
    const auto strict = anima::symmetry_scores(m, walk<T>().frame_time(), p);
    REQUIRE_FALSE(strict.candidates.empty());
    for (const auto& c : strict.candidates) {
        CHECK(c.frame >= static_cast<std::size_t>(p.radius));
        CHECK(c.frame + static_cast<std::size_t>(p.radius) < walk<T>().frames());
    }
    // With one pair allowed, a frame next to the clip's start looks symmetric
    // by accident and would be among the candidates.
    p.min_pairs = 1;
    const auto loose = anima::symmetry_scores(m, walk<T>().frame_time(), p);
    CHECK(std::any_of(loose.candidates.begin(), loose.candidates.end(),
                      [&](const auto& c) { return c.frame < static_cast<std::size_t>(p.radius) ||
                                                  c.frame + static_cast<std::size_t>(p.radius) >= walk<T>().frames(); }));
    p.min_pairs = p.radius + 1;
    CHECK(contains(invalid_argument_message([&] { anima::symmetry_scores(m, T(0.01), p); }), "min_pairs"));
}

TEST_CASE_TEMPLATE("candidate_min_pairs: the radius by default, capped by the clip, or as given", T, float, double) {
    anima::symmetry_params<T> p;
    p.radius = 10;
    CHECK(anima::candidate_min_pairs(p, 343) == 10);
    CHECK(anima::candidate_min_pairs(p, 21) == 10);  // the middle frame has 10 pairs
    CHECK(anima::candidate_min_pairs(p, 20) == 9);
    CHECK(anima::candidate_min_pairs(p, 5) == 2);
    CHECK(anima::candidate_min_pairs(p, 1) == 1);  // at least 1
    CHECK(anima::candidate_min_pairs(p, 0) == 1);
    p.min_pairs = 4;
    CHECK(anima::candidate_min_pairs(p, 343) == 4);
    CHECK(anima::candidate_min_pairs(p, 5) == 4);  // as given, even above what the clip has
    // It is what symmetry_scores uses: every candidate of a short clip has
    // at least that many pairs.
    const matrix<T> m = features(walk<T>()).topRows(31);
    anima::symmetry_params<T> q = params_for<T>(frame_metric::mahalanobis);
    q.radius = 20;
    const auto r = anima::symmetry_scores(m, walk<T>().frame_time(), q);
    const int need = anima::candidate_min_pairs(q, 31);
    CHECK(need == 15);
    REQUIRE_FALSE(r.candidates.empty());
    for (const auto& c : r.candidates) CHECK(r.pairs[c.frame] >= need);
}

TEST_CASE_TEMPLATE("a real clip played forwards to frame k and back is most symmetric at k, both metrics", T, float, double) {
    struct trial {
        const anima::clip<T>* source;
        std::size_t first, k, back_to;
    };
    // back_to > first: the backward part is shorter, the turn is not centred.
    const std::vector<trial> trials{{&walk<T>(), 0, 60, 0}, {&walk<T>(), 100, 150, 100}, {&walk<T>(), 30, 300, 200},
                                    {&run<T>(), 0, 40, 0},  {&run<T>(), 20, 100, 70},    {&run<T>(), 60, 82, 60}};
    anima::resequence_params recorded;
    recorded.root = anima::root_path::recorded;
    for (const auto& t : trials)
        for (bool repeat_turn : {false, true})
            for (auto metric : {frame_metric::mahalanobis, frame_metric::l2}) {
                CAPTURE(t.source->frames());
                CAPTURE(t.first);
                CAPTURE(t.k);
                CAPTURE(repeat_turn);
                CAPTURE(anima::to_string(metric));
                const auto stream = there_and_back(t.first, t.first + t.k, t.back_to, repeat_turn);
                const auto c = anima::resequence(*t.source, stream, recorded);
                const auto result = anima::symmetry_scores(c, params_for<T>(metric));
                check_well_formed(result, static_cast<Eigen::Index>(c.frames()));
                const auto k = static_cast<Eigen::Index>(t.k);
                if (!repeat_turn) {
                    Eigen::Index best = 0;
                    result.score.maxCoeff(&best);
                    CHECK(best >= k - 1);
                    CHECK(best <= k + 1);
                    // An exact mirror: every pair around k is the same frame twice.
                    CHECK(result.score[k] == T(1));
                    REQUIRE_FALSE(result.candidates.empty());
                    CHECK(result.candidates.front().frame == t.k);
                } else {
                    // The turning frame shown twice: the mirror is half a frame
                    // off, k scores below 1 and a natural turning point of the
                    // walk may score higher; k or k+1 must still be a candidate.
                    CHECK(std::any_of(result.candidates.begin(), result.candidates.end(),
                                      [&](const auto& c) { return c.frame == t.k || c.frame == t.k + 1; }));
                }
            }
}

TEST_CASE_TEMPLATE("a constant clip and a frozen DOF give finite scores in [0, 1]", T, float, double) {
    for (auto metric : {frame_metric::mahalanobis, frame_metric::l2}) {
        CAPTURE(anima::to_string(metric));
        const auto p = params_for<T>(metric);
        // The walk's frame 80 held for 50 frames.
        anima::clip<T> held = walk<T>().slice(80, 81);
        held.resize(50);
        const auto r = anima::symmetry_scores(held, p);
        check_well_formed(r, 50);
        for (Eigen::Index i = 0; i < 50; ++i) {
            CHECK(r.weighted_distance[i] == T(0));
            CHECK(r.score[i] == (i == 0 || i == 49 ? T(0) : T(1)));
        }
        // One plateau: one candidate, its first frame with a full window.
        REQUIRE(r.candidates.size() == 1);
        CHECK(r.candidates[0].frame == static_cast<std::size_t>(p.radius));

        // A real clip with a rotation DOF frozen (the root's ground DOFs are
        // zero in the features already): whatever value it is frozen at.
        matrix<T> m = features(walk<T>()).topRows(200);
        m.col(10).setConstant(T(0.3));
        const auto frozen = anima::symmetry_scores(m, walk<T>().frame_time(), p);
        check_well_formed(frozen, 200);
        CHECK_FALSE(frozen.candidates.empty());
        CHECK(frozen.score.minCoeff() < frozen.score.maxCoeff());
        m.col(10).setConstant(T(-2));
        const auto elsewhere = anima::symmetry_scores(m, walk<T>().frame_time(), p);
        for (Eigen::Index i = 0; i < 200; ++i)
            CHECK(static_cast<double>(elsewhere.score[i]) == doctest::Approx(static_cast<double>(frozen.score[i])));

        // Motion so small that 1 / variance would overflow: weights stay
        // finite, so do the scores.
        matrix<T> tiny = matrix<T>::Zero(20, 3);
        for (Eigen::Index f = 1; f < 20; f += 2) tiny(f, 0) = std::sqrt(std::numeric_limits<T>::min());
        CHECK(anima::velocity_precision(tiny, T(1)).allFinite());
        check_well_formed(anima::symmetry_scores(tiny, T(1), p), 20);
    }
}

TEST_CASE_TEMPLATE("empty, one-, two- and three-frame clips have defined results", T, float, double) {
    for (auto metric : {frame_metric::mahalanobis, frame_metric::l2}) {
        CAPTURE(anima::to_string(metric));
        const auto p = params_for<T>(metric);
        const matrix<T> m = features(walk<T>()).topRows(3);
        const T dt = T(0.01);

        const auto empty = anima::symmetry_scores(matrix<T>(0, m.cols()), dt, p);
        CHECK(empty.score.size() == 0);
        CHECK(empty.pairs.empty());
        CHECK(empty.candidates.empty());
        const auto empty_clip = anima::symmetry_scores(walk<T>().slice(0, 0), p);
        CHECK(empty_clip.score.size() == 0);

        for (Eigen::Index n : {1, 2}) {
            const auto r = anima::symmetry_scores(m.topRows(n), dt, p);
            check_well_formed(r, n);
            CHECK(r.score.isZero());
            CHECK(r.weighted_distance.isZero());
            CHECK(r.pairs == std::vector<int>(static_cast<std::size_t>(n), 0));
            CHECK(r.candidates.empty());
        }
        // Three frames: one pair, at the middle frame, which is then the least
        // symmetric frame there is (score 0) unless frames 0 and 2 are equal.
        const auto three = anima::symmetry_scores(m, dt, p);
        check_well_formed(three, 3);
        CHECK(three.pairs == std::vector<int>{0, 1, 0});
        CHECK(three.score[1] == T(0));
        CHECK(three.candidates.empty());
        matrix<T> mirrored = m;
        mirrored.row(2) = m.row(0);
        const auto sym = anima::symmetry_scores(mirrored, dt, p);
        CHECK(sym.score[1] == T(1));
        REQUIRE(sym.candidates.size() == 1);
        CHECK(sym.candidates[0].frame == 1);

        // No DOF at all: nothing ever differs.
        const auto no_dofs = anima::symmetry_scores(matrix<T>(7, 0), dt, p);
        check_well_formed(no_dofs, 7);
        CHECK(no_dofs.score[3] == T(1));
    }
}

TEST_CASE_TEMPLATE("symmetry_scores: bad parameters and input throw anima::invalid_argument", T, float, double) {
    const matrix<T> m = features(walk<T>()).topRows(40);
    const T dt = T(0.01);
    const auto message = [&](const anima::symmetry_params<T>& p, const matrix<T>& dofs = {}, T frame_time = T(0.01)) {
        return invalid_argument_message([&] { anima::symmetry_scores(dofs.size() ? dofs : m, frame_time, p); });
    };
    auto p = params_for<T>(frame_metric::mahalanobis);
    for (int radius : {0, -1, INT_MIN}) {
        p.radius = radius;
        CHECK(contains(message(p), "radius"));
    }
    p.radius = 10;
    for (int s : {-1, 6, 10, INT_MAX}) {
        p.smoothness = s;
        const std::string text = message(p);
        CHECK(contains(text, "smoothness"));
        CHECK(contains(text, "[0, 5]"));
    }
    p.smoothness = 5;
    CHECK(message(p).empty());
    p.smoothness = 0;
    p.candidate_radius = -1;
    CHECK(contains(message(p), "candidate radius"));
    p.candidate_radius = 0;
    CHECK(contains(message(p, m, T(0)), "frame time"));
    matrix<T> bad = m;
    bad(12, 3) = std::numeric_limits<T>::quiet_NaN();
    CHECK(contains(message(p, bad), "frame 12"));
    p.distance.regularization = T(2);
    CHECK(contains(message(p), "regularization"));
    p.distance = {};
    p.distance.metric = frame_metric::l2;
    p.distance.block_size = 5;
    CHECK(contains(message(p), "block size"));
    p.distance.block_size = 3;

    // Squared distances past the scalar's range: an error, not a NaN score.
    matrix<T> huge = m;
    huge.row(20) *= std::sqrt(std::numeric_limits<T>::max());
    CHECK(contains(message(p, huge), "overflow"));

    // A radius far beyond the clip is fine (and allocates nothing for it);
    // so is the widest smoothness allowed for it, where 2(n-s) would overflow an int.
    for (int s : {0, INT_MAX / 2}) {
        p.radius = INT_MAX;
        p.smoothness = s;
        const auto r = anima::symmetry_scores(m, dt, p);
        check_well_formed(r, m.rows());
        for (Eigen::Index i = 0; i < m.rows(); ++i)
            CHECK(r.pairs[static_cast<std::size_t>(i)] == std::min<Eigen::Index>(i, m.rows() - 1 - i));
    }
    p.smoothness = INT_MAX / 2 + 2;
    CHECK(contains(message(p), "smoothness"));
}

TEST_CASE("every clip of the shared data set: finite scores and turning candidates, both metrics") {
    const std::filesystem::path folder = std::filesystem::path(ANIMA_SHARED_DATA_DIR) / "bvh";
    if (!std::filesystem::is_directory(folder)) {
        MESSAGE("skipped: " << folder.string() << " not found");
        return;
    }
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(folder))
        if (entry.path().extension() == ".bvh") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    REQUIRE_FALSE(files.empty());
    for (const auto& file : files) {
        CAPTURE(file.filename().string());
        // Frames 0-5 of the Daz clips are a T-pose and the blend out of it.
        const auto full = anima::read_bvh<double>(file.string());
        const auto c = full.slice(10, full.frames());
        for (auto metric : {frame_metric::mahalanobis, frame_metric::l2}) {
            CAPTURE(anima::to_string(metric));
            const auto r = anima::symmetry_scores(c, params_for<double>(metric));
            check_well_formed(r, static_cast<Eigen::Index>(c.frames()));
            CHECK(r.candidates.size() >= 1);
            if (r.candidates.size() >= 2) {
                anima::symmetric_playback<double> playback(c.frames(), r.candidates);
                for (std::size_t f : playback.take(3 * c.frames())) {
                    CHECK(f >= playback.first_turning_frame());
                    CHECK(f <= playback.last_turning_frame());
                }
            }
        }
    }
}

TEST_CASE("symmetry_scores on float mocap with subnormal components: double's scores, the caller's mode kept") {
    // Squares of the run's 1e-19-degree channels are subnormal in float;
    // symmetry_scores flushes them inside its own scope.
    const auto f = anima::read_bvh<float>(anima_test::bundled("run_cmu_09_01.bvh"));
    const auto d = anima::read_bvh<double>(anima_test::bundled("run_cmu_09_01.bvh"));
    REQUIRE(anima_test::gradual_underflow());
    const auto sf = anima::symmetry_scores(f);
    CHECK(anima_test::gradual_underflow());
    const auto sd = anima::symmetry_scores(d);
    REQUIRE(sf.score.size() == sd.score.size());
    CHECK((sf.score.template cast<double>() - sd.score).cwiseAbs().maxCoeff() < 1e-3);
}
