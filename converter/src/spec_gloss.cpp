// converter/src/spec_gloss.cpp — the published specular-glossiness → metallic-roughness
// conversion (pnb_converter/spec_gloss.h says where it comes from).
#include "pnb_converter/spec_gloss.h"

#include <algorithm>
#include <cmath>

namespace pnb::converter {

namespace {

constexpr float kDielectricSpecular = 0.04f; // F0 of a dielectric in the metal-rough model
constexpr float kEpsilon = 1e-6f;

float perceivedBrightness(float r, float g, float b) {
    return std::sqrt(0.299f * r * r + 0.587f * g * g + 0.114f * b * b);
}

// The metallic that makes a metal-rough material with this diffuse brightness reflect
// `specular` (a quadratic in metallic; 0 below the dielectric's own specular).
float solveMetallic(float diffuse, float specular, float oneMinusSpecularStrength) {
    if (specular < kDielectricSpecular) return 0.0f;
    const float a = kDielectricSpecular;
    const float b = diffuse * oneMinusSpecularStrength / (1.0f - kDielectricSpecular) + specular -
                    2.0f * kDielectricSpecular;
    const float c = kDielectricSpecular - specular;
    const float d = std::max(b * b - 4.0f * a * c, 0.0f);
    return std::clamp((-b + std::sqrt(d)) / (2.0f * a), 0.0f, 1.0f);
}

float clamp01(float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; }

} // namespace

MetalRough specGlossToMetalRough(Vec4 diffuse, Vec3 specular, float glossiness) {
    // The extension's values are in [0, 1]; anything else (a broken file) is clamped first, so
    // the quadratic never sees an infinity.
    diffuse = {clamp01(diffuse.x), clamp01(diffuse.y), clamp01(diffuse.z), clamp01(diffuse.w)};
    specular = {clamp01(specular.x), clamp01(specular.y), clamp01(specular.z)};
    glossiness = clamp01(glossiness);
    const float oneMinusSpecularStrength =
        1.0f - std::max({specular.x, specular.y, specular.z});
    const float metallic = solveMetallic(perceivedBrightness(diffuse.x, diffuse.y, diffuse.z),
                                         perceivedBrightness(specular.x, specular.y, specular.z),
                                         oneMinusSpecularStrength);
    const float fromDiffuse =
        oneMinusSpecularStrength / (1.0f - kDielectricSpecular) / std::max(1.0f - metallic, kEpsilon);
    const float fromSpecular = 1.0f / std::max(metallic, kEpsilon);
    const float t = metallic * metallic;
    auto channel = [&](float d, float s) {
        const float base = d * fromDiffuse;
        const float metal = (s - kDielectricSpecular * (1.0f - metallic)) * fromSpecular;
        return clamp01(base + (metal - base) * t);
    };
    MetalRough out;
    out.baseColor = {channel(diffuse.x, specular.x), channel(diffuse.y, specular.y),
                     channel(diffuse.z, specular.z), clamp01(diffuse.w)};
    out.metallic = metallic;
    out.roughness = clamp01(1.0f - glossiness);
    return out;
}

} // namespace pnb::converter
