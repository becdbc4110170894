// The light clusters' CPU math (light_clusters.h): bounding spheres, the grid, the decision.
#include "lights/light_clusters.h"

#include <algorithm>
#include <cmath>

namespace pnb::player {

glm::vec4 lightBoundingSphere(const GpuLight& light, const glm::mat4& view) {
    const int type = int(light.directionType.w);
    if (type == int(LightType::Directional)) return {0, 0, 0, -1};
    const float range = std::max(light.positionRange.w, 0.0f);
    glm::vec3 centre(light.positionRange);
    float radius = range;
    if (type == int(LightType::Spot)) {
        // cone.x = cos(outer). The sector's apex, axis tip and rim all lie on the sphere of
        // radius range / (2 cos outer) centred that far down the axis (docs/PLAYER.md).
        const float cosOuter = std::clamp(light.cone.x, 0.0f, 1.0f);
        if (cosOuter > 0.5f) {
            radius = range / (2.0f * cosOuter);
            centre += glm::vec3(light.directionType) * radius;
        }
    }
    return {glm::vec3(view * glm::vec4(centre, 1.0f)), radius};
}

LightClusterGrid lightClusterGrid(uint32_t width, uint32_t height, uint32_t tilePx,
                                  uint32_t slices, uint32_t lights, float zNear, float zFar) {
    LightClusterGrid g;
    tilePx = std::max(tilePx, 1u);
    g.tilesX = (std::max(width, 1u) + tilePx - 1) / tilePx;
    g.tilesY = (std::max(height, 1u) + tilePx - 1) / tilePx;
    g.slices = std::max(slices, 1u);
    g.words = (lights + 31) / 32;
    g.invTilePx = 1.0f / float(tilePx);
    zFar = std::max(zFar, 2.0f * zNear);
    // log(zNear) * scale + bias = 0 and log(zFar) * scale + bias = slices.
    g.sliceScale = float(double(g.slices) / std::log(double(zFar) / double(zNear)));
    g.sliceBias = float(-std::log(double(zNear)) * double(g.sliceScale));
    return g;
}

bool clustersWanted(const RenderSettings& s, uint32_t localLights) {
    if (localLights == 0 || s.lightCulling == LightCulling::Off) return false;
    return s.lightCulling == LightCulling::Clusters || localLights >= s.lightClusterMin;
}

} // namespace pnb::player
