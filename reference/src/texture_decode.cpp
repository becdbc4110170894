// Container textures as linear float RGBA (texture_decode.h).
#include "texture_decode.h"

#include <cstring>

#include <glm/gtc/packing.hpp>

namespace pnb::reference::detail {

namespace {

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

} // namespace

std::optional<LinearTexture> decodeTexture(const Scene& scene, uint32_t index) {
    if (index >= scene.textures.size()) return std::nullopt;
    const TextureDesc& d = scene.textures[index];
    const TextureMip* mip = nullptr;
    for (const TextureMip& m : scene.textureMips)
        if (m.texture == index && m.level == 0) mip = &m;
    if (!mip || d.dimension != TextureDimension::Tex2D || d.width == 0 || d.height == 0) return std::nullopt;
    int channels = 0, bytes = 0;
    switch (d.format) {
    case TextureFormat::R8: channels = 1, bytes = 1; break;
    case TextureFormat::RG8: channels = 2, bytes = 1; break;
    case TextureFormat::RGB8: channels = 3, bytes = 1; break;
    case TextureFormat::RGBA8: channels = 4, bytes = 1; break;
    case TextureFormat::R16F: channels = 1, bytes = 2; break;
    case TextureFormat::RG16F: channels = 2, bytes = 2; break;
    case TextureFormat::RGBA16F: channels = 4, bytes = 2; break;
    case TextureFormat::R32F: channels = 1, bytes = 4; break;
    case TextureFormat::RG32F: channels = 2, bytes = 4; break;
    case TextureFormat::RGBA32F: channels = 4, bytes = 4; break;
    default: return std::nullopt; // BC formats
    }
    const size_t count = size_t(d.width) * d.height;
    if (mip->data.size() < count * size_t(channels * bytes)) return std::nullopt;
    LinearTexture t;
    t.width = d.width;
    t.height = d.height;
    t.wrapU = d.wrapU;
    t.wrapV = d.wrapV;
    t.texels.resize(count);
    const std::byte* p = mip->data.data();
    for (size_t i = 0; i < count; ++i) {
        float raw[4] = {0, 0, 0, 1};
        for (int c = 0; c < channels; ++c) {
            const std::byte* q = p + (i * size_t(channels) + size_t(c)) * size_t(bytes);
            if (bytes == 1) {
                raw[c] = float(uint8_t(*q)) / 255.0f;
                if (d.colorSpace == ColorSpace::Srgb && c < 3) raw[c] = srgbToLinear(raw[c]);
            } else if (bytes == 2) {
                uint16_t h;
                std::memcpy(&h, q, 2);
                raw[c] = glm::unpackHalf1x16(h);
            } else {
                std::memcpy(&raw[c], q, 4);
            }
        }
        glm::vec4 texel;
        for (int k = 0; k < 4; ++k) {
            switch (d.swizzle[size_t(k)]) {
            case Swizzle::R: texel[k] = raw[0]; break;
            case Swizzle::G: texel[k] = raw[1]; break;
            case Swizzle::B: texel[k] = raw[2]; break;
            case Swizzle::A: texel[k] = raw[3]; break;
            case Swizzle::Zero: texel[k] = 0.0f; break;
            default: texel[k] = 1.0f; break;
            }
        }
        t.texels[i] = texel;
    }
    return t;
}

} // namespace pnb::reference::detail
