// pnb_reference/shadow_color_metrics.h — the player's colour shadow visibility (light through
// glass, issue 43: `pnb-play --dump shadow_color`) against the truth's
// (ShadowTracer::colorVisibility), per frame.
//
// Pure CPU arithmetic over per-pixel RGB arrays; no Embree, no images, no files.
//
// Conventions (those of shadow_metrics.h, per channel):
//   - A value is the light of each colour that reaches the point: 1 unblocked, 0 blocked, in
//     between through glass (the truth) or filtered (the player). "No geometry": NaN or ±inf in
//     any channel of either, or a negative channel in the player's (its -1).
//   - Misclassification, per channel: the states a pixel can be in are 0 (blocked), t (the
//     truth's value, when strictly between 0 and 1) and 1 (unblocked). The player's value goes
//     to the nearest state, a tie to the brighter one; a pixel is misclassified when, in some
//     channel, that state is not the truth's. Where the truth is 0 or 1 this is exactly
//     classifyShadow's 0.5 threshold (lit when >= 0.5), so on such pixels compareShadowColor of
//     a grey player gives compareShadow's figures.
//   - False lit / false shadow: the player is brighter / darker than the truth in the
//     misclassified channels (the sign of the sum of their states' steps; a tie, one channel each
//     way, by the sign of the sum of their differences, zero counting as false shadow).
// Preconditions (asserted in debug builds): paired spans have equal sizes. In release builds
// only the common prefix is used.
#pragma once

#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

namespace pnb::reference {

struct ShadowColorMetrics {
    uint64_t pixels = 0;             // valid in both player and reference
    uint64_t translucentPixels = 0;  // of those, the truth is not 0 or 1 in all three channels
    double misclassifiedPercent = 0; // some channel in another state than the truth's
    double falseLitPercent = 0;      // misclassified brighter (light leaks, glass missing)
    double falseShadowPercent = 0;   // misclassified darker (acne, glass too dark or opaque)
    double meanAbsError = 0;         // mean over pixels and channels of |player - reference|
    uint64_t coverageMismatch = 0;   // exactly one of the two has geometry

    // Irradiance-weighted error per channel (only with weights), as compareShadow's on each
    // channel: a pixel's |player - reference| (player clamped to [0, 1]) counts with weight w,
    // over the truth's irradiance sum(w x reference) of that channel. 0 when the truth has no
    // irradiance in the channel and the player no error either, else 100.
    bool weighted = false;
    glm::dvec3 litIrradiance{0.0};
    glm::dvec3 weightedErrorPercent{0.0};
    glm::dvec3 weightedFalseLitPercent{0.0};    // the part where the player is brighter
    glm::dvec3 weightedFalseShadowPercent{0.0}; // the part where it is darker
};

// How one pixel counts in compareShadowColor (for error maps): left out, agreeing (the truth
// unblocked in all channels, blocked in all, or anything else: through glass), or misclassified
// one way or the other.
enum class ShadowColorClass : uint8_t {
    Unclassified,
    AgreeLit,
    AgreeShadow,
    AgreeTranslucent,
    FalseLit,
    FalseShadow
};
ShadowColorClass classifyShadowColor(glm::vec3 player, glm::vec3 reference);

// `weights` (optional: empty, or one per pixel; non-finite or negative counts as 0) adds the
// irradiance-weighted figures.
ShadowColorMetrics compareShadowColor(std::span<const glm::vec3> player, std::span<const glm::vec3> reference,
                                      std::span<const float> weights = {});

} // namespace pnb::reference
