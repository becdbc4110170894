// pnb/texture_transform.h — KHR_texture_transform on the CPU: where a texture slot samples for
// a vertex UV. A property of the container's TextureSlot, so the ray-traced reference samples
// exactly where the player's shaders do (the GLSL copy is slotUv in shaders/include/material.glsl).
#pragma once

#include <cmath>

#include "pnb/chunks.h"

namespace pnb {

// uv' = T * R * S * uv, with the extension's rotation matrix R = (cos r, sin r; -sin r, cos r)
// given row by row: u' = c u + s v, v' = -s u + c v (UV space, v down the image).
inline Vec2 textureTransformUv(Vec2 offset, Vec2 scale, float rotationRadians, Vec2 uv) {
    const float c = std::cos(rotationRadians), s = std::sin(rotationRadians);
    const float su = uv.x * scale.x, sv = uv.y * scale.y;
    return {c * su + s * sv + offset.x, -s * su + c * sv + offset.y};
}

inline Vec2 textureTransformUv(const TextureSlot& slot, Vec2 uv) {
    return textureTransformUv(slot.offset, slot.scale, slot.rotationRadians, uv);
}

} // namespace pnb
