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

    // The scorecard: the same error (noise removed, as correctedRmsePercent) for the baselines a
    // real-time indirect light has to beat, in the same pixels. An indirect light whose error is
    // not below the best constant's gives the user nothing for its cost.
    double zeroRmsePercent = 0;          // no indirect light at all
    double bestConstantRmsePercent = 0;  // the truth's mean everywhere (the best constant ambient)
    double bestScale = 0;                // least-squares factor s minimising sum (s p - r)^2
    double scaledRmsePercent = 0;        // the player times bestScale: its pattern's error alone
    // Pearson correlation of player and truth luminance, the truth's noise variance taken out of
    // its variance (so few rays do not lower it); 0 where either is constant. Below ~0.8 the
    // spatial pattern is wrong, whatever the scale.
    double correlation = 0;
    // The headline: correctedRmsePercent / bestConstantRmsePercent (< 1: better than a constant).
    double rmseOverBestConstant = 0;
};

// Whether one pixel counts in compareIndirect: all three values finite (a per-pixel view of a
// frame, pnb-play --error-maps, uses this for the same pixel set).
bool comparedPixel(const glm::vec3& player, const glm::vec3& reference, const glm::vec3& standardError);

// `player`, `reference`, `standardError` are per pixel (same size; NaN = no surface). Every
// "noise removed" figure subtracts the mean squared standard error from the mean squared error:
// E[(p - r^)^2] = (p - r)^2 + Var(r^) for a truth r^ independent of the player.
IndirectErrorMetrics compareIndirect(std::span<const glm::vec3> player, std::span<const glm::vec3> reference,
                                     std::span<const glm::vec3> standardError);

inline double luminance(const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

} // namespace pnb::reference
