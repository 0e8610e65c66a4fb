// Builds against anima::anima only; Eigen and GLM must come with it. The
// headers are compiled here as in a user's project: with the user's
// compiler and flags, without anima's precompiled header, and with
// templates instantiated (a transition, in float and double), which
// including them alone does not do.
#include <anima/anima.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <glm/glm.hpp>

#include <cmath>

namespace {

// A two-joint figure bending its spine, joined from frame 20 to frame 5.
template <class T>
bool transition_is_finite() {
    using vec3 = Eigen::Matrix<T, 3, 1>;
    anima::skeleton<T> sk;
    sk.add_joint("Hips", -1, vec3(T(0), T(1), T(0)));
    sk.add_joint("Spine", 0, vec3(T(0), T(0.2), T(0)));
    anima::clip<T> c(sk, 30, T(1) / T(120));
    for (std::size_t f = 0; f < c.frames(); ++f)
        c.set_rotation(f, 1, Eigen::Quaternion<T>(Eigen::AngleAxis<T>(T(0.03) * T(f), vec3::UnitX())));
    const auto t = anima::make_transition(c, 20, c, 5);
    return std::isfinite(t.duration) && t.duration > T(0);
}

}  // namespace

int main() {
    const Eigen::Vector3d e(1.0, 2.0, 3.0);
    const glm::dvec3 g(1.0, 2.0, 3.0);
    const bool deps_ok = e.sum() == g.x + g.y + g.z;
    const bool transitions_ok = transition_is_finite<float>() && transition_is_finite<double>();
    return anima::version_major == 0 && deps_ok && transitions_ok ? 0 : 1;
}
