// texture_decode.h — a container texture's level 0 decoded to linear float RGBA and sampled
// bilinearly, for the Monte-Carlo tracers (base colours in indirect_tracer.cpp, the environment's
// radiance in sky_tracer.cpp). Internal to pnb_reference.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "pnb/scene.h"

namespace pnb::reference::detail {

// A 2D texture's level 0 as linear RGBA, sampled bilinearly with its wrap modes as the GPU
// does (texel centres at (i + 1/2) / size).
struct LinearTexture {
    uint32_t width = 0, height = 0;
    Wrap wrapU = Wrap::Repeat, wrapV = Wrap::Repeat;
    std::vector<glm::vec4> texels; // row t = 0 first (FORMAT.md: neither UVs nor images flipped)

    glm::vec4 sample(glm::vec2 uv) const {
        auto wrap = [](float x, uint32_t size, Wrap mode) {
            int n = int(size);
            int i = int(std::floor(x));
            switch (mode) {
            case Wrap::ClampToEdge: return std::clamp(i, 0, n - 1);
            case Wrap::MirroredRepeat: {
                int period = ((i % (2 * n)) + 2 * n) % (2 * n);
                return period < n ? period : 2 * n - 1 - period;
            }
            default: return ((i % n) + n) % n;
            }
        };
        float x = uv.x * float(width) - 0.5f, y = uv.y * float(height) - 0.5f;
        if (!std::isfinite(x) || !std::isfinite(y)) return glm::vec4(1.0f);
        float fx = x - std::floor(x), fy = y - std::floor(y);
        int x0 = wrap(x, width, wrapU), x1 = wrap(x + 1.0f, width, wrapU);
        int y0 = wrap(y, height, wrapV), y1 = wrap(y + 1.0f, height, wrapV);
        auto at = [&](int i, int j) { return texels[size_t(j) * width + size_t(i)]; };
        return (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) + (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
    }
};

// Level 0 of 2D texture `index` (8-bit formats, sRGB decoded; 16F; 32F; swizzle applied), or
// nothing for block-compressed formats, a cube, or missing or short texel data.
std::optional<LinearTexture> decodeTexture(const Scene& scene, uint32_t index);

} // namespace pnb::reference::detail
