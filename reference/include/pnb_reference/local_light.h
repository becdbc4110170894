// pnb_reference/local_light.h — a point or spot light of a container, placed in the world; the
// irradiance it gives a surface point with exactly the player's falloff; which points it reaches;
// and the player's shadows of it against the truth (ShadowTracer::visibilityToPoint), weighted
// by that irradiance.
//
// Does: places light K of the LGHT chunk with the node that references it (pnb/node_transform.h,
// in double, as the player does); evaluates lights.glsl's range window, inverse square and spot
// cone (rangeAttenuation, spotConeFactor) on the CPU; restricts compareShadow to the pixels the
// light reaches.
//
// Does NOT do: tracing (ShadowTracer does), colour (a light's colour is a constant factor of its
// irradiance and cancels out of every weighted percentage), directional lights (the sun is judged
// with lambertWeights and a direction), lights placed by several nodes (the first node places it;
// placementNodes says how many there are), area or soft lights.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "pnb/scene.h"
#include "pnb_reference/shadow_color_metrics.h"
#include "pnb_reference/shadow_metrics.h"
#include "pnb_reference/shadow_tracer.h"

namespace pnb::reference {

// A point or spot light where the container puts it.
struct LocalLight {
    uint32_t index = 0; // into the LGHT chunk
    std::string name;   // "light 1 'bulb'" (for messages)
    LightType type = LightType::Point;
    uint32_t node = 0;                    // the node that places it: the first that references it
    uint32_t placementNodes = 0;          // how many nodes reference it (> 1: an instanced light)
    glm::dvec3 position{0.0};             // world space: the node's world translation
    glm::dvec3 direction{0.0, 0.0, -1.0}; // unit, world: where it shines (the node's -Z)
    float intensity = 0;                  // candela
    float range = 0;                  // pnb::effectiveLightRange: its own range or the cut-off's
    bool ownRange = false;            // range is the light's own (else the 0.01 lux cut-off's)
    float cosOuter = 0, cosInner = 1; // spot cone (point lights: -1 and 1, every direction)
    bool castsShadows = true;         // the light's flag: the truth is traced either way (the
                                      // player draws no shadow of a light without it)
};

// Light `index` of the scene placed by its node. Errors (Input, naming the light): index past the
// LGHT chunk, a directional light, a light no node references (it has no position), a pose whose
// clip does not exist. `at`: the instant whose node placement puts it (frame_pose.h).
TracerResult<LocalLight> placeLocalLight(const Scene& scene, uint32_t index, const FramePose& at = {});

// lights.glsl's falloff, on the CPU. These must equal shaders/include/lights.glsl
// (rangeAttenuation and its spot term, where a light is shaded) formula for formula, constants
// included (in double here, float there); a change there is a change here
// (tests/reference/local_light_test.cpp checks hand-computed values).
//   rangeAttenuation: window^2 / max(d^2, 1e-4), window = clamp(1 - (d^2 / range^2)^2, 0, 1);
//                     range <= 0: the inverse square alone.
//   spotConeFactor:   t^2, t = clamp((cosAngle - cosOuter) / max(cosInner - cosOuter, 1e-4), 0, 1).
double rangeAttenuation(double distanceSquared, double range);
double spotConeFactor(double cosAngle, double cosOuter, double cosInner);

// The irradiance (lux, before colour) light gives a point with normal `normal` (unit), `toLight`
// the vector from the point to the light: intensity x max(n.l, 0) x rangeAttenuation(d^2, range)
// x (spots) spotConeFactor. In double, so a weight near the range does not flush to zero.
double localLightIrradiance(const LocalLight& light, glm::dvec3 toLight, glm::dvec3 normal);

// Whether the light reaches the point at all: d < range, (spots) the angle from the axis inside
// the outer cone (cos > cosOuter), and n.l > 0. Exactly where localLightIrradiance is > 0.
bool localLightReaches(const LocalLight& light, glm::dvec3 toLight, glm::dvec3 normal);

// Per pixel of a frame: the light's irradiance (0 where it does not reach or there is no surface)
// and whether it reaches. `positions` and `lightPosition` relative to the same origin (the
// eye); the normal is the shading normal where known (non-zero, finite), else `fallback`'s (see
// weightNormals); no usable normal: not reached.
struct LocalLightWeights {
    std::vector<float> irradiance;
    std::vector<uint8_t> reached;
    uint64_t reachedCount = 0;
};
LocalLightWeights localLightWeights(const LocalLight& light, glm::dvec3 lightPosition,
                                    std::span<const glm::vec3> positions,
                                    std::span<const glm::vec3> normals,
                                    std::span<const glm::vec3> fallback);

// compareShadow over the pixels the light reaches only (elsewhere neither side is judged: the
// player's maps need not cover them), each weighted by its irradiance there. The binary figures
// count reached pixels; the weighted ones are compareShadow's with these weights (which are 0
// outside the reach anyway).
ShadowErrorMetrics compareLocalShadow(std::span<const float> player,
                                      std::span<const float> reference,
                                      const LocalLightWeights& weights);

// compareShadowColor likewise: the pixels the light reaches only, weighted by its irradiance.
ShadowColorMetrics compareLocalShadowColor(std::span<const glm::vec3> player,
                                           std::span<const glm::vec3> reference,
                                           const LocalLightWeights& weights);

} // namespace pnb::reference
