// pnb_reference/image_error.h — the plain image errors beside FLIP (flip.h): relative MSE of two
// linear HDR images, the share of it a Monte-Carlo reference's own noise explains, the summary
// figures of an error map (mean, weighted median and quartiles as FLIP's authors report them),
// and the magma colouring of a map in [0, 1]. docs/REFERENCE.md, "Image metrics".
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace pnb::reference {

// Relative MSE's epsilon: (t - r)^2 / (r^2 + eps). It keeps near-black pixels from dominating the
// mean (r = 0 would divide by zero, and a reference of 1e-3 would weigh an error a million times
// more than one at 1): below radiance sqrt(eps) = 0.1 the error counts in absolute terms, above
// it in relative terms. 0.01 is the value of the denoising literature (Rousselle et al. 2011 and
// after) and of issue 40's contract; in the player's HDR units before exposure, 0.1 is about
// half of mid-grey at exposure 1.
constexpr double kRelMseEpsilon = 0.01;

struct RelativeMse {
    double mean = 0;        // over compared pixels and the three channels
    uint64_t pixels = 0;    // compared: both pixels finite in all channels
    std::vector<float> map; // per pixel, the mean over channels; NaN where not compared
};
// Relative MSE of `test` against `reference` (same size, linear; sizes differing: {0, 0, empty}).
RelativeMse relativeMse(std::span<const glm::vec3> test, std::span<const glm::vec3> reference,
                        double epsilon = kRelMseEpsilon);

// The relative MSE a reference's own Monte-Carlo noise adds: for an unbiased estimate r^ of r
// with standard error s, E[(r^ - r)^2] = s^2, so the expected relMSE of the estimate against the
// converged image is mean over pixels and channels of s^2 / (r^2 + eps), with r^ standing in for
// r. A test image's relMSE against r^ is its own relMSE plus about this much.
// Pixels where either is not finite are left out; 0 when the sizes differ.
double noiseRelativeMse(std::span<const glm::vec3> reference,
                        std::span<const glm::vec3> standardError, double epsilon = kRelMseEpsilon);

// An error map's summary. The weighted quantiles weigh each pixel by its error (FLIP's tool
// reports these): the weighted median is the error below which half the map's total error lies,
// so a few large errors move it where the plain median would ignore them.
struct ErrorSummary {
    uint64_t pixels = 0; // finite values
    double mean = 0, weightedMedian = 0, weightedQuartile1 = 0, weightedQuartile3 = 0, min = 0,
           max = 0;
};
ErrorSummary summarizeError(std::span<const float> map);
// The smallest value v of `map` with sum_{x <= v} x >= q * sum x (q in [0, 1]); 0 for an all-zero
// map.
double weightedQuantile(std::span<const float> map, double q);

// matplotlib's "magma" at t in [0, 1] (clamped; NaN: 0), 8-bit sRGB: the colour map FLIP's papers
// draw their error maps with, black-purple (0) to pale yellow (1). Sampled at 9 stops, linear in
// between (as pnb-play's error maps draw it).
std::array<uint8_t, 3> magma(double t);
// A map through magma, 3 bytes per pixel in the map's order.
std::vector<uint8_t> magmaImage(std::span<const float> map);

} // namespace pnb::reference
