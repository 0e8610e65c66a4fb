// Quaternion algebra, exp/log/pow, rotation vectors, axis-angle and angular
// velocity, checked against GLM, Eigen and a long double reference.
#include "rotation_test_util.hpp"

#include <anima/core/error.hpp>
#include <anima/rotation/angular_velocity.hpp>
#include <anima/rotation/axis_angle.hpp>
#include <anima/rotation/euler.hpp>
#include <anima/rotation/exp_log.hpp>
#include <anima/rotation/quaternion.hpp>
#include <anima/rotation/shortest_arc.hpp>
#include <anima/rotation/swing_twist.hpp>
#include <anima/rotation/detail/so3.hpp>

#include <unsupported/Eigen/AutoDiff>

#include <type_traits>
#include <vector>

using namespace rt;

namespace {
// Row-major rotation matrices from the two libraries.
template <class Q>
std::array<vec, 3> eigen_matrix(const Q& q) {
    const auto m = to_eigen(q).toRotationMatrix();
    return {vec{m(0, 0), m(0, 1), m(0, 2)}, vec{m(1, 0), m(1, 1), m(1, 2)}, vec{m(2, 0), m(2, 1), m(2, 2)}};
}
template <class Q>
std::array<vec, 3> glm_matrix(const Q& q) {
    const auto m = glm::mat3_cast(to_glm(q));  // column-major: m[column][row]
    return {vec{m[0][0], m[1][0], m[2][0]}, vec{m[0][1], m[1][1], m[2][1]}, vec{m[0][2], m[1][2], m[2][2]}};
}
vec times(const std::array<vec, 3>& m, const vec& v) {
    vec r{};
    for (int i = 0; i < 3; ++i) r[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
    return r;
}
template <class Q>
Q bad(int component, scalar<Q> value) {
    ld c[4] = {0.5, 0.5, 0.5, 0.5};
    c[component] = value;
    return make<Q>(c[0], c[1], c[2], c[3]);
}
}  // namespace

TEST_CASE_TEMPLATE("multiply, conjugate, dot, norm and inverse agree with the native library", Q,
                   ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    const Q i_ = make<Q>(0, 1, 0, 0), j_ = make<Q>(0, 0, 1, 0), k_ = make<Q>(0, 0, 0, 1);
    CHECK(diff(anima::multiply(i_, j_), k_) == 0);  // Hamilton: i j = k
    rng r(11);
    for (int i = 0; i < 100; ++i) {
        const Q a = r.any<Q>(), b = r.any<Q>(), c = r.any<Q>();
        const ld na = std::sqrt(ld(anima::dot(a, a))), nb = anima::norm(b), nc = anima::norm(c);
        CHECK(diff(anima::multiply(a, b), a * b) <= 8 * e * na * nb);
        CHECK(diff(anima::multiply(anima::multiply(a, b), c), anima::multiply(a, anima::multiply(b, c))) <=
              16 * e * na * nb * nc);
        CHECK(std::abs(anima::dot(a, b) - ld(glm::dot(to_glm(a), to_glm(b)))) <= 8 * e * na * nb);
        const lq pa = to_lq(a);
        CHECK(std::abs(na - std::sqrt(pa.w * pa.w + pa.x * pa.x + pa.y * pa.y + pa.z * pa.z)) <= 4 * e * na);
        CHECK(diff(anima::conjugate(a), to_eigen(a).conjugate()) == 0);
        CHECK(diff(anima::inverse(a), glm::inverse(to_glm(a))) <= 8 * e / na);
        CHECK(diff(anima::multiply(anima::inverse(a), a), anima::identity<Q>()) <= 8 * e);
        CHECK(diff(anima::multiply(a, anima::inverse(a)), anima::identity<Q>()) <= 8 * e);
    }
}

TEST_CASE_TEMPLATE("normalize, inverse and log reject zero and non-finite quaternions", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    rng r(12);
    for (int i = 0; i < 50; ++i) {
        const Q q = r.any<Q>();
        const Q n = anima::normalize(q);
        CHECK(norm_error(n) <= 2 * eps<T>());
        CHECK(diff(n, glm::normalize(to_glm(q))) <= 4 * eps<T>());
    }
    std::vector<Q> rejected{make<Q>(0, 0, 0, 0)};
    for (int c = 0; c < 4; ++c) {
        rejected.push_back(bad<Q>(c, std::numeric_limits<T>::quiet_NaN()));
        rejected.push_back(bad<Q>(c, std::numeric_limits<T>::infinity()));
    }
    for (const Q& q : rejected) {
        CHECK_THROWS_AS(anima::normalize(q), anima::invalid_argument);
        CHECK_THROWS_AS(anima::inverse(q), anima::invalid_argument);
        CHECK_THROWS_AS(anima::log(q), anima::invalid_argument);
        CHECK_THROWS_AS(anima::to_rotation_vector(q), anima::error);
    }
}

TEST_CASE_TEMPLATE("quaternion_cast moves a rotation between GLM and Eigen, float and double, exactly", Q,
                   ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    rng r(21);
    for (int i = 0; i < 20; ++i) {
        const Q q = r.any<Q>();
        const lq p = to_lq(q);
        // Every target type holds the same four components (float -> double exactly).
        const auto g = anima::quaternion_cast<glm::qua<double>>(q);
        const auto e = anima::quaternion_cast<Eigen::Quaterniond>(q);
        CHECK((g.w == p.w && g.x == p.x && g.y == p.y && g.z == p.z));
        CHECK((e.w() == p.w && e.x() == p.x && e.y() == p.y && e.z() == p.z));
        // and back, through the other library: the same bits.
        CHECK(diff(anima::quaternion_cast<Q>(anima::quaternion_cast<Eigen::Quaternion<T>>(
                       anima::quaternion_cast<glm::qua<T>>(q))),
                   q) == 0);
        // Results computed on one type used as the other (a clip's Eigen rotations in a GLM engine).
        const auto half = anima::slerp(anima::quaternion_cast<Eigen::Quaternion<T>>(q),
                                       anima::quaternion_cast<Eigen::Quaternion<T>>(anima::identity<Q>()), T(0.5));
        CHECK(diff(anima::quaternion_cast<glm::qua<T>>(half), anima::slerp(q, anima::identity<Q>(), T(0.5))) == 0);
    }
}

TEST_CASE_TEMPLATE("rotate matches q * v and the Eigen and GLM rotation matrices", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    static_assert(std::is_same_v<decltype(anima::rotate(Q{}, std::array<double, 3>{})), vector3<Q>>);
    const auto quarter_z = from_lq<Q>(rot(pi / 2, {0, 0, 1}));
    CHECK(vdiff(anima::rotate(quarter_z, std::array<double, 3>{1, 0, 0}), vec{0, 1, 0}) <= 2 * e);
    rng r(13);
    for (int i = 0; i < 100; ++i) {
        const Q q = r.unit<Q>(), p = r.unit<Q>();
        const vec v{r.uniform(-3, 3), r.uniform(-3, 3), r.uniform(-3, 3)};
        const auto rv = anima::rotate(q, make_vec<Q>(v));
        const ld s = 8 * e * vnorm(v);
        CHECK(vdiff(rv, q * make_vec<Q>(v)) <= s);
        CHECK(vdiff(rv, times(eigen_matrix(q), to_vec(make_vec<Q>(v)))) <= s);
        CHECK(vdiff(rv, times(glm_matrix(q), to_vec(make_vec<Q>(v)))) <= s);
        CHECK(vdiff(rv, anima::rotate(neg(q), v)) <= s);
        // Hamilton product: q p applies p first.
        CHECK(vdiff(anima::rotate(anima::multiply(q, p), v), anima::rotate(q, anima::rotate(p, v))) <= 2 * s);
    }
}

TEST_CASE_TEMPLATE("align_hemisphere and canonicalize pick a sign without changing the rotation", Q,
                   ANIMA_QUAT_TYPES) {
    rng r(14);
    for (int i = 0; i < 100; ++i) {
        const Q q = r.unit<Q>(), ref = r.unit<Q>();
        const Q a = anima::align_hemisphere(q, ref), c = anima::canonicalize(q);
        CHECK(anima::dot(a, ref) >= 0);
        CHECK(diff(a, anima::dot(q, ref) >= 0 ? q : neg(q)) == 0);
        CHECK(to_lq(c).w >= 0);
        CHECK(diff(c, to_lq(q).w >= 0 ? q : neg(q)) == 0);
        CHECK(diff(anima::canonicalize(neg(q)), c) == 0);
    }
    const Q x = make<Q>(0, 1, 0, 0);  // dot == 0 keeps q
    CHECK(diff(anima::align_hemisphere(anima::identity<Q>(), x), anima::identity<Q>()) == 0);
}

TEST_CASE_TEMPLATE("angle and angle_between are accurate near 0 and near pi", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    CHECK(anima::angle(anima::identity<Q>()) == 0);
    rng r(15);
    for (int i = 0; i < 20; ++i) {
        const lq q = i == 0 ? lq{1, 0, 0, 0} : r.unit_lq();
        const Q qt = from_lq<Q>(q);
        CHECK(anima::angle_between(qt, qt) <= 4 * e);
        CHECK(anima::angle_between(qt, neg(qt)) <= 4 * e);
        const vec axis = r.unit_vector();
        for (ld a : {1e-8L, 1e-5L, 1e-3L, 0.5L, 2.0L, pi - 1e-3L, pi - 1e-6L, pi - 1e-8L, pi}) {
            const Q b = from_lq<Q>(q * rot(a, axis));
            CAPTURE(a);
            CHECK(std::abs(anima::angle_between(qt, b) - a) <= 8 * e);  // absolute: relative 2e-7 at 1e-8 rad
            CHECK(std::abs(anima::angle_between(b, qt) - a) <= 8 * e);
            CHECK(std::abs(anima::angle(from_lq<Q>(rot(a, axis))) - a) <= 4 * e);
            CHECK(std::abs(anima::angle(neg(from_lq<Q>(rot(a, axis)))) - a) <= 4 * e);
        }
        const Q b = r.unit<Q>();
        CHECK(std::abs(anima::angle_between(qt, b) - to_eigen(qt).angularDistance(to_eigen(b))) <= 16 * e);
    }
}

TEST_CASE_TEMPLATE("exp, log and pow", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    CHECK(diff(anima::log(anima::identity<Q>()), make<Q>(0, 0, 0, 0)) == 0);
    const Q log_minus_one = anima::log(make<Q>(-1, 0, 0, 0));
    CHECK(finite(log_minus_one));
    CHECK(diff(log_minus_one, make<Q>(0, pi, 0, 0)) <= 2 * e);
    CHECK(diff(anima::exp(log_minus_one), make<Q>(-1, 0, 0, 0)) <= 4 * e);
    rng r(16);
    for (int i = 0; i < 100; ++i) {
        const Q q = r.any<Q>();
        const lq p = to_lq(q);
        const ld n = anima::norm(q);
        CHECK(diff(anima::exp(anima::log(q)), q) <= 16 * e * n);
        // log against the closed form (ln|q|, atan2(|v|, w) v / |v|)
        const ld s = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z), k = std::atan2(s, p.w) / s;
        CHECK(diff(anima::log(q), lq{std::log(n), k * p.x, k * p.y, k * p.z}) <= 8 * e);
        // exp against the closed form e^w (cos|v|, sin|v| v / |v|)
        const ld ew = std::exp(p.w), sv = std::sin(s) / s;
        CHECK(diff(anima::exp(q), lq{ew * std::cos(s), ew * sv * p.x, ew * sv * p.y, ew * sv * p.z}) <=
              8 * e * ew);
        // a tiny vector part keeps full relative precision
        const Q tiny = anima::exp(make<Q>(0, 1e-10L * p.x, 0, 0));
        CHECK(std::abs(to_lq(tiny).x - ld(T(1e-10L * p.x))) <= 2 * e * std::abs(to_lq(tiny).x));

        const Q u = r.unit<Q>();
        const Q h = anima::pow(u, T(0.5));
        CHECK(diff(anima::multiply(h, h), u) <= 8 * e);
        CHECK(diff(anima::pow(u, T(1)), u) <= 8 * e);
        CHECK(diff(anima::pow(u, T(0)), anima::identity<Q>()) == 0);
        CHECK(diff(anima::pow(u, T(-1)), anima::conjugate(u)) <= 8 * e);
        // u^t turns t times u's angle on u's side of the double cover (angle in [0, 2 pi]).
        const T t = T(r.uniform(-2, 2));
        const lq c = to_lq(u);
        const vec axis{c.x, c.y, c.z};
        CHECK(diff(anima::pow(u, t), rot(t * 2 * std::atan2(vnorm(axis), c.w), axis)) <= 16 * e);
    }
}

TEST_CASE_TEMPLATE("exp, pow, from_rotation_vector and from_euler refuse non-finite input and stay exact for huge vectors",
                   Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>(), nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    for (const T x : {nan, inf, -inf}) {
        CAPTURE(x);
        for (int c = 0; c < 4; ++c) CHECK_THROWS_AS(anima::exp(bad<Q>(c, x)), anima::invalid_argument);
        CHECK_THROWS_WITH_AS(anima::pow(anima::identity<Q>(), x), doctest::Contains("anima::pow: t must be finite"),
                             anima::invalid_argument);
        CHECK_THROWS_WITH_AS(anima::from_rotation_vector<Q>(make_vec<Q>(vec{0, ld(x), 0})),
                             doctest::Contains("anima::from_rotation_vector: the rotation vector must be finite"),
                             anima::invalid_argument);
        CHECK_THROWS_WITH_AS(anima::from_euler<Q>(0, 0, x, anima::euler_order::zyx),
                             doctest::Contains("anima::from_euler: a2 must be finite"), anima::invalid_argument);
    }
    // e^w overflows: refused, where (inf, 0 * inf, ...) would hold NaN.
    CHECK_THROWS_WITH_AS(anima::exp(make<Q>(1000, 0, 0, 0)), doctest::Contains("e^w is finite"),
                         anima::invalid_argument);
    CHECK(diff(anima::exp(make<Q>(-1000, 1, 2, 3)), make<Q>(0, 0, 0, 0)) == 0);  // e^w underflows to zero exactly
    // t * log(q) overflows: a 3 rad half angle times the largest t.
    CHECK_THROWS_WITH_AS(anima::pow(from_lq<Q>(rot(6, vec{1, 0, 0})), std::numeric_limits<T>::max()),
                         doctest::Contains("t * log(q) must be finite"), anima::invalid_argument);
    // Lengths whose square overflows (1e30 in float, 1e160 in double): a unit
    // result, exact against long double when the vector lies on an axis.
    const T big = std::sqrt(std::numeric_limits<T>::max()) * T(4);
    for (int axis = 0; axis < 3; ++axis) {
        vec v{0, 0, 0};
        v[static_cast<std::size_t>(axis)] = ld(big);
        const Q q = anima::from_rotation_vector<Q>(make_vec<Q>(v));
        REQUIRE(finite(q));
        const ld half = ld(big) / 2;
        lq expected{std::cos(half), 0, 0, 0};
        (axis == 0 ? expected.x : axis == 1 ? expected.y : expected.z) = std::sin(half);
        CHECK(diff(q, expected) <= 2 * e);
        CHECK(diff(anima::exp(make<Q>(0, v[0], v[1], v[2])), lq{std::cos(ld(big)), std::sin(ld(big)) * (v[0] > 0),
                                                                     std::sin(ld(big)) * (v[1] > 0),
                                                                     std::sin(ld(big)) * (v[2] > 0)}) <= 2 * e);
    }
    // Off the axes the angle itself is only known to a relative epsilon, so
    // only the length and the axis (the vector part along v) are checked.
    const vec v{ld(big), ld(-big / 3), ld(big / 5)};
    const Q q = anima::from_rotation_vector<Q>(make_vec<Q>(v));
    REQUIRE(finite(q));
    CHECK(norm_error(q) <= 4 * e);
    const lq l = to_lq(q);
    const ld along = (l.x * v[0] + l.y * v[1] + l.z * v[2]) / vnorm(v);
    CHECK(std::abs(along * along - (l.x * l.x + l.y * l.y + l.z * l.z)) <= 8 * e);
    CHECK(finite(anima::pow(from_lq<Q>(rot(1, vec{0, 1, 0})), big)));
    // A length that overflows itself is refused.
    CHECK_THROWS_WITH_AS(anima::exp(make<Q>(0, std::numeric_limits<T>::max(), std::numeric_limits<T>::max(), 0)),
                         doctest::Contains("overflows"), anima::invalid_argument);
    CHECK(finite(anima::from_euler<Q>(big, -big, big, anima::euler_order::xyz)));
}

// detail::log_unit's near-identity series must keep the r^4/5 term of
// atan(r)/r: its threshold small_angle() was chosen for sinc's r^4/120 term,
// and without it the error just below the threshold is 24 epsilon.
TEST_CASE_TEMPLATE("log and to_rotation_vector are accurate to a few ulps near the identity", Q,
                   ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    rng r(17);
    ld worst = 0, worst_half = 0;  // error in ulps of the result
    for (int i = 0; i <= 400; ++i) {
        const ld half = std::pow(10.0L, -9 + 9.0L * i / 400);  // half angle 1e-9 .. 1
        const Q q = from_lq<Q>(rot(2 * half, r.unit_vector()));
        const lq p = to_lq(q);
        const ld s = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z), k = std::atan2(s, p.w) / s;
        const lq l = to_lq(anima::log(q));
        const vec ref{2 * k * p.x, 2 * k * p.y, 2 * k * p.z};
        const ld err =
            std::max(vdiff(anima::to_rotation_vector(q), ref), vdiff(vec{2 * l.x, 2 * l.y, 2 * l.z}, ref)) /
            (eps<T>() * 2 * k * s);
        if (err > worst) worst = err, worst_half = half;
    }
    CAPTURE(worst_half);
    CHECK(worst <= 8);
}

TEST_CASE_TEMPLATE("rotation vector round trip from 1e-10 rad to pi - 1e-6", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    CHECK(diff(anima::from_rotation_vector<Q>(std::array<double, 3>{0, 0, 0}), anima::identity<Q>()) == 0);
    CHECK(vdiff(anima::to_rotation_vector(anima::identity<Q>()), vec{0, 0, 0}) == 0);
    rng r(18);
    for (int i = 0; i < 30; ++i) {
        const vec axis = r.unit_vector();
        for (ld a : {1e-10L, 1e-6L, 0.3L, 1.0L, 2.0L, 3.0L, pi - 1e-3L, pi - 1e-6L}) {
            const vec v{a * axis[0], a * axis[1], a * axis[2]};
            const Q q = anima::from_rotation_vector<Q>(make_vec<Q>(v));
            CAPTURE(a);
            CHECK(diff(q, rot(a, axis)) <= 4 * e);
            CHECK(vdiff(anima::to_rotation_vector(q), v) <= 8 * e * a);
            CHECK(vdiff(anima::to_rotation_vector(neg(q)), v) <= 8 * e * a);
        }
    }
}

TEST_CASE_TEMPLATE("axis-angle conversions", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    const auto id = anima::to_axis_angle(anima::identity<Q>());
    CHECK(id.angle == 0);
    CHECK(vdiff(id.axis, vec{1, 0, 0}) == 0);
    CHECK(anima::to_axis_angle(neg(anima::identity<Q>())).angle == 0);
    // Each refusal names the argument and its value.
    CHECK_THROWS_WITH_AS(anima::from_axis_angle<Q>(std::array<T, 3>{0, 0, 0}, T(1)),
                         "anima::from_axis_angle: axis must be non-zero and finite, got (0, 0, 0)",
                         anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::from_axis_angle<Q>(std::array<T, 3>{std::nanf(""), 0, 1}, T(1)),
                         "anima::from_axis_angle: axis must be non-zero and finite, got (nan, 0, 1)",
                         anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::from_axis_angle<Q>(std::array<T, 3>{0, 0, 1}, std::numeric_limits<T>::infinity()),
                         "anima::from_axis_angle: angle must be finite, got inf", anima::invalid_argument);
    // An axis whose squared length overflows is still a direction.
    const T huge = std::numeric_limits<T>::max() / T(2);
    CHECK(diff(anima::from_axis_angle<Q>(std::array<T, 3>{0, huge, 0}, T(1)),
               anima::from_axis_angle<Q>(std::array<T, 3>{0, 1, 0}, T(1))) == 0);
    CHECK_THROWS_WITH_AS(anima::swing_twist(anima::identity<Q>(), std::array<T, 3>{0, 0, 0}),
                         "anima::swing_twist: axis must be non-zero and finite, got (0, 0, 0)", anima::invalid_argument);
    CHECK_THROWS_AS(anima::to_axis_angle(make<Q>(0, 0, 0, 0)), anima::invalid_argument);
    rng r(19);
    for (int i = 0; i < 100; ++i) {
        const vec axis = r.unit_vector();
        const ld scale = r.uniform(0.01, 100), a = r.uniform(-7, 7);
        const Q q =
            anima::from_axis_angle<Q>(make_vec<Q>({scale * axis[0], scale * axis[1], scale * axis[2]}), T(a));
        CHECK(diff(q, rot(ld(T(a)), axis)) <= 4 * e);
        using V = glm::vec<3, T>;
        CHECK(diff(q, glm::angleAxis(T(a), V(T(axis[0]), T(axis[1]), T(axis[2])))) <= 4 * e);
        CHECK(diff(q, Eigen::Quaternion<T>(
                          Eigen::AngleAxis<T>(T(a), make_vec<Eigen::Quaternion<T>>(axis)))) <= 4 * e);

        const Q u = r.unit<Q>();
        const auto aa = anima::to_axis_angle(u);
        CHECK(aa.angle >= 0);
        CHECK(aa.angle <= T(pi));
        CHECK(std::abs(vnorm(to_vec(aa.axis)) - 1) <= 2 * e);
        CHECK(std::abs(aa.angle - anima::angle(u)) <= 2 * e);
        CHECK(angle_between(to_lq(u), rot(aa.angle, to_vec(aa.axis))) <= 8 * e);
    }
}

TEST_CASE_TEMPLATE("shortest_arc turns a onto b by the angle between them, also when they nearly oppose", Q,
                   ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    // The error of q(a) against b, of q's angle against the angle between a
    // and b, and of q's axis against perpendicular to a, all in long double
    // from the T-rounded inputs.
    const auto check = [&](const vec& a0, const vec& b0, ld scale_a, ld scale_b) {
        const vector3<Q> va = make_vec<Q>({scale_a * a0[0], scale_a * a0[1], scale_a * a0[2]});
        const vector3<Q> vb = make_vec<Q>({scale_b * b0[0], scale_b * b0[1], scale_b * b0[2]});
        const Q q = anima::shortest_arc<Q>(va, vb);
        REQUIRE(finite(q));
        CHECK(norm_error(q) <= 4 * e);
        vec a = to_vec(va), b = to_vec(vb);
        const ld na = vnorm(a), nb = vnorm(b);
        for (auto& x : a) x /= na;
        for (auto& x : b) x /= nb;
        const vec qa = rotate(unit(to_lq(q)), a);
        CHECK(vdiff(qa, b) <= 8 * e);
        const vec c{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        const ld angle = std::atan2(vnorm(c), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
        CHECK(std::abs(angle_between(lq{1, 0, 0, 0}, to_lq(q)) - angle) <= 8 * e);
        const lq p = to_lq(q);
        CHECK(std::abs(p.x * a[0] + p.y * a[1] + p.z * a[2]) <= 4 * e);  // the axis is perpendicular to a
    };
    rng r(23);
    for (int i = 0; i < 200; ++i) {
        const vec a = r.unit_vector(), b = r.unit_vector();
        check(a, b, r.uniform(0.01, 100), r.uniform(0.01, 100));
        // Nearly the same and nearly opposite directions: b = +-a tilted by delta.
        const vec u = r.unit_vector();
        vec perp{a[1] * u[2] - a[2] * u[1], a[2] * u[0] - a[0] * u[2], a[0] * u[1] - a[1] * u[0]};
        const ld np = vnorm(perp);
        for (auto& x : perp) x /= np;
        for (const ld delta : {1e-2L, 1e-4L, 1e-6L, 1e-9L, 0.0L}) {
            for (const ld sign : {1.0L, -1.0L}) {
                const vec t{sign * a[0] * std::cos(delta) + perp[0] * std::sin(delta),
                            sign * a[1] * std::cos(delta) + perp[1] * std::sin(delta),
                            sign * a[2] * std::cos(delta) + perp[2] * std::sin(delta)};
                check(a, t, 1, r.uniform(0.5, 2));
            }
        }
    }
    // Exactly opposite coordinate axes: a half turn about a perpendicular axis.
    for (int k = 0; k < 3; ++k) {
        vec a{0, 0, 0};
        a[k] = 1;
        check(a, vec{-a[0], -a[1], -a[2]}, 1, 3);
        const Q q = anima::shortest_arc<Q>(make_vec<Q>(a), make_vec<Q>({-a[0], -a[1], -a[2]}));
        CHECK(std::abs(to_lq(q).w) <= e);
    }
    CHECK(diff(anima::shortest_arc<Q>(make_vec<Q>({1, 2, 3}), make_vec<Q>({2, 4, 6})), anima::identity<Q>()) == 0);
    CHECK_THROWS_WITH_AS(anima::shortest_arc<Q>(make_vec<Q>({0, 0, 0}), make_vec<Q>({1, 0, 0})),
                         "anima::shortest_arc: from must be non-zero and finite, got (0, 0, 0)", anima::invalid_argument);
    CHECK_THROWS_WITH_AS(anima::shortest_arc<Q>(make_vec<Q>({1, 0, 0}), make_vec<Q>({std::nan(""), 0, 0})),
                         "anima::shortest_arc: to must be non-zero and finite, got (nan, 0, 0)", anima::invalid_argument);
    CHECK_THROWS_AS(anima::shortest_arc<Q>(make_vec<Q>({1, 0, 0}), make_vec<Q>({0, 0, HUGE_VALL})),
                    anima::invalid_argument);
    // Lengths whose squares over- or underflow T.
    for (const ld s : {1e-30L, 1e30L, ld(std::numeric_limits<T>::denorm_min()), ld(std::numeric_limits<T>::max())})
        check(vec{0.6L, 0, 0.8L}, vec{0, 1, 0}, s, 1);
}

TEST_CASE_TEMPLATE("angular velocity of a constant-rate rotation", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    const ld w = 2.5;
    rng r(20);
    for (int i = 0; i < 20; ++i) {
        const vec axis = r.unit_vector();
        const lq q0 = r.unit_lq();
        const ld t = r.uniform(0, 3);
        for (ld dt : {1e-3L, 1.0L / 30, 0.1L}) {
            const ld tol = 16 * e / dt + 8 * e * w;
            const vec expect{w * axis[0], w * axis[1], w * axis[2]};
            // q(t) = exp(w t axis / 2): both frames agree.
            const Q a = from_lq<Q>(rot(w * t, axis)), b = from_lq<Q>(rot(w * (t + dt), axis));
            CHECK(vdiff(anima::angular_velocity(a, b, T(dt)), expect) <= tol);
            CHECK(vdiff(anima::angular_velocity(a, b, T(dt), anima::angular_frame::local), expect) <= tol);
            // q(t) = q0 rot(w t): w axis in the local frame, rotated by q0 in the parent frame.
            const Q c = from_lq<Q>(q0 * rot(w * t, axis)), d = from_lq<Q>(q0 * rot(w * (t + dt), axis));
            CHECK(vdiff(anima::angular_velocity(c, d, T(dt), anima::angular_frame::local), expect) <= tol);
            CHECK(vdiff(anima::angular_velocity(c, d, T(dt)), rotate(q0, expect)) <= tol);
            CHECK(vdiff(anima::angular_velocity(neg(c), d, T(dt)), rotate(q0, expect)) <= tol);
        }
    }
}

TEST_CASE_TEMPLATE("angular_velocities over a sequence", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T dt = T(0.04);
    rng r(21);
    std::vector<Q> curve;
    for (int i = 0; i < 6; ++i) curve.push_back(r.unit<Q>());
    for (auto frame : {anima::angular_frame::parent, anima::angular_frame::local}) {
        const auto v = anima::angular_velocities(curve, dt, frame);
        REQUIRE(v.size() == curve.size());
        CHECK(vdiff(v[0], anima::angular_velocity(curve[0], curve[1], dt, frame)) == 0);
        for (std::size_t i = 1; i + 1 < curve.size(); ++i)
            CHECK(vdiff(v[i], anima::angular_velocity(curve[i - 1], curve[i + 1], 2 * dt, frame)) == 0);
        CHECK(vdiff(v[5], anima::angular_velocity(curve[4], curve[5], dt, frame)) == 0);
    }
    // Samples of a constant-rate rotation: every difference, central or one-sided, is w axis.
    const vec axis = r.unit_vector();
    std::vector<Q> steady;
    for (int i = 0; i < 5; ++i) steady.push_back(from_lq<Q>(rot(2.5L * i * ld(dt), axis)));
    for (const auto& w : anima::angular_velocities(steady, dt))
        CHECK(vdiff(w, vec{2.5L * axis[0], 2.5L * axis[1], 2.5L * axis[2]}) <= 16 * eps<T>() / dt);
    const std::array<Q, 2> pair{curve[0], curve[1]};
    const auto two = anima::angular_velocities(pair, dt);
    REQUIRE(two.size() == 2);
    CHECK(vdiff(two[0], two[1]) == 0);
    CHECK(anima::angular_velocities(std::vector<Q>{}, dt).empty());
    const auto one = anima::angular_velocities(std::vector<Q>{curve[0]}, dt);
    REQUIRE(one.size() == 1);
    CHECK(vdiff(one[0], vec{0, 0, 0}) == 0);
    for (T bad_dt :
         {T(0), T(-0.1), std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::infinity()}) {
        CHECK_THROWS_AS(anima::angular_velocity(curve[0], curve[1], bad_dt), anima::invalid_argument);
        CHECK_THROWS_AS(anima::angular_velocities(curve, bad_dt), anima::invalid_argument);
        CHECK_THROWS_AS(anima::angular_velocities(std::vector<Q>{}, bad_dt), anima::invalid_argument);
    }
}

TEST_CASE_TEMPLATE("norm, normalize, inverse, log and pow work for 1e-200, 1e200 and denormal quaternions", Q,
                   ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    rng r(14);
    for (int i = 0; i < 50; ++i) {
        const Q u = r.unit<Q>();
        const T t = T(r.uniform(-2, 2));
        for (const T s : awkward_scales<T>()) {
            CAPTURE(s);
            const Q q = scaled(u, s);
            const lq stored = to_lq(q), ref = unit(stored);
            const ld length = std::sqrt(stored.w * stored.w + stored.x * stored.x + stored.y * stored.y +
                                        stored.z * stored.z);
            CHECK(std::abs(anima::norm(q) - length) <= 2 * e * length);
            const Q n = anima::normalize(q);
            REQUIRE(finite(n));
            CHECK(diff(n, ref) <= 2 * e);
            const Q l = anima::log(q);
            REQUIRE(finite(l));
            const lq lr = to_lq(anima::log(from_lq<Q>(ref)));
            CHECK(std::abs(ld(to_lq(l).w) - std::log(length)) <= 4 * e * std::max(ld(1), std::abs(std::log(length))));
            CHECK(vdiff(vec{to_lq(l).x, to_lq(l).y, to_lq(l).z}, vec{lr.x, lr.y, lr.z}) <= 8 * e);
            const Q p = anima::pow(q, t);
            REQUIRE(finite(p));
            CHECK(diff(p, anima::pow(from_lq<Q>(ref), t)) <= 8 * e);
            CHECK(vdiff(anima::to_rotation_vector(q), anima::to_rotation_vector(from_lq<Q>(ref))) <= 8 * e);
            if (s >= std::ldexp(T(1), -(std::numeric_limits<T>::max_exponent * 2) / 3) &&
                s <= std::ldexp(T(1), (std::numeric_limits<T>::max_exponent * 2) / 3)) {
                const Q v = anima::inverse(q);  // conj(q) / |q|^2: |q|^2 itself would over- or underflow
                REQUIRE(finite(v));
                CHECK(diff(anima::multiply(q, v), anima::identity<Q>()) <= 8 * e);
            }
        }
    }
    // The inverse of a denormal quaternion overflows: refused, not infinite.
    const T tiny = std::numeric_limits<T>::denorm_min() * T(4);
    CHECK_THROWS_AS(anima::inverse(make<Q>(tiny, 0, 0, 0)), anima::invalid_argument);
    CHECK(diff(anima::normalize(make<Q>(tiny, 0, 0, 0)), make<Q>(1, 0, 0, 0)) == 0);
}

namespace {
/// exp of the pure quaternion (0, h) in long double, for the reference derivatives.
std::array<ld, 4> exp_ld(const vec& h) {
    const ld a = vnorm(h);
    const ld k = a == 0 ? 1 : std::sin(a) / a;
    return {std::cos(a), k * h[0], k * h[1], k * h[2]};
}
}  // namespace

TEST_CASE_TEMPLATE("the quaternion core runs on AutoDiff scalars with derivatives at and near the identity", T, float,
                   double) {
    // exp_pure and log_unit on Eigen::AutoDiffScalar (what the flight objective
    // differentiates): values equal to the plain scalar's, derivatives equal
    // to central differences of a long double exp, including at v = 0 where
    // |v| has no derivative and below and above the series' switch-over.
    using ad = Eigen::AutoDiffScalar<Eigen::Matrix<T, 3, 1>>;
    const T e = eps<T>();
    rng r(15);
    for (const ld length : {0.0L, 1e-9L, 1e-4L, 5e-3L, 0.05L, 0.5L, 2.0L, 3.0L}) {
        const vec axis = r.unit_vector();
        const vec h{length * axis[0], length * axis[1], length * axis[2]};
        const ad hx{static_cast<T>(h[0]), 3, 0}, hy{static_cast<T>(h[1]), 3, 1}, hz{static_cast<T>(h[2]), 3, 2};
        const anima::detail::quat4<ad> q = anima::detail::exp_pure(hx, hy, hz);
        const anima::detail::quat4<T> plain = anima::detail::exp_pure(T(h[0]), T(h[1]), T(h[2]));
        CAPTURE(length);
        CHECK(q.w.value() == plain.w);
        CHECK(q.x.value() == plain.x);
        const ad* out[4] = {&q.w, &q.x, &q.y, &q.z};
        for (int c = 0; c < 3; ++c) {
            vec hp = h, hm = h;
            const ld step = 1e-7L;
            hp[c] += step;
            hm[c] -= step;
            const auto fp = exp_ld(hp), fm = exp_ld(hm);
            for (int k = 0; k < 4; ++k) {
                const ld ref = (fp[k] - fm[k]) / (2 * step);
                CHECK(std::abs(ld(out[k]->derivatives()[c]) - ref) <= 16 * e + 1e-9L);
            }
        }
        // log_unit inverts exp_pure on the AutoDiff scalar too: d(log(exp h))/dh = I.
        ad vx, vy, vz;
        anima::detail::log_unit(q, vx, vy, vz);
        const ad* v[3] = {&vx, &vy, &vz};
        for (int i = 0; i < 3; ++i)
            for (int c = 0; c < 3; ++c)
                CHECK(std::abs(ld(v[i]->derivatives()[c]) - (i == c ? 1 : 0)) <= 64 * e * (1 + length * length));
    }
}

TEST_CASE_TEMPLATE("select_less takes one branch by value, evaluates only it, and keeps its derivatives", T, float,
                   double) {
    // The switch-over of every series in the core: the branch not taken may
    // be singular (a square root at 0), so it must not run, and on AutoDiff
    // scalars the result's derivatives are those of the branch taken.
    int near_calls = 0, far_calls = 0;
    const auto pick = [&](T x) {
        return anima::detail::select_less(
            x, T(1), [&] { return ++near_calls, x * x; }, [&] { return ++far_calls, std::sqrt(x); });
    };
    CHECK(pick(T(0.5)) == T(0.25));
    CHECK(near_calls == 1);
    CHECK(far_calls == 0);
    CHECK(pick(T(4)) == T(2));
    CHECK(pick(T(1)) == T(1));  // not below: the closed form
    CHECK(near_calls == 1);
    CHECK(far_calls == 2);

    using ad = Eigen::AutoDiffScalar<Eigen::Matrix<T, 1, 1>>;
    const auto root_or_square = [](const ad& x) {
        using std::sqrt;
        return anima::detail::select_less(
            x, ad(T(1e-3)), [&] { return ad(x * x); }, [&] { return ad(sqrt(x)); });
    };
    const ad zero{T(0), 1, 0}, four{T(4), 1, 0};
    const ad at_zero = root_or_square(zero), at_four = root_or_square(four);
    CHECK(at_zero.value() == T(0));
    CHECK(at_zero.derivatives()[0] == T(0));  // d(x^2)/dx, not the square root's infinity
    CHECK(at_four.value() == T(2));
    CHECK(at_four.derivatives()[0] == T(0.25));
}

TEST_CASE_TEMPLATE("right_jacobian_so3 maps rotation-vector steps to body angular velocity", T, float, double) {
    // exp(v + dv) = exp(v) exp(Jr(v) dv) to first order, checked with a long
    // double central difference, from 0 across the series' switch-overs to pi.
    using mat3 = Eigen::Matrix<T, 3, 3>;
    using vec3 = Eigen::Matrix<T, 3, 1>;
    rng r(16);
    for (const ld length : {0.0L, 1e-6L, 1e-3L, 0.02L, 0.5L, 0.99L, 1.01L, 2.0L, 3.1L}) {
        const vec axis = r.unit_vector();
        const vec v{length * axis[0], length * axis[1], length * axis[2]};
        const mat3 jr = anima::detail::right_jacobian_so3(vec3(T(v[0]), T(v[1]), T(v[2])));
        const lq q = rot(2 * vnorm(v) == 0 ? 0 : vnorm(v), vnorm(v) == 0 ? vec{1, 0, 0} : v);
        for (int c = 0; c < 3; ++c) {
            const ld step = 1e-8L;
            vec vp = v, vm = v;
            vp[c] += step;
            vm[c] -= step;
            const lq dp = conj(q) * rot(vnorm(vp), vp), dm = conj(q) * rot(vnorm(vm), vm);
            // body angular velocity: the vector part of 2 q^-1 dq, divided by the step
            for (int i = 0; i < 3; ++i) {
                const ld ref = ((i == 0 ? dp.x : i == 1 ? dp.y : dp.z) - (i == 0 ? dm.x : i == 1 ? dm.y : dm.z)) / step;
                CAPTURE(length);
                CHECK(std::abs(ld(jr(i, c)) - ref) <= 8 * eps<T>() + 1e-9L);
            }
        }
    }
}
