// A rigid-body model of a human built from a skeleton: one rigid body per
// joint (the bone(s) that joint's rotation moves), with mass, centre of mass
// and inertia tensor from de Leva's anthropometric table, scaled to the
// skeleton's bone lengths and a body mass. Units: metres, kilograms, seconds.
//
// Each de Leva segment is assigned to a joint (`proximal`); its axis runs from
// that joint to `distal` (a descendant joint) or, when distal is empty, to the
// joint's End Site, or, when there is none (or it has zero length), along the
// bone that ends at the joint, with de Leva's mean length scaled by the ratio
// of the skeleton's thigh to de Leva's thigh. Joints that carry no segment
// (clavicles, fingers, toes, the neck) are massless.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/flight/anthropometry.hpp>
#include <anima/motion/forward_kinematics.hpp>
#include <anima/motion/skeleton.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace anima {

/// Bodies of a floating-base tree, parents first (parents[j] < j, -1 for the
/// root). Body j's frame sits at joint j and turns with joint j's rotation.
template <class T>
struct rigid_body_model {
    using vector3 = Eigen::Matrix<T, 3, 1>;
    using matrix3 = Eigen::Matrix<T, 3, 3>;

    std::vector<std::string> names;
    std::vector<int> parents;
    std::vector<vector3> offsets;   ///< joint position in the parent's frame, metres
    std::vector<T> masses;          ///< kg
    std::vector<vector3> coms;      ///< centre of mass in the body's frame, metres
    std::vector<matrix3> inertias;  ///< inertia about the centre of mass, body frame, kg m^2

    std::size_t size() const noexcept { return parents.size(); }

    T total_mass() const {
        T m(0);
        for (const T& x : masses) m += x;
        return m;
    }

    /// Appends a body; checks the parent, finiteness, a non-negative mass and a
    /// symmetric inertia. Returns its index.
    std::size_t add_body(std::string name, int parent, const vector3& offset, T mass, const vector3& com,
                         const matrix3& inertia) {
        const std::string where = "anima::rigid_body_model::add_body('" + name + "')";
        using std::isfinite;
        if (parent < -1 || parent >= static_cast<int>(size()))
            throw invalid_argument(where + ": parent " + std::to_string(parent) + " is not an existing body");
        if (!offset.allFinite() || !com.allFinite() || !inertia.allFinite())
            throw invalid_argument(where + ": offset, centre of mass or inertia is not finite");
        if (!(mass >= T(0)) || !isfinite(mass))
            throw invalid_argument(where + ": mass must be finite and >= 0, got " +
                                   detail::argument_text(mass));
        if (!((inertia - inertia.transpose()).cwiseAbs().maxCoeff() <= T(1e-6) * (T(1) + inertia.cwiseAbs().maxCoeff())))
            throw invalid_argument(where + ": inertia is not symmetric");
        names.push_back(std::move(name));
        parents.push_back(parent);
        offsets.push_back(offset);
        masses.push_back(mass);
        coms.push_back(com);
        inertias.push_back(inertia);
        return size() - 1;
    }

    /// The same model in another scalar type (e.g. an automatic-derivative one).
    template <class S>
    rigid_body_model<S> cast() const {
        rigid_body_model<S> out;
        out.names = names;
        out.parents = parents;
        for (std::size_t j = 0; j < size(); ++j) {
            out.offsets.push_back(offsets[j].template cast<S>());
            out.masses.push_back(S(masses[j]));
            out.coms.push_back(coms[j].template cast<S>());
            out.inertias.push_back(inertias[j].template cast<S>());
        }
        return out;
    }
};

/// A de Leva segment carried by a joint (see the header comment).
struct segment_assignment {
    segment_kind kind;
    std::string proximal;
    std::string distal;  ///< empty: End Site, or the continued bone with the scaled mean length
};

namespace detail {

inline bool has_all(std::initializer_list<const char*> wanted, const std::vector<std::string>& have) {
    for (const char* w : wanted) {
        bool found = false;
        for (const auto& h : have) found = found || h == w;
        if (!found) return false;
    }
    return true;
}

}  // namespace detail

/// The segment map for the two CMU layouts (the 31-joint ASF conversion and
/// the Daz/cgspeed one: see docs/flight.md). Throws anima::invalid_argument
/// naming the missing joints for any other skeleton: pass a map of your own.
template <class T>
std::vector<segment_assignment> default_segment_map(const skeleton<T>& sk) {
    std::vector<std::string> have;
    for (const auto& j : sk.joints()) have.push_back(j.name);
    using k = segment_kind;
    if (detail::has_all({"LowerBack", "Spine", "Spine1", "Neck1", "Head", "LeftArm", "LeftForeArm", "LeftHand",
                               "RightArm", "RightForeArm", "RightHand", "LeftUpLeg", "LeftLeg", "LeftFoot",
                               "LeftToeBase", "RightUpLeg", "RightLeg", "RightFoot", "RightToeBase"},
                        have))
        return {{k::lower_trunk, "LowerBack", "Spine"}, {k::middle_trunk, "Spine", "Spine1"},
                {k::upper_trunk, "Spine1", "Neck1"},    {k::head, "Head", ""},
                {k::upper_arm, "LeftArm", "LeftForeArm"}, {k::forearm, "LeftForeArm", "LeftHand"},
                {k::hand, "LeftHand", ""},              {k::upper_arm, "RightArm", "RightForeArm"},
                {k::forearm, "RightForeArm", "RightHand"}, {k::hand, "RightHand", ""},
                {k::thigh, "LeftUpLeg", "LeftLeg"},     {k::shank, "LeftLeg", "LeftFoot"},
                {k::foot, "LeftFoot", "LeftToeBase"},   {k::thigh, "RightUpLeg", "RightLeg"},
                {k::shank, "RightLeg", "RightFoot"},    {k::foot, "RightFoot", "RightToeBase"}};
    if (detail::has_all({"hip", "abdomen", "chest", "neck", "head", "lShldr", "lForeArm", "lHand", "rShldr",
                               "rForeArm", "rHand", "lThigh", "lShin", "lFoot", "rThigh", "rShin", "rFoot"},
                        have))
        return {{k::lower_trunk, "hip", "abdomen"},   {k::middle_trunk, "abdomen", "chest"},
                {k::upper_trunk, "chest", "neck"},    {k::head, "head", ""},
                {k::upper_arm, "lShldr", "lForeArm"}, {k::forearm, "lForeArm", "lHand"},
                {k::hand, "lHand", ""},               {k::upper_arm, "rShldr", "rForeArm"},
                {k::forearm, "rForeArm", "rHand"},    {k::hand, "rHand", ""},
                {k::thigh, "lThigh", "lShin"},        {k::shank, "lShin", "lFoot"},
                {k::foot, "lFoot", ""},               {k::thigh, "rThigh", "rShin"},
                {k::shank, "rShin", "rFoot"},         {k::foot, "rFoot", ""}};
    throw invalid_argument(
        "anima::default_segment_map: the skeleton (root '" + (sk.empty() ? std::string("none") : sk[0].name) +
        "') has neither the CMU 31-joint names (LowerBack, Spine1, LeftUpLeg...) nor the Daz names (hip, abdomen, "
        "lThigh...): pass a segment map");
}

/// Metres per skeleton unit for the two CMU layouts: 0.056444 for the ASF
/// conversion (CMU's FAQ: length unit = 1/0.45 inch), 0.01 for the Daz one
/// (centimetres); empty for other skeletons.
template <class T>
std::optional<T> layout_metres_per_unit(const skeleton<T>& sk) {
    if (sk.find("LowerBack") && sk.find("LeftUpLeg")) return T(0.056444);
    if (sk.find("abdomen") && sk.find("lThigh")) return T(0.01);
    return std::nullopt;
}

/// layout_metres_per_unit, or anima::invalid_argument for other skeletons.
template <class T>
T default_metres_per_unit(const skeleton<T>& sk) {
    if (const auto unit = layout_metres_per_unit(sk)) return *unit;
    throw invalid_argument("anima::default_metres_per_unit: unknown skeleton layout (root '" +
                           (sk.empty() ? std::string("none") : sk[0].name) + "'): give metres_per_unit");
}

template <class T>
struct body_model_params {
    T body_mass = T(70);                          ///< kg, > 0
    anima::sex sex = anima::sex::male;
    T metres_per_unit = T(0);                     ///< 0: default_metres_per_unit(skeleton)
    std::vector<segment_assignment> segments;     ///< empty: default_segment_map(skeleton)
    Eigen::Matrix<T, 3, 1> lateral_axis{T(1), T(0), T(0)};  ///< medio-lateral direction in the rest pose
};

/// Builds the model of a skeleton (in its rest pose: every joint frame is
/// aligned with the world). Segment masses are rescaled so that they sum to
/// body_mass exactly, also when a map leaves some de Leva segments out.
template <class T>
rigid_body_model<T> make_body_model(const skeleton<T>& sk, const body_model_params<T>& params = {}) {
    using vector3 = Eigen::Matrix<T, 3, 1>;
    using matrix3 = Eigen::Matrix<T, 3, 3>;
    const char* where = "anima::make_body_model";
    if (sk.empty()) throw invalid_argument(std::string(where) + ": empty skeleton");
    check_positive(where, "body_mass", params.body_mass);
    if (!(params.metres_per_unit >= T(0)) || !std::isfinite(params.metres_per_unit))
        throw invalid_argument(std::string(where) + ": metres_per_unit must be >= 0 and finite, got " +
                               detail::argument_text(params.metres_per_unit));
    if (!(params.lateral_axis.norm() > T(0)) || !params.lateral_axis.allFinite())
        throw invalid_argument(std::string(where) + ": lateral_axis must be a finite non-zero vector");
    const T unit = params.metres_per_unit > T(0) ? params.metres_per_unit : default_metres_per_unit(sk);
    const auto map = params.segments.empty() ? default_segment_map(sk) : params.segments;
    const auto rest = rest_positions(sk).first;
    const std::size_t n = sk.size();

    // Segment axes in metres, in the rest (world-aligned) frame.
    std::vector<vector3> axes(map.size(), vector3::Zero());
    std::vector<std::size_t> joint_of(map.size());
    std::vector<bool> taken(n, false);
    T thigh_ratio(0);
    for (std::size_t s = 0; s < map.size(); ++s) {
        const auto& a = map[s];
        const auto j = sk.find(a.proximal);
        if (!j) throw invalid_argument(std::string(where) + ": segment " + std::string(to_string(a.kind)) +
                                       ": no joint named '" + a.proximal + "'");
        if (taken[*j]) throw invalid_argument(std::string(where) + ": joint '" + a.proximal + "' carries two segments");
        taken[*j] = true;
        joint_of[s] = *j;
        if (!a.distal.empty()) {
            const auto d = sk.find(a.distal);
            if (!d) throw invalid_argument(std::string(where) + ": segment " + std::string(to_string(a.kind)) +
                                           ": no joint named '" + a.distal + "'");
            int p = static_cast<int>(*d);
            while (p != -1 && p != static_cast<int>(*j)) p = sk[static_cast<std::size_t>(p)].parent;
            if (p == -1) throw invalid_argument(std::string(where) + ": '" + a.distal + "' is not below '" + a.proximal + "'");
            axes[s] = (rest[*d] - rest[*j]) * unit;
        } else if (sk[*j].end_site && sk[*j].end_site->norm() > T(0)) {
            axes[s] = *sk[*j].end_site * unit;
        }
        if (a.kind == segment_kind::thigh && thigh_ratio == T(0) && axes[s].norm() > T(0))
            thigh_ratio = axes[s].norm() / T(de_leva_parameters(segment_kind::thigh, params.sex).mean_length);
    }
    if (thigh_ratio == T(0)) thigh_ratio = T(1);
    for (std::size_t s = 0; s < map.size(); ++s) {
        if (axes[s].norm() > T(0)) continue;
        const auto j = joint_of[s];
        vector3 dir = sk[j].offset;
        if (!(dir.norm() > T(0)))
            throw invalid_argument(std::string(where) + ": segment " + std::string(to_string(map[s].kind)) + " at '" +
                                   map[s].proximal + "' has no length: give a distal joint");
        axes[s] = dir.normalized() * (T(de_leva_parameters(map[s].kind, params.sex).mean_length) * thigh_ratio);
    }

    T fraction_sum(0);
    for (const auto& a : map) fraction_sum += T(de_leva_parameters(a.kind, params.sex).mass_fraction);

    rigid_body_model<T> model;
    std::vector<T> mass(n, T(0));
    std::vector<vector3> com(n, vector3::Zero());
    std::vector<matrix3> inertia(n, matrix3::Zero());
    const vector3 lateral = params.lateral_axis.normalized();
    for (std::size_t s = 0; s < map.size(); ++s) {
        const auto& par = de_leva_parameters(map[s].kind, params.sex);
        const auto j = joint_of[s];
        const T length = axes[s].norm();
        const vector3 e_long = axes[s] / length;
        const T f = T(par.measured_from_far_end ? 1.0 - par.com_fraction : par.com_fraction);
        const T m = params.body_mass * T(par.mass_fraction) / fraction_sum;
        // The flexion (sagittal) axis is medio-lateral; for a limb lying along
        // it (an arm in the T-pose) take the coordinate axis least aligned
        // with the limb instead (its two transverse radii differ little).
        vector3 ref = lateral;
        if (std::abs(ref.dot(e_long)) > T(0.9)) {
            Eigen::Index axis = 0;
            e_long.cwiseAbs().minCoeff(&axis);
            ref = vector3::Unit(axis);
        }
        const vector3 e_sag = (ref - e_long * e_long.dot(ref)).normalized();
        const vector3 e_tr = e_long.cross(e_sag);
        const T l2 = length * length;
        const T rs = T(par.radius_sagittal), rt = T(par.radius_transverse), rl = T(par.radius_longitudinal);
        mass[j] = m;
        com[j] = f * axes[s];
        inertia[j] = m * l2 * (rs * rs * e_sag * e_sag.transpose() + rt * rt * e_tr * e_tr.transpose() +
                               rl * rl * e_long * e_long.transpose());
    }
    for (std::size_t j = 0; j < n; ++j)
        model.add_body(sk[j].name, sk[j].parent, sk[j].offset * unit, mass[j], com[j], inertia[j]);
    return model;
}

}  // namespace anima
