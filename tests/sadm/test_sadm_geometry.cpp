// The geometric building blocks of SADM: PGM/PPM and .pts files, bilinear
// sampling, block-mean resampling, PCA against Eigen's dense SVD, Procrustes alignment and its
// invariances, Delaunay triangulation against brute-force properties, and
// the piecewise-affine warp.
#include "sadm_test_support.hpp"

#include <anima/image/bilinear.hpp>
#include <anima/image/block_mean.hpp>
#include <anima/image/pnm.hpp>
#include <anima/sadm/delaunay.hpp>
#include <anima/sadm/landmarks.hpp>
#include <anima/sadm/pca.hpp>
#include <anima/sadm/piecewise_affine_warp.hpp>
#include <anima/sadm/procrustes.hpp>

#include <doctest/doctest.h>

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace {

using namespace sadm_test;

std::string parse_error_message(const std::string& text) {
    try {
        anima::parse_pnm(text, "img.pgm");
    } catch (const anima::parse_error& e) {
        return e.what();
    }
    return "";
}

// ---------------------------------------------------------------------------
// Images
// ---------------------------------------------------------------------------

TEST_CASE("pnm: binary and text PGM/PPM decode to the same pixels; writing reads back") {
    const auto p5 = anima::parse_pnm(std::string("P5\n# comment\n3 2\n255\n") + std::string("\x00\x10\x20\x30\x40\xff", 6));
    CHECK(p5.pixels.width == 3);
    CHECK(p5.pixels.height == 2);
    CHECK(p5.pixels(2, 1) == 255);
    const auto p2 = anima::parse_pnm("P2\n3 2\n255\n0 16 32\n48 64 255\n");
    CHECK(p2.pixels.pixels == p5.pixels.pixels);
    const auto p3 = anima::parse_pnm("P3 1 1 255 10 20 30");
    const auto grey = anima::to_grey<double>(p3.pixels);
    CHECK(grey(0, 0) == doctest::Approx(0.299 * 10 + 0.587 * 20 + 0.114 * 30));
    const auto p16 = anima::parse_pnm(std::string("P5 1 1 1000\n") + std::string("\x03\xe8", 2));
    CHECK(p16.pixels(0, 0) == 1000);
    anima::image<unsigned char> img(4, 3, 3);
    for (std::size_t k = 0; k < img.pixels.size(); ++k) img.pixels[k] = static_cast<unsigned char>(k * 7);
    const auto back = anima::parse_pnm(anima::format_pnm(img));
    CHECK(back.pixels.channels == 3);
    CHECK(std::equal(img.pixels.begin(), img.pixels.end(), back.pixels.pixels.begin(), back.pixels.pixels.end()));
}

TEST_CASE("pnm: malformed files give file:line messages") {
    CHECK(contains(parse_error_message("P7\n1 1\n255\n"), "img.pgm:1:"));
    CHECK(contains(parse_error_message("P2\n2 1\n255\n0\n300\n"), "img.pgm:5: sample 300 exceeds maxval 255"));
    CHECK(contains(parse_error_message("P2\n2 1\n255\n0\n"), "img.pgm:5: file ends before the sample"));
    CHECK(contains(parse_error_message("P5\n2 2\n255\nab"), "file ends inside the pixel data"));
    CHECK(contains(parse_error_message("P5\n0 2\n255\n"), "img.pgm:2: image size 0 x 2"));
    CHECK(contains(parse_error_message("P5\n1 1\n0\n"), "maxval 0"));
    CHECK(contains(parse_error_message("P"), "img.pgm:1: file ends before the magic number"));
    CHECK_THROWS_AS(anima::read_pnm("/nonexistent/x.pgm"), anima::io_error);
    anima::grey_image<double> g(1, 1);
    g(0, 0) = std::nan("");
    CHECK(contains(invalid_argument_message([&] { anima::to_bytes(g, "write"); }), "pixel (x 0, y 0) is not finite"));
}

TEST_CASE_TEMPLATE("bilinear sampling is exact on affine images and clamps at the border", T, float, double) {
    matrix<T> img(5, 7);
    for (Eigen::Index y = 0; y < 5; ++y)
        for (Eigen::Index x = 0; x < 7; ++x) img(y, x) = T(2) * static_cast<T>(x) - T(3) * static_cast<T>(y) + T(1);
    CHECK(anima::sample_bilinear(img, T(2.25), T(3.5)) == doctest::Approx(2 * 2.25 - 3 * 3.5 + 1));
    CHECK(anima::sample_bilinear(img, T(6), T(4)) == img(4, 6));
    CHECK(anima::sample_bilinear(img, T(-3), T(-2)) == img(0, 0));
    CHECK(anima::sample_bilinear(img, T(100), T(1)) == img(1, 6));
    CHECK(anima::sample_bilinear(img, std::numeric_limits<T>::quiet_NaN(), T(0)) == img(0, 0));
}

TEST_CASE_TEMPLATE("block_mean_resample averages blocks when shrinking and repeats values when enlarging", T, float,
                   double) {
    matrix<T> m(4, 6);
    for (Eigen::Index y = 0; y < 4; ++y)
        for (Eigen::Index x = 0; x < 6; ++x) m(y, x) = static_cast<T>(10 * y + x);
    const matrix<T> half = anima::block_mean_resample(m, 2, 3);  // 2 x 2 blocks
    CHECK(half(0, 0) == doctest::Approx((0 + 1 + 10 + 11) / 4.0));
    CHECK(half(1, 2) == doctest::Approx((24 + 25 + 34 + 35) / 4.0));
    // 6 columns to 4: blocks of 1, 2, 1 and 2 columns ([p 6 / 4, (p + 1) 6 / 4)).
    const matrix<T> uneven = anima::block_mean_resample(m, 4, 4);
    CHECK(uneven(0, 0) == m(0, 0));
    CHECK(uneven(0, 1) == doctest::Approx((1 + 2) / 2.0));
    CHECK(uneven(3, 3) == doctest::Approx((34 + 35) / 2.0));
    const matrix<T> twice = anima::block_mean_resample(m, 8, 12);
    for (Eigen::Index y = 0; y < 8; ++y)
        for (Eigen::Index x = 0; x < 12; ++x) CHECK(twice(y, x) == m(y / 2, x / 2));
    CHECK(anima::block_mean_resample(m, 4, 6) == m);
    CHECK(anima::block_mean_resample(m, 1, 1)(0, 0) == doctest::Approx(m.mean()));
    CHECK_THROWS_AS(anima::block_mean_resample(m, 0, 3), anima::invalid_argument);
    CHECK_THROWS_AS(anima::block_mean_resample(matrix<T>(0, 0), 2, 2), anima::invalid_argument);
}

// ---------------------------------------------------------------------------
// Landmarks
// ---------------------------------------------------------------------------

std::string pts_error(const std::string& text) {
    try {
        anima::parse_pts<double>(text, "f.pts");
    } catch (const anima::parse_error& e) {
        return e.what();
    }
    return "";
}

TEST_CASE_TEMPLATE("pts: parse, format and read back exactly", T, float, double) {
    const auto s = anima::parse_pts<T>("version: 1\nn_points: 3\n{\n1.5 2\n-3 4.25\r\n5 6\n}\n");
    REQUIRE(s.rows() == 3);
    CHECK(s(1, 0) == T(-3));
    CHECK(s(1, 1) == T(4.25));
    anima::random_source rng(3);
    const anima::landmark_set<T> r = random_points<T>(rng, 68, 300);
    CHECK(anima::parse_pts<T>(anima::format_pts(r)) == r);
    CHECK(anima::from_shape_vector(anima::to_shape_vector(r)) == r);
}

TEST_CASE("pts: malformed files name the line") {
    CHECK(contains(pts_error("n_points: 3\n"), "f.pts:1: expected 'version: 1'"));
    CHECK(contains(pts_error("version: 1\nn_points: -2\n"), "f.pts:2: expected 'n_points: N'"));
    CHECK(contains(pts_error("version: 1\nn_points: 2\n{\n1 2\n}\n"), "f.pts:5: '}' after 1 points"));
    CHECK(contains(pts_error("version: 1\nn_points: 1\n{\n1 x\n}\n"), "f.pts:4: expected two numbers"));
    CHECK(contains(pts_error("version: 1\nn_points: 1\n{\n1 nan\n}\n"), "f.pts:4: expected two numbers"));
    CHECK(contains(pts_error("version: 1\nn_points: 1\n{\n1 2\n"), "file ends before '}'"));
    CHECK(contains(pts_error("version: 1\nn_points: 1\n{\n1 2 3\n}\n"), "f.pts:4: expected two numbers"));
}

// ---------------------------------------------------------------------------
// PCA
// ---------------------------------------------------------------------------

template <class T>
void check_against_svd(const matrix<T>& x) {
    const auto model = anima::pca<T>::fit(x, {T(1), 0});
    const matrix<double> centred = x.template cast<double>().rowwise() - x.template cast<double>().colwise().mean();
    Eigen::JacobiSVD<matrix<double>> svd(centred, Eigen::ComputeThinV);
    const double denom = static_cast<double>(x.rows() - 1);
    const double tol = std::is_same_v<T, double> ? 1e-9 : 2e-3;
    const Eigen::Index rank = std::min(x.rows() - 1, x.cols());
    REQUIRE(model.size() == rank);
    for (Eigen::Index k = 0; k < rank; ++k) {
        const double expected = svd.singularValues()(k) * svd.singularValues()(k) / denom;
        CHECK(static_cast<double>(model.eigenvalues()(k)) == doctest::Approx(expected).epsilon(tol));
        // Same direction up to sign.
        const double dot = std::abs(model.components().col(k).template cast<double>().dot(svd.matrixV().col(k)));
        CHECK(dot == doctest::Approx(1.0).epsilon(tol));
    }
    const matrix<T> ptp = model.components().transpose() * model.components();
    CHECK((ptp - matrix<T>::Identity(rank, rank)).cwiseAbs().maxCoeff() < T(tol));
    // With every component kept, project/reconstruct is the identity on the data.
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
        const vector<T> row = x.row(i).transpose();
        CHECK((model.reconstruct(model.project(row)) - row).norm() < T(tol) * (T(1) + row.norm()) * T(10));
    }
    CHECK(static_cast<double>(model.total_variance()) == doctest::Approx(centred.squaredNorm() / denom).epsilon(tol));
}

TEST_CASE_TEMPLATE("pca agrees with Eigen's SVD with fewer samples than dimensions and more", T, float, double) {
    anima::random_source rng(11);
    check_against_svd<T>(random_matrix<T>(rng, 6, 40));   // Gram route
    check_against_svd<T>(random_matrix<T>(rng, 30, 5));   // covariance route
    check_against_svd<T>(random_matrix<T>(rng, 7, 7));
}

TEST_CASE_TEMPLATE("pca keeps components by retained variance or count", T, float, double) {
    anima::random_source rng(5);
    // Planted spectrum: variances 100, 25, 4, 1, 0.01 along random orthonormal axes.
    const matrix<T> q = Eigen::HouseholderQR<matrix<T>>(random_matrix<T>(rng, 12, 5)).householderQ() * matrix<T>::Identity(12, 5);
    const double sd[] = {10, 5, 2, 1, 0.1};
    matrix<T> x(400, 12);
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
        vector<T> v = vector<T>::Constant(12, T(3));
        for (int k = 0; k < 5; ++k) v += static_cast<T>(sd[k] * gaussian(rng)) * q.col(k);
        x.row(i) = v.transpose();
    }
    const auto all = anima::pca<T>::fit(x, {T(1), 0});
    const T total = all.eigenvalues().sum();
    const auto by_fraction = anima::pca<T>::fit(x, {T(0.95), 0});
    // The fewest leading components reaching 95 %.
    T sum = 0;
    Eigen::Index expected = 0;
    while (sum < T(0.95) * total) sum += all.eigenvalues()(expected++);
    CHECK(by_fraction.size() == expected);
    CHECK(by_fraction.explained_fraction() >= T(0.95) - T(1e-4));
    CHECK(anima::pca<T>::fit(x, {T(0.5), 3}).size() == 3);
    CHECK(anima::pca<T>::fit(x, {T(0.5), 50}).size() == 5);  // capped at the rank
    CHECK(static_cast<double>(all.eigenvalues()(0)) == doctest::Approx(100).epsilon(0.2));
}

TEST_CASE_TEMPLATE("pca: one sample, one dimension, constant data", T, float, double) {
    const matrix<T> one = matrix<T>::Constant(1, 9, T(2));
    const auto a = anima::pca<T>::fit(one);
    CHECK(a.size() == 0);
    CHECK(a.reconstruct(vector<T>()) == vector<T>::Constant(9, T(2)));
    CHECK(a.project(vector<T>::Zero(9)).size() == 0);
    const auto c = anima::pca<T>::fit(matrix<T>::Constant(20, 4, T(-1)));
    CHECK(c.size() == 0);
    CHECK(c.explained_fraction() == T(1));
    matrix<T> line(5, 1);
    line << 1, 2, 3, 4, 5;
    const auto d1 = anima::pca<T>::fit(line);
    REQUIRE(d1.size() == 1);
    CHECK(d1.eigenvalues()(0) == doctest::Approx(2.5));
    CHECK(d1.project(vector<T>::Constant(1, T(5)))(0) == doctest::Approx(2));
    CHECK(contains(invalid_argument_message([] { anima::pca<T>::fit(matrix<T>(0, 3)); }), "at least one sample"));
    matrix<T> bad = matrix<T>::Zero(2, 2);
    bad(1, 0) = std::numeric_limits<T>::infinity();
    CHECK(contains(invalid_argument_message([&] { anima::pca<T>::fit(bad); }), "sample 1, element 0 is not finite"));
    CHECK(contains(invalid_argument_message([&] { anima::pca<T>::fit(line, {T(0), 0}); }), "retained_variance"));
    CHECK(contains(invalid_argument_message([&] { d1.project(vector<T>::Zero(2)); }), "has size 2, expected 1"));
}

TEST_CASE_TEMPLATE("pca keeps a small spread about a large offset, drops rounding noise, refuses overflow", T, float,
                   double) {
    // A spread of 1e-3 (float: 10) about an offset of 1e6 is information: the
    // rank floor is centring's rounding, not the offset's square times epsilon.
    const T offset = T(1e6), spread = static_cast<T>(std::is_same_v<T, float> ? 10.0 : 1e-3);
    matrix<T> x(10, 3);
    for (Eigen::Index i = 0; i < x.rows(); ++i)
        x.row(i) << offset + spread * static_cast<T>(i), offset - spread * static_cast<T>(i % 3), offset;
    const auto p = anima::pca<T>::fit(x);
    CHECK(p.size() == 2);
    CHECK(p.explained_fraction() > T(0.99));
    // The same samples but for one unit in the last place: no components.
    matrix<T> noise = matrix<T>::Constant(10, 3, offset);
    for (Eigen::Index i = 0; i < noise.rows(); i += 2) noise(i, 1) = std::nextafter(offset, T(2) * offset);
    CHECK(anima::pca<T>::fit(noise).size() == 0);
    // Squares past the type's range: refused, not 0 components.
    const T huge = static_cast<T>(std::is_same_v<T, float> ? 1e19 : 1e155);
    matrix<T> wide(4, 2);
    wide << huge, T(0), -huge, T(1), huge, T(2), -huge, T(3);
    CHECK(contains(invalid_argument_message([&] { (void)anima::pca<T>::fit(wide); }), "overflows in this precision"));
}

TEST_CASE_TEMPLATE("pca clamp bounds every parameter to +-3 sqrt(lambda) (Eq 6)", T, float, double) {
    anima::random_source rng(8);
    const auto model = anima::pca<T>::fit(random_matrix<T>(rng, 10, 30));
    for (int trial = 0; trial < 50; ++trial) {
        const vector<T> b = random_matrix<T>(rng, model.size(), 1, 10);
        const vector<T> c = model.clamp(b);
        for (Eigen::Index i = 0; i < b.size(); ++i) {
            const T bound = T(3) * std::sqrt(model.eigenvalues()(i));
            CHECK(std::abs(c(i)) <= bound);
            if (std::abs(b(i)) <= bound) CHECK(c(i) == b(i));  // inside: untouched
            else CHECK(std::abs(c(i)) == doctest::Approx(bound));
        }
    }
    vector<T> nan = vector<T>::Zero(model.size());
    nan(0) = std::numeric_limits<T>::quiet_NaN();
    CHECK(model.clamp(nan)(0) == T(0));
}

// ---------------------------------------------------------------------------
// Procrustes
// ---------------------------------------------------------------------------

template <class T>
anima::similarity2<T> random_similarity(anima::random_source& rng) {
    anima::similarity2<T> s;
    s.scale = static_cast<T>(0.2 + 3 * rng.uniform());
    s.angle = static_cast<T>(6 * rng.uniform() - 3);
    s.translation << static_cast<T>(100 * rng.uniform() - 50), static_cast<T>(100 * rng.uniform() - 50);
    return s;
}

TEST_CASE_TEMPLATE("align_similarity recovers a planted similarity and never reflects", T, float, double) {
    anima::random_source rng(21);
    const T tol = tolerance<T>(1e-10, 2e-3);
    for (int trial = 0; trial < 20; ++trial) {
        const anima::landmark_set<T> a = random_points<T>(rng, 12);
        const auto s = random_similarity<T>(rng);
        const auto found = anima::align_similarity(a, s.apply(a));
        CHECK((found.apply(a) - s.apply(a)).cwiseAbs().maxCoeff() < tol * T(100));
        CHECK(found.scale == doctest::Approx(s.scale).epsilon(tol));
        const auto round = s.inverse().apply(s.apply(a));
        CHECK((round - a).cwiseAbs().maxCoeff() < tol * T(100));
    }
    // A mirror image is not reachable: the best proper fit leaves a residual.
    const anima::landmark_set<T> a = random_points<T>(rng, 12);
    anima::landmark_set<T> mirrored = a;
    mirrored.col(0) *= T(-1);
    CHECK((anima::align_similarity(a, mirrored).apply(a) - mirrored).norm() > T(1));
    CHECK(contains(invalid_argument_message([&] {
                       anima::align_similarity<T>(anima::landmark_set<T>::Ones(4, 2), a.topRows(4));
                   }),
                   "all coincide"));
}

TEST_CASE_TEMPLATE("generalised Procrustes is invariant to rotation, scale and translation of any input", T, float, double) {
    anima::random_source rng(4);
    const anima::landmark_set<T> base = random_points<T>(rng, 20);
    std::vector<anima::landmark_set<T>> shapes;
    for (int k = 0; k < 8; ++k)
        shapes.push_back(random_similarity<T>(rng).apply(base + random_points<T>(rng, 20, 0.8)));
    const auto ref = anima::generalized_procrustes(shapes);
    CHECK(ref.converged);
    CHECK(ref.mean.norm() == doctest::Approx(1).epsilon(tolerance<T>(1e-12, 1e-5)));
    CHECK(ref.mean.colwise().mean().norm() < tolerance<T>(1e-12, 1e-6));
    const T tol = tolerance<T>(1e-9, 2e-4);
    // Moving a later shape changes nothing.
    auto moved = shapes;
    moved[5] = random_similarity<T>(rng).apply(moved[5]);
    const auto r = anima::generalized_procrustes(moved);
    CHECK((r.mean - ref.mean).cwiseAbs().maxCoeff() < tol);
    for (std::size_t k = 0; k < shapes.size(); ++k) CHECK((r.aligned[k] - ref.aligned[k]).cwiseAbs().maxCoeff() < tol);
    // Moving the first (which fixes the frame) moves everything by one common similarity.
    moved = shapes;
    moved[0] = random_similarity<T>(rng).apply(moved[0]);
    const auto f = anima::generalized_procrustes(moved);
    const auto common = anima::align_similarity(f.mean, ref.mean);
    CHECK(common.scale == doctest::Approx(1).epsilon(tol));
    for (std::size_t k = 0; k < shapes.size(); ++k)
        CHECK((common.apply(f.aligned[k]) - ref.aligned[k]).cwiseAbs().maxCoeff() < tol);
    // The aligned shapes are closer to the mean than any other similarity would make them.
    for (std::size_t k = 0; k < shapes.size(); ++k) {
        const auto again = anima::align_similarity(ref.aligned[k], ref.mean);
        CHECK(again.scale == doctest::Approx(1).epsilon(tol));
        CHECK(std::abs(again.angle) < tol);
    }
    CHECK(contains(invalid_argument_message([] { anima::generalized_procrustes<T>({}); }), "no shapes"));
}

// ---------------------------------------------------------------------------
// Delaunay
// ---------------------------------------------------------------------------

template <class T>
std::vector<int> convex_hull(const anima::landmark_set<T>& p) {
    std::vector<int> idx(static_cast<std::size_t>(p.rows()));
    for (std::size_t k = 0; k < idx.size(); ++k) idx[k] = static_cast<int>(k);
    std::sort(idx.begin(), idx.end(), [&](int a, int b) { return p(a, 0) < p(b, 0) || (p(a, 0) == p(b, 0) && p(a, 1) < p(b, 1)); });
    const auto cross = [&](int o, int a, int b) {
        return (static_cast<double>(p(a, 0)) - p(o, 0)) * (static_cast<double>(p(b, 1)) - p(o, 1)) -
               (static_cast<double>(p(a, 1)) - p(o, 1)) * (static_cast<double>(p(b, 0)) - p(o, 0));
    };
    std::vector<int> h(2 * idx.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < idx.size(); ++i) {
        while (k >= 2 && cross(h[k - 2], h[k - 1], idx[i]) <= 0) --k;
        h[k++] = idx[i];
    }
    for (std::size_t i = idx.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross(h[k - 2], h[k - 1], idx[i]) <= 0) --k;
        h[k++] = idx[i];
    }
    h.resize(k - 1);
    return h;
}

template <class T>
void check_delaunay(const anima::landmark_set<T>& p) {
    const auto tris = anima::delaunay_triangulation(p);
    const auto hull = convex_hull(p);
    const Eigen::Index n = p.rows();
    // Points on the hull's boundary, collinear ones included.
    Eigen::Index on_hull = 0;
    for (Eigen::Index q = 0; q < n; ++q)
        for (std::size_t k = 0; k < hull.size(); ++k) {
            const int a = hull[k], b = hull[(k + 1) % hull.size()];
            const Eigen::Matrix<double, 1, 2> pa = p.row(a).template cast<double>(), pb = p.row(b).template cast<double>(),
                                              pq = p.row(q).template cast<double>();
            const double cross = (pb(0) - pa(0)) * (pq(1) - pa(1)) - (pb(1) - pa(1)) * (pq(0) - pa(0));
            const double along = (pq - pa).dot(pb - pa);
            if (std::abs(cross) <= 1e-9 * (pb - pa).squaredNorm() && along >= 0 && along <= (pb - pa).squaredNorm()) {
                ++on_hull;
                break;
            }
        }
    CHECK(static_cast<Eigen::Index>(tris.size()) == 2 * n - 2 - on_hull);
    double area = 0, hull_area = 0;
    for (const auto& t : tris) {
        const double a = static_cast<double>(anima::triangle_area(p, t));
        CHECK(a > 0);
        area += a;
        for (Eigen::Index q = 0; q < n; ++q) {
            if (q == t[0] || q == t[1] || q == t[2]) continue;
            const double det = anima::detail::in_circle<double>(p(t[0], 0), p(t[0], 1), p(t[1], 0), p(t[1], 1), p(t[2], 0),
                                                                p(t[2], 1), p(q, 0), p(q, 1));
            CHECK(det <= 1e-6 * std::pow(static_cast<double>(p.cwiseAbs().maxCoeff()), 4));  // empty circumcircle
        }
    }
    for (std::size_t k = 0; k < hull.size(); ++k) {
        const int a = hull[k], b = hull[(k + 1) % hull.size()];
        hull_area += 0.5 * (static_cast<double>(p(a, 0)) * p(b, 1) - static_cast<double>(p(b, 0)) * p(a, 1));
    }
    CHECK(area == doctest::Approx(hull_area).epsilon(1e-5));
}

TEST_CASE_TEMPLATE("Delaunay triangulation: empty circumcircles, covers the hull, Euler's count", T, float, double) {
    anima::random_source rng(9);
    for (int n : {3, 4, 10, 68, 150}) check_delaunay<T>(random_points<T>(rng, n, 50));
    // A regular grid: four points on every circle (ties), still a valid triangulation.
    anima::landmark_set<T> grid(30, 2);
    for (int k = 0; k < 30; ++k) grid.row(k) << static_cast<T>(k % 6), static_cast<T>(k / 6);
    check_delaunay<T>(grid);
}

TEST_CASE_TEMPLATE("Delaunay triangulation refuses degenerate point sets", T, float, double) {
    anima::landmark_set<T> dup(4, 2);
    dup << 0, 0, 1, 0, 0, 1, 1, 0;
    CHECK(contains(invalid_argument_message([&] { anima::delaunay_triangulation(dup); }), "points 1 and 3 coincide"));
    anima::landmark_set<T> line(5, 2);
    for (int k = 0; k < 5; ++k) line.row(k) << static_cast<T>(k), static_cast<T>(2 * k + 1);
    CHECK(contains(invalid_argument_message([&] { anima::delaunay_triangulation(line); }), "all 5 points lie on one line"));
    CHECK(contains(invalid_argument_message([&] { anima::delaunay_triangulation<T>(dup.topRows(2)); }), "at least 3 points"));
}

// ---------------------------------------------------------------------------
// Piecewise-affine warp
// ---------------------------------------------------------------------------

TEST_CASE_TEMPLATE("the warp maps every landmark exactly onto the target shape", T, float, double) {
    anima::random_source rng(13);
    const anima::landmark_set<T> from = random_points<T>(rng, 25, 40);
    const anima::landmark_set<T> to = from + random_points<T>(rng, 25, 2);
    const auto tris = anima::delaunay_triangulation(from);
    const anima::piecewise_affine_warp<T> warp(from, to, tris);
    for (Eigen::Index k = 0; k < from.rows(); ++k) {
        const auto q = warp.apply(from.row(k));
        REQUIRE(q.has_value());
        CHECK((*q - to.row(k)).cwiseAbs().maxCoeff() < tolerance<T>(1e-10, 1e-4));
    }
    CHECK_FALSE(warp.apply(typename anima::piecewise_affine_warp<T>::point(T(1000), T(1000))).has_value());
    // A global affine change of shape is reproduced exactly everywhere inside.
    Eigen::Matrix<T, 2, 2> a;
    a << T(1.2), T(0.3), T(-0.1), T(0.9);
    const anima::landmark_set<T> affine = (from * a.transpose()).rowwise() + Eigen::Matrix<T, 1, 2>(T(3), T(-2));
    const anima::piecewise_affine_warp<T> global(from, affine, tris);
    for (int trial = 0; trial < 50; ++trial) {
        const auto p = random_points<T>(rng, 1, 15);
        const auto q = global.apply(p.row(0));
        if (!q) continue;
        const Eigen::Matrix<T, 1, 2> expected = p.row(0) * a.transpose() + Eigen::Matrix<T, 1, 2>(T(3), T(-2));
        CHECK((*q - expected).cwiseAbs().maxCoeff() < tolerance<T>(1e-10, 1e-4));
    }
}

TEST_CASE_TEMPLATE("warping an image between identical shapes is the identity; affine images stay exact", T, float, double) {
    anima::random_source rng(17);
    const Eigen::Index rows = 40, cols = 50;
    anima::landmark_set<T> shape = random_points<T>(rng, 15, 15);
    shape.col(0).array() += T(25);
    shape.col(1).array() += T(20);
    const auto tris = anima::delaunay_triangulation(shape);
    const matrix<T> img = random_matrix<T>(rng, rows, cols, 100);
    const matrix<T> same = anima::warp_image(img, shape, shape, tris, rows, cols, T(-1));
    const auto raster = anima::rasterize_triangles(shape, tris, rows, cols);
    REQUIRE(raster.size() > 100);
    for (std::size_t k = 0; k < raster.size(); ++k)
        CHECK(same(raster.y(k), raster.x(k)) == doctest::Approx(img(raster.y(k), raster.x(k))).epsilon(tolerance<T>(1e-9, 1e-4)));
    CHECK((raster.mask() == (same.array() != T(-1))).all());
    // An affine ramp warped by a translation of the shape is the shifted ramp.
    matrix<T> ramp(rows, cols);
    for (Eigen::Index y = 0; y < rows; ++y)
        for (Eigen::Index x = 0; x < cols; ++x) ramp(y, x) = T(0.5) * static_cast<T>(x) + T(2) * static_cast<T>(y);
    const anima::landmark_set<T> shifted = shape.rowwise() + Eigen::Matrix<T, 1, 2>(T(1.5), T(-2.25));
    const matrix<T> moved = anima::warp_image(ramp, shape, shifted, tris, rows, cols);
    const auto moved_raster = anima::rasterize_triangles(shifted, tris, rows, cols);
    for (std::size_t k = 0; k < moved_raster.size(); ++k) {
        const T x = static_cast<T>(moved_raster.x(k)) - T(1.5), y = static_cast<T>(moved_raster.y(k)) + T(2.25);
        CHECK(moved(moved_raster.y(k), moved_raster.x(k)) == doctest::Approx(T(0.5) * x + T(2) * y).epsilon(tolerance<T>(1e-9, 1e-4)));
    }
    // Every pixel centre inside the hull is covered exactly once.
    std::size_t inside = 0;
    const anima::piecewise_affine_warp<T> id(shape, shape, tris);
    for (Eigen::Index y = 0; y < rows; ++y)
        for (Eigen::Index x = 0; x < cols; ++x)
            if (id.apply(typename anima::piecewise_affine_warp<T>::point(static_cast<T>(x), static_cast<T>(y)))) ++inside;
    CHECK(inside == raster.size());
}

}  // namespace
