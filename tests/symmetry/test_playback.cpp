// Symmetric playback (Eq 6 and the adaptive turning rule), frame coverage,
// video-texture jumps and playback, and resequencing a clip from a frame
// stream with each root-path policy.
#include "symmetry_test_support.hpp"

#include <anima/core/error.hpp>
#include <anima/core/random.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/contacts.hpp>
#include <anima/motion/resequence.hpp>
#include <anima/motion/speed_limits.hpp>
#include <anima/motion/frame_distance.hpp>
#include <anima/motion/frame_features.hpp>
#include <anima/symmetry/render_stream.hpp>
#include <anima/symmetry/symmetric_playback.hpp>
#include <anima/symmetry/symmetry_scores.hpp>
#include <anima/symmetry/video_texture.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

using namespace symmetry_test;
using anima::frame_metric;

template <class T>
std::vector<anima::turning_candidate<T>> candidates_of(const anima::clip<T>& c, frame_metric metric) {
    anima::symmetry_params<T> p;
    p.distance.metric = metric;
    return anima::symmetry_scores(c, p).candidates;
}

template <class T>
std::vector<anima::turning_candidate<T>> make_candidates(const std::vector<std::pair<std::size_t, double>>& list) {
    std::vector<anima::turning_candidate<T>> out;
    for (const auto& [frame, p] : list) out.push_back({frame, static_cast<T>(2 * p), static_cast<T>(p)});
    return out;
}

std::size_t distinct(const std::vector<std::size_t>& stream) {
    return std::set<std::size_t>(stream.begin(), stream.end()).size();
}

// The stream moves by one frame at a time and reverses exactly at the
// recorded turns, each at a candidate frame; nothing leaves [first, last].
template <class T>
void check_stream(const std::vector<std::size_t>& stream, const anima::symmetric_playback<T>& playback,
                  const std::vector<anima::turning_candidate<T>>& candidates) {
    std::set<std::size_t> turning;
    for (const auto& c : candidates) turning.insert(c.frame);
    const std::set<std::size_t> turns(playback.turns().begin(), playback.turns().end());
    CHECK(turns.size() == playback.turns().size());
    for (std::size_t t = 0; t < stream.size(); ++t) {
        REQUIRE(stream[t] >= playback.first_turning_frame());
        REQUIRE(stream[t] <= playback.last_turning_frame());
        if (t > 0) REQUIRE((stream[t] == stream[t - 1] + 1 || stream[t] + 1 == stream[t - 1]));
        if (t > 0 && t + 1 < stream.size()) {
            const bool reversed = stream[t - 1] == stream[t + 1];
            REQUIRE(reversed == (turns.count(t) == 1));
            if (reversed) REQUIRE(turning.count(stream[t]) == 1);
        }
    }
}

}  // namespace

// ---------------------------------------------------------------------------
// Symmetric playback
// ---------------------------------------------------------------------------

TEST_CASE_TEMPLATE("symmetric playback stays in the clip, turns only at candidates, reverses there", T, float, double) {
    for (const anima::clip<T>* c : {&walk<T>(), &run<T>()})
        for (auto metric : {frame_metric::mahalanobis, frame_metric::l2})
            for (bool adaptive : {true, false}) {
                CAPTURE(c->frames());
                CAPTURE(anima::to_string(metric));
                CAPTURE(adaptive);
                const auto candidates = candidates_of(*c, metric);
                REQUIRE(candidates.size() >= 2);
                anima::playback_params<T> p;
                p.adaptive = adaptive;
                p.seed = 7;
                anima::symmetric_playback<T> playback(c->frames(), candidates, p);
                const auto stream = playback.take(20 * c->frames());
                check_stream(stream, playback, candidates);
                CHECK(playback.turns().size() > 10);
                std::vector<std::size_t> frames;
                for (const auto& x : candidates) frames.push_back(x.frame);
                CHECK(playback.first_turning_frame() == *std::min_element(frames.begin(), frames.end()));
                CHECK(playback.last_turning_frame() == *std::max_element(frames.begin(), frames.end()));
            }
}

TEST_CASE_TEMPLATE("symmetric playback is reproducible: same seed same stream, another seed another", T, float, double) {
    const auto candidates = candidates_of(walk<T>(), frame_metric::mahalanobis);
    for (bool adaptive : {true, false}) {
        anima::playback_params<T> p;
        p.adaptive = adaptive;
        p.seed = 42;
        anima::symmetric_playback<T> a(walk<T>().frames(), candidates, p), b(walk<T>().frames(), candidates, p);
        const auto sa = a.take(5000);
        std::vector<std::size_t> sb;
        for (int k = 0; k < 5000; ++k) sb.push_back(b.next());  // next() and take() agree
        CHECK(sa == sb);
        CHECK(a.turns() == b.turns());
        p.seed = 43;
        anima::symmetric_playback<T> other(walk<T>().frames(), candidates, p);
        CHECK(other.take(5000) != sa);
    }
}

TEST_CASE("random_source: the standard's mt19937_64 stream, converted the same way everywhere") {
    // The C++ standard fixes the 10000th output of a default-seeded mt19937_64.
    anima::random_source standard(5489);
    for (int k = 1; k < 10000; ++k) standard.raw();
    CHECK(standard.raw() == 9981545732273789042ULL);

    anima::random_source r1(5), r2(5);
    std::mt19937_64 engine(5);
    for (int k = 0; k < 1000; ++k) {
        const double u = r1.uniform();
        CHECK(u == r2.uniform());
        CHECK(u == std::ldexp(static_cast<double>(engine() >> 11), -53));  // the top 53 bits
        CHECK(u >= 0.0);
        CHECK(u < 1.0);
        const auto b = r1.below(7);
        CHECK(b == r2.below(7));
        CHECK(b < 7);
        engine.discard(1);  // below(7) used one value: a rejection is rarer than 1 in 2^61
    }
    CHECK(anima::random_source(5).raw() != anima::random_source(6).raw());
    CHECK(anima::random_source(1).below(1) == 0);
}

TEST_CASE_TEMPLATE("adaptive turning: a turn lowers the probability by the penalty, a pass multiplies it by k", T, float,
                   double) {
    const auto candidates = make_candidates<T>({{3, 0.5}, {12, 0.3}, {20, 0.95}, {27, 0.01}, {33, 0.4}});
    anima::playback_params<T> p;
    p.seed = 3;
    p.turn_penalty = T(0.15);
    p.gain = T(1.5);
    p.min_probability = T(0.05);
    p.max_probability = T(0.8);
    anima::symmetric_playback<T> playback(40, candidates, p);
    // Start values (Eq 5) are clamped into the bounds.
    CHECK(playback.probability(3) == T(0.5));
    CHECK(playback.probability(20) == T(0.8));
    CHECK(playback.probability(27) == T(0.05));
    CHECK(playback.probability(5) == T(0));
    CHECK(playback.probability(1000) == T(0));

    std::map<std::size_t, T> before;
    int turned = 0, passed = 0, forced = 0;
    for (int step = 0; step < 4000; ++step) {
        for (const auto& c : candidates) before[c.frame] = playback.probability(c.frame);
        const std::size_t turns_before = playback.turns().size();
        const std::size_t shown = playback.next();
        const bool turn = playback.turns().size() > turns_before;
        for (const auto& c : candidates) {
            const T now = playback.probability(c.frame);
            CHECK(now >= p.min_probability);
            CHECK(now <= p.max_probability);
            if (c.frame != shown) CHECK(now == before[c.frame]);  // only the frame shown adapts
        }
        if (step == 0) {
            CHECK(playback.probability(shown) == before[shown]);  // the start frame was not arrived at
            continue;
        }
        if (shown == playback.first_turning_frame() || shown == playback.last_turning_frame()) {
            CHECK(turn);  // the ends always turn, and do not adapt
            CHECK(playback.probability(shown) == before[shown]);
            ++forced;
        } else if (before.count(shown)) {
            const T was = before[shown];
            if (turn) {
                ++turned;
                CHECK(playback.probability(shown) == std::max(p.min_probability, T(was - p.turn_penalty)));
                if (was > p.min_probability) CHECK(playback.probability(shown) < was);
            } else {
                ++passed;
                CHECK(playback.probability(shown) == std::min(p.max_probability, T(was * p.gain)));
                if (was < p.max_probability) CHECK(playback.probability(shown) > was);
            }
        } else {
            CHECK_FALSE(turn);  // never turns elsewhere
        }
    }
    CHECK(turned > 20);
    CHECK(passed > 20);
    CHECK(forced > 20);

    // Fixed probabilities never change.
    p.adaptive = false;
    anima::symmetric_playback<T> fixed(40, candidates, p);
    fixed.take(2000);
    CHECK(fixed.probability(12) == T(0.3));
    CHECK(fixed.probability(33) == T(0.4));
}

TEST_CASE_TEMPLATE("adaptive playback shows more of a real clip than fixed probabilities", T, float, double) {
    for (const anima::clip<T>* c : {&walk<T>(), &run<T>()})
        for (auto metric : {frame_metric::mahalanobis, frame_metric::l2}) {
            CAPTURE(c->frames());
            CAPTURE(anima::to_string(metric));
            const auto candidates = candidates_of(*c, metric);
            // Frames shown within a stream twice the clip's length, and how
            // evenly a stream twenty times as long spreads over the clip,
            // summed over seeds (one stream is a matter of luck).
            std::size_t shown[2] = {0, 0};
            double evenness[2] = {0, 0};
            for (std::uint64_t seed = 1; seed <= 20; ++seed)
                for (int adaptive = 0; adaptive < 2; ++adaptive) {
                    anima::playback_params<T> p;
                    p.adaptive = adaptive == 1;
                    p.seed = seed;
                    anima::symmetric_playback<T> playback(c->frames(), candidates, p);
                    const auto stream = playback.take(20 * c->frames());
                    shown[adaptive] += distinct(
                        std::vector<std::size_t>(stream.begin(), stream.begin() + static_cast<std::ptrdiff_t>(2 * c->frames())));
                    evenness[adaptive] += anima::coverage(stream, c->frames()).evenness;
                }
            if (std::is_same_v<T, double>)
                MESSAGE(anima::to_string(metric)
                        << ", " << c->frames() << " frames: distinct frames in 2x the clip, adaptive " << shown[1] / 20.0
                        << " vs fixed " << shown[0] / 20.0 << "; evenness " << evenness[1] / 20 << " vs " << evenness[0] / 20);
            // Within twice the clip's length the two are within noise of each
            // other (either may win); over the long stream adaptive playback
            // spreads the visits more evenly on every clip and metric.
            CHECK(evenness[1] > evenness[0]);
        }
}

TEST_CASE_TEMPLATE("render_stream: feet held through the turns, the root and the rest as resequenced", T, float, double) {
    const auto& c = walk<T>();
    anima::playback_params<T> pp;
    pp.seed = 3;
    anima::symmetric_playback<T> playback(c.frames(), candidates_of(c, frame_metric::mahalanobis), pp);
    const std::size_t frames = anima_test::sanitized_build ? 250 : 500;  // half the IK under the sanitizers
    const auto stream = playback.take(frames);
    const auto& turns = playback.turns();
    REQUIRE(turns.size() >= 2);
    anima::render_stream_params<T> rp;
    rp.plant_feet = false;
    const auto loose = anima::render_stream(c, stream, turns, rp);
    const auto plain = anima::resequence(c, stream);
    CHECK(loose.planted_runs == 0);
    for (std::size_t f = 0; f < stream.size(); ++f) {
        REQUIRE(loose.motion.root_position(f) == plain.root_position(f));
        for (std::size_t j = 0; j < c.joints(); ++j) REQUIRE(loose.motion.rotation(f, j).coeffs() == plain.rotation(f, j).coeffs());
    }
    const auto planted = anima::render_stream(c, stream, turns);  // planting is the default
    CHECK(planted.planted_runs >= 2);
    anima::contact_params<T> cp;
    cp.use_speed = false;  // sliding feet count as planted
    const auto skate = [&](const anima::clip<T>& m) { return anima::foot_skate(anima::find_contacts(m, cp)).median; };
    MESSAGE("playback skate / input: " << skate(loose.motion) / skate(c) << " loose, " << skate(planted.motion) / skate(c)
                                       << " planted");
    CHECK(skate(planted.motion) < T(0.5) * skate(loose.motion));
    // Only the legs move: the root's path is the resequenced one, and no
    // joint turns faster than the walk's own fastest.
    for (std::size_t f = 0; f < stream.size(); ++f) REQUIRE(planted.motion.root_position(f) == plain.root_position(f));
    const auto source = anima::clip_speed_limits(c).joint, played = anima::clip_speed_limits(planted.motion).joint;
    for (std::size_t j = 0; j < c.joints(); ++j) {
        CAPTURE(c.skeleton()[j].name);
        CHECK(played[j] <= source[j] * T(1.001) + T(1e-4));
    }
    // No events, nothing planted; an event past the stream is refused.
    CHECK(anima::render_stream(c, stream, {}).planted_runs == 0);
    CHECK(contains(invalid_argument_message([&] { (void)anima::render_stream(c, stream, {3, frames}); }),
                   "event 1 is output frame " + std::to_string(frames) + ", outside the stream's " +
                       std::to_string(frames) + " frames"));
}

TEST_CASE("coverage: fraction of frames shown and evenness of the visits") {
    auto c = anima::coverage<double>({0, 1, 1, 2}, 4);
    CHECK(c.visited == doctest::Approx(0.75));
    // Visits 1/4, 1/2, 1/4: entropy 1.5 ln 2 over ln 4.
    CHECK(c.evenness == doctest::Approx(0.75));
    c = anima::coverage<double>({0, 1, 2, 3, 3, 2, 1, 0}, 4);
    CHECK(c.visited == 1.0);
    CHECK(c.evenness == doctest::Approx(1.0));
    c = anima::coverage<double>({2, 2, 2}, 5);
    CHECK(c.visited == doctest::Approx(0.2));
    CHECK(c.evenness == 0.0);
    CHECK(anima::coverage<float>({}, 5).visited == 0.0f);
    CHECK(anima::coverage<double>({0, 0}, 1).evenness == 1.0);
    CHECK(anima::coverage<double>({}, 0).visited == 0.0);
    const std::string message = invalid_argument_message([] { anima::coverage<double>({0, 5}, 5); });
    CHECK(contains(message, "frame 5"));
}

TEST_CASE_TEMPLATE("symmetric playback: memory follows the candidates and the take, not the clip's length", T, float, double) {
    const auto two = make_candidates<T>({{5, 0.9}, {20, 0.8}});
    anima::playback_params<T> p;
    // The clip's length only bounds the candidates: a huge one plays as a short one.
    for (const std::size_t frames : {std::numeric_limits<std::size_t>::max(), std::size_t(1) << 40}) {
        anima::symmetric_playback<T> huge(frames, two, p), small(30, two, p);
        CHECK(huge.take(500) == small.take(500));
    }
    const auto message = [&](std::size_t frames, const std::vector<anima::turning_candidate<T>>& list,
                             const anima::playback_params<T>& q) {
        return invalid_argument_message([&] { anima::symmetric_playback<T>(frames, list, q); });
    };
    const std::size_t most = (std::size_t(1) << 30) / sizeof(long);
    CHECK(message(std::size_t(1) << 40, make_candidates<T>({{5, 0.9}, {std::size_t(1) << 39, 0.8}}), p) ==
          "anima::symmetric_playback: the last candidate frame must be below " + std::to_string(most) + " (" +
              std::to_string(sizeof(long)) + " bytes each, max_memory 1024 MiB), got 549755813888");
    // Takes: up to max_memory, or the largest vector when it is lifted.
    anima::symmetric_playback<T> playback(30, two, p);
    const std::size_t most_frames = (std::size_t(1) << 30) / sizeof(std::size_t);
    for (const std::size_t n : {std::numeric_limits<std::size_t>::max(), std::size_t(1) << 40, most_frames + 1})
        CHECK(invalid_argument_message([&] { (void)playback.take(n); }) ==
              "anima::symmetric_playback::take: n must be at most " + std::to_string(most_frames) + " (" +
                  std::to_string(sizeof(std::size_t)) + " bytes each, max_memory 1024 MiB), got " + std::to_string(n));
    p.max_memory = 0;
    anima::symmetric_playback<T> unlimited(30, two, p);
    CHECK(contains(invalid_argument_message([&] { (void)unlimited.take(std::numeric_limits<std::size_t>::max()); }),
                   "bytes each, the largest vector), got 18446744073709551615"));
    p.max_memory = 256;  // the table's 21 entries fit, and takes of 32 frames
    anima::symmetric_playback<T> tight(30, two, p);
    CHECK(tight.take(256 / sizeof(std::size_t)).size() == 256 / sizeof(std::size_t));
    CHECK(contains(invalid_argument_message([&] { (void)tight.take(256 / sizeof(std::size_t) + 1); }), "n must be at most"));
    CHECK(contains(message(40, make_candidates<T>({{5, 0.9}, {35, 0.8}}), p), "the last candidate frame must be below 32"));
    p.max_memory = -1;
    CHECK(message(30, two, p) == "anima::symmetric_playback: max_memory must be non-negative, got -1");
}

TEST_CASE("coverage: any number of clip frames, memory in proportion to the stream") {
    const std::vector<std::size_t> stream{1, 2, 3, 3};
    const auto big = anima::coverage<double>(stream, std::numeric_limits<std::size_t>::max());
    CHECK(big.visited == doctest::Approx(3.0 / 18446744073709551615.0));
    CHECK(big.evenness == doctest::Approx(-(2 * 0.25 * std::log(0.25) + 0.5 * std::log(0.5)) /
                                           std::log(18446744073709551615.0)));
    // Frames far apart are counted as close ones are.
    const auto far = anima::coverage<double>({0, std::size_t(1) << 40, std::size_t(1) << 40, 7}, std::size_t(1) << 41);
    const auto near = anima::coverage<double>({0, 9, 9, 7}, std::size_t(1) << 41);
    CHECK(far.visited == near.visited);
    CHECK(far.evenness == near.evenness);
    CHECK(contains(invalid_argument_message([] { anima::coverage<double>({1, 2, 99}, 10); }), "frame 99"));
}

TEST_CASE_TEMPLATE("symmetric playback: start frame, and errors for unusable candidates or parameters", T, float, double) {
    const auto candidates = make_candidates<T>({{5, 0.3}, {15, 0.3}, {25, 0.3}});
    anima::playback_params<T> p;
    // Before the first candidate: starts there, going forwards.
    auto s = anima::symmetric_playback<T>(30, candidates, p).take(3);
    CHECK(s == std::vector<std::size_t>{5, 6, 7});
    p.start_frame = 29;  // beyond the last: starts there, going backwards
    s = anima::symmetric_playback<T>(30, candidates, p).take(3);
    CHECK(s == std::vector<std::size_t>{25, 24, 23});
    p.start_frame = 15;  // on a candidate: no turn before anything was shown
    s = anima::symmetric_playback<T>(30, candidates, p).take(2);
    CHECK(s == std::vector<std::size_t>{15, 16});
    p.start_frame = 0;

    const auto message = [&](std::size_t frames, const std::vector<anima::turning_candidate<T>>& list,
                             const anima::playback_params<T>& q) {
        return invalid_argument_message([&] { anima::symmetric_playback<T>(frames, list, q); });
    };
    CHECK(contains(message(30, make_candidates<T>({{5, 0.3}}), p), "at least two"));
    CHECK(contains(message(30, {}, p), "at least two"));
    CHECK(contains(message(20, candidates, p), "candidate frame 25"));
    CHECK(contains(message(30, make_candidates<T>({{5, 0.3}, {9, 0.2}, {5, 0.1}}), p), "listed twice"));
    CHECK(contains(message(30, make_candidates<T>({{5, 0.3}, {9, std::numeric_limits<double>::quiet_NaN()}}), p), "non-finite"));
    const T nan = std::numeric_limits<T>::quiet_NaN();
    const std::vector<std::pair<T, T>> bad_bounds{
        {T(-0.1), T(0.5)}, {T(0.6), T(0.5)}, {T(0.1), T(1.5)}, {nan, T(0.5)}, {T(0.1), nan}};
    const std::vector<std::string> bound_messages{"min_probability must be in [0, 1], got -0.1",
                                                  "max_probability must be in [0.6, 1], got 0.5",
                                                  "max_probability must be in [0.1, 1], got 1.5",
                                                  "min_probability must be in [0, 1], got nan",
                                                  "max_probability must be in [0.1, 1], got nan"};
    for (std::size_t i = 0; i < bad_bounds.size(); ++i) {
        auto q = p;
        q.min_probability = bad_bounds[i].first;
        q.max_probability = bad_bounds[i].second;
        CHECK(message(30, candidates, q) == "anima::symmetric_playback: " + bound_messages[i]);
    }
    for (T penalty : {T(-0.1), nan, std::numeric_limits<T>::infinity()}) {
        auto q = p;
        q.turn_penalty = penalty;
        CHECK(contains(message(30, candidates, q), "turn penalty"));
    }
    for (T gain : {T(0.9), T(0), nan, std::numeric_limits<T>::infinity()}) {
        auto q = p;
        q.gain = gain;
        CHECK(message(30, candidates, q) ==
              "anima::symmetric_playback: gain k must be finite and at least 1, got " + anima::detail::argument_text(gain));
    }
    auto q = p;
    q.turn_penalty = T(-0.25);
    CHECK(message(30, candidates, q) == "anima::symmetric_playback: turn penalty must be non-negative and finite, got -0.25");
    // A constant clip has a single candidate: playback says why it cannot run.
    anima::clip<T> held = walk<T>().slice(10, 11);
    held.resize(40);
    const auto still = anima::symmetry_scores(held).candidates;
    CHECK(contains(message(40, still, p), "at least two"));
}

// ---------------------------------------------------------------------------
// Video textures
// ---------------------------------------------------------------------------

namespace {

struct reference_jump {
    std::size_t to;
    double probability;
};

// The jump table straight from the full distance matrix: targets j of frame
// i are the max_targets eligible j with the smallest D(i, j-1); weights 1 for
// i+1 and exp(-D / sigma) for a jump, sigma a fraction of the mean eligible
// distance; drop what falls under min_probability once normalised.
template <class M, class T>
std::vector<std::vector<reference_jump>> reference_table(const M& d, const anima::video_texture_params<T>& params,
                                                         double& sigma) {
    const auto n = static_cast<long>(d.rows());
    double total = 0;
    long count = 0;
    std::vector<std::vector<std::pair<double, std::size_t>>> eligible(static_cast<std::size_t>(n));
    for (long i = 0; i < n; ++i)
        for (long j = 1; j < n; ++j)
            if (std::abs(j - (i + 1)) >= params.min_jump) {
                const auto dist = static_cast<double>(d(i, j - 1));
                eligible[static_cast<std::size_t>(i)].push_back({dist, static_cast<std::size_t>(j)});
                total += dist;
                ++count;
            }
    sigma = static_cast<double>(params.sigma_scale) * total / static_cast<double>(count);
    std::vector<std::vector<reference_jump>> out(static_cast<std::size_t>(n));
    for (long i = 0; i < n; ++i) {
        auto e = eligible[static_cast<std::size_t>(i)];
        std::sort(e.begin(), e.end());
        e.resize(std::min(e.size(), params.max_targets));
        std::vector<reference_jump> row;
        if (i + 1 < n) row.push_back({static_cast<std::size_t>(i + 1), 1.0});
        for (const auto& [dist, j] : e)
            row.push_back(
                {j, std::max(std::exp(-dist / sigma), i + 1 < n ? 0.0 : static_cast<double>(std::numeric_limits<T>::min()))});
        double sum = 0;
        for (const auto& r : row) sum += r.probability;
        std::vector<reference_jump> kept;
        for (const auto& r : row)
            if (r.probability / sum >= static_cast<double>(params.min_probability)) kept.push_back({r.to, r.probability});
        if (kept.empty())
            kept.push_back(
                *std::max_element(row.begin(), row.end(), [](auto& a, auto& b) { return a.probability < b.probability; }));
        double kept_sum = 0;
        for (const auto& r : kept) kept_sum += r.probability;
        for (auto& r : kept) r.probability /= kept_sum;
        std::sort(kept.begin(), kept.end(), [](auto& a, auto& b) { return a.to < b.to; });
        out[static_cast<std::size_t>(i)] = kept;
    }
    return out;
}

}  // namespace

TEST_CASE_TEMPLATE("video-texture jumps equal a brute force over the full distance matrix", T, float, double) {
    const matrix<T> m = anima::frame_features(walk<T>()).middleRows(60, 150);
    const T dt = walk<T>().frame_time();
    for (auto metric : {frame_metric::l2, frame_metric::mahalanobis}) {
        anima::frame_distance_params<T> distance_params;
        distance_params.metric = metric;
        const matrix<T> distances = anima::distance_matrix(m, anima::make_frame_distance(m, dt, distance_params));
        for (int min_jump : {1, 10, 40})
            for (double sigma_scale : {0.05, 0.3}) {
                CAPTURE(anima::to_string(metric));
                CAPTURE(min_jump);
                CAPTURE(sigma_scale);
                anima::video_texture_params<T> p;
                p.distance.metric = metric;
                p.min_jump = min_jump;
                p.sigma_scale = static_cast<T>(sigma_scale);
                p.max_targets = 3;
                const auto table = anima::video_texture_jumps(m, dt, p);
                double sigma = 0;
                const auto ref = reference_table(distances, p, sigma);
                CHECK(static_cast<double>(table.sigma) == doctest::Approx(sigma).epsilon(tolerance<T>(1e-10, 1e-4)));
                REQUIRE(table.from.size() == ref.size());
                for (std::size_t i = 0; i < ref.size(); ++i) {
                    CAPTURE(i);
                    auto row = table.from[i];
                    // Probabilities sum to 1, most likely first.
                    T sum = T(0);
                    for (const auto& e : row) sum += e.probability;
                    CHECK(static_cast<double>(sum) == doctest::Approx(1.0).epsilon(tolerance<T>(1e-12, 1e-5)));
                    CHECK(std::is_sorted(row.begin(), row.end(), [](auto& a, auto& b) { return a.probability > b.probability; }));
                    for (const auto& e : row) {
                        CHECK(e.to < ref.size());
                        CHECK(e.probability >= p.min_probability);
                        const long gap = static_cast<long>(e.to) - static_cast<long>(i + 1);
                        CHECK((gap == 0 || std::abs(gap) >= min_jump));
                    }
                    CHECK(row.size() <= p.max_targets + 1);
                    std::sort(row.begin(), row.end(), [](auto& a, auto& b) { return a.to < b.to; });
                    REQUIRE(row.size() == ref[i].size());
                    for (std::size_t k = 0; k < row.size(); ++k) {
                        CHECK(row[k].to == ref[i][k].to);
                        CHECK(static_cast<double>(row[k].probability) ==
                              doctest::Approx(ref[i][k].probability).epsilon(tolerance<T>(1e-9, 1e-4)));
                    }
                }
                // The last frame has no continuation but somewhere to go.
                CHECK_FALSE(table.from.back().empty());
            }
    }
}

TEST_CASE_TEMPLATE("video-texture playback: in range, follows the table, reproducible", T, float, double) {
    const matrix<T> m = anima::frame_features(walk<T>());
    anima::video_texture_params<T> p;
    p.sigma_scale = T(0.2);
    const auto table = anima::video_texture_jumps(m, walk<T>().frame_time(), p);
    anima::video_texture_playback<T> a(table, 11), b(table, 11), other(table, 12);
    const auto stream = a.take(30000);
    CHECK(stream == b.take(30000));
    CHECK(a.jumps() == b.jumps());
    CHECK(stream != other.take(30000));
    CHECK(stream.front() == 0);
    std::size_t jumps = 0;
    for (std::size_t t = 0; t + 1 < stream.size(); ++t) {
        REQUIRE(stream[t] < static_cast<std::size_t>(m.rows()));
        const auto& out = table.from[stream[t]];
        REQUIRE(std::any_of(out.begin(), out.end(), [&](const auto& e) { return e.to == stream[t + 1]; }));
        if (stream[t + 1] != stream[t] + 1) {
            REQUIRE(jumps < a.jumps().size());
            CHECK(a.jumps()[jumps++] == t);
        }
    }
    CHECK(jumps > 30);
    // Playback reaches past the clip's last frame by jumping back.
    CHECK(std::count(stream.begin(), stream.end(), static_cast<std::size_t>(m.rows() - 1)) > 1);

    // Sampling follows the probabilities: from frame 0, to 1 (0.7) or 3 (0.3).
    anima::jump_table<T> hand;
    hand.from = {{{1, T(0.7)}, {3, T(0.3)}}, {{2, T(1)}}, {{0, T(1)}}, {{0, T(1)}}};
    anima::video_texture_playback<T> sampled(hand, 5, 0);
    const auto s = sampled.take(40000);
    std::size_t from0 = 0, to3 = 0;
    for (std::size_t t = 0; t + 1 < s.size(); ++t)
        if (s[t] == 0) {
            ++from0;
            to3 += s[t + 1] == 3;
        }
    CHECK(static_cast<double>(to3) / static_cast<double>(from0) == doctest::Approx(0.3).epsilon(0.05));
}

namespace {
// The walk's first 40 frames of features, and video_texture_jumps' message on them.
template <class T>
matrix<T> jump_features() {
    return anima::frame_features(walk<T>()).topRows(40);
}
template <class T>
std::string jumps_message(const anima::video_texture_params<T>& p, const matrix<T>& dofs) {
    return invalid_argument_message([&] { anima::video_texture_jumps(dofs, walk<T>().frame_time(), p); });
}
}  // namespace

TEST_CASE_TEMPLATE("video-texture jumps: the largest min_jump, DOFs past the scalar's range, values named", T, float, double) {
    const matrix<T> m = jump_features<T>();
    const auto message = jumps_message<T>;
    anima::video_texture_params<T> p;
    p.min_jump = std::numeric_limits<int>::max();
    CHECK(message(p, m) == "anima::video_texture_jumps: the clip has 40 frames; jumps of at least 2147483647 frames "
                           "need more than 2147483648");
    p = {};
    p.min_jump = 0;
    CHECK(message(p, m) == "anima::video_texture_jumps: min_jump must be at least 1, got 0");
    p = {};
    p.min_probability = T(1);
    CHECK(message(p, m) == "anima::video_texture_jumps: min_probability must be in [0, 1), got 1");
    p.min_probability = std::numeric_limits<T>::quiet_NaN();
    CHECK(message(p, m) == "anima::video_texture_jumps: min_probability must be in [0, 1), got nan");
    p = {};
    p.sigma_scale = T(-2);
    CHECK(message(p, m) == "anima::video_texture_jumps: sigma_scale must be positive and finite, got -2");
    p = {};
    p.max_targets = 0;
    CHECK(message(p, m) == "anima::video_texture_jumps: max_targets must be at least 1, got 0");
    // Finite DOFs whose distances overflow: the caller's scale, not sigma.
    p = {};
    anima::random_source rng(4);
    matrix<T> noise(40, 3);
    for (Eigen::Index i = 0; i < noise.size(); ++i) noise(i) = static_cast<T>(2 * rng.uniform() - 1);
    for (const T scale : {std::numeric_limits<T>::max(), static_cast<T>(std::is_same_v<T, float> ? 1e30 : 1e300)}) {
        const matrix<T> huge = noise * scale;
        REQUIRE(huge.allFinite());
        CHECK(message(p, huge) ==
              "anima::video_texture_jumps: the distances between frames overflow the scalar type; scale the DOFs down");
    }
}

TEST_CASE_TEMPLATE("video-texture jumps and playback: errors for bad parameters, short clips, bad tables", T, float, double) {
    const matrix<T> m = jump_features<T>();
    const auto message = jumps_message<T>;
    anima::video_texture_params<T> p;
    for (T scale : {T(0), T(-1), std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::infinity()}) {
        auto q = p;
        q.sigma_scale = scale;
        CHECK(contains(message(q, m), "sigma"));
    }
    auto q = p;
    q.min_jump = 0;
    CHECK(contains(message(q, m), "min_jump"));
    q = p;
    q.max_targets = 0;
    CHECK(contains(message(q, m), "max_targets"));
    q = p;
    q.min_probability = T(1);
    CHECK(contains(message(q, m), "min_probability"));
    q = p;
    q.min_jump = 39;  // 40 frames: jumps of 39 need more than 40
    CHECK(contains(message(q, m), "40 frames"));
    CHECK(contains(message(p, matrix<T>(0, m.cols())), "0 frames"));
    CHECK(contains(message(p, m.topRows(1)), "1 frames"));
    q.min_jump = 38;
    CHECK(message(q, m).empty());
    matrix<T> bad = m;
    bad(3, 3) = std::numeric_limits<T>::infinity();
    CHECK(contains(message(p, bad), "frame 3"));

    // A clip that never moves: every jump is as good as the continuation.
    anima::clip<T> held = walk<T>().slice(10, 11);
    held.resize(30);
    const auto frozen = anima::video_texture_jumps(anima::frame_features(held), walk<T>().frame_time(), p);
    for (const auto& row : frozen.from)
        for (const auto& e : row) CHECK(std::isfinite(e.probability));
    CHECK(frozen.sigma > T(0));

    const auto playback_message = [](const anima::jump_table<T>& t, std::size_t start = 0) {
        return invalid_argument_message([&] { anima::video_texture_playback<T>(t, 1, start); });
    };
    anima::jump_table<T> t;
    CHECK(contains(playback_message(t), "empty"));
    t.from = {{{1, T(1)}}, {}};
    CHECK(contains(playback_message(t), "frame 1 has no successor"));
    t.from = {{{1, T(1)}}, {{5, T(1)}}};
    CHECK(contains(playback_message(t), "bad jump from frame 1"));
    t.from = {{{1, T(1)}}, {{0, T(-1)}}};
    CHECK(contains(playback_message(t), "bad jump"));
    t.from = {{{1, T(1)}}, {{0, T(1)}}};
    CHECK(contains(playback_message(t, 2), "start frame 2"));
}

// ---------------------------------------------------------------------------
// Resequencing
// ---------------------------------------------------------------------------

namespace {

template <class T>
using vec3 = Eigen::Matrix<T, 3, 1>;

template <class T>
vec3<T> ground(vec3<T> v) {
    v.y() = T(0);  // both bundled clips are Y-up
    return v;
}

template <class T>
anima::clip<T> resequenced(const anima::clip<T>& source, const std::vector<std::size_t>& stream, anima::root_path root) {
    anima::resequence_params p;
    p.root = root;
    return anima::resequence(source, stream, p);
}

}  // namespace

TEST_CASE_TEMPLATE("resequence: a root path that overflows names resequence and the frame", T, float, double) {
    // Two frames at +-max/4: each step is max/2 along the ground; played
    // back and forth with keep_direction the root goes on from -max/4 to
    // max/4, 3 max/4, and overflows at output frame 3.
    using vec3 = Eigen::Matrix<T, 3, 1>;
    anima::skeleton<T> sk;
    sk.add_joint("hip", -1, vec3(0, 1, 0),
                 {anima::channel::x_position, anima::channel::y_position, anima::channel::z_position,
                  anima::channel::z_rotation, anima::channel::x_rotation, anima::channel::y_rotation});
    anima::clip<T> c(sk, 2, T(1) / 30);
    const T quarter = std::numeric_limits<T>::max() / T(4);
    c.set_root_position(0, vec3(-quarter, 1, 0));
    c.set_root_position(1, vec3(quarter, 1, 0));
    anima::resequence_params p;
    p.root = anima::root_path::keep_direction;
    p.up = anima::signed_axis{anima::axis::y, 1};
    CHECK_THROWS_WITH_AS(anima::resequence(c, {0, 1, 0, 1}, p),
                         doctest::Contains("anima::resequence: the accumulated root path overflows the scalar type at "
                                           "output frame 3"),
                         anima::invalid_argument);
    CHECK_NOTHROW(anima::resequence(c, {0, 1, 0}, p));
}

TEST_CASE_TEMPLATE("resequence: every policy copies the pose and takes the height from the source frame", T, float, double) {
    const auto& c = walk<T>();
    // Forwards, backwards, a repeated frame and two jumps.
    std::vector<std::size_t> stream = there_and_back(40, 120, 60);
    stream.push_back(60);
    for (std::size_t f = 250; f < 300; ++f) stream.push_back(f);
    for (std::size_t f = 0; f < 20; ++f) stream.push_back(f);
    for (auto root : {anima::root_path::recorded, anima::root_path::in_place, anima::root_path::accumulated,
                      anima::root_path::keep_direction}) {
        CAPTURE(anima::to_string(root));
        const auto out = resequenced(c, stream, root);
        REQUIRE(out.frames() == stream.size());
        CHECK(out.frame_time() == c.frame_time());
        CHECK(out.skeleton().size() == c.skeleton().size());
        for (std::size_t k = 0; k < stream.size(); ++k) {
            // Equal up to the renormalisation every stored rotation gets.
            for (std::size_t j = 0; j < c.joints(); ++j)
                CHECK((out.rotation(k, j).coeffs() - c.rotation(stream[k], j).coeffs()).norm() <=
                      T(8) * std::numeric_limits<T>::epsilon());
            CHECK(out.root_position(k).y() == c.root_position(stream[k]).y());
            if (root == anima::root_path::recorded) CHECK(out.root_position(k) == c.root_position(stream[k]));
            if (root == anima::root_path::in_place) CHECK(ground(out.root_position(k)) == ground(c.root_position(stream[0])));
        }
        CHECK(anima::parse_root_path(anima::to_string(root)) == root);
    }
    CHECK(contains(invalid_argument_message([] { anima::parse_root_path("teleport"); }), "'teleport'"));
}

TEST_CASE_TEMPLATE("resequence: a contiguous stream gives the recorded path when steps are accumulated", T, float, double) {
    const auto& c = walk<T>();
    // Forwards, back and forwards again, moving one frame at a time.
    std::vector<std::size_t> stream = there_and_back(10, 200, 90);
    for (std::size_t f = 91; f < 330; ++f) stream.push_back(f);
    const auto recorded = resequenced(c, stream, anima::root_path::recorded);
    const auto accumulated = resequenced(c, stream, anima::root_path::accumulated);
    for (std::size_t k = 0; k < stream.size(); ++k)
        CHECK((accumulated.root_position(k) - recorded.root_position(k)).norm() <= tolerance<T>(1e-9, 2e-3));
}

TEST_CASE_TEMPLATE("resequence: keep_direction travels on while the limbs play backwards", T, float, double) {
    const auto& c = walk<T>();
    const std::size_t k = 150;
    const auto stream = there_and_back(0, k, 0);  // 0..150, 149..0
    const auto out = resequenced(c, stream, anima::root_path::keep_direction);
    const vec3<T> forward = ground<T>(c.root_position(k) - c.root_position(0));
    REQUIRE(forward.norm() > T(10));  // the walk travels about 28 units in these frames
    // The backward half moves as far, the same way, as the forward half.
    const vec3<T> back = ground<T>(out.root_position(stream.size() - 1) - out.root_position(k));
    CHECK((back - forward).norm() <= tolerance<T>(1e-9, 2e-3));
    // ... one step at a time: every reversed step is the forward step it replays.
    for (std::size_t i = k + 1; i < stream.size(); ++i) {
        const vec3<T> step = ground<T>(out.root_position(i) - out.root_position(i - 1));
        const vec3<T> replayed = ground<T>(c.root_position(stream[i - 1]) - c.root_position(stream[i]));
        CHECK((step - replayed).norm() <= tolerance<T>(1e-9, 1e-4));
    }
    // The other policies walk back to the start instead.
    const auto accumulated = resequenced(c, stream, anima::root_path::accumulated);
    CHECK(ground<T>(accumulated.root_position(stream.size() - 1) - c.root_position(0)).norm() <= tolerance<T>(1e-9, 2e-3));
}

TEST_CASE_TEMPLATE("resequence: a jump continues from where the figure is, no teleport", T, float, double) {
    const auto& c = walk<T>();
    std::vector<std::size_t> stream;
    for (std::size_t f = 0; f <= 50; ++f) stream.push_back(f);
    for (std::size_t f = 200; f <= 230; ++f) stream.push_back(f);
    stream.push_back(0);  // a jump to the first frame moves as frame 0 -> 1 did
    for (auto root : {anima::root_path::accumulated, anima::root_path::keep_direction}) {
        const auto out = resequenced(c, stream, root);
        vec3<T> expected = ground<T>(c.root_position(0));
        for (std::size_t i = 0; i < stream.size(); ++i) {
            if (i > 0) {
                // The source's own step into frame f; for frame 0, the step out of it.
                const std::size_t f = stream[i];
                expected += f > 0 ? ground<T>(c.root_position(f) - c.root_position(f - 1))
                                  : ground<T>(c.root_position(1) - c.root_position(0));
            }
            CHECK((ground<T>(out.root_position(i)) - expected).norm() <= tolerance<T>(1e-9, 1e-3));
        }
        // At the jump the figure moves one step, not the 150 frames' distance.
        CHECK(ground<T>(out.root_position(51) - out.root_position(50)).norm() < T(1));
        CHECK(ground<T>(c.root_position(200) - c.root_position(50)).norm() > T(10));
    }
}

TEST_CASE_TEMPLATE("resequence: empty stream, out-of-range index", T, float, double) {
    const auto& c = run<T>();
    CHECK(anima::resequence(c, {}).frames() == 0);
    const auto one = anima::resequence(c, {7});
    REQUIRE(one.frames() == 1);
    CHECK(one.root_position(0) == c.root_position(7));
    const std::string message = invalid_argument_message([&] { anima::resequence(c, {0, 1, c.frames()}); });
    CHECK(contains(message, "index 2"));
    CHECK(contains(message, "frame " + std::to_string(c.frames())));
    CHECK(contains(invalid_argument_message([&] { anima::resequence(c.slice(0, 0), {0}); }), "0 frames"));
}
