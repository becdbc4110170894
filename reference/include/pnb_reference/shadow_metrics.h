// pnb_reference/shadow_metrics.h — how far the player's shadows are from the ray-traced truth,
// per frame and across frames, and how shadow-map texels compare with screen pixels.
//
// Pure CPU arithmetic over per-pixel float arrays (any order, typically an image's rows); no
// Embree, no images, no files.
//
// Conventions shared by every function:
//   - A shadow value is 1 for lit, 0 for shadowed; a player value may lie in between (filtered).
//     "No geometry" is NaN (or ±inf) for both inputs, or any negative value for the player.
//   - Classification: lit when value >= kLitThreshold (0.5), shadowed otherwise.
//   - Percentages are of the pixels counted (valid in both inputs), in [0, 100]; 0 when none.
// Preconditions (API misuse, asserted in debug builds): paired spans have equal sizes. In release
// builds only the common prefix is used.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace pnb::reference {

inline constexpr float kLitThreshold = 0.5f;

struct ShadowErrorMetrics {
    uint64_t pixels = 0;               // valid in both player and reference
    double misclassifiedPercent = 0;   // lit/shadow classification differs
    double falseLitPercent = 0;        // player lit, reference shadowed (light leaks)
    double falseShadowPercent = 0;     // player shadowed, reference lit (acne, overdarkening)
    double meanAbsError = 0;           // mean |player - reference| (unclamped player values)
    uint64_t coverageMismatch = 0;     // pixels where exactly one of the two has geometry

    // Irradiance-weighted error (only with weights): each pixel's |player - reference| counts
    // with the weight w = max(N.L, 0) it receives light with, over the truth's lit irradiance
    // sum(w * reference). Answers "how much of the light that should reach the surfaces is
    // wrong", where the binary figures answer "how many pixels are wrong": a grazing wall
    // (N.L ~ 0) misclassified from edge to edge adds to the binary figures only. Player values
    // are clamped to [0, 1]. When the truth has no lit irradiance: 0 if the player has no error
    // either, else 100.
    bool weighted = false;                 // weights were given
    double litIrradiance = 0;              // sum(w * reference) over the counted pixels
    double weightedErrorPercent = 0;       // 100 * sum(w |player - reference|) / litIrradiance
    double weightedFalseLitPercent = 0;    // the part where the player is brighter (leaks)
    double weightedFalseShadowPercent = 0; // the part where the player is darker
};

// How one pixel counts in compareShadow: left out (either input has no geometry), agreeing
// (lit or shadowed in both), or misclassified one way or the other. compareShadow counts with
// this, so a per-pixel view of a frame (pnb-play --error-maps) matches its percentages exactly.
enum class ShadowClass : uint8_t { Unclassified, AgreeLit, AgreeShadow, FalseLit, FalseShadow };
ShadowClass classifyShadow(float player, float reference);

// The player's shadow factor (1 lit .. 0 shadowed; negative or NaN = no geometry) against the
// reference visibility (1 / 0; NaN = no geometry). `weights` (optional: empty, or one per pixel;
// non-finite or negative counts as 0) adds the irradiance-weighted figures, see above.
ShadowErrorMetrics compareShadow(std::span<const float> player, std::span<const float> reference,
                                 std::span<const float> weights = {});

// Unit normals of the surfaces seen in a position image (width x height, rows contiguous;
// non-finite = no geometry) from the positions of neighbouring pixels: on each axis the
// neighbour closer in space (so a silhouette's far side is not mixed in), crossed, and turned
// to face `eye`. Zero where a pixel has no valid neighbour on an axis. For surfaces whose
// shading normal is unknown (the player's normal dump holds deferred surfaces only).
std::vector<glm::vec3> normalsFromPositions(std::span<const glm::vec3> positions, int width,
                                            int height, glm::vec3 eye = glm::vec3(0.0f));

// The normal each pixel's irradiance weight is computed with: the shading normal where it is
// known (non-zero, finite), else `fallback`'s (either may be empty: all unknown), normalised;
// zero where neither is usable. One entry per pixel of the longer span.
std::vector<glm::vec3> weightNormals(std::span<const glm::vec3> normals,
                                     std::span<const glm::vec3> fallback);

// The weight of each pixel for compareShadow: max(dot(normal, towardLight), 0), the normal as
// weightNormals picks it (0 where there is none). Normals need not be unit length; towardLight
// must be non-zero.
std::vector<float> lambertWeights(std::span<const glm::vec3> normals,
                                  std::span<const glm::vec3> fallback, glm::vec3 towardLight);

// Temporal flicker: the percentage of pixels valid in both frames whose lit/shadow classification
// changed between `previous` and `current` (both player values or both reference values).
double flickerPercent(std::span<const float> previous, std::span<const float> current);

// Screen-pixel-to-shadow-texel ratio statistics of one cascade.
struct RatioStats {
    int cascade = 0;       // cascade index
    uint64_t pixels = 0;   // pixels of this cascade with a valid ratio
    double median = 0;     // 50th percentile of the ratio
    double p95 = 0;        // 95th percentile of the ratio
};

// Per pixel the player provides the cascade index (a float holding an integer; negative or NaN =
// no cascade) and ratio = shadow texel world size / screen pixel world size (> 0 and finite, else
// the pixel is skipped: > 1 means a texel covers more than a pixel, i.e. undersampling).
// Returns one entry per cascade that has pixels, ascending by cascade (the index is rounded to
// the nearest integer). Percentiles interpolate linearly between closest ranks (numpy's default,
// "linear"): p-th percentile of sorted x[0..n-1] = x[lo] + (h - lo) * (x[lo+1] - x[lo]) with
// h = (n - 1) * p / 100, lo = floor(h).
std::vector<RatioStats> texelRatioByCascade(std::span<const float> cascade,
                                            std::span<const float> ratio);

// The p-th percentile (0..100) of `values` by the rule above; reorders `values`. 0 when empty.
double percentile(std::span<double> values, double p);

} // namespace pnb::reference
