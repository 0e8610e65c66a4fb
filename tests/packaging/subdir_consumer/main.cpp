// Builds against anima::anima only; Eigen and GLM must come with it.
#include <anima/anima.hpp>

#include <Eigen/Core>
#include <glm/glm.hpp>

int main() {
    const Eigen::Vector3d e(1.0, 2.0, 3.0);
    const glm::dvec3 g(1.0, 2.0, 3.0);
    const bool deps_ok = e.sum() == g.x + g.y + g.z;
    return anima::version_major == 0 && deps_ok ? 0 : 1;
}
