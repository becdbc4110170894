#include "node_transform.h"

#include <glm/gtc/quaternion.hpp>

namespace pnb::player {

glm::dmat4 nodeLocalMatrix(const Node& n) {
    glm::dquat q(n.rotation.w, n.rotation.x, n.rotation.y, n.rotation.z);
    glm::dmat4 m = glm::mat4_cast(glm::normalize(q));
    m[0] *= double(n.scale.x);
    m[1] *= double(n.scale.y);
    m[2] *= double(n.scale.z);
    m[3] = glm::dvec4(n.translation.x, n.translation.y, n.translation.z, 1.0);
    return m;
}

} // namespace pnb::player
