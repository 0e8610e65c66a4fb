// A flight problem as a file: the skeleton, the body model's parameters, the
// keys and the flight settings of `anima flight KEYS.json`, read into one
// struct a caller can hand to flight_problem. The format (docs/flight.md):
//
//   {"skeleton": "walk.bvh",                  BVH, relative to the key file
//    "body_mass": 70, "sex": "male",          optional
//    "metres_per_unit": 0.056444,             optional (default: the layout's)
//    "gravity": [0, -9.81, 0],                optional, m/s^2
//    "ballistic": {"start": [..], "velocity": [..]},   optional
//    "root_tolerance": 0.05, "joint_tolerance": 0.1,   optional (model 1)
//    "keys": [{"time": 0, "root_position": [x, y, z],
//              "rotations": {"Hips": {"euler_degrees": [z, x, y], "order": "ZXY"},
//                            "LeftArm": {"quaternion": [w, x, y, z]}}}, ...]}
//
// Joints a key does not name keep their rest rotation. Every error is an
// anima::parse_error naming the file and the line of the offending value.
#pragma once

#include <anima/bvh/reader.hpp>
#include <anima/core/constants.hpp>
#include <anima/core/error.hpp>
#include <anima/core/file_io.hpp>
#include <anima/core/json_reader.hpp>
#include <anima/flight/body_model.hpp>
#include <anima/flight/flight_objective.hpp>
#include <anima/flight/key_trajectory.hpp>
#include <anima/flight/somersault.hpp>
#include <anima/motion/skeleton.hpp>
#include <anima/rotation/euler.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace anima {

/// Everything a flight problem needs, as read from a key set.
template <class T>
struct flight_key_set {
    std::string name;                  ///< the key file's name, or the example's
    anima::skeleton<T> skeleton;       ///< the figure the keys pose
    rigid_body_model<T> model;         ///< its bodies (de Leva), in SI units
    flight_keys<T> keys;               ///< times, root positions, rotations per joint
    flight_settings<T> settings;       ///< gravity, ballistic root, tolerances
    T metres_per_unit = T(1);          ///< of the skeleton's offsets
};

/// What a key set may leave out.
template <class T>
struct flight_key_set_defaults {
    T body_mass = T(70);  ///< kg, when the file gives no "body_mass"
};

namespace detail {

/// Reads members of one JSON key set, reporting file and line.
template <class T>
class key_set_reader {
public:
    using vector3 = Eigen::Matrix<T, 3, 1>;

    explicit key_set_reader(std::string file) : file_(std::move(file)) {}

    [[noreturn]] void fail(const json_value& at, const std::string& message) const {
        throw parse_error(file_, at.line(), message);
    }

    const json_value& need(const json_value& object, const char* key, json_value::kind kind) const {
        const json_value* v = object.find(key);
        if (!v) fail(object, std::string("missing \"") + key + "\"");
        expect(*v, key, kind);
        return *v;
    }

    void expect(const json_value& v, const std::string& what, json_value::kind kind) const {
        if (v.type() != kind)
            fail(v, "\"" + what + "\" must be " + json_value::kind_name(kind) + ", got " + json_value::kind_name(v.type()));
    }

    T number(const json_value& object, const char* key, T fallback) const {
        const json_value* v = object.find(key);
        if (!v) return fallback;
        expect(*v, key, json_value::kind::number);
        return T(v->number());
    }

    std::string text(const json_value& object, const char* key, std::string fallback) const {
        const json_value* v = object.find(key);
        if (!v) return fallback;
        expect(*v, key, json_value::kind::string);
        return v->string();
    }

    vector3 vec3(const json_value& v, const std::string& what) const {
        if (!v.is_array() || v.array().size() != 3 || !v.array()[0].is_number() || !v.array()[1].is_number() ||
            !v.array()[2].is_number())
            fail(v, "\"" + what + "\" must be an array of 3 numbers");
        return vector3(T(v.array()[0].number()), T(v.array()[1].number()), T(v.array()[2].number()));
    }

    vector3 vec3(const json_value& object, const char* key, const vector3& fallback) const {
        const json_value* v = object.find(key);
        return v ? vec3(*v, key) : fallback;
    }

    Eigen::Quaternion<T> rotation(const json_value& r, const std::string& joint) const {
        if (!r.is_object()) fail(r, "\"" + joint + "\" must be an object with \"quaternion\" or \"euler_degrees\"");
        if (const json_value* q = r.find("quaternion")) {
            const bool four = q->is_array() && q->array().size() == 4;
            for (std::size_t k = 0; four && k < 4; ++k)
                if (!q->array()[k].is_number()) fail(*q, "\"quaternion\" of \"" + joint + "\" must be [w, x, y, z]");
            if (!four) fail(*q, "\"quaternion\" of \"" + joint + "\" must be [w, x, y, z]");
            const auto& a = q->array();
            return Eigen::Quaternion<T>(T(a[0].number()), T(a[1].number()), T(a[2].number()), T(a[3].number()));
        }
        if (const json_value* e = r.find("euler_degrees")) {
            const vector3 a = vec3(*e, "euler_degrees");
            euler_order order{};
            try {
                order = parse_euler_order(text(r, "order", "ZXY"));
            } catch (const invalid_argument& bad) {
                fail(r, "\"" + joint + "\": " + bad.what());
            }
            return from_euler<Eigen::Quaternion<T>>(radians(a[0]), radians(a[1]), radians(a[2]), order);
        }
        fail(r, "\"" + joint + "\": give \"quaternion\" or \"euler_degrees\"");
    }

private:
    std::string file_;
};

}  // namespace detail

/// The key set in `text`. `file` names it in errors and is where a relative
/// "skeleton" path starts from. Throws anima::parse_error (file:line) for
/// bad JSON or a bad member, anima::io_error when the skeleton's BVH cannot
/// be read; the keys are checked by flight_problem when it is built.
template <class T = double>
flight_key_set<T> parse_flight_key_set(std::string_view text, const std::string& file,
                                       const flight_key_set_defaults<T>& defaults = {}) {
    using kind = json_value::kind;
    const json_value doc = parse_json(text, file);
    const detail::key_set_reader<T> in(file);
    if (!doc.is_object()) in.fail(doc, "a key set is a JSON object");

    flight_key_set<T> out;
    out.name = std::filesystem::path(file).filename().string();
    const json_value& skeleton_path = in.need(doc, "skeleton", kind::string);
    std::filesystem::path bvh(skeleton_path.string());
    if (bvh.is_relative()) bvh = std::filesystem::path(file).parent_path() / bvh;
    out.skeleton = read_bvh<T>(bvh.string()).skeleton();

    body_model_params<T> body;
    body.body_mass = in.number(doc, "body_mass", defaults.body_mass);
    const std::string sex_name = in.text(doc, "sex", "male");
    if (sex_name != "male" && sex_name != "female")
        in.fail(*doc.find("sex"), "\"sex\" must be \"male\" or \"female\", got \"" + sex_name + "\"");
    body.sex = sex_name == "male" ? sex::male : sex::female;
    body.metres_per_unit = in.number(doc, "metres_per_unit", T(0));
    try {
        out.model = make_body_model(out.skeleton, body);
    } catch (const invalid_argument& bad) {
        in.fail(doc, bad.what());
    }
    out.metres_per_unit = body.metres_per_unit > T(0) ? body.metres_per_unit : default_metres_per_unit(out.skeleton);

    out.settings.gravity = in.vec3(doc, "gravity", out.settings.gravity);
    if (const json_value* b = doc.find("ballistic")) {
        in.expect(*b, "ballistic", kind::object);
        ballistic_path<T> path;
        path.start = in.vec3(*b, "start", path.start);
        path.velocity = in.vec3(*b, "velocity", path.velocity);
        out.settings.ballistic = path;
    }
    out.settings.root_tolerance = in.number(doc, "root_tolerance", out.settings.root_tolerance);
    out.settings.joint_tolerance = in.number(doc, "joint_tolerance", out.settings.joint_tolerance);

    const json_value& keys = in.need(doc, "keys", kind::array);
    for (const json_value& key : keys.array()) {
        in.expect(key, "keys[" + std::to_string(out.keys.size()) + "]", kind::object);
        out.keys.times.push_back(T(in.need(key, "time", kind::number).number()));
        out.keys.root_positions.push_back(in.vec3(key, "root_position", Eigen::Matrix<T, 3, 1>::Zero()));
        std::vector<Eigen::Quaternion<T>> rotations(out.skeleton.size(), Eigen::Quaternion<T>::Identity());
        if (const json_value* r = key.find("rotations")) {
            in.expect(*r, "rotations", kind::object);
            for (const auto& [joint, value] : r->object()) {
                const auto j = out.skeleton.find(joint);
                if (!j) in.fail(value, "\"" + joint + "\": the skeleton has no joint of that name");
                rotations[*j] = in.rotation(value, joint);
            }
        }
        out.keys.rotations.push_back(std::move(rotations));
    }
    return out;
}

/// The key set in the file at `path` (see parse_flight_key_set).
template <class T = double>
flight_key_set<T> read_flight_key_set(const std::string& path, const flight_key_set_defaults<T>& defaults = {}) {
    return parse_flight_key_set<T>(read_file(path), path, defaults);
}

/// The paper's somersault (somersault_keys, somersault_settings) on a CMU
/// 31-joint skeleton, as a key set.
template <class T>
flight_key_set<T> somersault_key_set(const anima::skeleton<T>& sk, const flight_key_set_defaults<T>& defaults = {},
                                     const somersault_params<T>& params = {}) {
    flight_key_set<T> out;
    out.name = "somersault";
    out.skeleton = sk;
    body_model_params<T> body;
    body.body_mass = defaults.body_mass;
    out.model = make_body_model(sk, body);
    out.metres_per_unit = default_metres_per_unit(sk);
    out.keys = somersault_keys(sk, params);
    out.settings = somersault_settings<T>(params);
    return out;
}

}  // namespace anima
