// FLIP's image planes and its one filter operation (flip*.cpp only): a separable correlation with
// the image's edge pixels repeated outward (so a uniform image stays uniform up to its border, as
// the papers' filters assume).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace pnb::reference::flip_detail {

// One channel, row-major.
struct Plane {
    uint32_t width = 0, height = 0;
    std::vector<float> v;
    Plane() = default;
    Plane(uint32_t w, uint32_t h) : width(w), height(h), v(size_t(w) * h, 0.0f) {}
};

// out(x, y) = sum_{i,j} kx[i] ky[j] in(x + i - rx, y + j - ry), indices clamped to the image.
// Both kernels have odd length (centre rx = kx.size() / 2).
Plane correlateSeparable(const Plane& in, std::span<const float> kx, std::span<const float> ky);

// The colour half of LDR-FLIP (flip_color.cpp): Delta E_c per pixel, inputs display-linear [0, 1].
std::vector<float> colorError(std::span<const glm::vec3> test, std::span<const glm::vec3> reference,
                              uint32_t width, uint32_t height, double ppd);
// The feature half (flip_feature.cpp): Delta E_f per pixel from the two images' luminance Y/Y_n.
std::vector<float> featureError(const Plane& testY, const Plane& referenceY, double ppd);
// Y / Y_n of display-linear RGB clamped to [0, 1] (the feature pipeline's achromatic channel).
Plane normalizedLuminance(std::span<const glm::vec3> image, uint32_t width, uint32_t height);

} // namespace pnb::reference::flip_detail
