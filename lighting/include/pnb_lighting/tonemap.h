// pnb_lighting/tonemap.h — the player's HDR -> display mapping on the CPU: exposure, the
// Narkowicz (2015) ACES fit, the sRGB transfer function the player's sRGB framebuffer applies on
// write. This file MIRRORS shaders/tonemap.frag (change both together): the displayed image is
// sRGB_encode(acesFitted(min(hdr * exposure, 65504))) per channel, so a truth's HDR image and
// the player's HDR dump become the images a viewer sees in one and the same way.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/vec3.hpp>

namespace pnb::lighting {

inline float acesFitted(float x) {
    return std::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

// The sRGB encoding (IEC 61966-2-1) of a linear value in [0, 1], as GL_FRAMEBUFFER_SRGB writes it.
inline float srgbEncode(float linear) {
    const float c = std::clamp(linear, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

// The displayed colour (sRGB-encoded, in [0, 1]) of linear HDR radiance `hdr` at `exposure`.
// +Inf is white (the min, as the shader's); NaN, which the shader would pass on, is black here.
inline glm::vec3 displayColor(glm::vec3 hdr, float exposure) {
    glm::vec3 out;
    for (int c = 0; c < 3; ++c) {
        const float x = std::min(hdr[c] * exposure, 65504.0f);
        out[c] = std::isnan(x) ? 0.0f : srgbEncode(acesFitted(x));
    }
    return out;
}

} // namespace pnb::lighting
