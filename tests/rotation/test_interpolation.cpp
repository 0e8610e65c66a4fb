// lerp, nlerp, slerp and squad, checked against a long double reference
// slerp, glm::slerp, Eigen's slerp and glm::squad / glm::intermediate.
#define GLM_ENABLE_EXPERIMENTAL
#include "rotation_test_util.hpp"

#include <anima/rotation/angular_velocity.hpp>
#include <anima/rotation/detail/angle_series.hpp>
#include <anima/rotation/lerp.hpp>
#include <anima/rotation/quaternion.hpp>
#include <anima/rotation/slerp.hpp>
#include <anima/rotation/squad.hpp>

#include <glm/gtx/quaternion.hpp>

#include <vector>

using namespace rt;

namespace {
/// Keys of a smooth random walk, neighbours in the same hemisphere.
template <class Q>
std::vector<Q> walk(rng& r, int n) {
    std::vector<Q> keys{r.unit<Q>()};
    for (int i = 1; i < n; ++i)
        keys.push_back(from_lq<Q>(to_lq(keys.back()) * rot(r.uniform(0.3, 1.2), r.unit_vector())));
    return keys;
}
}  // namespace

TEST_CASE_TEMPLATE("lerp is the raw blend; nlerp is normalised and takes the short way", Q,
                   ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    rng r(31);
    for (int i = 0; i < 100; ++i) {
        const Q a = r.unit<Q>(), b = r.unit<Q>();
        const T t = T(r.uniform(-0.5, 1.5));
        CHECK(diff(anima::lerp(a, b, t), scale(to_lq(a), 1 - ld(t)) + scale(to_lq(b), t)) <= 4 * e);
        const Q far = anima::dot(a, b) < 0 ? b : neg(b);  // a.far < 0: lerp must not flip it
        CHECK(diff(anima::lerp(a, far, T(0.5)), scale(to_lq(a) + to_lq(far), 0.5)) <= 2 * e);

        const Q n = anima::nlerp(a, b, t);
        CHECK(norm_error(n) <= 2 * e);
        CHECK(diff(n, anima::nlerp(a, neg(b), t)) == 0);
        CHECK(diff(n, unit(scale(to_lq(a), 1 - ld(t)) + scale(to_lq(anima::align_hemisphere(b, a)), t))) <=
              4 * e);
        CHECK(diff(anima::nlerp(a, b, T(0)), a) <= 2 * e);
        CHECK(diff(anima::nlerp(a, b, T(1)), anima::align_hemisphere(b, a)) <= 2 * e);
        CHECK(diff(anima::nlerp(a, b, T(0.5)), anima::slerp(a, b, T(0.5))) <= 4 * e);
        CHECK(diff(anima::nlerp(a, neg(a), t), a) <= 2 * e);
    }
    const Q q = r.unit<Q>();
    CHECK(diff(anima::lerp(q, neg(q), T(0.5)), make<Q>(0, 0, 0, 0)) == 0);  // the long way round: no rotation
    // A NaN or infinite t is refused, naming t, rather than blended into NaN.
    for (const T t : {std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::infinity()}) {
        CHECK_THROWS_WITH_AS(anima::lerp(q, q, t), doctest::Contains("anima::lerp: t must be finite"),
                             anima::invalid_argument);
        CHECK_THROWS_WITH_AS(anima::nlerp(q, q, t), doctest::Contains("anima::nlerp: t must be finite"),
                             anima::invalid_argument);
    }
}

TEST_CASE_TEMPLATE("slerp follows the shorter great arc at constant speed", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    rng r(32);
    for (int i = 0; i < 200; ++i) {
        const Q a = r.unit<Q>(), b = r.unit<Q>();
        CHECK(diff(anima::slerp(a, b, T(0)), a) <= 2 * e);
        CHECK(diff(anima::slerp(a, b, T(1)), anima::align_hemisphere(b, a)) <= 2 * e);
        const T x = T(r.uniform(-0.5, 1.5));  // extrapolation too
        CHECK(norm_error(anima::slerp(a, b, x)) <= 2 * e);
        const lq pa = to_lq(a), pb = to_lq(b);  // inputs a hair off unit length still give a unit result
        const ld up = 1 + 64 * e, down = 1 - 64 * e;
        CHECK(norm_error(anima::slerp(make<Q>(up * pa.w, up * pa.x, up * pa.y, up * pa.z),
                                      make<Q>(down * pb.w, down * pb.x, down * pb.y, down * pb.z), x)) <=
              2 * e);
        CHECK(diff(anima::slerp(a, b, x), ref_slerp(to_lq(a), to_lq(b), x)) <= 8 * e);
        CHECK(diff(anima::slerp(a, b, x), anima::slerp(a, neg(b), x)) <= 2 * e);

        const T t = T(r.uniform(0, 1));
        const Q s = anima::slerp(a, b, t);
        CAPTURE(t);
        const ld angle = angle_between(to_lq(a), to_lq(b));
        CHECK(std::abs(angle_between(to_lq(a), to_lq(s)) - t * angle) <= 8 * e);
        CHECK(std::abs(angle_between(to_lq(s), to_lq(b)) - (1 - t) * angle) <= 8 * e);
        CHECK(diff(s, glm::slerp(to_glm(a), to_glm(b), t)) <= 64 * e);
        CHECK(diff(s, to_eigen(a).slerp(t, to_eigen(b))) <= 64 * e);
    }
}

TEST_CASE_TEMPLATE("slerp of identical, nearly identical and antipodal inputs", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    rng r(33);
    for (int i = 0; i < 20; ++i) {
        const vec axis = r.unit_vector();
        const lq q = i == 0 ? lq{1, 0, 0, 0} : r.unit_lq();
        const Q a = from_lq<Q>(q), q2 = r.unit<Q>();
        for (T t : {T(0), T(0.25), T(0.5), T(1), T(1.75)}) {
            CAPTURE(t);
            for (const Q& s : {anima::slerp(a, a, t), anima::slerp(a, neg(a), t)}) {
                CHECK(finite(s));
                CHECK(diff_up_to_sign(s, a) <= 2 * e);
            }
            CHECK(diff_up_to_sign(anima::slerp(a, neg(q2), t), anima::slerp(a, q2, t)) <= 2 * e);
        }
        // From 1e-9 rad apart up, across the switch from a series to sin(k theta) / sin(theta):
        // t is honoured (no early-out) and the result is exact to a few ulps.
        for (ld angle : {1e-9L, 1e-6L, 1e-4L, 5e-4L, 1e-3L, 0.01L, 0.05L, 0.1L, 0.2L}) {
            const Q b = from_lq<Q>(q * rot(angle, axis));
            for (T t : {T(0), T(0.25), T(0.5), T(1), T(1.75)}) {
                CAPTURE(angle);
                CAPTURE(t);
                const Q s = anima::slerp(a, b, t);
                const lq ref = ref_slerp(to_lq(a), to_lq(b), t), p = to_lq(s);
                CHECK(finite(s));
                CHECK(norm_error(s) <= 2 * e);
                CHECK(diff(s, ref) <= 2 * e);
                CHECK(std::abs(angle_between(to_lq(a), p) - t * angle_between(to_lq(a), to_lq(b))) <= 4 * e);
                if (i == 0)  // from the identity: vector part sin(t angle / 2) axis, relative precision
                    CHECK(vdiff(vec{p.x, p.y, p.z}, vec{ref.x, ref.y, ref.z}) <=
                          4 * e * std::sqrt(ref.x * ref.x + ref.y * ref.y + ref.z * ref.z));
            }
        }
    }
}

TEST_CASE_TEMPLATE("squad interpolates its keys and matches glm::squad", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    using G = glm::qua<T>;
    const T e = eps<T>();
    rng r(34);
    for (int run = 0; run < 10; ++run) {
        const std::vector<Q> q = walk<Q>(r, 5);
        std::vector<Q> s;
        std::vector<G> glm_s;
        for (std::size_t i = 0; i < q.size(); ++i) {
            const Q& prev = q[i == 0 ? 0 : i - 1];
            const Q& next = q[i + 1 == q.size() ? i : i + 1];
            s.push_back(anima::squad_control_point(prev, q[i], next));
            glm_s.push_back(glm::intermediate(to_glm(prev), to_glm(q[i]), to_glm(next)));
            CHECK(diff_up_to_sign(s[i], glm_s[i]) <= 16 * e);
            // Neighbours on the other side of the double cover give the same control point.
            CHECK(diff(anima::squad_control_point(neg(prev), q[i], next), s[i]) <= 2 * e);
            CHECK(diff(anima::squad_control_point(prev, q[i], neg(next)), s[i]) <= 2 * e);
            CHECK(diff_up_to_sign(anima::squad_control_point(neg(prev), neg(q[i]), neg(next)), s[i]) <=
                  2 * e);
        }
        // At an end (prev = q) the formula reduces to q (q^-1 next)^(-1/4).
        CHECK(diff(s[0], anima::slerp(q[0], q[1], T(-0.25))) <= 8 * e);
        for (std::size_t i = 0; i + 1 < q.size(); ++i) {
            CHECK(diff(anima::squad(q[i], q[i + 1], s[i], s[i + 1], T(0)), q[i]) <= 2 * e);
            CHECK(diff(anima::squad(q[i], q[i + 1], s[i], s[i + 1], T(1)), q[i + 1]) <= 2 * e);
            for (T t : {T(0.1), T(0.3), T(0.5), T(0.8), T(0.95)}) {
                const G ref = glm::squad(to_glm(q[i]), to_glm(q[i + 1]), glm_s[i], glm_s[i + 1], t);
                CHECK(diff(anima::squad(q[i], q[i + 1], s[i], s[i + 1], t), ref) <= 64 * e);
            }
        }
    }
}

namespace {
/// Angular velocity at the start (t = 0) or end (t = 1) of a squad segment:
/// one-sided differences over h and 2h, Richardson-extrapolated to O(h^2).
template <class Q>
vec squad_rate(const Q& a, const Q& b, const Q& sa, const Q& sb, bool at_end, scalar<Q> h) {
    using T = scalar<Q>;
    const auto at = [&](T t) { return anima::squad(a, b, sa, sb, at_end ? T(1) - t : t); };
    const auto d1 = to_vec(anima::angular_velocity(at(0), at(h), h));
    const auto d2 = to_vec(anima::angular_velocity(at(0), at(2 * h), 2 * h));
    const ld sign = at_end ? -1 : 1;
    return {sign * (2 * d1[0] - d2[0]), sign * (2 * d1[1] - d2[1]), sign * (2 * d1[2] - d2[2])};
}
}  // namespace

TEST_CASE_TEMPLATE("squad with Shoemake control points has continuous angular velocity", Q,
                   ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const bool dbl = sizeof(T) == sizeof(double);
    const T h = dbl ? T(2e-5) : T(5e-3);
    const ld tol = dbl ? 1e-6L : 3e-3L;  // relative: O(h^2) truncation, eps / h rounding
    rng r(35);
    for (int run = 0; run < 10; ++run) {
        const std::vector<Q> q = walk<Q>(r, 5);
        std::vector<Q> s;
        for (std::size_t i = 0; i < q.size(); ++i)
            s.push_back(
                anima::squad_control_point(q[i == 0 ? 0 : i - 1], q[i], q[i + 1 == q.size() ? i : i + 1]));
        for (std::size_t i = 1; i + 1 < q.size(); ++i) {
            CAPTURE(i);
            const vec before = squad_rate(q[i - 1], q[i], s[i - 1], s[i], true, h);
            const vec after = squad_rate(q[i], q[i + 1], s[i], s[i + 1], false, h);
            CHECK(vdiff(before, after) <= tol * vnorm(after));
            // The same measurement detects a kink: with the keys as control points
            // (piecewise slerp) the velocity jumps at every key of a curved path.
            const vec b0 = squad_rate(q[i - 1], q[i], q[i - 1], q[i], true, h);
            const vec a0 = squad_rate(q[i], q[i + 1], q[i], q[i + 1], false, h);
            CHECK(vdiff(b0, a0) > 0.1L * vnorm(a0));
        }
    }
}

TEST_CASE_TEMPLATE("squad of a key pair turns monotonically for every key angle up to 180 degrees", Q,
                   ANIMA_QUAT_TYPES) {
    // With Shoemake's end control points every quaternion involved lies on the
    // one great circle through a and b: squad(t) = a (a^-1 b)^g(t) with
    // g(t) = t + t(1 - t)(t - 1/2), increasing from 0 to 1, g(1/2) = 1/2. A
    // blend that picks its own shorter arc between the control points (more
    // than 90 degrees apart once the keys are more than 120 degrees apart)
    // turns backwards instead: 29.5 degrees at t = 1/2 for a 121 degree key.
    using T = scalar<Q>;
    const ld tol = 64 * eps<T>();
    rng r(36);
    for (int degrees = 1; degrees <= 180; ++degrees) {
        for (const ld alpha : {ld(degrees) * pi / 180, ld(degrees) * pi / 180 - 1e-4L}) {
            const Q a = r.unit<Q>();
            const Q b0 = from_lq<Q>(to_lq(a) * rot(alpha, r.unit_vector()));
            const Q b = degrees % 2 == 0 ? neg(b0) : b0;  // either sign of the second key
            const Q s1 = anima::squad_control_point(a, a, b), s2 = anima::squad_control_point(a, b, b);
            const ld angle = angle_between(to_lq(a), to_lq(b));
            CAPTURE(degrees);
            CAPTURE(alpha);
            CHECK(diff(anima::squad(a, b, s1, s2, T(0)), a) <= 2 * eps<T>());
            CHECK(diff_up_to_sign(anima::squad(a, b, s1, s2, T(1)), b) <= 2 * eps<T>());
            ld previous = 0;
            for (int k = 0; k <= 64; ++k) {
                const T t = T(k) / T(64);
                const Q q = anima::squad(a, b, s1, s2, t);
                CAPTURE(t);
                REQUIRE(finite(q));
                CHECK(norm_error(q) <= 2 * eps<T>());
                const ld g = ld(t) + ld(t) * (1 - ld(t)) * (ld(t) - 0.5L);
                const ld turned = angle_between(to_lq(a), to_lq(q));
                CHECK(std::abs(turned - g * angle) <= tol);
                CHECK(turned >= previous - 4 * eps<T>());
                previous = turned;
            }
        }
    }
}

TEST_CASE_TEMPLATE("squad crosses keys on either side of the double cover the same way", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    rng r(37);
    for (int run = 0; run < 10; ++run) {
        // Large steps (100 to 170 degrees) between keys given with random signs.
        std::vector<Q> q{r.unit<Q>()};
        for (int i = 1; i < 5; ++i) {
            const Q next = from_lq<Q>(to_lq(q.back()) * rot(r.uniform(1.75, 2.95), r.unit_vector()));
            q.push_back(r.uniform(0, 1) < 0.5 ? neg(next) : next);
        }
        std::vector<Q> s;
        for (std::size_t i = 0; i < q.size(); ++i)
            s.push_back(
                anima::squad_control_point(q[i == 0 ? 0 : i - 1], q[i], q[i + 1 == q.size() ? i : i + 1]));
        for (std::size_t i = 0; i + 1 < q.size(); ++i) {
            // Flipping the sign of the end key (and so of its control point,
            // which is built on its side) must not change the curve.
            for (int k = 0; k <= 16; ++k) {
                const T t = T(k) / T(16);
                const Q x = anima::squad(q[i], q[i + 1], s[i], s[i + 1], t);
                const Q y = anima::squad(q[i], neg(q[i + 1]), s[i], neg(s[i + 1]), t);
                CHECK(diff(x, y) <= 2 * e);
                // The curve stays close to the segment's own slerp: the long
                // way round would be up to 180 degrees off.
                CHECK(angle_between(to_lq(x), to_lq(anima::slerp(q[i], q[i + 1], t))) <= 0.8L);
            }
        }
    }
}

TEST_CASE_TEMPLATE("slerp and squad normalise 1e-200, 1e200 and denormal inputs, and reject zero and NaN", Q,
                   ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    rng r(38);
    for (int i = 0; i < 50; ++i) {
        const Q a = r.unit<Q>(), b = r.unit<Q>();
        const T t = T(r.uniform(0, 1));
        for (const T sa : awkward_scales<T>()) {
            for (const T sb : awkward_scales<T>()) {
                CAPTURE(sa);
                CAPTURE(sb);
                const Q as = scaled(a, sa), bs = scaled(b, sb);
                const Q s = anima::slerp(as, bs, t);
                REQUIRE(finite(s));
                CHECK(norm_error(s) <= 2 * e);
                // The reference uses the components as stored: denormal ones
                // have lost bits, which is the input's error, not slerp's.
                CHECK(diff(s, ref_slerp(unit(to_lq(as)), unit(to_lq(bs)), t)) <= 8 * e);
                const Q c = anima::squad(as, bs, as, bs, t);
                REQUIRE(finite(c));
                CHECK(norm_error(c) <= 2 * e);
            }
        }
    }
    const Q a = r.unit<Q>();
    const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
    for (const Q& bad : {make<Q>(0, 0, 0, 0), make<Q>(nan, 0, 0, 0), make<Q>(0, inf, 0, 0), make<Q>(1, 0, 0, -inf)}) {
        CHECK_THROWS_AS(anima::slerp(a, bad, T(0.5)), anima::error);
        CHECK_THROWS_AS(anima::slerp(bad, a, T(0.25)), anima::error);
        CHECK_THROWS_AS(anima::squad(a, bad, a, a, T(0.5)), anima::error);
        CHECK_THROWS_AS(anima::squad(a, a, a, bad, T(0.5)), anima::error);
        CHECK_THROWS_AS(anima::squad_control_point(a, bad, a), anima::error);
    }
    CHECK_THROWS_AS(anima::slerp(a, a, nan), anima::error);
    CHECK_THROWS_AS(anima::squad(a, a, a, a, inf), anima::error);
}

TEST_CASE_TEMPLATE("slerp's worst angle error on mixed inputs is within GLM's accuracy", Q, ANIMA_QUAT_TYPES) {
    // 4096 pairs: uniformly random, 1e-6 rad apart, nearly antipodal 4-vectors
    // (the same rotation up to 1e-6 rad) and rotations 150 to 180 degrees
    // apart; t uniform in [0, 1]. The error is the angle between anima's result
    // and a long double slerp, the same for GLM's and Eigen's own slerp.
    using T = scalar<Q>;
    const bool dbl = sizeof(T) == sizeof(double);
    const ld bound = dbl ? 2e-15L : 5e-7L;
    rng r(39);
    ld worst = 0, worst_glm = 0, worst_eigen = 0;
    for (int i = 0; i < 4096; ++i) {
        const lq a = r.unit_lq(), b = mixed_partner(r, a, i);
        const Q qa = from_lq<Q>(a), qb = from_lq<Q>(b);
        const T t = T(r.uniform(0, 1));
        const lq ref = ref_slerp(to_lq(qa), to_lq(qb), t);  // from the inputs as rounded to T
        worst = std::max(worst, angle_between(to_lq(anima::slerp(qa, qb, t)), ref));
        worst_glm = std::max(worst_glm, angle_between(to_lq(glm::slerp(to_glm(qa), to_glm(qb), t)), ref));
        worst_eigen = std::max(worst_eigen, angle_between(to_lq(to_eigen(qa).slerp(t, to_eigen(qb))), ref));
    }
    CAPTURE(worst_glm);
    CAPTURE(worst_eigen);
    CHECK(worst <= bound);
    CHECK(worst <= 2 * std::max(worst_glm, worst_eigen));
}

TEST_CASE_TEMPLATE("slerp is accurate on mid-range pairs and on both sides of the direct series' limit and tiers", Q,
                   ANIMA_QUAT_TYPES) {
    // Rotations 5 to 175 degrees apart, and 4-vector angles with 1 - cos(theta)
    // just below and above slerp_direct_limit (where the weights switch from
    // the series in cos(theta) - 1 to the quartered angle) and each bound of
    // direct_series_bounds (where the direct series is cut shorter): the same
    // bounds as on the mixed set, and the components within 4 eps of a long
    // double slerp.
    using T = scalar<Q>;
    const T e = eps<T>();
    const bool dbl = sizeof(T) == sizeof(double);
    const ld bound = dbl ? 2e-15L : 5e-7L;
    std::vector<ld> switches{2 * std::acos(1 - ld(anima::detail::slerp_direct_limit<T>()))};  // rotation angles
    for (int k = 0; k < anima::detail::direct_series_tiers<T>; ++k)
        switches.push_back(2 * std::acos(1 - ld(anima::detail::direct_series_bounds<T>[k])));
    rng r(42);
    ld worst = 0;
    for (int i = 0; i < 4000; ++i) {
        const lq a = r.unit_lq();
        const ld switch_angle = switches[static_cast<std::size_t>(i / 4) % switches.size()];
        const ld angle = i % 2 == 0 ? r.uniform(5, 175) * pi / 180 : switch_angle * (1 + (i % 4 == 1 ? -1 : 1) * 1e-4L);
        const Q qa = from_lq<Q>(a), qb = from_lq<Q>(a * rot(angle, r.unit_vector()));
        const T t = T(r.uniform(0, 1));
        const Q s = anima::slerp(qa, qb, t);
        const lq ref = ref_slerp(to_lq(qa), to_lq(qb), t);
        CAPTURE(angle);
        CHECK(norm_error(s) <= 2 * e);
        CHECK(diff(s, ref) <= 4 * e);
        worst = std::max(worst, angle_between(to_lq(s), ref));
    }
    CHECK(worst <= bound);
}

TEST_CASE_TEMPLATE("slerp's single fast-path test routes every other input to the general path", Q, ANIMA_QUAT_TYPES) {
    // The fast path takes t in [0, 1] and inputs within sqrt(eps)/4 of unit
    // squared length in one test; just outside it, results must still be a
    // correct slerp (extrapolation, normalisation), and NaN or infinite t
    // must throw rather than leak into the result.
    using T = scalar<Q>;
    const T e = eps<T>();
    rng r(40);
    for (int i = 0; i < 100; ++i) {
        const Q a = r.unit<Q>(), b = r.unit<Q>();
        const lq pa = to_lq(a), pb = to_lq(b);
        for (const T t : {std::nextafter(T(0), T(-1)), T(-0.0), std::nextafter(T(1), T(2)), T(-1e-3), T(1.001)}) {
            CAPTURE(t);
            const Q s = anima::slerp(a, b, t);
            CHECK(norm_error(s) <= 2 * e);
            CHECK(diff(s, ref_slerp(pa, pb, t)) <= 8 * e);
        }
        // Squared lengths 1 +- 0.6 sqrt(eps) each: either alone passes the
        // test, together they do not; and 1 + sqrt(eps), far outside.
        const ld step = 0.3L * std::sqrt(ld(e));
        for (const ld grow : {1 + step, 1 - step, 1 + 2 * step, 1 - 2 * step}) {
            for (const ld shrink : {1 + step, 1 - step, 1 + 2 * step}) {
                const Q as = make<Q>(grow * pa.w, grow * pa.x, grow * pa.y, grow * pa.z);
                const Q bs = make<Q>(shrink * pb.w, shrink * pb.x, shrink * pb.y, shrink * pb.z);
                const T t = T(r.uniform(0, 1));
                CAPTURE(grow);
                CAPTURE(shrink);
                const Q s = anima::slerp(as, bs, t);
                CHECK(norm_error(s) <= 2 * e);
                CHECK(diff(s, ref_slerp(unit(to_lq(as)), unit(to_lq(bs)), t)) <= 8 * e);
            }
        }
        const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
        for (const T t : {nan, inf, -inf}) {
            CHECK_THROWS_AS(anima::slerp(a, b, t), anima::invalid_argument);
            CHECK_THROWS_AS(anima::squad(a, b, a, b, t), anima::invalid_argument);
        }
    }
}

TEST_CASE_TEMPLATE("slerp is exact at t = 0 and 1 and continuous across the switch to the series", Q,
                   ANIMA_QUAT_TYPES) {
    // The weights come from one of two series, chosen by 1 - cos(theta)
    // against sqrt(eps) (theta the 4-vector angle). Angles on both sides of
    // that switch, and the singular cases (identical, 1e-6 rad apart,
    // antipodal, 1e-6 rad from antipodal), against a long double slerp.
    using T = scalar<Q>;
    const T e = eps<T>();
    const ld switch_angle = 4 * std::acos(1 - std::sqrt(ld(e)));  // rotation angle (twice the 4-vector angle)
    rng r(41);
    for (int i = 0; i < 50; ++i) {
        const lq a = r.unit_lq();
        const vec axis = r.unit_vector();
        std::vector<lq> others{a, scale(a, -1)};
        for (const ld angle : {1e-6L, switch_angle * (1 - 1e-3L), switch_angle, switch_angle * (1 + 1e-3L), 0.5L, 2.0L,
                               pi - 1e-6L}) {
            others.push_back(a * rot(angle, axis));
            others.push_back(scale(a * rot(angle, axis), -1));
        }
        const Q qa = from_lq<Q>(a);
        for (const lq& o : others) {
            const Q qb = from_lq<Q>(o);
            const Q s0 = anima::slerp(qa, qb, T(0)), s1 = anima::slerp(qa, qb, T(1));
            CHECK(diff(s0, qa) <= 2 * e);
            CHECK(diff(s1, anima::align_hemisphere(qb, qa)) <= 2 * e);
            for (const T t : {T(1e-6), T(0.25), T(0.5), T(0.75), T(1) - T(1e-6)}) {
                CAPTURE(t);
                const Q s = anima::slerp(qa, qb, t);
                const lq ref = ref_slerp(to_lq(qa), to_lq(qb), t);
                REQUIRE(finite(s));
                CHECK(norm_error(s) <= 2 * e);
                CHECK(diff(s, ref) <= 4 * e);
                // t is honoured at every angle: no early-out to a or b.
                CHECK(angle_between(to_lq(s), ref) <= 4 * e);
            }
        }
    }
}

namespace {
/// Squad in long double: q2 and s2 on q1's side, then three slerps along the arcs as given.
lq ref_squad(const lq& q1, lq q2, const lq& s1, lq s2, ld t) {
    if (q1.w * q2.w + q1.x * q2.x + q1.y * q2.y + q1.z * q2.z < 0) {
        q2 = scale(q2, -1);
        s2 = scale(s2, -1);
    }
    return ref_slerp_as_given(ref_slerp_as_given(q1, q2, t), ref_slerp_as_given(s1, s2, t), 2 * t * (1 - t));
}
/// Log (rotation vector / 2 form: angle/2 * axis) of a unit quaternion, long double.
vec ref_log(const lq& q) {
    const ld s = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
    if (s == 0) return {0, 0, 0};
    const ld k = std::atan2(s, q.w) / s;
    return {k * q.x, k * q.y, k * q.z};
}
lq ref_exp(const vec& v) {
    const ld a = vnorm(v);
    if (a == 0) return {1, 0, 0, 0};
    const ld k = std::sin(a) / a;
    return {std::cos(a), k * v[0], k * v[1], k * v[2]};
}
/// Shoemake's control point in long double, neighbours moved to q's hemisphere.
lq ref_control_point(lq p, const lq& q, lq n) {
    const auto dot = [](const lq& a, const lq& b) { return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z; };
    if (dot(q, p) < 0) p = scale(p, -1);
    if (dot(q, n) < 0) n = scale(n, -1);
    const vec a = ref_log(conj(q) * n), b = ref_log(conj(q) * p);
    return q * ref_exp({-(a[0] + b[0]) / 4, -(a[1] + b[1]) / 4, -(a[2] + b[2]) / 4});
}
}  // namespace

TEST_CASE_TEMPLATE("squad's joint fast path matches a long double squad, also at its singular cases", Q,
                   ANIMA_QUAT_TYPES) {
    // Both inner blends of squad share t and run together; the series they
    // use is exact at a zero angle, so identical keys, identical control
    // points, keys 1e-6 rad apart and keys given on opposite sides of the
    // double cover need no branch of their own.
    using T = scalar<Q>;
    const T e = eps<T>();
    rng r(42);
    for (int i = 0; i < 200; ++i) {
        const lq q1 = r.unit_lq();
        lq q2;
        switch (i % 5) {
        case 0: q2 = q1; break;
        case 1: q2 = q1 * rot(1e-6L, r.unit_vector()); break;
        case 2: q2 = scale(q1 * rot(r.uniform(0.1, 1.5), r.unit_vector()), -1); break;
        case 3: q2 = q1 * rot(pi - 1e-6L, r.unit_vector()); break;
        default: q2 = q1 * rot(r.uniform(0.1, 1.5), r.unit_vector()); break;
        }
        const Q a = from_lq<Q>(q1), b = from_lq<Q>(q2);
        const Q sa = anima::squad_control_point(a, a, b), sb = i % 5 == 0 ? sa : anima::squad_control_point(a, b, b);
        CAPTURE(i);
        CHECK(diff(anima::squad(a, b, sa, sb, T(0)), a) <= 2 * e);
        CHECK(diff_up_to_sign(anima::squad(a, b, sa, sb, T(1)), b) <= 2 * e);
        for (const T t : {T(1e-6), T(0.2), T(0.5), T(0.9), T(1) - T(1e-6)}) {
            CAPTURE(t);
            const Q s = anima::squad(a, b, sa, sb, t);
            REQUIRE(finite(s));
            CHECK(norm_error(s) <= 2 * e);
            CHECK(diff(s, ref_squad(to_lq(a), to_lq(b), to_lq(sa), to_lq(sb), t)) <= 8 * e);
        }
    }
}

TEST_CASE_TEMPLATE("squad_control_point matches a long double control point near its singular cases", Q,
                   ANIMA_QUAT_TYPES) {
    // Polynomial logarithms (both at once) and exponential against atan2,
    // sin and cos in long double: identical neighbours, neighbours 1e-6 rad
    // away, neighbours given on the other side of the double cover, and
    // neighbours up to 180 degrees away (the exponential's argument then
    // reaches pi/4, the end of its polynomial's range).
    using T = scalar<Q>;
    const T e = eps<T>();
    rng r(43);
    for (int i = 0; i < 300; ++i) {
        const lq q = r.unit_lq();
        const ld big = pi - 1e-6L;
        lq p, n;
        switch (i % 5) {
        case 0: p = n = q; break;
        case 1: p = q * rot(1e-6L, r.unit_vector()), n = q * rot(1e-6L, r.unit_vector()); break;
        case 2: p = scale(q * rot(1.0L, r.unit_vector()), -1), n = scale(q * rot(2.0L, r.unit_vector()), -1); break;
        case 3: {
            const vec axis = r.unit_vector();
            p = n = q * rot(big, axis);  // both logs (pi/2) axis: the exponential's argument is pi/4
            break;
        }
        default: p = q * rot(r.uniform(0, 3.1), r.unit_vector()), n = q * rot(r.uniform(0, 3.1), r.unit_vector());
        }
        const Q qp = from_lq<Q>(p), qq = from_lq<Q>(q), qn = from_lq<Q>(n);
        const Q s = anima::squad_control_point(qp, qq, qn);
        CAPTURE(i);
        REQUIRE(finite(s));
        CHECK(norm_error(s) <= 4 * e);
        CHECK(diff(s, ref_control_point(to_lq(qp), to_lq(qq), to_lq(qn))) <= 8 * e);
        if (i % 5 == 0) CHECK(diff(s, qq) <= 2 * e);
    }
}
