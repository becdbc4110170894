// pnb_reference/flip.h — FLIP, the perceptual image difference of NVIDIA's Andersson et al.,
// implemented from the papers (not from their code):
//  - LDR-FLIP: "FLIP: A Difference Evaluator for Alternating Images", HPG 2020 (the colour and
//    feature pipelines, error = colour^(1 - feature));
//  - HDR-FLIP: "Visualizing Errors in Rendered High Dynamic Range Images", Eurographics 2021 (the
//    maximum of LDR-FLIP over a range of exposures chosen from the reference, ACES tone mapped).
// What the whole-frame truth (issue 40) is judged with: a per-pixel map in [0, 1] (0 identical,
// 1 the largest difference FLIP can report) and its mean. docs/REFERENCE.md, "Image metrics".
//
// Images are row-major RGB, `width * height` pixels; the row order does not matter (every filter
// is symmetric). LDR inputs are display-linear RGB in [0, 1] (what an sRGB display emits before
// its transfer function: decode an 8-bit sRGB file with srgbToLinear first); values outside are
// clamped, NaN is 0. Every function returns empty maps when a size does not match width * height.
// HDR inputs are linear radiance >= 0 (negative values count as 0; NaN as 0, +Inf as the brightest
// finite value FLIP's tone map sees).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace pnb::reference {

// The papers' constants (HPG 2020 §4 and §5; EG 2021 §4).
namespace flip_constants {
constexpr double kColorExponent = 0.7;         // q_c: the HyAB distance is raised to it
constexpr double kCompressionPoint = 0.4;      // p_c: the share of c_max mapped to ...
constexpr double kCompressionTarget = 0.95;    // p_t: ... this colour error
constexpr double kFeatureExponent = 0.5;       // q_f
constexpr double kFeatureWidthDegrees = 0.082; // w: peak-to-trough of the edge detector
constexpr double kExposureToneTarget = 0.85;   // HDR: the tone-mapped value of max / median
} // namespace flip_constants

// Pixels per degree of visual angle for a monitor `monitorWidthMetres` wide with
// `monitorWidthPixels` pixels seen from `distanceMetres`: distance * (pixels / width) * pi / 180.
double pixelsPerDegree(double distanceMetres, double monitorWidthPixels, double monitorWidthMetres);
// The papers' default observer: 0.7 m from a 0.7 m wide 3840-pixel monitor (67.02 ppd).
double defaultPixelsPerDegree();

// c_max: the HyAB distance between Hunt-adjusted linear green (0,1,0) and blue (0,0,1), raised to
// q_c — the largest colour difference, which the colour error maps to 1.
double flipColorMax();
// The colour error's compression of a q_c-powered HyAB distance `powered` into [0, 1]:
// [0, p_c c_max] -> [0, p_t] linearly, [p_c c_max, c_max] -> [p_t, 1].
double flipCompressColor(double powered);

// The two halves of LDR-FLIP per pixel, and their combination error = color^(1 - feature).
struct LdrFlipParts {
    std::vector<float> color;   // Delta E_c in [0, 1]
    std::vector<float> feature; // Delta E_f in [0, 1]
    std::vector<float> error;   // the FLIP map
};
LdrFlipParts ldrFlipParts(std::span<const glm::vec3> test, std::span<const glm::vec3> reference,
                          uint32_t width, uint32_t height, double ppd = defaultPixelsPerDegree());
// LDR-FLIP of two display-linear images: the per-pixel map. Exactly symmetric in its inputs.
std::vector<float> ldrFlip(std::span<const glm::vec3> test, std::span<const glm::vec3> reference,
                           uint32_t width, uint32_t height, double ppd = defaultPixelsPerDegree());

// The sRGB transfer function (IEC 61966-2-1) each way, per channel.
float srgbToLinear(float encoded);
float linearToSrgb(float linear);

// A tone map: linear HDR radiance -> display-linear [0, 1] (before the display's sRGB encoding).
using ToneMap = std::function<glm::vec3(const glm::vec3& hdr)>;
// The player's displayed image (shaders/tonemap.frag): acesFitted(min(hdr * exposure, 65504)),
// Narkowicz's ACES fit x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14) clamped to [0, 1]; the sRGB
// framebuffer then encodes it (so this is display-linear, what ldrFlip takes).
glm::vec3 playerToneMap(const glm::vec3& hdr, double exposure);
// LDR-FLIP of two HDR images after the same tone map: what a viewer of both frames sees.
std::vector<float> toneMappedLdrFlip(std::span<const glm::vec3> test,
                                     std::span<const glm::vec3> reference, uint32_t width,
                                     uint32_t height, const ToneMap& toneMap,
                                     double ppd = defaultPixelsPerDegree());
// The same with the player's tone map at `exposure`: pnb-judge's frame_flip_ldr.
std::vector<float> playerLdrFlip(std::span<const glm::vec3> test,
                                 std::span<const glm::vec3> reference, uint32_t width,
                                 uint32_t height, double exposure,
                                 double ppd = defaultPixelsPerDegree());

// HDR-FLIP's tone map (EG 2021 §4): Narkowicz's ACES fit of 0.6 x (his pre-exposure, which the
// paper keeps; the player's tonemap.frag drops it), per channel, clamped to [0, 1].
double hdrFlipAces(double x);
// The input value the tone map takes to `target` (the root of a quadratic): x_max for 0.85.
double hdrFlipAcesInverse(double target);

// The exposures (in stops: the image is multiplied by 2^c) HDR-FLIP evaluates.
struct ExposureRange {
    double start = 0;   // log2(x_max / max luminance): the brightest reference pixel maps to 0.85
    double stop = 0;    // log2(x_max / median luminance): the median maps to 0.85
    uint32_t count = 1; // max(2, ceil(stop - start)); 1 when start == stop
};
// From the reference's Rec. 709 luminance (EG 2021 §4). All black: {0, 0, 1}. A median of 0
// (more than half the pixels black; the paper's stop would be infinite) is replaced by the median
// of the non-zero luminances.
ExposureRange hdrFlipExposureRange(std::span<const glm::vec3> reference);

struct HdrFlipResult {
    std::vector<float> error;            // per pixel: max over exposures of LDR-FLIP
    std::vector<uint16_t> exposureIndex; // which exposure gave it (the first on a tie)
    ExposureRange exposures;
};
// HDR-FLIP of two linear HDR images, over `range` (default: hdrFlipExposureRange(reference)),
// the exposures on all cores (the result does not depend on how many).
// Not symmetric: the exposures come from the reference.
HdrFlipResult hdrFlip(std::span<const glm::vec3> test, std::span<const glm::vec3> reference,
                      uint32_t width, uint32_t height, double ppd = defaultPixelsPerDegree());
HdrFlipResult hdrFlip(std::span<const glm::vec3> test, std::span<const glm::vec3> reference,
                      uint32_t width, uint32_t height, const ExposureRange& range,
                      double ppd = defaultPixelsPerDegree());

} // namespace pnb::reference
