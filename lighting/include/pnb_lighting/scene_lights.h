// pnb_lighting/scene_lights.h — which light is "the sun", and which way a placed light shines:
// the rules the player shades by and the reference traces by. They live below both, so the truth
// judges exactly the light the player drew (a renderer and its judge that each pick "the first
// directional light" their own way disagree the day one of them changes).
#pragma once

#include <cstddef>

#include <glm/glm.hpp>

#include "pnb/chunks.h"

namespace pnb::lighting {

// Where a light placed by a node with world matrix `world` shines: the node's -Z
// (KHR_lights_punctual, FORMAT.md "LGHT"), unit. A degenerate (zero-scale) node gives NaN, which
// reaches nothing: every comparison with it is false.
inline glm::dvec3 lightTravel(const glm::dmat4& world) {
    return glm::normalize(glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0));
}

// The light the sun's cascaded shadows follow: a directional light that casts shadows.
inline bool isShadowingSun(const Light& l) {
    return l.type == LightType::Directional && l.castsShadows;
}

// Index of the shadowing sun among `count` lights, desc(i) giving the i-th light's descriptor:
// the first light isShadowingSun accepts; -1 if none.
template <class DescOf> int shadowingSunIndex(size_t count, DescOf desc) {
    for (size_t i = 0; i < count; ++i)
        if (isShadowingSun(desc(i))) return int(i);
    return -1;
}

// The sun that one-bounce GI reflects (and the GI truth traces): the shadowing sun, else the
// first directional light; -1 if there is no directional light.
template <class DescOf> int bouncedSunIndex(size_t count, DescOf desc) {
    if (int s = shadowingSunIndex(count, desc); s >= 0) return s;
    for (size_t i = 0; i < count; ++i)
        if (desc(i).type == LightType::Directional) return int(i);
    return -1;
}

} // namespace pnb::lighting
