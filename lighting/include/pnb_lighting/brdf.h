// pnb_lighting/brdf.h — the glTF 2.0 metallic-roughness BRDF (Appendix B of the glTF
// specification) on the CPU: GGX distribution, height-correlated Smith visibility, Schlick
// Fresnel, Lambert diffuse weighted (1 - F)(1 - metallic).
//
// This file MIRRORS shaders/include/brdf.glsl, formula for formula and clamp for clamp (the
// same 1e-4 floor on n.v, the same 1e-6 floor in the visibility's denominator, the same pi in
// float): the whole-frame truth (pnb_reference's FrameTracer) shades with it, so that a
// difference between the player and the truth is never a difference of BRDF definitions.
// Change both together.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace pnb::lighting {

// brdf.glsl's PNB_PI, as a float literal like the shader's.
inline constexpr float kBrdfPi = 3.14159265358979f;

inline float distributionGgx(float nDotH, float alpha) {
    const float a2 = alpha * alpha;
    const float d = nDotH * nDotH * (a2 - 1.0f) + 1.0f;
    return a2 / (kBrdfPi * d * d);
}

inline float visibilitySmithGgxCorrelated(float nDotV, float nDotL, float alpha) {
    const float a2 = alpha * alpha;
    const float gv = nDotL * std::sqrt(nDotV * nDotV * (1.0f - a2) + a2);
    const float gl = nDotV * std::sqrt(nDotL * nDotL * (1.0f - a2) + a2);
    return 0.5f / std::max(gv + gl, 1e-6f);
}

inline glm::vec3 fresnelSchlick(glm::vec3 f0, float vDotH) {
    // The shader clamps the base for pow() (a negative base is NaN on Mesa); kept here so the
    // two agree bit for bit in intent.
    return f0 + (glm::vec3(1.0f) - f0) * std::pow(std::max(1.0f - vDotH, 0.0f), 5.0f);
}

// f(l, v): the BRDF alone (per steradian, no cosine), as shadeBrdf uses it. Zero when l is
// below the surface. n, v, l unit; v points from the surface to the viewer, l to the light.
inline glm::vec3 evaluateBrdf(glm::vec3 baseColor, float metallic, float roughness, glm::vec3 n, glm::vec3 v,
                              glm::vec3 l) {
    const float nDotL = std::max(glm::dot(n, l), 0.0f);
    if (nDotL <= 0.0f) return glm::vec3(0.0f);
    const glm::vec3 h = glm::normalize(v + l);
    const float nDotV = std::max(glm::dot(n, v), 1e-4f);
    const float nDotH = std::clamp(glm::dot(n, h), 0.0f, 1.0f);
    const float vDotH = std::clamp(glm::dot(v, h), 0.0f, 1.0f);
    const float alpha = roughness * roughness;
    const glm::vec3 f0 = glm::mix(glm::vec3(0.04f), baseColor, metallic);
    const glm::vec3 f = fresnelSchlick(f0, vDotH);
    const glm::vec3 diffuse = (glm::vec3(1.0f) - f) * (1.0f - metallic) * baseColor / kBrdfPi;
    const glm::vec3 specular = f * distributionGgx(nDotH, alpha) * visibilitySmithGgxCorrelated(nDotV, nDotL, alpha);
    return diffuse + specular;
}

// brdf.glsl's shadeBrdf: radiance towards v from one light of radiance `lightColor` along l.
inline glm::vec3 shadeBrdf(glm::vec3 baseColor, float metallic, float roughness, glm::vec3 n, glm::vec3 v,
                           glm::vec3 l, glm::vec3 lightColor) {
    const float nDotL = std::max(glm::dot(n, l), 0.0f);
    return evaluateBrdf(baseColor, metallic, roughness, n, v, l) * lightColor * nDotL;
}

} // namespace pnb::lighting
