// frame_bsdf.h — importance sampling of the player's BRDF (pnb_lighting/brdf.h) for FrameTracer:
// one-sample MIS of two lobes, GGX (the half vector drawn with pdf D(h) (n.h), Walter et al.
// 2007) and cosine (Malley), picked with the probability of the specular part's estimated
// share, weighted by the combined pdf p = P_spec p_ggx + (1 - P_spec) p_cos, so a smooth metal
// converges as fast as a white wall. Internal to pnb_reference.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "cosine_sampling.h" // CosineFrame
#include "pnb_lighting/brdf.h"

namespace pnb::reference::detail {

struct BsdfLobes {
    glm::vec3 baseColor{1.0f};
    float metallic = 0, roughness = 1;
    glm::vec3 n{0.0f, 0.0f, 1.0f}; // unit shading normal
    glm::vec3 v{0.0f, 0.0f, 1.0f}; // unit, towards the viewer
    float specularProbability = 0.5f;

    bool lambertian = false; // FrameTraceSettings::lambertianOnly: albedo baseColor, no specular

    BsdfLobes(glm::vec3 base, float metal, float rough, glm::vec3 normal, glm::vec3 view, bool lambertianOnly = false)
        : baseColor(base), metallic(metal), roughness(rough), n(normal), v(view), lambertian(lambertianOnly) {
        if (lambertian) {
            baseColor *= 1.0f - metallic;
            specularProbability = 0.0f;
            return;
        }
        // The lobes' shares at normal incidence of the view: Fresnel's weight for the specular
        // part, (1 - F)(1 - metallic) x base colour for the diffuse one (luminance).
        auto luminance = [](glm::vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; };
        const glm::vec3 f0 = glm::mix(glm::vec3(0.04f), baseColor, metallic);
        const float nDotV = std::max(glm::dot(n, v), 1e-4f);
        const glm::vec3 f = lighting::fresnelSchlick(f0, nDotV);
        const float specular = luminance(f);
        const float diffuse = luminance((glm::vec3(1.0f) - f) * (1.0f - metallic) * baseColor);
        specularProbability = specular + diffuse > 0.0f ? specular / (specular + diffuse) : 0.5f;
        // Never starve a lobe the BRDF has: each keeps at least 5 % where it is not zero.
        if (diffuse > 0.0f) specularProbability = std::clamp(specularProbability, 0.05f, 0.95f);
    }

    float alpha() const { return roughness * roughness; }

    // The combined pdf (per steradian) of drawing l.
    float pdf(glm::vec3 l) const {
        const float nDotL = glm::dot(n, l);
        if (nDotL <= 0.0f) return 0.0f;
        if (specularProbability <= 0.0f) return nDotL / lighting::kBrdfPi;
        const glm::vec3 h = glm::normalize(v + l);
        const float nDotH = std::clamp(glm::dot(n, h), 0.0f, 1.0f);
        const float vDotH = std::max(glm::dot(v, h), 1e-6f);
        const float ggx = lighting::distributionGgx(nDotH, alpha()) * nDotH / (4.0f * vDotH);
        const float cosine = nDotL / lighting::kBrdfPi;
        return specularProbability * ggx + (1.0f - specularProbability) * cosine;
    }

    // A direction from three uniform numbers (u0 picks the lobe); may lie below the surface
    // (the caller then ends the path: the BRDF is zero there).
    glm::vec3 sample(float u0, float u1, float u2) const {
        const CosineFrame frame(n);
        const float phi = 6.28318530717958648f * u2;
        if (u0 < specularProbability) {
            const float a2 = alpha() * alpha();
            const float cosTheta = std::sqrt(std::max(0.0f, (1.0f - u1) / (1.0f + (a2 - 1.0f) * u1)));
            const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
            const glm::vec3 h = frame.t * (sinTheta * std::cos(phi)) + frame.b * (sinTheta * std::sin(phi)) + frame.n * cosTheta;
            return glm::normalize(2.0f * glm::dot(v, h) * h - v);
        }
        const float r = std::sqrt(u1);
        return glm::normalize(frame.t * (r * std::cos(phi)) + frame.b * (r * std::sin(phi)) +
                              frame.n * std::sqrt(std::max(0.0f, 1.0f - u1)));
    }

    glm::vec3 value(glm::vec3 l) const {
        if (lambertian) return glm::dot(n, l) > 0.0f ? baseColor / lighting::kBrdfPi : glm::vec3(0.0f);
        return lighting::evaluateBrdf(baseColor, metallic, roughness, n, v, l);
    }
};

} // namespace pnb::reference::detail
