// The variable-timing transition (classification, timing, per-joint
// interpolation, root path, placement of the next clip) and the baselines it
// is compared with, on the bundled CMU clips, the shared ones when present,
// and synthetic clips built from them.

// Heap allocations are counted around a call: this comes before any header
// that includes Eigen.
#include "../heap_count.hpp"
#include "../test_support.hpp"

#include <anima/bvh/reader.hpp>
#include <anima/core/constants.hpp>
#include <anima/core/error.hpp>
#include <anima/motion/clip.hpp>
#include <anima/motion/reorient.hpp>
#include <anima/motion/resample.hpp>
#include <anima/rotation/angular_velocity.hpp>
#include <anima/rotation/exp_log.hpp>
#include <anima/rotation/lerp.hpp>
#include <anima/rotation/quaternion.hpp>
#include <anima/rotation/slerp.hpp>
#include <anima/rotation/squad.hpp>
#include <anima/rotation/swing_twist.hpp>
#include <anima/transition.hpp>

#include <doctest/doctest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace {

using clipd = anima::clip<double>;
using quatd = Eigen::Quaterniond;
using vec3 = Eigen::Vector3d;
using anima::interpolation;
using anima::joint_role;
using anima::motion_class;
constexpr double pi = anima::pi<double>;
const vec3 up = vec3::UnitY();  // both bundled layouts are Y-up, in centimetres (Daz) / CMU units

std::string bundled(const std::string& name) { return std::string(ANIMA_TEST_DATA_DIR) + "/" + name; }

// The bundled run from frame 10: frame 0 is a T-pose and frames 1-5 blend out of it.
template <class T>
const anima::clip<T>& run() {
    static const anima::clip<T> c = [] {
        const auto full = anima::read_bvh<T>(bundled("run_cmu_09_01.bvh"));
        return full.slice(10, full.frames());
    }();
    return c;
}
const clipd& walk31() {
    static const clipd c = anima::read_bvh<double>(bundled("walk_cmu31_02_01.bvh"));
    return c;
}

// A clip of the shared data set from frame 10, or null (with a MESSAGE) when it is absent.
const clipd* shared_clip(const std::string& name) {
    static std::map<std::string, clipd> cache;
    if (const auto it = cache.find(name); it != cache.end()) return &it->second;
    const std::string path = std::string(ANIMA_SHARED_DATA_DIR) + "/bvh/" + name;
    if (!std::ifstream(path).good()) {
        MESSAGE("skipped: " << path << " not found");
        return nullptr;
    }
    const auto full = anima::read_bvh<double>(path);
    return &cache.emplace(name, full.slice(10, full.frames())).first->second;
}

std::size_t index(const clipd& c, const char* name) { return c.skeleton().index_of(name); }
quatd about(double degrees, const vec3& axis) { return quatd(Eigen::AngleAxisd(degrees * pi / 180, axis.normalized())); }
double heading(const quatd& q) { return anima::twist_angle(q, up); }
double angle_gap(double a, double b) { return std::abs(std::remainder(a - b, 2 * pi)); }

// n copies of frame f of c.
clipd held(const clipd& c, std::size_t f, std::size_t n) {
    clipd out = c.slice(f, f + 1);
    out.resize(n);
    return out;
}

// c with joint j's rotation followed by r in every frame: its angular speeds do not change.
clipd post_rotated(clipd c, std::size_t j, const quatd& r) {
    for (std::size_t f = 0; f < c.frames(); ++f) c.set_rotation(f, j, c.rotation(f, j) * r);
    return c;
}

// c turned by the heading r and moved by shift (root only): the same motion elsewhere.
clipd moved(clipd c, const quatd& r, const vec3& shift) {
    for (std::size_t f = 0; f < c.frames(); ++f) {
        c.set_rotation(f, 0, r * c.rotation(f, 0));
        c.set_root_position(f, r * c.root_position(f) + shift);
    }
    return c;
}

// c with another skeleton of the same size (rotations and root translations copied).
clipd on_skeleton(const clipd& c, const anima::skeleton<double>& sk) {
    clipd out(sk, c.frames(), c.frame_time());
    for (std::size_t f = 0; f < c.frames(); ++f)
        for (std::size_t j = 0; j < std::min(c.joints(), sk.size()); ++j) {
            out.set_rotation(f, j, c.rotation(f, j));
            if (sk.translation_slot(j) >= 0 && c.skeleton().translation_slot(j) >= 0)
                out.set_translation(f, j, c.translation(f, j));
        }
    return out;
}

// Largest rotation of joint j between consecutive frames f, f+1 for f in [first, last).
double largest_step(const clipd& c, std::size_t first, std::size_t last, std::size_t j) {
    double m = 0;
    for (std::size_t f = first; f < last; ++f) m = std::max(m, anima::angle_between(c.rotation(f, j), c.rotation(f + 1, j)));
    return m;
}
double largest_root_step(const clipd& c, std::size_t first, std::size_t last) {
    double m = 0;
    for (std::size_t f = first; f < last; ++f) m = std::max(m, (c.root_position(f + 1) - c.root_position(f)).norm());
    return m;
}

// Mean angular speed of joint j over the one-frame steps in [first, last).
double mean_speed(const clipd& c, std::size_t first, std::size_t last, std::size_t j) {
    double s = 0;
    for (std::size_t f = first; f < last; ++f) s += anima::angle_between(c.rotation(f, j), c.rotation(f + 1, j));
    return s / c.frame_time() / static_cast<double>(last - first);
}

// Root velocity and acceleration at `frame`: least-squares quadratic through
// the `count` frames ending there, by the normal equations.
anima::point_motion<double> quadratic_fit(const clipd& c, std::size_t frame, std::size_t count) {
    Eigen::Matrix3d n = Eigen::Matrix3d::Zero(), rhs = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < count; ++i) {
        const double s = -static_cast<double>(i) * c.frame_time();
        const vec3 phi(1, s, s * s);
        n += phi * phi.transpose();
        rhs += phi * c.root_position(frame - i).transpose();
    }
    const Eigen::Matrix3d coef = n.ldlt().solve(rhs);
    return {coef.row(1).transpose(), 2 * coef.row(2).transpose()};
}

// Eq 12 (or Eq 13 with flight_acc) from A's trigger, vertically corrected
// linearly in t so that it ends at B's start height.
struct root_path {
    vec3 p0, v, acc;
    double total = 0, correction = 0;
    vec3 at(double t) const { return p0 + t * v + 0.5 * t * t * acc + (t / total) * correction * up; }
};
root_path expected_path(const clipd& a, std::size_t trigger, const clipd& b, std::size_t b_start, double total,
                        std::optional<vec3> flight_acc = std::nullopt) {
    const auto fit = quadratic_fit(a, trigger, static_cast<std::size_t>(std::lround(0.25 / a.frame_time())) + 1);
    root_path p{a.root_position(trigger), fit.velocity, flight_acc ? *flight_acc : fit.acceleration, total, 0};
    p.correction = b.root_position(b_start).dot(up) - p.at(total).dot(up);
    return p;
}

template <class F>
std::string thrown_message(F&& f) {
    try {
        f();
    } catch (const anima::invalid_argument& e) {
        return e.what();
    }
    return "(nothing thrown)";
}

bool is_key(joint_role r) { return r == joint_role::root || r == joint_role::leg || r == joint_role::foot; }

// Every in-between rotation is the documented blend of A's trigger rotation
// and placed B's first: fingers lerp with the linear parameter, the others by
// their method with the transition's parameter; squad's control points come
// from A's frame before the trigger and placed B's second frame.
double worst_blend_error(const clipd& a, std::size_t trigger, const anima::transition<double>& t,
                         const std::vector<joint_role>& roles) {
    const clipd& pb = t.placed_b;
    double worst = 0;
    for (std::size_t j = 0; j < a.joints(); ++j) {
        const quatd q1 = a.rotation(trigger, j), q2 = anima::align_hemisphere(pb.rotation(0, j), q1);
        const quatd s1 = anima::squad_control_point(a.rotation(trigger - 1, j), q1, pb.rotation(0, j));
        const quatd s2 = anima::squad_control_point(q1, pb.rotation(0, j), pb.rotation(1, j));
        for (std::size_t k = 1; k <= t.frames.frames(); ++k) {
            const double tk = a.frame_time() * static_cast<double>(k);
            const double h = anima::interpolation_parameter(tk, t.duration, t.parameter);
            const double h_linear = anima::interpolation_parameter(tk, t.duration, anima::easing::linear);
            quatd expected;
            switch (t.methods[j]) {
                case interpolation::lerp: expected = anima::nlerp(q1, q2, roles[j] == joint_role::finger ? h_linear : h); break;
                case interpolation::squad: expected = anima::squad(q1, pb.rotation(0, j), s1, s2, h); break;
                default: expected = anima::slerp(q1, q2, h); break;
            }
            worst = std::max(worst, anima::angle_between(t.frames.rotation(k - 1, j), expected));
        }
    }
    return worst;
}

}  // namespace

TEST_CASE("joint_roles on the Daz and CMU-31 layouts") {
    const auto& daz = run<double>();
    const auto roles = anima::joint_roles(daz.skeleton());
    REQUIRE(roles.size() == daz.joints());
    const auto role = [&](const char* n) { return roles[index(daz, n)]; };
    CHECK(role("hip") == joint_role::root);
    for (const char* n : {"rButtock", "rThigh", "rShin", "lButtock", "lThigh", "lShin"}) CHECK_MESSAGE(role(n) == joint_role::leg, n);
    for (const char* n : {"rFoot", "lFoot"}) CHECK_MESSAGE(role(n) == joint_role::foot, n);
    for (const char* n : {"rIndex1", "rThumb2", "rMid1", "rRing2", "lPinky1", "lIndex2"}) CHECK_MESSAGE(role(n) == joint_role::finger, n);
    for (const char* n : {"abdomen", "chest", "neck", "head", "leftEye", "rCollar", "rShldr", "lForeArm", "rHand"})
        CHECK_MESSAGE(role(n) == joint_role::other, n);
    CHECK(std::count(roles.begin(), roles.end(), joint_role::finger) == 20);
    CHECK(std::count(roles.begin(), roles.end(), joint_role::leg) == 6);
    CHECK(std::count(roles.begin(), roles.end(), joint_role::foot) == 2);

    const auto& cmu = walk31();
    const auto r31 = anima::joint_roles(cmu.skeleton());
    const auto role31 = [&](const char* n) { return r31[index(cmu, n)]; };
    CHECK(role31("Hips") == joint_role::root);
    for (const char* n : {"LeftUpLeg", "LeftLeg", "RightUpLeg", "RightLeg", "LHipJoint"}) CHECK_MESSAGE(role31(n) == joint_role::leg, n);
    for (const char* n : {"LeftFoot", "LeftToeBase", "RightFoot", "RightToeBase"}) CHECK_MESSAGE(role31(n) == joint_role::foot, n);
    for (const char* n : {"LThumb", "RThumb", "LeftHandIndex1", "RightFingerBase"}) CHECK_MESSAGE(role31(n) == joint_role::finger, n);
    for (const char* n : {"LowerBack", "Spine1", "Neck1", "Head", "LeftArm", "RightHand"}) CHECK_MESSAGE(role31(n) == joint_role::other, n);

    // Case-insensitive; every root of a forest is a root whatever its name.
    anima::skeleton<double> sk;
    sk.add_joint("LEFTFOOT", -1, vec3::Zero());
    sk.add_joint("Left_ANKLE", 0, vec3::UnitY());
    sk.add_joint("KneeCap", 1, vec3::UnitY());
    sk.add_joint("pinkyTip", 2, vec3::UnitY());
    sk.add_joint("FootProp", -1, vec3::UnitX());
    const auto r = anima::joint_roles(sk);
    CHECK(r == std::vector<joint_role>{joint_role::root, joint_role::foot, joint_role::leg, joint_role::finger, joint_role::root});
}

TEST_CASE("classify_motion: the real run, a held frame, a synthetic hop") {
    const auto& r = run<double>();
    const auto roles = anima::joint_roles(r.skeleton());
    const auto c = anima::classify_motion(r, roles);
    CHECK(c.type == motion_class::plane_motion);
    CHECK(c.up == anima::signed_axis{anima::axis::y, 1});
    CHECK(c.metres_per_unit == 0.01);
    CHECK(c.foot_range > 3.0);  // metres: the run covers about 4 m
    CHECK(anima::classify_motion(walk31(), anima::joint_roles(walk31().skeleton())).type == motion_class::plane_motion);

    const auto still = anima::classify_motion(held(r, 30, 100), roles);
    CHECK(still.type == motion_class::on_the_spot);
    CHECK(still.longest_airborne == 0);
    CHECK(still.foot_range < 1e-12);
    CHECK(still.hip_rise == 0);

    // 0.5 s standing, a 0.6 s parabolic hop of the whole figure, 0.5 s standing.
    const auto hop = [&](double rise_m) {
        clipd h = held(r, 10, 192);
        for (std::size_t f = 60; f < 132; ++f) {
            const double u = static_cast<double>(f - 60) / 72;
            h.set_root_position(f, h.root_position(f) + 4 * rise_m * 100 * u * (1 - u) * up);
        }
        return h;
    };
    const clipd high = hop(0.5), low = hop(0.05);
    const auto ch = anima::classify_motion(high, roles);
    CHECK(ch.type == motion_class::space_flight);
    CHECK(ch.hip_rise == doctest::Approx(0.5).epsilon(1e-9));
    // The feet move faster than contact_speed except near the apex.
    CHECK(ch.longest_airborne >= 0.15);
    CHECK(ch.longest_airborne < 0.6);
    const auto cl = anima::classify_motion(low, roles);
    CHECK(cl.type == motion_class::on_the_spot);
    CHECK(cl.longest_airborne == 0);  // 0.33 m/s at take-off: the feet never lose contact

    anima::classify_params p;
    p.flight_hip_rise = 0.6;  // above the rise
    CHECK(anima::classify_motion(high, roles, p).type == motion_class::on_the_spot);
    p.flight_hip_rise = 0.15;
    p.flight_min_time = ch.longest_airborne + 0.01;
    CHECK(anima::classify_motion(high, roles, p).type == motion_class::on_the_spot);
    p.flight_min_time = 0.15;
    p.contact_speed = 5;  // nothing is that fast: always in contact
    CHECK(anima::classify_motion(high, roles, p).type == motion_class::on_the_spot);
    anima::classify_params q;
    q.flight_hip_rise = 0.05;  // the run's flight phases rise about 7 cm
    CHECK(anima::classify_motion(r, roles, q).type == motion_class::space_flight);
    q.on_spot_distance = 10;  // metres: not enough to call the run plane motion either way
    q.flight_hip_rise = 1;
    CHECK(anima::classify_motion(r, roles, q).type == motion_class::on_the_spot);

    // The same hop on a figure whose up axis is -Y: the class must not change.
    const clipd flipped = anima::rotate_clip(high, about(180, vec3::UnitZ()));
    const auto cf = anima::classify_motion(flipped, roles);
    CHECK(cf.up == anima::signed_axis{anima::axis::y, -1});
    CHECK(cf.hip_rise == doctest::Approx(0.5).epsilon(1e-9));
    CHECK(cf.type == motion_class::space_flight);

    for (auto bad : {&anima::classify_params::on_spot_distance, &anima::classify_params::contact_speed}) {
        anima::classify_params b;
        b.*bad = 0;
        CHECK_THROWS_AS(anima::classify_motion(r, roles, b), anima::invalid_argument);
    }
    anima::classify_params b;
    b.flight_min_time = -1;
    CHECK_THROWS_AS(anima::classify_motion(r, roles, b), anima::invalid_argument);
    b = {};
    b.flight_hip_rise = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(anima::classify_motion(r, roles, b), anima::invalid_argument);
    b = {};
    b.metres_per_unit = 0.0;
    CHECK_THROWS_AS(anima::classify_motion(r, roles, b), anima::invalid_argument);
    CHECK_THROWS_AS(anima::classify_motion(r, std::vector<joint_role>(3, joint_role::foot)), anima::invalid_argument);
}

TEST_CASE("interpolation_parameter: Eq 10 and Eq 11") {
    using anima::easing;
    const double T = 0.8;
    const auto h = [&](double t, easing e) { return anima::interpolation_parameter(t, T, e); };
    for (int i = 0; i <= 16; ++i) CHECK(h(T * i / 16, easing::linear) == doctest::Approx(i / 16.0).epsilon(1e-15));
    CHECK(h(0, easing::ease_in_out) == 0);
    CHECK(h(T, easing::ease_in_out) == 1);
    CHECK(h(T / 2, easing::ease_in_out) == doctest::Approx(0.5).epsilon(1e-15));
    CHECK(h(T / 4, easing::ease_in_out) == doctest::Approx(0.125).epsilon(1e-15));  // 2 (1/4)^2
    CHECK(h(3 * T / 4, easing::ease_in_out) == doctest::Approx(0.875).epsilon(1e-15));
    const double e = 1e-7;
    // Continuous at T/2 with the same slope 2/T on both sides; flat at both ends.
    CHECK(std::abs(h(T / 2 - e, easing::ease_in_out) - 0.5) < 3 * e / T);
    CHECK(std::abs(h(T / 2 + e, easing::ease_in_out) - 0.5) < 3 * e / T);
    CHECK((h(T / 2, easing::ease_in_out) - h(T / 2 - e, easing::ease_in_out)) / e == doctest::Approx(2 / T).epsilon(1e-6));
    CHECK((h(T / 2 + e, easing::ease_in_out) - h(T / 2, easing::ease_in_out)) / e == doctest::Approx(2 / T).epsilon(1e-6));
    CHECK(h(e, easing::ease_in_out) / e < 1e-5);
    CHECK((1 - h(T - e, easing::ease_in_out)) / e < 1e-5);
    double previous = -1;
    bool increasing = true, symmetric = true;
    for (int i = 0; i <= 1000; ++i) {
        const double t = T * i / 1000, v = h(t, easing::ease_in_out);
        increasing = increasing && v > previous;
        symmetric = symmetric && std::abs(v + h(T - t, easing::ease_in_out) - 1) < 1e-14;
        previous = v;
    }
    CHECK(increasing);
    CHECK(symmetric);
    for (easing k : {easing::linear, easing::ease_in_out}) {
        CHECK(h(-0.3, k) == 0);
        CHECK(h(T + 0.3, k) == 1);
        CHECK(anima::interpolation_parameter(0.1, 0.0, k) == 1);
        CHECK(anima::interpolation_parameter(0.25f, 1.0f, k) == doctest::Approx(k == easing::linear ? 0.25 : 0.125));
    }
}

TEST_CASE("identical poses: T is the minimum and the in-betweens hold the pose") {
    const auto& a = run<double>();
    const std::size_t trigger = 60;
    const double dt = a.frame_time();
    for (double min_duration : {0.1, 0.05, 0.003}) {
        CAPTURE(min_duration);
        anima::transition_params p;
        p.timing.min_duration = min_duration;
        p.continuous_root = false;  // Eq 12 as printed
        const auto t = anima::make_transition(a, trigger, a, trigger, p);
        CHECK(t.timing.duration == min_duration);
        CHECK(t.timing.unclamped < 1e-12);
        const auto steps = std::max<long>(1, std::lround(min_duration / dt));
        CHECK(t.duration == doctest::Approx(dt * static_cast<double>(steps)).epsilon(1e-14));
        REQUIRE(t.frames.frames() == static_cast<std::size_t>(steps - 1));
        CHECK(t.frames.frame_time() == dt);
        CHECK(t.parameter == anima::easing::ease_in_out);  // plane motion to plane motion
        double worst = 0;
        for (std::size_t k = 0; k < t.frames.frames(); ++k)
            for (std::size_t j = 0; j < a.joints(); ++j)
                worst = std::max(worst, anima::angle_between(t.frames.rotation(k, j), a.rotation(trigger, j)));
        CHECK(worst < 1e-9);
        // The root follows Eq 12 from A's quadratic fit, corrected to end at the trigger height.
        const auto path = expected_path(a, trigger, a, trigger, t.duration);
        CHECK((t.root_at_trigger.velocity - path.v).norm() < 1e-6 * path.v.norm());
        CHECK((t.root_at_trigger.acceleration - path.acc).norm() < 1e-6 * path.acc.norm());
        double root_error = 0;
        for (std::size_t k = 1; k <= t.frames.frames(); ++k)
            root_error = std::max(root_error, (t.frames.root_position(k - 1) - path.at(dt * static_cast<double>(k))).norm());
        CHECK(root_error < 1e-6);
        CHECK((t.placed_b.root_position(0) - path.at(t.duration)).norm() < 1e-6);
        const auto joined = anima::join(a, trigger, t);
        CHECK(joined.end_frame - joined.start_frame == static_cast<std::size_t>(steps));
        CHECK(joined.motion.frames() == trigger + 1 + t.frames.frames() + (a.frames() - trigger));
    }

    // A root moving exactly on a horizontal parabola: Eq 12 continues it
    // exactly; the Hermite path ends at the same point but with the velocity
    // B has at its start (frame 40's, measured exactly on a parabola).
    clipd glide = held(a, 30, 80);
    const vec3 start = glide.root_position(0), v(150, 0, -40), acc(-60, 0, 90);
    const auto on_path = [&](double t) { return vec3(start + t * v + 0.5 * t * t * acc); };
    for (std::size_t f = 0; f < glide.frames(); ++f) glide.set_root_position(f, on_path(dt * static_cast<double>(f)));
    for (const bool continuous : {false, true}) {
        CAPTURE(continuous);
        anima::transition_params p;
        p.continuous_root = continuous;
        const auto t = anima::make_transition(glide, 40, glide, 40, p);
        CHECK((t.root_at_trigger.velocity - (v + 40 * dt * acc)).norm() < 1e-7);
        CHECK((t.root_at_trigger.acceleration - acc).norm() < 1e-6);
        const vec3 v_trigger = v + 40 * dt * acc, p0 = on_path(40 * dt), p1 = on_path(40 * dt + t.duration);
        if (continuous) CHECK((t.root_velocity_at_b - v_trigger).norm() < 1e-6);
        const auto expected = [&](double time) {
            if (!continuous) return on_path(40 * dt + time);
            const double T = t.duration, s = time / T;
            return vec3((2 * s * s * s - 3 * s * s + 1) * p0 + (s * s * s - 2 * s * s + s) * T * v_trigger +
                        (-2 * s * s * s + 3 * s * s) * p1 + (s * s * s - s * s) * T * v_trigger);
        };
        double root_error = 0;
        for (std::size_t k = 1; k <= t.frames.frames(); ++k)
            root_error = std::max(root_error, (t.frames.root_position(k - 1) - expected(dt * static_cast<double>(k))).norm());
        CHECK(root_error < 1e-8);
        CHECK((t.placed_b.root_position(0) - on_path(dt * 40 + t.duration)).norm() < 1e-8);
    }
}

TEST_CASE("gravity only where the body is in the air: no hop between standing frames of a jump clip") {
    const auto& r = run<double>();
    // 0.5 s standing, a 0.6 s parabolic hop 0.5 m high, 0.5 s standing.
    clipd hop = held(r, 10, 192);
    for (std::size_t f = 60; f < 132; ++f) {
        const double u = static_cast<double>(f - 60) / 72;
        hop.set_root_position(f, hop.root_position(f) + 4 * 0.5 * 100 * u * (1 - u) * up);
    }
    const auto cls = anima::classify_motion(hop, anima::joint_roles(hop.skeleton()));
    REQUIRE(cls.type == motion_class::space_flight);
    REQUIRE(cls.airborne.size() == 1);
    CHECK(cls.airborne[0].first >= 60);
    CHECK(cls.airborne[0].first <= 70);
    CHECK(cls.airborne[0].last >= 121);
    CHECK(cls.airborne[0].last <= 131);

    // Standing to standing: Eq 12, and the root stays at standing height.
    const auto ground = anima::make_transition(hop, 20, hop, 170);
    CHECK_FALSE(ground.flight);
    double highest = 0;
    for (std::size_t k = 0; k < ground.frames.frames(); ++k)
        highest = std::max(highest, (ground.frames.root_position(k) - hop.root_position(20)).dot(up));
    CHECK(highest < 1e-9);  // the held pose's root does not move: no lift at all
    // From the air, or into it: Eq 13.
    CHECK(anima::make_transition(hop, 96, hop, 170).flight);
    CHECK(anima::make_transition(hop, 20, hop, 96).flight);
}

TEST_CASE("on the ground the root meets B's velocity where B starts; Eq 12 leaves it jumping") {
    // The issue's walk pair: frame 100 -> frame 250 of the 31-joint walk.
    const auto& w = walk31();
    const auto velocity_jump = [&](bool continuous, double& start_jump) {
        anima::transition_params p;
        p.continuous_root = continuous;
        const auto t = anima::make_transition(w, 100, w, 250, p);
        REQUIRE_FALSE(t.flight);
        const auto j = anima::join(w, 100, t);
        const auto& m = j.motion;
        const auto second = [&](std::size_t f) {
            return (m.root_position(f + 1) - 2 * m.root_position(f) + m.root_position(f - 1)).norm();
        };
        start_jump = second(j.start_frame);
        // The path is one cubic: its fourth differences vanish inside the window.
        if (continuous && j.end_frame - j.start_frame > 5)
            for (std::size_t f = j.start_frame + 2; f + 2 <= j.end_frame; ++f) {
                const vec3 d4 = m.root_position(f - 2) - 4 * m.root_position(f - 1) + 6 * m.root_position(f) -
                                4 * m.root_position(f + 1) + m.root_position(f + 2);
                CHECK(d4.norm() < 1e-9 * m.root_position(f).norm() + 1e-9);
            }
        return second(j.end_frame);
    };
    double start_hermite = 0, start_eq12 = 0;
    const double hermite = velocity_jump(true, start_hermite), eq12 = velocity_jump(false, start_eq12);
    MESSAGE("root second difference at B's start: Hermite " << hermite << ", Eq 12 " << eq12);
    CHECK(eq12 > 4 * hermite);
    // Both start from A's fitted velocity: the same at the trigger.
    CHECK(start_hermite < 4 * start_eq12 + 1e-9);
}

TEST_CASE("variable timing: a larger pose difference takes longer at the same speeds") {
    const auto& a = run<double>();
    const std::size_t trigger = 60, shin = index(a, "rShin"), arm = index(a, "rForeArm");
    const auto roles = anima::joint_roles(a.skeleton());
    anima::transition_params p;
    p.timing.min_duration = 0;
    const auto window = static_cast<std::size_t>(std::lround(p.timing.speed_window / a.frame_time()));
    const double speed_a = mean_speed(a, trigger - window, trigger, shin);
    const double speed_b = mean_speed(a, trigger, trigger + window, shin);  // B is A, post-rotated
    std::vector<double> durations;
    for (double degrees : {20.0, 60.0}) {
        CAPTURE(degrees);
        const clipd b = post_rotated(a, shin, about(degrees, vec3(1, 0.2, 0)));
        const auto t = anima::make_transition(a, trigger, b, trigger, p);
        REQUIRE(t.timing.joints.size() == a.joints());
        for (std::size_t j = 0; j < a.joints(); ++j) {
            CHECK(t.timing.joints[j].joint == j);
            CHECK(t.timing.joints[j].role == roles[j]);
            CHECK(t.timing.joints[j].key == is_key(roles[j]));
        }
        const auto& jt = t.timing.joints[shin];
        CHECK(jt.angle == doctest::Approx(degrees * pi / 180).epsilon(1e-9));
        CHECK(jt.speed_a == doctest::Approx(speed_a).epsilon(1e-9));
        CHECK(jt.speed_b == doctest::Approx(speed_b).epsilon(1e-9));
        CHECK(jt.time == doctest::Approx(jt.angle / std::max(0.5 * (speed_a + speed_b), 0.5)).epsilon(1e-12));
        CHECK(t.timing.limiting_joint == shin);
        CHECK(t.timing.unclamped == jt.time);
        CHECK(t.timing.duration == jt.time);
        durations.push_back(t.timing.duration);

        // A non-key joint turning further is timed and reported but does not set T.
        const clipd b2 = post_rotated(b, arm, about(150, vec3(0, 1, 1)));
        const auto t2 = anima::make_transition(a, trigger, b2, trigger, p);
        CHECK(t2.timing.joints[arm].angle == doctest::Approx(150 * pi / 180).epsilon(1e-9));
        CHECK(t2.timing.joints[arm].time > t2.timing.duration);
        CHECK(t2.timing.limiting_joint == shin);
        CHECK(t2.timing.duration == t.timing.duration);
    }
    CHECK(durations[1] > durations[0]);
    CHECK(durations[1] == doctest::Approx(3 * durations[0]).epsilon(1e-9));  // same speeds: T proportional to the angle
}

TEST_CASE("variable timing: clamping and the floors on frozen clips") {
    const auto& r = run<double>();
    const clipd a = held(r, 20, 40);
    clipd b = held(r, 60, 40);
    for (std::size_t f = 0; f < b.frames(); ++f) {  // same root: the legs alone differ
        b.set_rotation(f, 0, a.rotation(0, 0));
        b.set_root_position(f, a.root_position(0));
    }
    const auto roles = anima::joint_roles(r.skeleton());
    double largest = 0;
    std::size_t widest = 0;
    for (std::size_t j = 0; j < a.joints(); ++j) {
        const double d = 2 * std::acos(std::min(1.0, std::abs(a.rotation(0, j).coeffs().dot(b.rotation(0, j).coeffs()))));
        if (is_key(roles[j]) && d > largest) {
            largest = d;
            widest = j;
        }
    }
    REQUIRE(largest > 0.7);
    anima::transition_params p;
    p.timing.max_duration = 10;
    auto t = anima::make_transition(a, 10, b, 10, p);
    CHECK(t.class_a.type == motion_class::on_the_spot);
    CHECK(t.parameter == anima::easing::linear);  // spot to spot
    CHECK(t.timing.joints[widest].speed_a == 0);
    CHECK(t.timing.limiting_joint == widest);
    CHECK(t.timing.duration == doctest::Approx(largest / p.timing.min_speed).epsilon(1e-7));
    CHECK(worst_blend_error(a, 10, t, roles) < 1e-9);
    p.timing.min_speed = 4;
    CHECK(anima::make_transition(a, 10, b, 10, p).timing.duration == doctest::Approx(largest / 4).epsilon(1e-7));
    p.timing.min_speed = 0.5;
    p.timing.model = anima::timing_model::constant_acceleration;
    t = anima::make_transition(a, 10, b, 10, p);
    CHECK(t.timing.duration == doctest::Approx(std::sqrt(2 * largest / p.timing.min_acceleration)).epsilon(1e-7));
    p.timing.min_acceleration = 8;
    t = anima::make_transition(a, 10, b, 10, p);
    CHECK(t.timing.duration == doctest::Approx(std::sqrt(2 * largest / 8)).epsilon(1e-7));
    CHECK(t.timing.limiting_joint == widest);

    // The default range [0.1, 1.2] s clamps the 1.4+ s the frozen legs ask for.
    t = anima::make_transition(a, 10, b, 10);
    CHECK(t.timing.unclamped == doctest::Approx(largest / 0.5).epsilon(1e-7));
    CHECK(t.timing.duration == 1.2);
    CHECK(t.duration == doctest::Approx(a.frame_time() * 144).epsilon(1e-12));
    CHECK(t.frames.frames() == 143);
    CHECK(std::isfinite(t.timing.duration));
    // A huge difference on moving clips clamps too.
    const std::size_t shin = index(r, "lShin");
    t = anima::make_transition(r, 60, post_rotated(r, shin, about(175, vec3::UnitX())), 60);
    CHECK(t.timing.unclamped > 0.2);
    anima::transition_params tight;
    tight.timing.max_duration = 0.2;
    t = anima::make_transition(r, 60, post_rotated(r, shin, about(175, vec3::UnitX())), 60, tight);
    CHECK(t.timing.duration == 0.2);
    CHECK(t.timing.limiting_joint == shin);
}

TEST_CASE("in-between quaternions stay unit in double and float") {
    const auto check = [](const auto& a, double tolerance) {
        double worst = 0;
        bool finite = true;
        for (auto [trigger, b_start] : {std::pair<std::size_t, std::size_t>{60, 20}, {80, 90}, {40, 120}}) {
            const auto t = anima::make_transition(a, trigger, a, b_start);
            const auto joined = anima::join(a, trigger, t);
            for (const auto* c : {&t.frames, &joined.motion})
                for (const auto& q : c->rotations()) {
                    worst = std::max(worst, static_cast<double>(std::abs(q.norm() - 1)));
                    finite = finite && q.coeffs().allFinite();
                }
        }
        CHECK(finite);
        CHECK(worst < tolerance);
    };
    check(run<double>(), 1e-12);
    check(run<float>(), 1e-5);
    const auto td = anima::make_transition(run<double>(), 60, run<double>(), 20);
    const auto tf = anima::make_transition(run<float>(), 60, run<float>(), 20);
    CHECK(static_cast<double>(tf.timing.duration) == doctest::Approx(td.timing.duration).epsilon(1e-4));
    CHECK(tf.timing.limiting_joint == td.timing.limiting_joint);
}

TEST_CASE("float motion with subnormal components: the transition flushes them inside and keeps the caller's mode") {
    // The run's BVH holds angles of 1e-19 degrees: in float some of its
    // quaternion components are subnormal, and the transition runs with them
    // flushed (anima::flush_denormals). Its frames agree with the double
    // transition's, and the caller's gradual underflow is untouched, also
    // when variable_timing throws from inside its guard.
    const auto& f = run<float>();
    std::size_t subnormal = 0;
    for (const auto& q : f.rotations())
        for (int i = 0; i < 4; ++i) subnormal += std::fpclassify(q.coeffs()[i]) == FP_SUBNORMAL;
    REQUIRE(subnormal > 0);
    const auto gradual = anima_test::gradual_underflow;
    REQUIRE(gradual());
    anima::transition_params params;
    params.timing.every_joint = false;
    anima::transition_frames<float> out;
    anima::transition_workspace<float> ws;
    anima::make_transition_into(f, 60, f, 20, params, out, ws);
    CHECK(gradual());
    const auto td = anima::make_transition(run<double>(), 60, run<double>(), 20);
    REQUIRE(out.frames.frames() == td.frames.frames());
    double worst = 0;
    for (std::size_t k = 0; k < out.frames.frames(); ++k)
        for (std::size_t j = 0; j < out.frames.joints(); ++j)
            worst = std::max(worst, anima::angle_between(out.frames.rotation(k, j).cast<double>(),
                                                         td.frames.rotation(k, j)));
    CHECK(worst < 1e-4);
    anima::timing_params bad;
    bad.min_speed = 0;
    CHECK_THROWS_AS(anima::variable_timing(f, 60, f, 20, anima::joint_roles(f.skeleton()), Eigen::Quaternionf::Identity(),
                                           bad),
                    anima::invalid_argument);
    CHECK(gradual());
    // The other whole-clip functions of the module hold a guard too.
    const auto roles = anima::joint_roles(f.skeleton());
    CHECK(anima::classify_motion(f, roles).type == anima::classify_motion(run<double>(), roles).type);
    CHECK(gradual());
    const auto faded = anima::crossfade(f, 60, f, 20, 0.2f);
    const auto inert = anima::inertialize(f, 60, f, 20, 0.1f);
    CHECK(gradual());
    bool finite = true;
    for (const auto* c : {&faded.motion, &inert.motion})
        for (const auto& q : c->rotations()) finite = finite && q.coeffs().allFinite();
    CHECK(finite);
}

TEST_CASE("per-joint methods: fingers lerp, large turns squad, the rest slerp; overrides") {
    const auto& a = run<double>();
    const std::size_t trigger = 60, b_start = 20, finger = index(a, "rIndex1"), thigh = index(a, "rThigh");
    const clipd b = post_rotated(a, finger, about(40, vec3(0, 0, 1)));
    const auto roles = anima::joint_roles(a.skeleton());
    const auto t = anima::make_transition(a, trigger, b, b_start);
    std::size_t squads = 0, slerps = 0;
    for (std::size_t j = 0; j < a.joints(); ++j) {
        const interpolation expected = roles[j] == joint_role::finger ? interpolation::lerp
                                       : t.timing.joints[j].angle >= pi / 6 ? interpolation::squad
                                                                            : interpolation::slerp;
        CHECK_MESSAGE(t.methods[j] == expected, a.skeleton()[j].name);
        squads += t.methods[j] == interpolation::squad;
        slerps += t.methods[j] == interpolation::slerp;
    }
    CHECK(t.timing.joints[finger].angle > pi / 6);  // a finger lerps however far it turns
    CHECK(squads > 0);
    CHECK(slerps > 0);
    CHECK(t.parameter == anima::easing::ease_in_out);
    CHECK(worst_blend_error(a, trigger, t, roles) < 1e-9);
    // The finger moves at constant speed (linear parameter), the others ease in.
    const std::size_t quarter = (t.frames.frames() + 1) / 4;
    const double fraction = anima::angle_between(t.frames.rotation(quarter - 1, finger), a.rotation(trigger, finger)) /
                            t.timing.joints[finger].angle;
    CHECK(fraction == doctest::Approx(static_cast<double>(quarter) * a.frame_time() / t.duration).epsilon(0.05));

    anima::transition_params p;
    p.methods.assign(a.joints(), interpolation::slerp);
    auto t2 = anima::make_transition(a, trigger, b, b_start, p);
    CHECK(std::all_of(t2.methods.begin(), t2.methods.end(), [](interpolation m) { return m == interpolation::slerp; }));
    CHECK(worst_blend_error(a, trigger, t2, roles) < 1e-9);
    p.methods.assign(a.joints(), interpolation::automatic);
    p.methods[thigh] = interpolation::lerp;
    t2 = anima::make_transition(a, trigger, b, b_start, p);
    for (std::size_t j = 0; j < a.joints(); ++j)
        CHECK(t2.methods[j] == (j == thigh ? interpolation::lerp : t.methods[j]));
    CHECK(worst_blend_error(a, trigger, t2, roles) < 1e-9);  // the thigh lerps with the eased parameter
    p.methods.clear();
    p.large_angle = 4;
    t2 = anima::make_transition(a, trigger, b, b_start, p);
    CHECK(std::count(t2.methods.begin(), t2.methods.end(), interpolation::squad) == 0);
    p.large_angle = pi / 6;
    p.parameter = anima::easing::linear;
    t2 = anima::make_transition(a, trigger, b, b_start, p);
    CHECK(t2.parameter == anima::easing::linear);
    CHECK(worst_blend_error(a, trigger, t2, roles) < 1e-9);

    // Roles override: the (unmoving) finger made a leg is key, and its 40
    // degrees at the floor speed need longer than the legs.
    p = {};
    p.roles = roles;
    p.roles[finger] = joint_role::leg;
    t2 = anima::make_transition(a, trigger, b, b_start, p);
    CHECK(t2.timing.joints[finger].key);
    CHECK(t2.methods[finger] == interpolation::squad);
    CHECK(t2.timing.limiting_joint == finger);
    CHECK(t2.timing.duration > t.timing.duration);
    p.roles.assign(a.joints(), joint_role::other);  // nothing is key: the minimum
    CHECK(anima::make_transition(a, trigger, b, b_start, p).timing.duration == 0.1);
}

TEST_CASE("the joined clip is continuous at both ends on real pairs") {
    const auto check = [](const clipd& a, std::size_t trigger, const clipd& b, std::size_t b_start) {
        const auto t = anima::make_transition(a, trigger, b, b_start);
        INFO("T = " << t.duration << " s (unclamped " << t.timing.unclamped << ", limited by "
                    << a.skeleton()[t.timing.limiting_joint].name << "), flight " << t.flight);
        const auto joined = anima::join(a, trigger, t);
        const clipd& m = joined.motion;
        REQUIRE(joined.start_frame == trigger);
        REQUIRE(joined.end_frame == trigger + t.frames.frames() + 1);
        const std::size_t k = 4;
        double excess = 0;
        std::string where;
        for (std::size_t j = 0; j < a.joints(); ++j) {
            const double own = std::max(largest_step(a, trigger - k, trigger, j), largest_step(b, b_start, b_start + k, j));
            for (std::size_t f : {joined.start_frame, joined.end_frame - 1}) {
                const double e = anima::angle_between(m.rotation(f, j), m.rotation(f + 1, j)) - own;
                if (e > excess) {
                    excess = e;
                    where = a.skeleton()[j].name + " at frame " + std::to_string(f);
                }
            }
        }
        CHECK_MESSAGE(excess < 1e-6, where);
        // T is set by a key joint, the slowest of them.
        const auto& timing = t.timing;
        CHECK(timing.joints[timing.limiting_joint].key);
        CHECK(timing.joints[timing.limiting_joint].time == timing.unclamped);
        CHECK(std::none_of(timing.joints.begin(), timing.joints.end(),
                           [&](const auto& jt) { return jt.key && jt.time > timing.unclamped; }));
        // Root: Eq 12 extrapolates the trigger's acceleration over T and the
        // height correction adds a constant vertical speed, so the root may
        // step faster than either clip by dt (T |a| + |correction| / T); a
        // misplaced B or a path not starting at A's root steps much further.
        const double own = std::max(largest_root_step(a, trigger - k, trigger), largest_root_step(b, b_start, b_start + k));
        const auto path = expected_path(a, trigger, b, b_start, t.duration,
                                        t.flight ? std::optional<vec3>(-9.81 / t.class_a.metres_per_unit * up) : std::nullopt);
        const double allowance = a.frame_time() * (t.duration * path.acc.norm() + std::abs(path.correction) / t.duration);
        CHECK((m.root_position(joined.start_frame + 1) - m.root_position(joined.start_frame)).norm() <= own + allowance);
        CHECK((m.root_position(joined.end_frame) - m.root_position(joined.end_frame - 1)).norm() <= own + allowance);
        CHECK((m.root_position(joined.end_frame) - path.at(t.duration)).norm() < 1e-6);
    };
    const auto& r = run<double>();
    check(r, 60, r, 20);
    check(r, 80, r, 90);
    check(r, 40, r, 50);
    const clipd* walk = shared_clip("walk_cmu_02_01.bvh");
    const clipd* run2 = shared_clip("run_cmu_02_03.bvh");
    const clipd* jump = shared_clip("jump_cmu_02_04.bvh");
    const clipd* kick = shared_clip("martialarts_frontkick_cmu_135_04.bvh");
    if (walk) check(r, 100, *walk, 100);
    if (walk && run2) check(*walk, 200, *run2, 30);
    if (jump) check(r, 100, *jump, 100);
    if (walk && kick) check(*walk, 150, *kick, 300);
}

TEST_CASE("flight: the root follows a parabola with the given gravity") {
    const auto& r = run<double>();
    const double dt = r.frame_time();
    const auto second_differences = [](const anima::joined_clip<double>& j, double& vertical, double& spread,
                                       double& horizontal) {
        std::vector<double> d;
        horizontal = 0;
        for (std::size_t f = j.start_frame + 1; f < j.end_frame; ++f) {
            const vec3 dd = j.motion.root_position(f + 1) - 2 * j.motion.root_position(f) + j.motion.root_position(f - 1);
            d.push_back(dd.dot(up));
            horizontal = std::max(horizontal, (dd - dd.dot(up) * up).norm());
        }
        const auto [lo, hi] = std::minmax_element(d.begin(), d.end());
        vertical = d.front();
        spread = *hi - *lo;
    };
    anima::transition_params p;
    p.classification.flight_hip_rise = 0.05;  // the run's 7 cm bounce counts as flight
    for (double k_g : {0.5, 0.25, 1.0}) {
        CAPTURE(k_g);
        p.gravity_factor = k_g;
        const auto t = anima::make_transition(r, 60, r, 20, p);
        REQUIRE(t.flight);
        CHECK(t.class_b.type == motion_class::space_flight);
        const auto joined = anima::join(r, 60, t);
        REQUIRE(joined.end_frame - joined.start_frame > 10);
        double vertical = 0, spread = 0, horizontal = 0;
        second_differences(joined, vertical, spread, horizontal);
        const double expected = -2 * k_g * 9.81 / 0.01 * dt * dt;
        CHECK(vertical == doctest::Approx(expected).epsilon(1e-9));
        CHECK(spread < 1e-9 * std::abs(expected));
        CHECK(horizontal < 1e-9);
        CHECK(joined.motion.root_position(joined.end_frame).dot(up) == doctest::Approx(r.root_position(20).dot(up)).epsilon(1e-12));
        const vec3 d = joined.motion.root_position(joined.end_frame) - r.root_position(60) - t.duration * t.root_at_trigger.velocity;
        CHECK((d - d.dot(up) * up).norm() < 1e-9);  // horizontally p0 + T v: no horizontal acceleration
    }
    p.gravity = 0;
    {
        const auto joined = anima::transition_clips(r, 60, r, 20, p);
        double vertical = 0, spread = 0, horizontal = 0;
        second_differences(joined, vertical, spread, horizontal);
        CHECK(std::abs(vertical) < 1e-9);
        CHECK(spread < 1e-9);
    }
    if (const clipd* jump = shared_clip("jump_cmu_02_04.bvh")) {
        const auto t = anima::make_transition(r, 100, *jump, 100);  // default thresholds
        CHECK(t.class_a.type == motion_class::plane_motion);
        CHECK(t.class_b.type == motion_class::space_flight);
        CHECK(t.flight);
        const auto joined = anima::join(r, 100, t);
        double vertical = 0, spread = 0, horizontal = 0;
        second_differences(joined, vertical, spread, horizontal);
        CHECK(vertical == doctest::Approx(-9.81 / 0.01 * dt * dt).epsilon(1e-9));
        CHECK(spread < 1e-9);
        CHECK(horizontal < 1e-9);
    }
}

TEST_CASE("squad passes through its keys") {
    std::mt19937 rng(7);
    std::normal_distribution<double> g;
    const auto random_q = [&] { return quatd(g(rng), g(rng), g(rng), g(rng)).normalized(); };
    for (int i = 0; i < 20; ++i) {
        const quatd q1 = random_q(), q2 = random_q(), s1 = random_q(), s2 = random_q();
        CHECK(anima::angle_between(anima::squad(q1, q2, s1, s2, 0.0), q1) < 1e-12);
        CHECK(anima::angle_between(anima::squad(q1, q2, s1, s2, 1.0), q2) < 1e-12);
    }
    const auto& r = run<double>();
    const std::size_t trigger = 60, b_start = 20;
    const auto t0 = anima::make_transition(r, trigger, r, b_start);
    const auto it = std::find(t0.methods.begin(), t0.methods.end(), interpolation::squad);
    REQUIRE(it != t0.methods.end());
    const auto j = static_cast<std::size_t>(it - t0.methods.begin());
    std::vector<double> first_gap, last_gap;
    for (double total : {0.25, 0.5, 1.0}) {
        anima::transition_params p;
        p.timing.min_duration = p.timing.max_duration = total;
        const auto t = anima::make_transition(r, trigger, r, b_start, p);
        REQUIRE(t.methods[j] == interpolation::squad);
        first_gap.push_back(anima::angle_between(t.frames.rotation(0, j), r.rotation(trigger, j)));
        last_gap.push_back(anima::angle_between(t.frames.rotation(t.frames.frames() - 1, j), t.placed_b.rotation(0, j)));
    }
    for (const auto* gap : {&first_gap, &last_gap}) {
        CHECK((*gap)[0] < 0.02);
        CHECK((*gap)[1] < (*gap)[0]);
        CHECK((*gap)[2] < (*gap)[1]);
        CHECK((*gap)[2] < (*gap)[0] / 8);  // the eased parameter is quadratic at the ends
    }
}

TEST_CASE("a joint turned 140 degrees between the clips turns monotonically, without a jump") {
    // B is the run with the abdomen (a spine joint) turned 140 degrees more in every frame, its
    // quaternions given on either side of the double cover. The transition
    // blends it by squad (a large turn); a blend that picked its own shorter
    // arc between the control points swung backwards and then jumped about
    // 177 degrees in one frame.
    const auto& r = run<double>();
    const std::size_t trigger = 60, b_start = 20;
    const std::size_t spine = r.skeleton().index_of("abdomen");
    for (const double sign : {1.0, -1.0}) {
        clipd b = r;
        const quatd turn(Eigen::AngleAxisd(140 * pi / 180, vec3(0.3, 1, -0.2).normalized()));
        for (std::size_t f = 0; f < b.frames(); ++f) {
            const quatd q = r.rotation(f, spine) * turn;
            b.set_rotation(f, spine, quatd(sign * q.w(), sign * q.x(), sign * q.y(), sign * q.z()));
        }
        const auto t = anima::make_transition(r, trigger, b, b_start);
        REQUIRE(t.methods[spine] == interpolation::squad);
        std::vector<quatd> path{r.rotation(trigger, spine)};
        for (std::size_t k = 0; k < t.frames.frames(); ++k) path.push_back(t.frames.rotation(k, spine));
        path.push_back(t.placed_b.rotation(0, spine));
        const double total = anima::angle_between(path.front(), path.back());
        CAPTURE(sign);
        CHECK(total > 2.2);  // beyond 120 degrees, where the control points are more than 90 apart
        double previous = 0, largest_step = 0;
        for (std::size_t k = 1; k < path.size(); ++k) {
            const double turned = anima::angle_between(path.front(), path[k]);
            CHECK(turned >= previous - 1e-9);
            previous = turned;
            largest_step = std::max(largest_step, anima::angle_between(path[k - 1], path[k]));
        }
        // Eased, so the middle steps exceed the mean; a jump would be most of the turn.
        CHECK(largest_step <= 2.5 * total / static_cast<double>(path.size() - 1));
    }
}

TEST_CASE("B is placed heading-aligned where the root path ends") {
    const auto& a = run<double>();
    const std::size_t trigger = 60, b_start = 20;
    const clipd b = moved(a, about(70, up), vec3(300, 4, -200));
    const auto t = anima::make_transition(a, trigger, b, b_start);
    const clipd& pb = t.placed_b;
    REQUIRE(pb.frames() == b.frames() - b_start);
    CHECK(angle_gap(heading(pb.rotation(0, 0)), heading(a.rotation(trigger, 0))) < 1e-9);
    // The predicted end point, horizontally; B's own start height vertically.
    const auto path = expected_path(a, trigger, b, b_start, t.duration);
    const vec3 end = pb.root_position(0), predicted = path.p0 + t.duration * path.v + 0.5 * t.duration * t.duration * path.acc;
    CHECK(std::abs(end.x() - predicted.x()) < 1e-6);
    CHECK(std::abs(end.z() - predicted.z()) < 1e-6);
    CHECK(end.y() == doctest::Approx(b.root_position(b_start).y()).epsilon(1e-12));
    // The rest of B is B turned about the vertical: same shape, same turns, same pose.
    double shape = 0, turns = 0, pose = 0;
    for (std::size_t f = 0; f < pb.frames(); ++f) {
        const vec3 dp = pb.root_position(f) - pb.root_position(0), db = b.root_position(b_start + f) - b.root_position(b_start);
        shape = std::max({shape, std::abs(dp.norm() - db.norm()), std::abs(dp.y() - db.y())});
        turns = std::max(turns, angle_gap(heading(pb.rotation(f, 0)) - heading(pb.rotation(0, 0)),
                                          heading(b.rotation(b_start + f, 0)) - heading(b.rotation(b_start, 0))));
        for (std::size_t j = 1; j < b.joints(); ++j)
            pose = std::max(pose, anima::angle_between(pb.rotation(f, j), b.rotation(b_start + f, j)));
    }
    CHECK(shape < 1e-9);
    CHECK(turns < 1e-9);
    CHECK(pose < 1e-12);
    // B's direction of travel turned with it: it now runs the way A ran.
    const vec3 travel_a = a.root_position(trigger) - a.root_position(trigger - 30);
    const vec3 travel_b = pb.root_position(30) - pb.root_position(0);
    CHECK(angle_gap(std::atan2(travel_a.x(), travel_a.z()), std::atan2(travel_b.x(), travel_b.z())) < 0.15);
    // The same transition from the unmoved B: placement removes B's own heading and place.
    const auto t0 = anima::make_transition(a, trigger, a, b_start);
    CHECK(t0.duration == t.duration);
    double same = 0;
    for (std::size_t f = 0; f < pb.frames(); ++f) {
        same = std::max(same, (t0.placed_b.root_position(f) + 4 * up - pb.root_position(f)).norm());  // B is 4 higher
        for (std::size_t j = 0; j < a.joints(); ++j)
            same = std::max(same, anima::angle_between(t0.placed_b.rotation(f, j), pb.rotation(f, j)));
    }
    CHECK(same < 1e-9);
}

TEST_CASE("B at another frame rate is resampled to A's") {
    const auto& a = run<double>();
    const double dt = a.frame_time();
    const clipd b60 = anima::resample(a, 1.0 / 60);
    REQUIRE(b60.frames() == 69);
    const auto t = anima::make_transition(a, 60, b60, 10);
    CHECK(t.frames.frame_time() == dt);
    CHECK(t.placed_b.frame_time() == dt);
    const auto joined = anima::join(a, 60, t);
    CHECK(joined.motion.frame_time() == dt);
    CHECK(largest_step(joined.motion, 0, joined.motion.frames() - 1, 0) < 0.1);  // no jump anywhere
    const auto cut = anima::direct_cut(a, 60, b60, 10);
    CHECK(cut.motion.frame_time() == dt);

    // B's frame 10 at 60 Hz is 1/6 s into B: the placed B must start there,
    // i.e. at frame 20 of B at 120 Hz.
    // (Mapping the frame by frame counts, 10 * 137 / 69 = 19, is one frame early.)
    const clipd b120 = anima::resample(b60, dt);
    const auto t120 = anima::make_transition(a, 60, b120, 20);
    double start_gap = 0, cut_gap = 0;
    for (std::size_t j = 1; j < a.joints(); ++j) {
        start_gap = std::max(start_gap, anima::angle_between(t.placed_b.rotation(0, j), b60.rotation(10, j)));
        cut_gap = std::max(cut_gap, anima::angle_between(cut.motion.rotation(61, j), b60.rotation(10, j)));
    }
    // (The file's frame time 0.00833333 is not exactly 1/120: 1e-5 rad of slack.)
    CHECK(start_gap < 1e-5);
    CHECK(cut_gap < 1e-5);
    CHECK(t.placed_b.frames() == t120.placed_b.frames());
    CHECK(t.duration == doctest::Approx(t120.duration));
}

TEST_CASE("errors: hierarchies, frames, sizes, parameters") {
    const auto& r = run<double>();
    const auto roles = anima::joint_roles(r.skeleton());
    const std::string m = thrown_message([&] { anima::make_transition(r, 60, walk31(), 10); });
    CHECK(m.find("'hip'") != std::string::npos);
    CHECK(m.find("'Hips'") != std::string::npos);
    CHECK_THROWS_AS(anima::make_transition(walk31(), 60, r, 10), anima::invalid_argument);

    // One joint renamed deep in the tree; another skeleton one joint longer;
    // different bone lengths are allowed.
    anima::skeleton<double> renamed, longer, scaled;
    for (std::size_t j = 0; j < r.joints(); ++j) {
        const auto& jt = r.skeleton()[j];
        renamed.add_joint(jt.name == "rThigh" ? "rUpperLeg" : jt.name, jt.parent, jt.offset, jt.channels);
        longer.add_joint(jt.name, jt.parent, jt.offset, jt.channels);
        scaled.add_joint(jt.name, jt.parent, 1.1 * jt.offset, jt.channels);
    }
    longer.add_joint("rToe", static_cast<int>(index(r, "rFoot")), vec3(0, 0, 10));
    const std::string mr = thrown_message([&] { anima::make_transition(r, 60, on_skeleton(r, renamed), 10); });
    CHECK(mr.find("'rThigh'") != std::string::npos);
    CHECK(mr.find("'rUpperLeg'") != std::string::npos);
    CHECK(mr.find(std::to_string(index(r, "rThigh"))) != std::string::npos);
    const std::string ml = thrown_message([&] { anima::make_transition(r, 60, on_skeleton(r, longer), 10); });
    CHECK(ml.find("rToe") != std::string::npos);
    CHECK_NOTHROW(anima::make_transition(r, 60, on_skeleton(r, scaled), 10));
    CHECK_THROWS_AS(anima::direct_cut(r, 60, walk31(), 10), anima::invalid_argument);
    CHECK_THROWS_AS(anima::crossfade(r, 60, on_skeleton(r, renamed), 10, 0.2), anima::invalid_argument);
    CHECK_THROWS_AS(anima::inertialize(r, 60, on_skeleton(r, longer), 10, 0.1), anima::invalid_argument);

    CHECK_THROWS_AS(anima::make_transition(r, r.frames(), r, 10), anima::invalid_argument);
    CHECK_THROWS_AS(anima::make_transition(r, 60, r, r.frames()), anima::invalid_argument);
    CHECK_NOTHROW(anima::make_transition(r, r.frames() - 1, r, r.frames() - 1));
    CHECK_NOTHROW(anima::make_transition(r, 0, r, 0));
    CHECK_THROWS_AS(anima::direct_cut(r, r.frames(), r, 10), anima::invalid_argument);
    CHECK_THROWS_AS(anima::crossfade(r, 60, r, r.frames(), 0.2), anima::invalid_argument);
    CHECK_THROWS_AS(anima::inertialize(r, 60, r, r.frames(), 0.1), anima::invalid_argument);
    CHECK_THROWS_AS(anima::crossfade(r, 60, r, 10, -0.1), anima::invalid_argument);
    CHECK_THROWS_AS(anima::inertialize(r, 60, r, 10, 0.0), anima::invalid_argument);
    const auto t = anima::make_transition(r, 60, r, 20);
    CHECK_THROWS_AS(anima::join(r, r.frames(), t), anima::invalid_argument);
    const quatd none = quatd::Identity();
    CHECK_THROWS_AS(anima::variable_timing(r, r.frames(), r, 0, roles, none), anima::invalid_argument);
    CHECK_THROWS_AS(anima::variable_timing(r, 0, r, 0, std::vector<joint_role>(2), none), anima::invalid_argument);

    const auto throws = [&](anima::transition_params p) {
        CHECK_THROWS_AS(anima::make_transition(r, 60, r, 20, p), anima::invalid_argument);
    };
    anima::transition_params p;
    p.roles.assign(5, joint_role::leg);
    throws(p);
    p = {};
    p.methods.assign(r.joints() + 1, interpolation::slerp);
    throws(p);
    p = {};
    p.large_angle = -1;
    throws(p);
    p = {};
    p.gravity = -9.81;
    throws(p);
    p = {};
    p.gravity_factor = std::numeric_limits<double>::infinity();
    throws(p);
    p = {};
    p.root_window = -0.1;
    throws(p);
    p = {};
    p.timing.min_duration = -0.1;
    throws(p);
    p = {};
    p.timing.max_duration = 0.05;  // below min_duration
    throws(p);
    p = {};
    p.timing.min_speed = 0;
    throws(p);
    p = {};
    p.timing.min_acceleration = -1;
    throws(p);
    p = {};
    p.timing.speed_window = -1;
    throws(p);
    p = {};
    p.classification.contact_speed = 0;
    throws(p);

    const auto joined = anima::join(r, 60, t);
    const auto c = anima::classify_motion(r, roles);
    CHECK_THROWS_AS(anima::measure_transition(joined, std::vector<joint_role>(3), c.up, 0.01), anima::invalid_argument);
    CHECK_THROWS_AS(anima::measure_transition(joined, roles, c.up, 0.0), anima::invalid_argument);
    auto broken = joined;
    broken.end_frame = joined.motion.frames();
    CHECK_THROWS_AS(anima::measure_transition(broken, roles, c.up, 0.01), anima::invalid_argument);
}

TEST_CASE_TEMPLATE("degenerate input: no joints, unbounded durations, bad windows and turns name the function and "
                   "argument",
                   T, float, double) {
    const anima::clip<T>& r = run<T>();
    using quat = Eigen::Quaternion<T>;
    const auto message = [](auto&& f) { return thrown_message(f); };
    const auto has = [](const std::string& m, const char* part) {
        CAPTURE(m);
        CHECK(m.find(part) != std::string::npos);
    };
    // A skeleton without joints: refused by every entry point (Eigen aborted
    // in classify_motion, the baselines blamed clip::rotation).
    const anima::clip<T> none(anima::skeleton<T>{}, 5, T(1) / 30);
    has(message([&] { anima::classify_motion(none, {}); }), "anima::classify_motion: the clip has frames but no joints");
    CHECK(anima::classify_motion(anima::clip<T>(anima::skeleton<T>{}, 0, T(1) / 30), {}).type ==
          motion_class::on_the_spot);
    has(message([&] { anima::make_transition(none, 2, none, 0); }), "anima::make_transition: the clips have no joints");
    has(message([&] { anima::direct_cut(none, 2, none, 0); }), "anima::direct_cut: the clips have no joints");
    has(message([&] { anima::crossfade(none, 2, none, 0, T(0.1)); }), "anima::crossfade: the clips have no joints");
    has(message([&] { anima::inertialize(none, 2, none, 0, T(0.1)); }), "anima::inertialize: the clips have no joints");

    // max_duration infinite, or a transition too long to hold (1e5 s at 120 Hz took 14 GB).
    anima::transition_params p;
    p.timing.min_duration = p.timing.max_duration = std::numeric_limits<double>::infinity();
    has(message([&] { anima::make_transition(r, 60, r, 0, p); }), "timing_params::min_duration must be");
    p.timing.min_duration = 0.1;
    has(message([&] { anima::make_transition(r, 60, r, 0, p); }),
        "anima::make_transition: timing_params::max_duration must be finite and at least min_duration (0.1), got inf");
    p.timing.min_duration = p.timing.max_duration = 1e5;
    has(message([&] { anima::make_transition(r, 60, r, 0, p); }), "more than transition_params::max_memory");
    anima::transition_frames<T> frames;
    anima::transition_workspace<T> ws;
    has(message([&] { anima::make_transition_into(r, 60, r, 0, p, frames, ws); }),
        "anima::make_transition_into: a transition of 1e+05 s");
    // A huge max_duration is only a bound: the transition takes what the motion asks.
    p = {};
    p.timing.max_duration = 1e9;
    CHECK(anima::make_transition(r, 60, r, 0, p).duration < T(2));
    p.max_memory = 0;  // no limit: a 2 s transition still runs
    p.timing.min_duration = p.timing.max_duration = 2;
    CHECK(anima::make_transition(r, 60, r, 0, p).duration == doctest::Approx(2.0).epsilon(0.01));

    // Parameters name themselves and their value.
    p = {};
    p.root_window = std::numeric_limits<double>::infinity();
    has(message([&] { anima::make_transition(r, 60, r, 0, p); }), "transition_params::root_window must be");
    p = {};
    p.gravity_factor = std::numeric_limits<double>::quiet_NaN();
    has(message([&] { anima::make_transition(r, 60, r, 0, p); }), "transition_params::gravity_factor must be finite");
    p = {};
    p.classification.metres_per_unit = std::numeric_limits<double>::quiet_NaN();
    has(message([&] { anima::make_transition(r, 60, r, 0, p); }),
        "anima::make_transition: classify_params::metres_per_unit must be positive and finite, got nan");
    p = {};
    p.large_angle = std::numeric_limits<double>::infinity();  // no joint uses squad
    for (const auto method : anima::make_transition(r, 60, r, 0, p).methods) CHECK(method != interpolation::squad);
    has(message([&] { anima::crossfade(r, 60, r, 0, T(-1)); }), "anima::crossfade: duration must be non-negative and finite, got -1");

    // A turn that is no rotation: refused (NaN timing silently dropped the root).
    const auto roles = anima::joint_roles(r.skeleton());
    const T nan = std::numeric_limits<T>::quiet_NaN();
    has(message([&] { anima::variable_timing(r, 60, r, 0, roles, quat(nan, 0, 0, 0)); }),
        "anima::variable_timing: b_root_turn");
    has(message([&] { anima::variable_timing(r, 60, r, 0, roles, quat(0, 0, 0, 0)); }),
        "anima::variable_timing: b_root_turn");
    // A scaled turn is the same turn, also where its squared norm overflows float.
    const quat turn(Eigen::AngleAxis<T>(T(0.7), Eigen::Matrix<T, 3, 1>::UnitY()));
    const auto unit = anima::variable_timing(r, 60, r, 0, roles, turn);
    const auto scaled = anima::variable_timing(r, 60, r, 0, roles, quat(turn.coeffs() * T(1e30)));
    CHECK(scaled.joints[0].angle == doctest::Approx(double(unit.joints[0].angle)).epsilon(1e-5));
    CHECK(scaled.duration == doctest::Approx(double(unit.duration)).epsilon(1e-5));
    has(message([&] { anima::interpolation_parameter(nan, T(1), anima::easing::linear); }),
        "anima::interpolation_parameter: t and total must not be NaN");

    // A joined window outside the clip: plant_transition_feet refuses it as
    // measure_transition does (it returned the window unchanged).
    auto joined = anima::direct_cut(r, 60, r, 0);
    joined.start_frame = 100;
    joined.end_frame = 5000;
    has(message([&] { anima::plant_transition_feet(joined); }), "anima::plant_transition_feet: transition frames [100, 5000]");
    joined.end_frame = 50;
    has(message([&] { anima::plant_transition_feet(joined); }), "are not inside the clip");
    has(message([&] {
            anima::measure_transition(anima::direct_cut(r, 60, r, 0), roles, anima::signed_axis{},
                                      std::numeric_limits<double>::infinity());
        }),
        "anima::measure_transition: metres_per_unit must be positive and finite, got inf");

    // Inertialization with the smallest normal half-life is a cut with no
    // NaN (y x0 overflowed, times a decay of 0); a subnormal one is refused.
    const auto cut = anima::inertialize(r, 60, r, 0, std::numeric_limits<T>::min());
    for (std::size_t f = 0; f < cut.motion.frames(); ++f)
        for (std::size_t j = 0; j < cut.motion.joints(); ++j) REQUIRE(cut.motion.rotation(f, j).coeffs().allFinite());
    has(message([&] { anima::inertialize(r, 60, r, 0, std::numeric_limits<T>::denorm_min()); }),
        "anima::inertialize: halflife must be positive, normal and finite");
    // Durations and half-lives take the clip's scalar type: double literals on a float clip.
    CHECK(anima::crossfade(r, 60, r, 0, 0.2).end_frame == anima::crossfade(r, 60, r, 0, T(0.2)).end_frame);
    CHECK(anima::inertialize(r, 60, r, 0, 0.1).end_frame == anima::inertialize(r, 60, r, 0, T(0.1)).end_frame);
    // A crossfade longer than size_t can count blends over what B has.
    CHECK(anima::crossfade(r, 60, r, 0, T(1e30)).motion.frames() == 61 + r.frames());
}

TEST_CASE("baselines: direct cut, crossfade, inertialization") {
    const auto& a = run<double>();
    const clipd b = moved(a, about(-50, up), vec3(-100, 0, 250));
    const std::size_t trigger = 60, b_start = 20;
    const double dt = a.frame_time();

    const auto cut = anima::direct_cut(a, trigger, b, b_start);
    CHECK(cut.start_frame == trigger);
    CHECK(cut.end_frame == trigger + 1);
    REQUIRE(cut.motion.frames() == trigger + 1 + b.frames() - b_start);
    double pose = 0, turn_drift = 0;
    const quatd turn = cut.motion.rotation(trigger + 1, 0) * b.rotation(b_start, 0).conjugate();
    for (std::size_t f = 0; f < b.frames() - b_start; ++f) {
        for (std::size_t j = 1; j < a.joints(); ++j)
            pose = std::max(pose, anima::angle_between(cut.motion.rotation(trigger + 1 + f, j), b.rotation(b_start + f, j)));
        turn_drift = std::max(turn_drift, anima::angle_between(cut.motion.rotation(trigger + 1 + f, 0) * b.rotation(b_start + f, 0).conjugate(), turn));
    }
    CHECK(pose < 1e-12);
    CHECK(turn_drift < 1e-9);
    CHECK(std::hypot(turn.x(), turn.z()) < 1e-12);  // the root is only turned about the vertical
    CHECK(angle_gap(heading(cut.motion.rotation(trigger + 1, 0)), heading(a.rotation(trigger, 0))) < 1e-9);
    // One frame of A's root velocity on, at B's own height.
    const vec3 next = 2 * a.root_position(trigger) - a.root_position(trigger - 1);
    const vec3 placed = cut.motion.root_position(trigger + 1);
    CHECK(std::hypot(placed.x() - next.x(), placed.z() - next.z()) < 1e-9);
    CHECK(placed.y() == doctest::Approx(b.root_position(b_start).y()).epsilon(1e-12));

    for (double d : {0.2, 0.1, 0.004}) {
        CAPTURE(d);
        const auto steps = static_cast<std::size_t>(std::max(1L, std::lround(d / dt)));
        const auto fade = anima::crossfade(a, trigger, b, b_start, d);
        CHECK(fade.start_frame == trigger);
        CHECK(fade.end_frame - fade.start_frame == steps);
        CHECK(fade.motion.frames() == cut.motion.frames());
        for (std::size_t j = 0; j < a.joints(); ++j) {
            // The first blended frame is A's next frame moved 1/steps of the way to B.
            const double gap = anima::angle_between(a.rotation(trigger + 1, j), cut.motion.rotation(trigger + 1, j));
            const double moved_by = anima::angle_between(fade.motion.rotation(trigger + 1, j), a.rotation(trigger + 1, j));
            CHECK(std::abs(moved_by - gap / static_cast<double>(steps)) < 1e-9 * gap + 1e-12);
            // From end_frame on it is the placed B.
            CHECK(anima::angle_between(fade.motion.rotation(fade.end_frame, j), cut.motion.rotation(fade.end_frame, j)) < 1e-12);
        }
    }
    // A B shorter than the fade: the fade stops where B does.
    const auto short_fade = anima::crossfade(a, trigger, b, b.frames() - 6, 0.2);
    CHECK(short_fade.motion.frames() == trigger + 1 + 6);
    // end_frame must be a frame of the clip, so measure_transition accepts it.
    CHECK(short_fade.end_frame < short_fade.motion.frames());

    const double halflife = 0.05;
    const auto inert = anima::inertialize(a, trigger, b, b_start, halflife);
    CHECK(inert.start_frame == trigger);
    REQUIRE(inert.motion.frames() == cut.motion.frames());
    // The first frame after the switch continues A (extrapolated one frame).
    double first = 0;
    std::vector<vec3> x0(a.joints()), v0(a.joints());
    for (std::size_t j = 0; j < a.joints(); ++j) {
        const quatd qa = a.rotation(trigger, j), step = a.rotation(trigger - 1, j).conjugate() * qa;
        first = std::max(first, anima::angle_between(inert.motion.rotation(trigger + 1, j), quatd(qa * step)));
        x0[j] = anima::to_rotation_vector(quatd(qa * step * cut.motion.rotation(trigger + 1, j).conjugate()));
        v0[j] = (anima::to_rotation_vector(quatd(qa * step * step * cut.motion.rotation(trigger + 2, j).conjugate())) - x0[j]) / dt;
    }
    CHECK(first < 1e-9);
    CHECK((inert.motion.root_position(trigger + 1) - next).norm() < 1e-9);
    // Then the offset to the placed B decays like the critically damped spring,
    // and after ten half-lives it is gone.
    double spring = 0, late = 0, at_end = 0, largest = 0;
    for (const auto& x : x0) largest = std::max(largest, x.norm());
    for (std::size_t f = 0; trigger + 1 + f < cut.motion.frames(); ++f) {
        const double t = dt * static_cast<double>(f);
        for (std::size_t j = 0; j < a.joints(); ++j) {
            const quatd qi = inert.motion.rotation(trigger + 1 + f, j), qb = cut.motion.rotation(trigger + 1 + f, j);
            const vec3 expected = anima::spring_decay(x0[j], v0[j], halflife, t);
            spring = std::max(spring, (anima::to_rotation_vector(quatd(qi * qb.conjugate())) - expected).norm());
            if (t >= 10 * halflife) late = std::max(late, anima::angle_between(qi, qb));
            if (trigger + 1 + f == inert.end_frame) at_end = std::max(at_end, anima::angle_between(qi, qb));
        }
    }
    CHECK(spring < 1e-9);
    CHECK(late < 1e-3);
    CHECK(inert.end_frame > inert.start_frame + 1);
    CHECK(at_end <= 0.01 * largest + 1e-12);
}

TEST_CASE("spring_decay is the critically damped solution") {
    const double x0 = 1.5, v0 = -4, halflife = 0.2, y = 2 * std::log(2.0) / halflife;
    const auto x = [&](double t) { return anima::spring_decay(x0, v0, halflife, t); };
    CHECK(x(0) == x0);
    const double h = 1e-5;
    CHECK((x(h) - x(-h)) / (2 * h) == doctest::Approx(v0).epsilon(1e-7));
    double residual = 0;
    for (double t = 0.01; t < 2; t += 0.037) {
        const double d1 = (x(t + h) - x(t - h)) / (2 * h), d2 = (x(t + h) - 2 * x(t) + x(t - h)) / (h * h);
        residual = std::max(residual, std::abs(d2 + 2 * y * d1 + y * y * x(t)));
    }
    CHECK(residual < 1e-3);  // against terms of size y^2 x0 ~ 70
    CHECK(std::abs(x(10 * halflife)) < 1e-4);
    CHECK(x(3) == doctest::Approx((x0 + (v0 + y * x0) * 3) * std::exp(-y * 3)).epsilon(1e-12));
    const vec3 xv = anima::spring_decay(vec3(1, -2, 0.5), vec3(0, 3, -1), halflife, 0.3);
    CHECK(xv.y() == doctest::Approx(anima::spring_decay(-2.0, 3.0, halflife, 0.3)).epsilon(1e-15));
}

TEST_CASE("a figure without feet: no skate, nothing planted, no error") {
    using anima::channel;
    anima::skeleton<double> sk;
    sk.add_joint("Box", -1, vec3::Zero(),
                 {channel::x_position, channel::y_position, channel::z_position, channel::z_rotation,
                  channel::x_rotation, channel::y_rotation});
    sk.add_joint("Lid", 0, vec3::Zero());  // flat: the figure has no height
    clipd box(sk, 60, 1.0 / 60);
    for (std::size_t f = 0; f < box.frames(); ++f) box.set_root_position(f, vec3(static_cast<double>(f), 0, 0));
    const auto joined = anima::direct_cut(box, 30, box, 10);
    const auto planted = anima::plant_transition_feet(joined);
    for (std::size_t f = 0; f < joined.motion.frames(); ++f)
        REQUIRE(planted.motion.root_position(f) == joined.motion.root_position(f));
    const auto q = anima::measure_transition(joined, anima::joint_roles(sk), anima::signed_axis{}, 1.0);
    CHECK(q.foot_skate_window == 0);
    CHECK(q.foot_skate_ratio == 0);
    CHECK_FALSE(anima::has_feet(box));
}

TEST_CASE_TEMPLATE("measure_transition: the root's slowest ground speed in the window against its ends', by hand",
                   T, float, double) {
    using anima::channel;
    using v3 = Eigen::Matrix<T, 3, 1>;
    anima::skeleton<T> sk;
    sk.add_joint("Box", -1, v3::Zero(),
                 {channel::x_position, channel::y_position, channel::z_position, channel::z_rotation,
                  channel::x_rotation, channel::y_rotation});
    // Forward 1 unit a frame, a quarter of that over frames 26..34; rising
    // 5 units a frame all along (up, +Y: not ground speed).
    anima::clip<T> box(sk, 60, T(1) / T(60));
    T x = 0;
    for (std::size_t f = 0; f < box.frames(); ++f) {
        if (f > 0) x += f >= 26 && f <= 34 ? T(0.25) : T(1);
        box.set_root_position(f, v3(x, T(5) * static_cast<T>(f), T(0)));
    }
    const anima::joined_clip<T> joined{box, 20, 40};
    const double metres_per_unit = 0.5;
    const auto q = anima::measure_transition(joined, anima::joint_roles(sk), anima::signed_axis{}, metres_per_unit);
    // Central differences: 1 unit a frame at both ends (60 units/s), a quarter
    // of it inside the slow stretch; in metres.
    const T tol = std::is_same_v<T, float> ? T(1e-4) : T(1e-12);
    CHECK(std::abs(q.root_speed_ends - T(30)) <= tol * T(30));
    CHECK(std::abs(q.root_speed_min - T(7.5)) <= tol * T(30));
    CHECK(std::abs(q.root_speed_ratio - T(0.25)) <= tol);
    // Standing still: no ratio.
    anima::clip<T> still(sk, 60, T(1) / T(60));
    const auto s = anima::measure_transition(anima::joined_clip<T>{still, 20, 40}, anima::joint_roles(sk),
                                             anima::signed_axis{}, metres_per_unit);
    CHECK(s.root_speed_ends == T(0));
    CHECK(s.root_speed_ratio == T(0));
}

TEST_CASE("measure_transition: the variable-timing transition is smoother than a direct cut") {
    const auto measure = [](const clipd& a, std::size_t trigger, const clipd& b, std::size_t b_start) {
        const auto roles = anima::joint_roles(a.skeleton());
        const auto c = anima::classify_motion(a, roles);
        const auto vt = anima::transition_clips(a, trigger, b, b_start);
        const auto cut = anima::direct_cut(a, trigger, b, b_start);
        const auto qv = anima::measure_transition(vt, roles, c.up, c.metres_per_unit);
        const auto qc = anima::measure_transition(cut, roles, c.up, c.metres_per_unit);
        INFO("peak angular acceleration (rad/s^2): variable timing " << qv.peak_angular_acceleration << ", direct cut "
                                                                   << qc.peak_angular_acceleration);
        CHECK(qv.length == doctest::Approx(static_cast<double>(vt.end_frame - vt.start_frame) * a.frame_time()));
        CHECK(qc.length == doctest::Approx(a.frame_time()));
        CHECK(qv.peak_angular_acceleration < qc.peak_angular_acceleration);
        CHECK(qv.peak_angular_jerk < qc.peak_angular_jerk);
        CHECK(qv.foot_slide >= 0);
    };
    measure(run<double>(), 60, run<double>(), 20);
    if (const clipd* walk = shared_clip("walk_cmu_02_01.bvh")) measure(run<double>(), 100, *walk, 100);
}

namespace {

template <class T>
bool same_bits(const T& a, const T& b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

template <class V>
bool same_bits(const std::vector<V>& a, const std::vector<V>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(V)) == 0);
}

template <class T>
bool same_clip(const anima::clip<T>& a, const anima::clip<T>& b) {
    return a.frames() == b.frames() && same_bits(a.frame_time(), b.frame_time()) && a.skeleton() == b.skeleton() &&
           same_bits(a.rotations(), b.rotations()) && same_bits(a.translations(), b.translations());
}

// Every field of a make_transition_into result, bit for bit, against make_transition's.
template <class T>
void check_same_transition(const anima::transition<T>& expected, const anima::transition_frames<T>& got) {
    CHECK(same_clip(got.frames, expected.frames));
    CHECK(same_bits(got.duration, expected.duration));
    CHECK(same_bits(got.timing.duration, expected.timing.duration));
    CHECK(same_bits(got.timing.unclamped, expected.timing.unclamped));
    CHECK(got.timing.limiting_joint == expected.timing.limiting_joint);
    REQUIRE(got.timing.joints.size() == expected.timing.joints.size());
    bool timing = true;
    for (std::size_t j = 0; j < got.timing.joints.size(); ++j) {
        const auto &g = got.timing.joints[j], &e = expected.timing.joints[j];
        timing = timing && g.joint == e.joint && g.role == e.role && g.key == e.key && same_bits(g.angle, e.angle) &&
                 same_bits(g.speed_a, e.speed_a) && same_bits(g.speed_b, e.speed_b) &&
                 same_bits(g.acceleration_a, e.acceleration_a) && same_bits(g.acceleration_b, e.acceleration_b) &&
                 same_bits(g.time, e.time);
    }
    CHECK(timing);
    CHECK(got.methods == expected.methods);
    CHECK(got.parameter == expected.parameter);
    const auto same_class = [](const anima::motion_classification& g, const anima::motion_classification& e) {
        return g.type == e.type && g.up == e.up && same_bits(g.metres_per_unit, e.metres_per_unit) &&
               same_bits(g.foot_range, e.foot_range) && same_bits(g.hip_rise, e.hip_rise);
    };
    CHECK(same_class(got.class_a, expected.class_a));
    CHECK(same_class(got.class_b, expected.class_b));
    CHECK(got.flight == expected.flight);
    CHECK(same_bits(got.root_at_trigger.velocity, expected.root_at_trigger.velocity));
    CHECK(same_bits(got.root_at_trigger.acceleration, expected.root_at_trigger.acceleration));
    CHECK(got.placement.first == expected.placement.first);
    CHECK(same_bits(got.placement.turn.coeffs(), expected.placement.turn.coeffs()));
    CHECK(same_bits(got.placement.pivot, expected.placement.pivot));
    CHECK(same_bits(got.placement.start, expected.placement.start));
}

// The placed B of make_transition is B played through the placement: the
// root turned and moved, frame by frame, bit for bit; the rest as it is.
template <class T>
bool placement_places(const anima::clip_placement<T>& where, const anima::clip<T>& b, const anima::clip<T>& placed) {
    if (placed.frames() != b.frames() - where.first) return false;
    const bool translated = b.skeleton().translation_slot(0) >= 0;
    for (std::size_t f = 0; f < placed.frames(); ++f)
        for (std::size_t j = 0; j < b.joints(); ++j) {
            const auto q = j == 0 ? where.rotation(b.rotation(where.first + f, 0)) : b.rotation(where.first + f, j);
            if (!same_bits(placed.rotation(f, j).coeffs(), q.coeffs())) return false;
            if (b.skeleton().translation_slot(j) < 0) continue;
            const auto p = j == 0 && translated ? where.position(b.root_position(where.first + f))
                                                : b.translation(where.first + f, j);
            if (!same_bits(placed.translation(f, j), p)) return false;
        }
    return true;
}

// A transition to run: clips, frames, parameters.
template <class T>
struct transition_case {
    std::string name;
    const anima::clip<T>* a;
    std::size_t trigger;
    const anima::clip<T>* b;
    std::size_t b_start;
    anima::transition_params params;
};

// The singular and ordinary transitions the tests above cover, on the run:
// different lengths, so that a reused output grows and shrinks. Classes are
// given (classifying at -O0 is slow) except where the classification is
// part of the case.
template <class T>
std::vector<transition_case<T>> transition_cases(const anima::clip<T>& r, const anima::clip<T>& one_frame,
                                                 const anima::clip<T>& spine_turned) {
    const auto roles = anima::joint_roles(r.skeleton());
    const auto classes = [&](anima::transition_params p, const anima::clip<T>& a, const anima::clip<T>& b) {
        p.class_a = anima::classify_motion(a, roles);
        p.class_b = &b == &a ? p.class_a : anima::classify_motion(b, roles);
        return p;
    };
    const anima::transition_params given = classes({}, r, r);
    std::vector<transition_case<T>> cases;
    const auto add = [&](std::string name, const anima::clip<T>& a, std::size_t at, const anima::clip<T>& b,
                         std::size_t to, anima::transition_params p) {
        cases.push_back({std::move(name), &a, at, &b, to, std::move(p)});
    };
    add("run 60 -> 20, classified in the call", r, 60, r, 20, {});
    add("run 80 -> 90", r, 80, r, 90, given);
    add("run 40 -> 120", r, 40, r, 120, given);
    for (double min_duration : {0.1, 0.05, 0.003}) {  // the last: no in-between frame
        anima::transition_params p = given;
        p.timing.min_duration = min_duration;
        add("identical poses, min_duration " + std::to_string(min_duration), r, 60, r, 60, p);
    }
    add("last frame to last frame (one frame of B)", r, r.frames() - 1, r, r.frames() - 1, given);
    add("first frame to first frame", r, 0, r, 0, given);
    add("one-frame clips", one_frame, 0, one_frame, 0, classes({}, one_frame, one_frame));
    add("a joint turned 140 degrees (squad)", r, 60, spine_turned, 20, classes({}, r, spine_turned));
    anima::transition_params p;
    p.classification.flight_hip_rise = 0.05;
    p.gravity_factor = 0.25;
    add("flight, classified in the call", r, 60, r, 20, p);
    p = given;
    p.methods.assign(r.joints(), interpolation::squad);
    add("all squad", r, 60, r, 20, p);
    p.methods.assign(r.joints(), interpolation::lerp);
    p.parameter = anima::easing::linear;
    add("all lerp, linear", r, 60, r, 20, p);
    p = given;
    p.roles.assign(r.joints(), joint_role::leg);
    p.timing.model = anima::timing_model::constant_acceleration;
    p.timing.speed_window = 0;
    p.timing.max_duration = 10;
    add("all legs, constant acceleration, one-step speed window", r, 60, r, 20, p);
    p = given;
    p.timing.min_duration = p.timing.max_duration = 1.2;
    p.root_window = 0;
    add("1.2 s, no root window", r, 50, r, 30, p);
    return cases;
}

template <class T>
anima::clip<T> with_turned_joint(const anima::clip<T>& c, std::size_t j, const Eigen::Quaternion<T>& turn) {
    anima::clip<T> out = c;
    for (std::size_t f = 0; f < c.frames(); ++f) out.set_rotation(f, j, c.rotation(f, j) * turn);
    return out;
}

template <class T>
void check_into_matches(const anima::clip<T>& r) {
    const anima::clip<T> one_frame = r.slice(30, 31);
    const Eigen::Matrix<T, 3, 1> axis = Eigen::Matrix<T, 3, 1>(T(0.3), 1, T(-0.2)).normalized();
    const Eigen::Quaternion<T> turn(Eigen::AngleAxis<T>(T(140 * pi / 180), axis));
    const anima::clip<T> spine_turned = with_turned_joint(r, r.skeleton().index_of("abdomen"), turn);
    const auto cases = transition_cases(r, one_frame, spine_turned);
    // One output and workspace for all cases, twice over (reused storage,
    // longer and shorter transitions), and a fresh pair for each.
    anima::transition_frames<T> out;
    anima::transition_workspace<T> ws;
    std::vector<anima::transition<T>> expected;
    for (const auto& c : cases) expected.push_back(anima::make_transition(*c.a, c.trigger, *c.b, c.b_start, c.params));
    for (int round = 0; round < 2; ++round)
        for (std::size_t i = 0; i < cases.size(); ++i) {
            const auto& c = cases[i];
            CAPTURE(c.name);
            CAPTURE(round);
            anima::make_transition_into(*c.a, c.trigger, *c.b, c.b_start, c.params, out, ws);
            check_same_transition(expected[i], out);
            if (round > 0) continue;
            anima::transition_frames<T> fresh;
            anima::transition_workspace<T> fresh_ws;
            anima::make_transition_into(*c.a, c.trigger, *c.b, c.b_start, c.params, fresh, fresh_ws);
            check_same_transition(expected[i], fresh);
            CHECK(placement_places(expected[i].placement, *c.b, expected[i].placed_b));
        }
}

}  // namespace

TEST_CASE("make_transition_into: make_transition's results bit for bit, in double and float") {
    check_into_matches(run<double>());
    check_into_matches(run<float>());
    // The 31-joint walk of the benchmark, into the output the run used: another skeleton.
    anima::transition_params p;
    p.class_a = p.class_b = anima::classify_motion(walk31(), anima::joint_roles(walk31().skeleton()));
    anima::transition_frames<double> out;
    anima::transition_workspace<double> ws;
    anima::make_transition_into(run<double>(), 60, run<double>(), 20, {}, out, ws);
    anima::make_transition_into(walk31(), 120, walk31(), 250, p, out, ws);
    check_same_transition(anima::make_transition(walk31(), 120, walk31(), 250, p), out);
    CHECK(out.frames.skeleton() == walk31().skeleton());
}

namespace {

using heap_count::allocations_in;

template <class T>
void check_no_allocation(const anima::clip<T>& r) {
    // Classes given, as a game would pass them: classifying a clip allocates.
    const auto roles = anima::joint_roles(r.skeleton());
    anima::transition_params given;
    given.class_a = given.class_b = anima::classify_motion(r, roles);
    anima::transition_params with_roles = given;
    with_roles.roles = roles;
    anima::transition_params key_only = given;
    key_only.timing.every_joint = false;
    const std::pair<std::size_t, std::size_t> frames[] = {{60, 20}, {80, 90}, {40, 120}, {60, 60}, {0, 0}};
    anima::transition_frames<T> out;
    anima::transition_workspace<T> ws;
    // The first calls size the output and the workspace...
    for (const auto* p : {&given, &with_roles, &key_only})
        for (auto [at, to] : frames) anima::make_transition_into(r, at, r, to, *p, out, ws);
    // ... after which no call allocates, whatever its frames and length.
    for (const auto* p : {&given, &with_roles, &key_only})
        for (const auto& f : frames) {
            CAPTURE(f.first);
            CAPTURE(f.second);
            CHECK(allocations_in([&] { anima::make_transition_into(r, f.first, r, f.second, *p, out, ws); }) == 0);
        }
    // The counter does count: make_transition allocates its result.
    CHECK(allocations_in([&] { anima::make_transition(r, 60, r, 20, given); }) > 0);
    // The same call again: nothing, and the same result as make_transition's.
    anima::make_transition_into(r, 60, r, 20, given, out, ws);
    CHECK(allocations_in([&] { anima::make_transition_into(r, 60, r, 20, given, out, ws); }) == 0);
    check_same_transition(anima::make_transition(r, 60, r, 20, given), out);
}

}  // namespace

TEST_CASE("make_transition_into allocates nothing once it has seen the skeleton and the length") {
    check_no_allocation(run<double>());
    check_no_allocation(run<float>());
    // The counter sees Eigen's allocations too.
    CHECK(allocations_in([] { Eigen::MatrixXd m(40, 40); }) > 0);
}

namespace {

// timing_params::every_joint = false against the default on the same
// transition: the key joints' speeds and times and so T as measured for
// every joint (to rounding: the series' length is chosen from the largest
// step of the joints measured), every angle bit for bit, the other joints'
// speeds and times NaN, and the frames the same to rounding.
template <class T>
void check_key_joints_only(const anima::clip<T>& c, std::size_t at, std::size_t to, anima::timing_model model) {
    CAPTURE(at);
    CAPTURE(to);
    anima::transition_params all;
    all.class_a = all.class_b = anima::classify_motion(c, anima::joint_roles(c.skeleton()));
    all.timing.model = model;
    anima::transition_params keys = all;
    keys.timing.every_joint = false;
    const auto expected = anima::make_transition(c, at, c, to, all);
    anima::transition_frames<T> got;
    anima::transition_workspace<T> ws;
    anima::make_transition_into(c, at, c, to, keys, got, ws);
    const double tolerance = std::is_same_v<T, float> ? 1e-4 : 1e-11;
    const auto close = [&](T g, T e) {
        return std::abs(static_cast<double>(g) - static_cast<double>(e)) <=
               tolerance * std::max(1.0, std::abs(static_cast<double>(e)));
    };
    CHECK(close(got.timing.duration, expected.timing.duration));
    CHECK(got.timing.limiting_joint == expected.timing.limiting_joint);
    std::size_t key = 0, other = 0;
    for (std::size_t j = 0; j < c.joints(); ++j) {
        const auto &g = got.timing.joints[j], &e = expected.timing.joints[j];
        CHECK(same_bits(g.angle, e.angle));
        CHECK(g.key == e.key);
        if (e.key) {
            ++key;
            CHECK(close(g.speed_a, e.speed_a));
            CHECK(close(g.speed_b, e.speed_b));
            CHECK(close(g.acceleration_a, e.acceleration_a));
            CHECK(close(g.acceleration_b, e.acceleration_b));
            CHECK(close(g.time, e.time));
        } else {
            ++other;
            CHECK((std::isnan(g.speed_a) && std::isnan(g.speed_b) && std::isnan(g.acceleration_a) &&
                   std::isnan(g.acceleration_b) && std::isnan(g.time)));
        }
    }
    CHECK(key > 0);
    CHECK(other > 0);
    REQUIRE(got.frames.frames() == expected.frames.frames());
    CHECK(got.methods == expected.methods);
    double worst = 0;
    for (std::size_t i = 0; i < got.frames.rotations().size(); ++i)
        worst = std::max(worst, static_cast<double>((got.frames.rotations()[i].coeffs() -
                                                     expected.frames.rotations()[i].coeffs()).cwiseAbs().maxCoeff()));
    CHECK(worst <= 100 * tolerance);
}

}  // namespace

TEST_CASE("timing of the key joints only: the same T, the other joints not measured") {
    for (const auto model : {anima::timing_model::velocity, anima::timing_model::constant_acceleration}) {
        check_key_joints_only(run<double>(), 60, 20, model);
        check_key_joints_only(run<double>(), 80, 90, model);
        check_key_joints_only(run<float>(), 60, 20, model);
        check_key_joints_only(walk31(), 120, 250, model);
    }
    // No key joint at all: T is the shortest, nothing is measured.
    const auto& r = run<double>();
    const std::vector<joint_role> none(r.joints(), joint_role::other);
    anima::timing_params p;
    p.every_joint = false;
    const auto t = anima::variable_timing(r, 60, r, 20, none, quatd::Identity(), p);
    CHECK(t.duration == doctest::Approx(p.min_duration));
    CHECK(std::isnan(t.joints[3].speed_a));
    CHECK(t.joints[3].angle == anima::variable_timing(r, 60, r, 20, none, quatd::Identity()).joints[3].angle);
}

TEST_CASE("make_transition_into: errors as make_transition's; B at another frame time is refused") {
    const auto& r = run<double>();
    anima::transition_frames<double> out;
    anima::transition_workspace<double> ws;
    const auto into = [&](const clipd& a, std::size_t at, const clipd& b, std::size_t to,
                          const anima::transition_params& p = {}) {
        anima::make_transition_into(a, at, b, to, p, out, ws);
    };
    CHECK(thrown_message([&] { into(r, 60, walk31(), 10); }).find("'hip'") != std::string::npos);
    CHECK_THROWS_AS(into(r, r.frames(), r, 10), anima::invalid_argument);
    CHECK_THROWS_AS(into(r, 60, r, r.frames()), anima::invalid_argument);
    anima::transition_params p;
    p.roles.assign(5, joint_role::leg);
    CHECK_THROWS_AS(into(r, 60, r, 20, p), anima::invalid_argument);
    p = {};
    p.timing.min_speed = 0;
    CHECK_THROWS_AS(into(r, 60, r, 20, p), anima::invalid_argument);
    const clipd b60 = anima::resample(r, 1.0 / 60);
    const std::string m = thrown_message([&] { into(r, 60, b60, 10); });
    CHECK(m.find("make_transition_into") != std::string::npos);
    CHECK(m.find("resample") != std::string::npos);
    // Resampled beforehand, B gives make_transition's transition, which resamples it itself.
    const clipd b120 = anima::resample(b60, r.frame_time());
    into(r, 60, b120, anima::detail::resampled_frame(std::size_t{10}, b60.frame_time(), b120));
    const auto t = anima::make_transition(r, 60, b60, 10);
    check_same_transition(t, out);
}

namespace {

template <class T>
void check_blend_many() {
    using quat = Eigen::Quaternion<T>;
    std::mt19937 rng(11);
    std::normal_distribution<double> g;
    const auto random = [&] { return static_cast<T>(g(rng)); };
    const auto random_q = [&] { return quat(random(), random(), random(), random()).normalized(); };
    const auto near = [&](const quat& q, double angle) {
        const Eigen::Matrix<T, 3, 1> axis(random(), random(), random());
        return quat(q * quat(Eigen::AngleAxis<T>(static_cast<T>(angle), axis.normalized())));
    };
    // Parameters of an eased transition, the ends, and some outside [0, 1].
    std::vector<T> t;
    for (int k = 1; k < 40; ++k) t.push_back(anima::interpolation_parameter(T(k), T(40), anima::easing::ease_in_out));
    for (T u : {T(0), T(1), T(0.5), T(-0.25), T(1.5), T(0.3)}) t.push_back(u);
    // Every other pair writes at a stride of 3, as into one joint's frames
    // of a clip; the quaternions between the results must stay as they were.
    const quat untouched(T(7), T(7), T(7), T(7));
    std::vector<quat> got(3 * t.size());
    int differ = 0, overwritten = 0;
    for (int i = 0; i < 200; ++i) {
        const quat a = random_q();
        // Far apart, nearly identical, identical, the other hemisphere, off unit length.
        const double angles[] = {2.5, 1.0, 0.2, 1e-3, 1e-9, 0.0};
        quat b = i % 7 == 6 ? random_q() : near(a, angles[i % 6]);
        if (i % 5 == 4) b.coeffs() = -b.coeffs();
        if (i % 11 == 10) b.coeffs() *= T(1.01);
        const std::size_t stride = i % 2 ? 3 : 1;
        const auto check_writes = [&](const auto& expected) {
            for (std::size_t k = 0; k < t.size(); ++k) {
                differ += !same_bits(got[k * stride].coeffs(), expected(t[k]).coeffs());
                for (std::size_t m = 1; m < stride; ++m)
                    overwritten += !same_bits(got[k * stride + m].coeffs(), untouched.coeffs());
            }
        };
        std::fill(got.begin(), got.end(), untouched);
        anima::detail::slerp_many(a, b, t.data(), t.size(), got.data(), stride);
        check_writes([&](T u) { return anima::slerp(a, b, u); });
        const quat s1 = near(a, 0.3), s2 = near(b, 0.2);
        std::fill(got.begin(), got.end(), untouched);
        anima::detail::squad_many(a, b, s1, s2, t.data(), t.size(), got.data(), stride);
        check_writes([&](T u) { return anima::squad(a, b, s1, s2, u); });
        // The fingers' normalised blend, b on a's side, against Eigen's normalisation.
        const quat b_side = a.coeffs().dot(b.coeffs()) < T(0) ? quat(-b.coeffs()) : b;
        std::fill(got.begin(), got.end(), untouched);
        anima::detail::lerp_many(a, b_side, t.data(), t.size(), got.data(), stride);
        check_writes([&](T u) {
            const Eigen::Matrix<T, 4, 1> q = a.coeffs() * (T(1) - u) + b_side.coeffs() * u;
            return quat(q * (T(1) / q.norm()));
        });
    }
    CHECK(overwritten == 0);
    CHECK(differ == 0);
}

}  // namespace

TEST_CASE("slerp, squad and lerp of one pair at many parameters are slerp's, squad's and the normalised blend, bit for bit") {
    check_blend_many<double>();
    check_blend_many<float>();
}

TEST_CASE("joint speeds: the mean |angular velocity| of the steps, for small and large steps") {
    // A joint turning by a growing angle per frame (up to 2.9 rad: every
    // series length, and steps beyond the series), and its mean speed and
    // acceleration over windows, against angular_velocity step by step.
    const auto check = [](auto zero, double tolerance) {
        using T = decltype(zero);
        using quat = Eigen::Quaternion<T>;
        anima::skeleton<T> sk;
        sk.add_joint("root", -1, Eigen::Matrix<T, 3, 1>::Zero());
        sk.add_joint("knee", 0, Eigen::Matrix<T, 3, 1>::UnitY());
        const std::size_t n = 60;
        anima::clip<T> c(sk, n, T(1) / T(120));
        quat q = quat::Identity();
        for (std::size_t f = 0; f < n; ++f) {
            const double step = 1e-4 * std::pow(1.2, static_cast<double>(f));  // 1e-4 .. 4.4 rad
            const Eigen::Matrix<T, 3, 1> axis = Eigen::Matrix<T, 3, 1>(1, T(f % 3), 2).normalized();
            q = quat(Eigen::AngleAxis<T>(static_cast<T>(std::min(step, 2.9)), axis)) * q;
            c.set_rotation(f, 1, q);
            const T heading = T(0.01) * static_cast<T>(f);
            c.set_rotation(f, 0, quat(Eigen::AngleAxis<T>(heading, Eigen::Matrix<T, 3, 1>::UnitY())));
        }
        anima::detail::rates_scratch<T> scratch;
        const std::vector<std::size_t> knee_only{1};
        double worst = 0;
        for (std::size_t first = 0; first + 1 < n; first += 7) {
            const std::size_t last = std::min(first + 12, n - 1);
            anima::detail::joint_rates(c, static_cast<std::ptrdiff_t>(first), static_cast<std::ptrdiff_t>(last),
                                       static_cast<const quat*>(nullptr), nullptr, scratch);
            double speed = 0, accel = 0;
            Eigen::Matrix<T, 3, 1> previous = Eigen::Matrix<T, 3, 1>::Zero();
            for (std::size_t k = first; k < last; ++k) {
                const auto w = anima::angular_velocity(c.rotation(k, 1), c.rotation(k + 1, 1), c.frame_time());
                speed += static_cast<double>(w.norm());
                if (k > first) accel += static_cast<double>((w - previous).norm() / c.frame_time());
                previous = w;
            }
            const auto steps = static_cast<double>(last - first);
            speed /= steps;
            if (steps > 1) accel /= steps - 1;
            const auto error = [](T got, double expected) {
                return std::abs(static_cast<double>(got) - expected) / expected;
            };
            worst = std::max(worst, error(scratch.mean_speed[1], speed));
            if (steps > 1) worst = std::max(worst, error(scratch.mean_acceleration[1], accel));
            // The knee alone: its rates first.
            anima::detail::joint_rates(c, static_cast<std::ptrdiff_t>(first), static_cast<std::ptrdiff_t>(last),
                                       static_cast<const quat*>(nullptr), &knee_only, scratch);
            REQUIRE(scratch.mean_speed.size() == 1);
            worst = std::max(worst, error(scratch.mean_speed[0], speed));
            if (steps > 1) worst = std::max(worst, error(scratch.mean_acceleration[0], accel));
        }
        CHECK(worst < tolerance);
    };
    check(0.0, 1e-13);
    check(0.0f, 1e-5);
}

namespace {

// Two legs under a hips joint, Y up, metres: the left foot (one point, no
// End Site) on the ground while its hip swings it from 20 degrees forward
// to 20 back over the clip, the right leg folded up off the ground (but at
// the ends, so that the ground is known under it too), and the
// root sliding backward instead of passing over the foot: the foot slides.
clipd swinging_leg() {
    using anima::channel;
    anima::skeleton<double> sk;
    sk.add_joint("Hips", -1, vec3::Zero(),
                 {channel::x_position, channel::y_position, channel::z_position, channel::z_rotation,
                  channel::x_rotation, channel::y_rotation});
    for (const char* side : {"Left", "Right"}) {
        const double x = side[0] == 'L' ? 0.1 : -0.1;
        const auto hip = sk.add_joint(std::string(side) + "UpLeg", 0, vec3(x, 0, 0), {channel::x_rotation});
        const auto knee = sk.add_joint(std::string(side) + "Leg", static_cast<int>(hip), vec3(0, -0.45, 0),
                                       {channel::x_rotation});
        sk.add_joint(std::string(side) + "Foot", static_cast<int>(knee), vec3(0, -0.45, 0), {channel::x_rotation});
    }
    sk.add_joint("Head", 0, vec3(0, 0.8, 0));  // the figure is 1.7 m tall
    clipd c(sk, 120, 1.0 / 120);
    for (std::size_t f = 0; f < c.frames(); ++f) {
        const double s = static_cast<double>(f) / static_cast<double>(c.frames() - 1);
        const double swing = (20 - 40 * s) * pi / 180;
        c.set_root_position(f, vec3(0, 0.9 * std::cos(swing), -0.7 * s));  // the foot on the ground, the root sliding back
        c.set_rotation(f, index(c, "LeftUpLeg"), about(-(20 - 40 * s), vec3::UnitX()));
        // Folded but for the first and last 10 frames, where the foot is on the ground too.
        const bool folded = f >= 10 && f + 10 < c.frames();
        c.set_rotation(f, index(c, "RightLeg"), about(folded ? 100 : 0, vec3::UnitX()));
    }
    return c;
}

}  // namespace

TEST_CASE("root_from_feet: a foot on the ground stays put, heights and the motion after the window as they were") {
    const clipd c = swinging_leg();
    const std::size_t left = index(c, "LeftFoot");
    anima::contact_params<double> cp;
    cp.use_speed = false;
    cp.feet = {"LeftFoot", "RightFoot"};
    const auto contacts = anima::find_contacts(c, cp);
    REQUIRE(contacts.feet.size() == 2);
    for (std::size_t f = 20; f <= 100; ++f) {
        REQUIRE(contacts.feet[0].in_contact[f]);
        REQUIRE_FALSE(contacts.feet[1].in_contact[f]);
    }
    const auto foot_at = [&](const clipd& clip, std::size_t f) { return anima::forward_kinematics(clip, f).positions[left]; };
    CHECK((foot_at(c, 60) - foot_at(c, 40)).norm() > 0.05);  // the recording slides the foot
    clipd out = c;
    anima::transition_feet_params<double> params;
    params.planting.contacts = cp;
    params.root_speed_band = 0;  // the feet alone: the band would keep the recorded root's speed
    const anima::frame_interval window{30, 90};
    anima::detail::root_from_feet(out, window, contacts, params, std::numeric_limits<double>::infinity());
    // Past the ramps (0.05 s = 6 frames, at most 1/8 of the window) the
    // foot's horizontal position does not move; heights are untouched.
    const vec3 planted = foot_at(out, 36);
    for (std::size_t f = 36; f <= 84; ++f) {
        CAPTURE(f);
        const vec3 d = foot_at(out, f) - planted;
        CHECK(std::hypot(d.x(), d.z()) < 1e-9);
    }
    for (std::size_t f = 0; f < c.frames(); ++f) CHECK(out.root_position(f).y() == c.root_position(f).y());
    // Before the window nothing moves; after it, the recording's steps.
    for (std::size_t f = 0; f <= window.first; ++f) CHECK(out.root_position(f) == c.root_position(f));
    for (std::size_t f = window.last + 1; f < c.frames(); ++f)
        CHECK((out.root_position(f) - out.root_position(f - 1) - (c.root_position(f) - c.root_position(f - 1))).norm() <
              1e-12);
    // Within the ramps the root's velocity turns from the recording's to the
    // foot's smoothly: no step changes by more than the ramp allows.
    double largest_change = 0;
    for (std::size_t f = window.first + 1; f <= window.last + 1; ++f)
        largest_change = std::max(largest_change, (out.root_position(f + 1) - 2 * out.root_position(f) +
                                                   out.root_position(f - 1)).norm());
    const double recorded_step = (c.root_position(61) - c.root_position(60)).norm();
    CHECK(largest_change < recorded_step);  // a jolt would change the step by about a whole step
    // With a limit, no step changes by more than it on either horizontal axis.
    const double limit = recorded_step / 20;
    clipd limited = c;
    anima::detail::root_from_feet(limited, window, contacts, params, limit);
    double worst = 0;
    for (std::size_t f = window.first; f <= window.last + 1; ++f) {
        const vec3 d = limited.root_position(f + 1) - 2 * limited.root_position(f) + limited.root_position(f - 1);
        worst = std::max({worst, std::abs(d.x()), std::abs(d.z())});
        CHECK(d.y() == doctest::Approx(c.root_position(f + 1).y() - 2 * c.root_position(f).y() + c.root_position(f - 1).y()));
    }
    CHECK(worst <= limit * (1 + 1e-9));
    CHECK((foot_at(limited, 60) - foot_at(limited, 40)).norm() > 1e-3);  // held back: the foot slides some
    // One contact height for entering and leaving (no band to fade over): the same.
    auto sharp = params;
    sharp.planting.contacts.height_off = sharp.planting.contacts.height_on;
    clipd stepped = c;
    anima::detail::root_from_feet(stepped, window, anima::find_contacts(c, sharp.planting.contacts), sharp,
                                  std::numeric_limits<double>::infinity());
    for (std::size_t f = 0; f < c.frames(); ++f) REQUIRE(stepped.root_position(f).allFinite());
    const vec3 held = foot_at(stepped, 36);
    for (std::size_t f = 36; f <= 84; ++f) CHECK((foot_at(stepped, f) - held).norm() < 1e-9);
    // Off: the path as it was.
    params.root_from_feet = false;
    const anima::joined_clip<double> joined{c, window.first, window.last};
    const auto legs_only = anima::plant_transition_feet(joined, params);
    for (std::size_t f = 0; f < c.frames(); ++f) CHECK(legs_only.motion.root_position(f) == c.root_position(f));
    params.root_ramp_fraction = 0.8;
    CHECK(thrown_message([&] { (void)anima::plant_transition_feet(joined, params); }).find("root_ramp_fraction") !=
          std::string::npos);
}

TEST_CASE_TEMPLATE("plant_transition_feet: with a speed band a run into a run keeps running", T, float, double) {
    // The blended legs step slower than the runner moves: following the feet
    // alone, the root fell from 224 to 54 units/s for 40 ms in this window.
    const auto& a = run<T>();
    const auto b = anima::read_bvh<T>(bundled("run_cmu_02_03.bvh"));
    const auto joined = anima::transition_clips(a, 50, b, 10);
    const auto ground_speed = [](const anima::clip<T>& c, std::size_t f) {
        const auto d = c.root_position(f + 1) - c.root_position(f);
        return static_cast<double>(std::hypot(d.x(), d.z())) / static_cast<double>(c.frame_time());
    };
    const double slower_end = std::min(ground_speed(joined.motion, joined.start_frame - 1),
                                       ground_speed(joined.motion, joined.end_frame));
    const auto slowest = [&](const anima::transition_feet_params<T>& p) {
        const auto planted = anima::plant_transition_feet(joined, p);
        double least = std::numeric_limits<double>::infinity();
        for (std::size_t f = joined.start_frame; f < joined.end_frame; ++f)
            least = std::min(least, ground_speed(planted.motion, f));
        return least;
    };
    anima::transition_feet_params<T> p;
    CHECK(p.root_speed_band == T(0.5));  // the default
    p.root_speed_band = T(0);
    CAPTURE(slower_end);
    CHECK(slowest(p) < 0.3 * slower_end);  // the stall, without a band
    const auto roles = anima::joint_roles(a.skeleton());
    const auto stall = [&] {
        return anima::measure_transition(anima::plant_transition_feet(joined, p), roles, anima::signed_axis{}, 1.0)
            .root_speed_ratio;
    };
    CHECK(stall() < T(0.3));  // measure_transition sees it too
    p.root_speed_band = T(0.5);
    CHECK(slowest(p) >= 0.5 * slower_end * (1 - 1e-4));
    p.root_speed_band = T(0.75);
    CHECK(slowest(p) >= 0.75 * slower_end * (1 - 1e-4));
    CHECK(stall() >= T(0.7));
    p.root_speed_band = T(1.5);
    CHECK(thrown_message([&] { (void)anima::plant_transition_feet(joined, p); }).find("root_speed_band") !=
          std::string::npos);
}

TEST_CASE("root_from_feet: a swing skimming the floor beside a planted foot drags it slower than the legs' stepping "
          "speed") {
    // Feet placed directly (position channels under the hips), Y up, metres:
    // the left foot should stay at z = 0.3 while the hips walk forward at
    // 0.6 m/s, but the recording moves the hips at 0.3 m/s, so it slides
    // back; the right foot skims the floor at the same height, 2.4 m/s
    // forward. Height alone calls both feet on the ground.
    using anima::channel;
    const std::vector<channel> moved{channel::x_position, channel::y_position, channel::z_position};
    anima::skeleton<double> sk;
    sk.add_joint("Hips", -1, vec3::Zero(),
                 {channel::x_position, channel::y_position, channel::z_position, channel::z_rotation,
                  channel::x_rotation, channel::y_rotation});
    sk.add_joint("LeftFoot", 0, vec3(0.1, -0.9, 0), moved);
    sk.add_joint("RightFoot", 0, vec3(-0.1, -0.9, 0), moved);
    sk.add_joint("Head", 0, vec3(0, 0.8, 0));
    clipd c(sk, 120, 1.0 / 120);
    for (std::size_t f = 0; f < c.frames(); ++f) {
        const double t = static_cast<double>(f) * c.frame_time();
        const double walked = 0.6 * t, recorded = 0.3 * t;
        c.set_root_position(f, vec3(0, 0.9, recorded));
        c.set_translation(f, index(c, "LeftFoot"), vec3(0.1, -0.9, 0.3 - walked));
        c.set_translation(f, index(c, "RightFoot"), vec3(-0.1, -0.9, 2.4 * t - recorded));
    }
    anima::transition_feet_params<double> params;
    params.planting.contacts.feet = {"LeftFoot", "RightFoot"};
    params.root_speed_band = 0;  // the feet's weights alone, as worked out below
    const auto contacts = anima::find_contacts(c, params.planting.contacts);
    REQUIRE(contacts.feet.size() == 2);
    for (std::size_t f = 10; f < 110; ++f) REQUIRE((contacts.feet[0].in_contact[f] && contacts.feet[1].in_contact[f]));
    const std::size_t left = index(c, "LeftFoot");
    const anima::frame_interval window{30, 90};
    // The left foot's fastest horizontal speed past the ramps, body heights per second.
    const auto fastest_slide = [&](const anima::transition_feet_params<double>& p) {
        clipd out = c;
        anima::detail::root_from_feet(out, window, contacts, p, std::numeric_limits<double>::infinity());
        double fastest = 0;
        for (std::size_t f = 37; f <= 84; ++f) {
            vec3 d = anima::forward_kinematics(out, f).positions[left] - anima::forward_kinematics(out, f - 1).positions[left];
            d.y() = 0;
            fastest = std::max(fastest, d.norm() / (c.frame_time() * contacts.body_height));
        }
        return fastest;
    };
    const double slide_speed = params.planting.slide_fraction * contacts.fast_foot_speed;
    const double recorded = 0.3 / contacts.body_height, shared = 0.5 * (2.4 + 0.3) / contacts.body_height;
    INFO("slide speed " << slide_speed << ", recorded " << recorded << ", shared equally " << shared);
    REQUIRE(shared > slide_speed);  // sharing equally would leave the legs nothing to hold
    // The right foot is 2.1 m/s faster: it counts slide_speed / (2 d) as
    // much as the left, which then moves at w / (1 + w) of the 2.7 m/s
    // between them: slower than the legs' stepping test, so they hold it.
    const double w = slide_speed / (2 * 2.1 / contacts.body_height);
    const double capped = fastest_slide(params);
    CHECK(capped == doctest::Approx(w / (1 + w) * 2.7 / contacts.body_height).epsilon(1e-6));
    CHECK(capped < slide_speed);
    auto equal = params;  // every foot as much as the others: the two feet's mean
    equal.planting.slide_fraction = 1e9;
    CHECK(fastest_slide(equal) == doctest::Approx(shared).epsilon(1e-6));
}

TEST_CASE("plant_transition_feet: the root from the feet halves the skate the legs alone leave, within the clips' own "
          "range of root acceleration") {
    struct pair_case {
        const clipd* a;
        std::size_t at;
        const clipd* b;
        std::size_t to;
        double ratio;  // the window's skate over the clips' own is at most this
    };
    // The walk's feet are all but still with the legs alone already; the
    // run's legs alone leave several times the clips' own skate.
    const pair_case cases[] = {{&walk31(), 100, &walk31(), 250, 0.5}, {&run<double>(), 60, &run<double>(), 100, 1.5}};
    // The largest root acceleration of a clip, m/s^2: the top of its own range.
    const auto largest = [](const clipd& c, double metres) {
        const auto root = anima::global_positions(c).leftCols(3).eval();
        const auto acc = anima::time_derivative(anima::time_derivative(root, c.frame_time()), c.frame_time());
        return acc.rowwise().norm().maxCoeff() * metres;
    };
    for (const auto& k : cases) {
        const auto roles = anima::joint_roles(k.a->skeleton());
        const auto cls = anima::classify_motion(*k.a, roles);
        const auto joined = anima::transition_clips(*k.a, k.at, *k.b, k.to);
        anima::transition_feet_params<double> legs_only;
        legs_only.root_from_feet = false;
        const auto legs = anima::measure_transition(anima::plant_transition_feet(joined, legs_only), roles, cls.up,
                                                    cls.metres_per_unit);
        const auto both = anima::measure_transition(anima::plant_transition_feet(joined), roles, cls.up, cls.metres_per_unit);
        INFO("frames " << k.at << " -> " << k.to << ": skate ratio " << both.foot_skate_ratio << ", legs alone "
                       << legs.foot_skate_ratio << "; peak root acceleration " << both.peak_root_acceleration);
        if (legs.foot_skate_ratio > 1.5) CHECK(both.foot_skate_window < 0.5 * legs.foot_skate_window);
        CHECK(both.foot_skate_ratio <= k.ratio);
        CHECK(both.peak_root_acceleration <=
              std::max(largest(*k.a, cls.metres_per_unit), largest(*k.b, cls.metres_per_unit)));
    }
}
