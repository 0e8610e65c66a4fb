// slerp_batch against a long double slerp and against the scalar slerp, at
// every position in and around a block, with one t or one per pair, in place,
// and with the blocks the vector path must hand to the scalar slerp.
#include "rotation_test_util.hpp"

#include <anima/rotation/slerp.hpp>
#include <anima/rotation/slerp_batch.hpp>

#include <string>
#include <vector>

using namespace rt;

namespace {
/// n pairs of the mixed slerp inputs (mixed_partner), t uniform in [0, 1].
template <class Q>
void mixed_pairs(rng& r, std::size_t n, std::vector<Q>& a, std::vector<Q>& b, std::vector<scalar<Q>>& t) {
    using T = scalar<Q>;
    a.clear(), b.clear(), t.clear();
    for (std::size_t i = 0; i < n; ++i) {
        const lq p = r.unit_lq();
        a.push_back(from_lq<Q>(p));
        b.push_back(from_lq<Q>(mixed_partner(r, p, i)));
        t.push_back(T(r.uniform(0, 1)));
    }
}
}  // namespace

TEST_CASE_TEMPLATE("slerp_batch matches a long double slerp on mixed inputs at GLM's accuracy", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    const ld bound = sizeof(T) == sizeof(double) ? 2e-15L : 5e-7L;
    rng r(61);
    std::vector<Q> a, b;
    std::vector<T> t;
    mixed_pairs(r, 4096, a, b, t);
    std::vector<Q> out(a.size());
    anima::slerp_batch(a.data(), b.data(), t.data(), a.size(), out.data());
    ld worst = 0, worst_scalar = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const lq ref = ref_slerp(to_lq(a[i]), to_lq(b[i]), t[i]);
        worst = std::max(worst, angle_between(to_lq(out[i]), ref));
        worst_scalar = std::max(worst_scalar, angle_between(to_lq(anima::slerp(a[i], b[i], t[i])), ref));
        CHECK(norm_error(out[i]) <= 2 * e);
        // The same side of the double cover as the scalar slerp: a's.
        CHECK(diff(out[i], anima::slerp(a[i], b[i], t[i])) <= 8 * e);
    }
    CAPTURE(worst_scalar);
    CHECK(worst <= bound);
}

TEST_CASE_TEMPLATE("slerp_batch at every size around a block, with one t, and in place", Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    constexpr std::size_t block = anima::detail::slerp_block_size<T>;
    rng r(62);
    for (const std::size_t n : {std::size_t(0), std::size_t(1), block - 1, block, block + 1, 3 * block + 5}) {
        CAPTURE(n);
        std::vector<Q> a, b;
        std::vector<T> t;
        mixed_pairs(r, n, a, b, t);
        std::vector<Q> out(n), one_t(n);
        anima::slerp_batch(a.data(), b.data(), t.data(), n, out.data());
        const T shared = T(r.uniform(0, 1));
        anima::slerp_batch(a.data(), b.data(), shared, n, one_t.data());
        for (std::size_t i = 0; i < n; ++i) {
            CHECK(diff(out[i], anima::slerp(a[i], b[i], t[i])) <= 8 * e);
            CHECK(diff(one_t[i], anima::slerp(a[i], b[i], shared)) <= 8 * e);
        }
        // In place: out is a.
        std::vector<Q> in_place = a;
        anima::slerp_batch(in_place.data(), b.data(), t.data(), n, in_place.data());
        for (std::size_t i = 0; i < n; ++i) CHECK(diff(in_place[i], out[i]) == 0);
    }
    // Identical and antipodal pairs give a at every t, and t = 0 and 1 the ends.
    std::vector<Q> a, b, out(2 * block);
    for (std::size_t i = 0; i < 2 * block; ++i) {
        a.push_back(r.unit<Q>());
        b.push_back(i % 2 == 0 ? a.back() : from_lq<Q>(scale(to_lq(a.back()), -1)));
    }
    for (const T t : {T(0), T(0.25), T(0.5), T(1)}) {
        anima::slerp_batch(a.data(), b.data(), t, a.size(), out.data());
        for (std::size_t i = 0; i < a.size(); ++i) CHECK(diff(out[i], a[i]) <= 2 * e);
    }
    std::vector<Q> c(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) c[i] = r.unit<Q>();
    anima::slerp_batch(a.data(), c.data(), T(0), a.size(), out.data());
    for (std::size_t i = 0; i < a.size(); ++i) CHECK(diff(out[i], a[i]) <= 2 * e);
    anima::slerp_batch(a.data(), c.data(), T(1), a.size(), out.data());
    for (std::size_t i = 0; i < a.size(); ++i) CHECK(diff_up_to_sign(out[i], c[i]) <= 2 * e);
}

TEST_CASE_TEMPLATE("slerp_batch hands extrapolation and non-unit blocks to the scalar slerp and names a bad pair",
                   Q, ANIMA_QUAT_TYPES) {
    using T = scalar<Q>;
    const T e = eps<T>();
    constexpr std::size_t block = anima::detail::slerp_block_size<T>;
    rng r(63);
    std::vector<Q> a, b;
    std::vector<T> t;
    mixed_pairs(r, 3 * block, a, b, t);
    // Block 0 extrapolates at one pair, block 1 has one input of length 2:
    // every pair of both must still be the scalar slerp's result.
    t[3] = T(1.5);
    b[block + 2] = scaled(b[block + 2], T(2));
    std::vector<Q> out(a.size());
    anima::slerp_batch(a.data(), b.data(), t.data(), a.size(), out.data());
    for (std::size_t i = 0; i < a.size(); ++i) {
        CAPTURE(i);
        CHECK(norm_error(out[i]) <= 2 * e);
        CHECK(diff(out[i], anima::slerp(a[i], b[i], t[i])) <= 8 * e);
    }
    const auto message = [&](std::vector<Q> qa, std::vector<T> qt) {
        try {
            anima::slerp_batch(qa.data(), b.data(), qt.data(), qa.size(), out.data());
        } catch (const anima::invalid_argument& error) {
            return std::string(error.what());
        }
        return std::string("no error");
    };
    std::vector<T> bad_t = t;
    bad_t[block + 5] = std::numeric_limits<T>::quiet_NaN();
    CHECK(message(a, bad_t).find("anima::slerp_batch: pair " + std::to_string(block + 5)) == 0);
    std::vector<Q> zero = a;
    zero[2 * block + 1] = anima::quat_traits<Q>::make(T(0), T(0), T(0), T(0));
    CHECK(message(zero, t).find("anima::slerp_batch: pair " + std::to_string(2 * block + 1)) == 0);
    CHECK_THROWS_AS(anima::slerp_batch(a.data(), b.data(), static_cast<const T*>(nullptr), a.size(), out.data()),
                    anima::invalid_argument);
    CHECK_THROWS_AS(anima::slerp_batch(a.data(), static_cast<const Q*>(nullptr), T(0.5), a.size(), out.data()),
                    anima::invalid_argument);
    anima::slerp_batch(static_cast<const Q*>(nullptr), static_cast<const Q*>(nullptr), T(0.5), 0,
                       static_cast<Q*>(nullptr));
}
