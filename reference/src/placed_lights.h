// placed_lights.h — the scene's lights where their nodes put them, as the Monte-Carlo tracers
// light with them (IndirectTracer, FrameTracer): in the player's order (by node), placed by the
// world matrices of the pose traced (PosedScene::world(), composed in double), positions relative to the tracer's origin, the range
// the player shades with (pnb/light_range.h). Internal to pnb_reference.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "pnb/node_transform.h"
#include "pnb/scene.h"

namespace pnb::reference::detail {

struct PlacedLight {
    const Light* desc = nullptr;          // its LGHT descriptor
    LightType type = LightType::Directional;
    glm::vec3 radiance{0.0f};             // colour x intensity
    glm::dvec3 position{0.0};             // origin-relative
    glm::vec3 travel{0.0f, -1.0f, 0.0f};  // the direction it shines in (directional, spot)
    double range = 0;                     // 0: unlimited
    double cosOuter = -1, cosInner = 1;   // a spot's cone (others: every direction)
};

// `world`: every node's world matrix (PosedScene::world()).
std::vector<PlacedLight> placeLights(const Scene& scene, const std::vector<Matrix4d>& world, glm::dvec3 origin);

} // namespace pnb::reference::detail
