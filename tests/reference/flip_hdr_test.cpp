// HDR-FLIP (EG 2021; flip.h): the exposure range from the reference's luminance, the tone map it
// is defined with, and the error growing with the brightness difference.
#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "pnb_reference/flip.h"
#include "pnb_reference/image_error.h"

namespace pnb::reference::test {

namespace {

std::vector<glm::vec3> hdrNoise(uint32_t w, uint32_t h, uint32_t seed) {
    std::mt19937 rng(seed);
    std::lognormal_distribution<float> radiance(0.0f, 1.5f); // a few stops either side of 1
    std::vector<glm::vec3> img(size_t(w) * h);
    for (auto& c : img)
        c = {radiance(rng), radiance(rng), radiance(rng)};
    return img;
}

std::vector<glm::vec3> scaled(std::vector<glm::vec3> img, float s) {
    for (auto& c : img)
        c *= s;
    return img;
}

} // namespace

// EG 2021 §4 (and Narkowicz 2016): the ACES fit of 0.6 x; t(0) = 0, large x saturates, and the
// inverse used for x_max is the value a bisection of t finds independently.
TEST(HdrFlip, AcesToneMapAndItsInverse) {
    auto narkowicz = [](double x) {
        return x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14);
    };
    for (double x : {0.01, 0.18, 1.0, 4.0})
        EXPECT_NEAR(hdrFlipAces(x), std::min(1.0, narkowicz(0.6 * x)), 1e-12);
    EXPECT_EQ(hdrFlipAces(0.0), 0.0);
    EXPECT_EQ(hdrFlipAces(-1.0), 0.0);
    EXPECT_EQ(hdrFlipAces(1e30), 1.0);
    EXPECT_EQ(hdrFlipAces(INFINITY), 1.0);
    double lo = 0.0, hi = 100.0;
    for (int i = 0; i < 200; ++i)
        ((hdrFlipAces(0.5 * (lo + hi)) < 0.85) ? lo : hi) = 0.5 * (lo + hi);
    EXPECT_NEAR(hdrFlipAcesInverse(0.85), lo, 1e-9);
    std::printf("x_max (t = 0.85): %.6f\n", lo);
}

// EG 2021 §4: start = log2(x_max / max Y), stop = log2(x_max / median Y), count = max(2,
// ceil(stop - start)). An image of grey pixels 0.25, 0.5, 0.5, 1, 8 has max 8 and median 0.5: the
// range is 4 stops wide and starts where 8 maps to x_max.
TEST(HdrFlip, ExposureRangeFromKnownLuminance) {
    const std::vector<glm::vec3> img = {glm::vec3(0.25f), glm::vec3(0.5f), glm::vec3(8.0f),
                                        glm::vec3(1.0f), glm::vec3(0.5f)};
    const double xMax = hdrFlipAcesInverse(0.85);
    const ExposureRange r = hdrFlipExposureRange(img);
    EXPECT_NEAR(r.start, std::log2(xMax / 8.0), 1e-6);
    EXPECT_NEAR(r.stop, std::log2(xMax / 0.5), 1e-6);
    EXPECT_EQ(r.count, 4u);
    // The paper's median is the interpolated 50th percentile: of 0.5 and 1 (even count), 0.75.
    const std::vector<glm::vec3> even = {glm::vec3(0.5f), glm::vec3(1.0f), glm::vec3(8.0f),
                                         glm::vec3(0.25f)};
    EXPECT_NEAR(hdrFlipExposureRange(even).stop, std::log2(xMax / 0.75), 1e-6);
    // Luminance is Rec. 709's: pure green 1 is luminance 0.7152.
    const std::vector<glm::vec3> green = {glm::vec3(0, 1, 0), glm::vec3(0, 0.5f, 0),
                                          glm::vec3(0, 0.25f, 0)};
    EXPECT_NEAR(hdrFlipExposureRange(green).start, std::log2(xMax / 0.7152), 1e-6);
    // Uniform: max = median, a single exposure; black: nothing to expose, one exposure at 0.
    const ExposureRange flat = hdrFlipExposureRange(std::vector<glm::vec3>(9, glm::vec3(2.0f)));
    EXPECT_EQ(flat.count, 1u);
    EXPECT_EQ(flat.start, flat.stop);
    const ExposureRange black = hdrFlipExposureRange(std::vector<glm::vec3>(9, glm::vec3(0.0f)));
    EXPECT_EQ(black.count, 1u);
    EXPECT_EQ(black.start, 0.0);
}

// Over half the frame black (a scene against an empty sky) would make the paper's stop exposure
// infinite; the median of the lit pixels stands in.
TEST(HdrFlip, MostlyBlackReferenceHasAFiniteRange) {
    std::vector<glm::vec3> img(10, glm::vec3(0.0f));
    img[0] = glm::vec3(4.0f);
    img[1] = glm::vec3(1.0f);
    img[2] = glm::vec3(1.0f);
    const ExposureRange r = hdrFlipExposureRange(img);
    const double xMax = hdrFlipAcesInverse(0.85);
    EXPECT_NEAR(r.stop, std::log2(xMax / 1.0), 1e-6);
    EXPECT_EQ(r.count, 2u);
}

TEST(HdrFlip, IdenticalIsZeroBrighterIsWorse) {
    const uint32_t w = 48, h = 32;
    const auto ref = hdrNoise(w, h, 7);
    const HdrFlipResult same = hdrFlip(ref, ref, w, h);
    EXPECT_GE(same.exposures.count, 2u);
    for (float e : same.error)
        ASSERT_EQ(e, 0.0f);
    const double twice = summarizeError(hdrFlip(scaled(ref, 2.0f), ref, w, h).error).mean;
    const double four = summarizeError(hdrFlip(scaled(ref, 4.0f), ref, w, h).error).mean;
    std::printf("HDR-FLIP of x2: %.4f, of x4: %.4f\n", twice, four);
    EXPECT_GT(twice, 0.02);
    EXPECT_GT(four, twice * 1.2);
}

// The maximum over exposures: never below LDR-FLIP at any one of them.
TEST(HdrFlip, IsTheMaximumOverItsExposures) {
    const uint32_t w = 40, h = 24;
    const auto ref = hdrNoise(w, h, 8), test = hdrNoise(w, h, 9);
    const HdrFlipResult hdr = hdrFlip(test, ref, w, h);
    const ExposureRange& r = hdr.exposures;
    const double step = (r.stop - r.start) / double(r.count - 1);
    for (uint32_t i = 0; i < r.count; ++i) {
        const double s = std::exp2(r.start + step * i);
        const ToneMap tm = [s](const glm::vec3& c) {
            return glm::vec3(float(hdrFlipAces(s * c.x)), float(hdrFlipAces(s * c.y)),
                             float(hdrFlipAces(s * c.z)));
        };
        const auto ldr = toneMappedLdrFlip(test, ref, w, h, tm);
        for (size_t p = 0; p < ldr.size(); ++p) {
            ASSERT_GE(hdr.error[p], ldr[p]);
            if (hdr.exposureIndex[p] == i) {
                ASSERT_EQ(hdr.error[p], ldr[p]);
            }
        }
    }
}

// Not symmetric: the exposures come from the reference. A frame twice as bright as its reference
// is judged over the reference's (darker) range; swapped, over the brighter one's.
TEST(HdrFlip, DependsOnWhichIsTheReference) {
    const uint32_t w = 48, h = 32;
    const auto dark = hdrNoise(w, h, 10), bright = scaled(dark, 2.0f);
    const HdrFlipResult a = hdrFlip(bright, dark, w, h), b = hdrFlip(dark, bright, w, h);
    EXPECT_NEAR(a.exposures.start - b.exposures.start, 1.0, 1e-5);
    EXPECT_NE(summarizeError(a.error).mean, summarizeError(b.error).mean);
}

} // namespace pnb::reference::test

namespace pnb::reference::test {

// A 480x270 frame (issue 40's size): one LDR-FLIP per exposure, on all cores. Printed for the
// record; the bound only catches a regression by an order of magnitude.
TEST(HdrFlip, Frame480x270Time) {
    const auto ref = hdrNoise(480, 270, 12), test = scaled(ref, 1.5f);
    const auto start = std::chrono::steady_clock::now();
    const HdrFlipResult r = hdrFlip(test, ref, 480, 270);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("HDR-FLIP 480x270, %u exposures: %.3f s\n", r.exposures.count, seconds);
    EXPECT_LT(seconds, 5.0 * r.exposures.count);
}

} // namespace pnb::reference::test
