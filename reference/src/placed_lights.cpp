// The scene's lights, placed (placed_lights.h).
#include "placed_lights.h"

#include <cmath>

#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "pnb/light_range.h"
#include "pnb/node_transform.h"
#include "pnb_lighting/scene_lights.h"

namespace pnb::reference::detail {

std::vector<PlacedLight> placeLights(const Scene& scene, const std::vector<Matrix4d>& worldMatrices,
                                     glm::dvec3 origin) {
    std::vector<PlacedLight> lights;
    for (size_t i = 0; i < scene.nodes.nodes.size(); ++i) {
        const Node& n = scene.nodes.nodes[i];
        if (n.light == kNone || n.light >= scene.lights.lights.size()) continue;
        const glm::dmat4 world = glm::make_mat4(worldMatrices[i].data());
        const Light& l = scene.lights.lights[n.light];
        PlacedLight p;
        p.desc = &l;
        p.type = l.type;
        p.radiance = glm::vec3(l.color.x, l.color.y, l.color.z) * l.intensity;
        p.position = glm::dvec3(world[3]) - origin;
        p.travel = glm::vec3(lighting::lightTravel(world));
        p.range = pnb::effectiveLightRange(l);
        if (l.type == LightType::Spot) {
            p.cosOuter = std::cos(l.outerConeRadians);
            p.cosInner = std::cos(l.innerConeRadians);
        }
        lights.push_back(p);
    }
    return lights;
}

} // namespace pnb::reference::detail
