// Adapts quaternion types to anima's rotation toolkit. The toolkit never wraps
// a user type: it reads the four components through quat_traits<Q> and builds
// the result through quat_traits<Q>::make, so glm::qua and Eigen::Quaternion are
// used as they are. Specialise quat_traits for any other type to plug it in.
#pragma once

#include <Eigen/Geometry>
#include <glm/ext/quaternion_double.hpp>
#include <glm/ext/quaternion_float.hpp>
#include <glm/ext/vector_double3.hpp>
#include <glm/ext/vector_float3.hpp>
#include <type_traits>

namespace anima {

/// Component access and construction for a quaternion type Q.
/// Required members: `scalar`, `vector3` (the 3-vector type results such as
/// rotation vectors come back as), `w(q)`, `x(q)`, `y(q)`, `z(q)`,
/// `make(w, x, y, z)` and `make_vector(x, y, z)`.
template <class Q, class Enable = void>
struct quat_traits;  // undefined: a type without traits is rejected at compile time

template <class T, glm::qualifier P>
struct quat_traits<glm::qua<T, P>> {
    using scalar = T;
    using vector3 = glm::vec<3, T, P>;
    static vector3 make_vector(T x, T y, T z) { return vector3(x, y, z); }
    static T w(const glm::qua<T, P>& q) { return q.w; }
    static T x(const glm::qua<T, P>& q) { return q.x; }
    static T y(const glm::qua<T, P>& q) { return q.y; }
    static T z(const glm::qua<T, P>& q) { return q.z; }
    static glm::qua<T, P> make(T w, T x, T y, T z) {
        // Assign members: GLM's constructor argument order has changed across
        // versions (and with GLM_FORCE_QUAT_DATA_XYZW), member names have not.
        glm::qua<T, P> q;
        q.w = w;
        q.x = x;
        q.y = y;
        q.z = z;
        return q;
    }
};

template <class T, int Options>
struct quat_traits<Eigen::Quaternion<T, Options>> {
    using scalar = T;
    using vector3 = Eigen::Matrix<T, 3, 1>;
    static vector3 make_vector(T x, T y, T z) { return vector3(x, y, z); }
    static T w(const Eigen::Quaternion<T, Options>& q) { return q.w(); }
    static T x(const Eigen::Quaternion<T, Options>& q) { return q.x(); }
    static T y(const Eigen::Quaternion<T, Options>& q) { return q.y(); }
    static T z(const Eigen::Quaternion<T, Options>& q) { return q.z(); }
    static Eigen::Quaternion<T, Options> make(T w, T x, T y, T z) {
        return Eigen::Quaternion<T, Options>(w, x, y, z);
    }
};

/// Scalar type of a quaternion type.
template <class Q>
using quat_scalar_t = typename quat_traits<std::decay_t<Q>>::scalar;

/// The 3-vector type that goes with a quaternion type (glm::vec3 for glm::qua,
/// Eigen::Vector3 for Eigen::Quaternion).
template <class Q>
using quat_vector3_t = typename quat_traits<std::decay_t<Q>>::vector3;

namespace detail {

template <class Q, class = void>
struct has_quat_traits : std::false_type {};
template <class Q>
struct has_quat_traits<Q, std::void_t<typename quat_traits<Q>::scalar>> : std::true_type {};

}  // namespace detail

/// True when Q can be used with the rotation toolkit.
template <class Q>
inline constexpr bool is_quaternion_v = detail::has_quat_traits<std::decay_t<Q>>::value;

}  // namespace anima
