// pnb_reference/indirect_metrics.h — how far the player's indirect irradiance is from the
// ray-traced one-bounce truth (IndirectTracer), per frame. Luminance is Rec. 709's
// (0.2126 R + 0.7152 G + 0.0722 B). Pixels count where both have a finite value.
#pragma once

#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

namespace pnb::reference {

struct IndirectErrorMetrics {
    uint64_t pixels = 0;
    double referenceMean = 0;     // mean reference luminance (the lights' units)
    double playerMean = 0;
    // sqrt(mean (player - reference)^2) / mean reference, luminance, percent.
    double relativeRmsePercent = 0;
    // The reference's own noise on the same scale: sqrt(mean standardError^2) / mean reference,
    // percent. An RMSE near it cannot be told from Monte-Carlo noise.
    double referenceNoisePercent = 0;
    // The player's own error with the reference's noise taken out: E[(p - r^)^2] = (p - r)^2 +
    // Var(r^), so sqrt(max(0, MSE - mean standardError^2)) / mean reference, percent. Reads true
    // even when the truth was traced with few rays.
    double correctedRmsePercent = 0;
    double energyRatio = 0;       // sum player / sum reference, luminance (1 = same total light)
    double channelRatio[3] = {0, 0, 0}; // per colour (colour bleeding: R, G, B each 1 ideally)
    // Light where there is none: the player's luminance in pixels whose reference is below
    // 3 standard errors and below 1 % of the reference mean, as a percent of the player's total.
    double leakPercent = 0;
};

// Whether one pixel counts in compareIndirect: all three values finite (a per-pixel view of a
// frame, pnb-play --error-maps, uses this for the same pixel set).
bool comparedPixel(const glm::vec3& player, const glm::vec3& reference, const glm::vec3& standardError);

// `player`, `reference`, `standardError` are per pixel (same size; NaN = no surface).
IndirectErrorMetrics compareIndirect(std::span<const glm::vec3> player, std::span<const glm::vec3> reference,
                                     std::span<const glm::vec3> standardError);

inline double luminance(const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

} // namespace pnb::reference
