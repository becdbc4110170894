// LDR-FLIP (flip.h): the colour and feature halves (flip_color.cpp, flip_feature.cpp) combined,
// the sRGB transfer functions, and the player's tone map for the fixed-exposure frame metric.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "flip_filter.h"
#include "pnb_lighting/tonemap.h"
#include "pnb_reference/flip.h"

namespace pnb::reference {

double pixelsPerDegree(double distanceMetres, double monitorWidthPixels,
                       double monitorWidthMetres) {
    return distanceMetres * (monitorWidthPixels / monitorWidthMetres) * std::numbers::pi / 180.0;
}

double defaultPixelsPerDegree() {
    return pixelsPerDegree(0.7, 3840.0, 0.7);
}

LdrFlipParts ldrFlipParts(std::span<const glm::vec3> test, std::span<const glm::vec3> reference,
                          uint32_t width, uint32_t height, double ppd) {
    LdrFlipParts parts;
    const size_t pixels = size_t(width) * height;
    if (pixels == 0 || test.size() != pixels || reference.size() != pixels) return parts;
    parts.color = flip_detail::colorError(test, reference, width, height, ppd);
    parts.feature =
        flip_detail::featureError(flip_detail::normalizedLuminance(test, width, height),
                                  flip_detail::normalizedLuminance(reference, width, height), ppd);
    parts.error.resize(pixels);
    // A feature difference makes a colour error count more: the exponent 1 - feature < 1 lifts it.
    for (size_t p = 0; p < pixels; ++p)
        parts.error[p] = float(std::pow(double(parts.color[p]), 1.0 - double(parts.feature[p])));
    return parts;
}

std::vector<float> ldrFlip(std::span<const glm::vec3> test, std::span<const glm::vec3> reference,
                           uint32_t width, uint32_t height, double ppd) {
    return ldrFlipParts(test, reference, width, height, ppd).error;
}

float srgbToLinear(float encoded) {
    return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

float linearToSrgb(float linear) {
    return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

glm::vec3 playerToneMap(const glm::vec3& hdr, double exposure) {
    glm::vec3 out;
    for (int c = 0; c < 3; ++c) {
        // NaN counts as black here; tonemap.frag's min() leaves it to the GPU.
        const float x = std::isnan(hdr[c]) ? 0.0f : std::min(float(double(hdr[c]) * exposure), 65504.0f);
        out[c] = lighting::acesFitted(x); // the player's curve, one definition (pnb_lighting/tonemap.h)
    }
    return out;
}

std::vector<float> toneMappedLdrFlip(std::span<const glm::vec3> test,
                                     std::span<const glm::vec3> reference, uint32_t width,
                                     uint32_t height, const ToneMap& toneMap, double ppd) {
    std::vector<glm::vec3> t(test.size()), r(reference.size());
    std::transform(test.begin(), test.end(), t.begin(), toneMap);
    std::transform(reference.begin(), reference.end(), r.begin(), toneMap);
    return ldrFlip(t, r, width, height, ppd);
}

std::vector<float> playerLdrFlip(std::span<const glm::vec3> test,
                                 std::span<const glm::vec3> reference, uint32_t width,
                                 uint32_t height, double exposure, double ppd) {
    return toneMappedLdrFlip(
        test, reference, width, height,
        [exposure](const glm::vec3& c) { return playerToneMap(c, exposure); }, ppd);
}

} // namespace pnb::reference
