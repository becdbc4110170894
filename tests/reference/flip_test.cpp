// LDR-FLIP (HPG 2020) and the player's tone map (flip.h): the papers' constants and the cases
// whose answer follows from the definitions, each with where the expectation comes from.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "flip_filter.h" // reference/src: the separable filter checked against its 2D definition
#include "pnb_reference/flip.h"
#include "pnb_reference/image_error.h"

namespace pnb::reference::test {

namespace {

std::vector<glm::vec3> uniform(uint32_t w, uint32_t h, glm::vec3 c) {
    return std::vector<glm::vec3>(size_t(w) * h, c);
}

std::vector<glm::vec3> noise(uint32_t w, uint32_t h, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<glm::vec3> img(size_t(w) * h);
    for (auto& c : img)
        c = {u(rng), u(rng), u(rng)};
    return img;
}

double mean(const std::vector<float>& v) {
    return summarizeError(v).mean;
}

// CIELab of a linear-RGB colour, written out here from the CIE 1976 definition (D65, sRGB's
// matrix), independently of flip_color.cpp.
glm::dvec3 cielab(glm::dvec3 rgb) {
    const double X = 0.4124564 * rgb.x + 0.3575761 * rgb.y + 0.1804375 * rgb.z;
    const double Y = 0.2126729 * rgb.x + 0.7151522 * rgb.y + 0.0721750 * rgb.z;
    const double Z = 0.0193339 * rgb.x + 0.1191920 * rgb.y + 0.9503041 * rgb.z;
    auto f = [](double t) {
        return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0;
    };
    const double fx = f(X / 0.95047), fy = f(Y), fz = f(Z / 1.08883);
    return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

} // namespace

// The separable correlation equals the 2D kernel kx[i] ky[j] applied directly, edges repeated.
TEST(Flip, SeparableFilterEqualsTheDirect2DKernel) {
    const uint32_t w = 23, h = 17;
    flip_detail::Plane in(w, h);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (float& v : in.v)
        v = u(rng);
    const std::vector<float> kx = {0.1f, -0.4f, 0.2f, 0.7f, 0.3f}, ky = {0.25f, 0.5f, -0.25f};
    const flip_detail::Plane out = flip_detail::correlateSeparable(in, kx, ky);
    for (int y = 0; y < int(h); ++y)
        for (int x = 0; x < int(w); ++x) {
            double direct = 0.0;
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 5; ++i) {
                    const int sx = std::clamp(x + i - 2, 0, int(w) - 1),
                              sy = std::clamp(y + j - 1, 0, int(h) - 1);
                    direct +=
                        double(kx[size_t(i)]) * ky[size_t(j)] * in.v[size_t(sy) * w + size_t(sx)];
                }
            ASSERT_NEAR(out.v[size_t(y) * w + size_t(x)], direct, 1e-5) << x << "," << y;
        }
}

// HPG 2020 §3 / EG 2021: 0.7 m from a 0.7 m wide 4K monitor is 67 pixels per degree.
TEST(Flip, DefaultObserverIs67PixelsPerDegree) {
    EXPECT_NEAR(defaultPixelsPerDegree(), 3840.0 * std::numbers::pi / 180.0, 1e-12);
    EXPECT_NEAR(defaultPixelsPerDegree(), 67.0206, 1e-4);
    EXPECT_NEAR(pixelsPerDegree(1.4, 3840.0, 0.7), 2.0 * defaultPixelsPerDegree(), 1e-9);
}

// HPG 2020 §4.2: c_max is the HyAB distance of Hunt-adjusted green and blue to the power q_c.
// Here from the textbook CIELab of sRGB green (87.74, -86.18, 83.18) and blue (32.30, 79.19,
// -107.86), computed independently above: 203.3^0.7 = 41.3.
TEST(Flip, ColorMaxIsHuntAdjustedGreenToBlue) {
    const glm::dvec3 g = cielab({0, 1, 0}), b = cielab({0, 0, 1});
    EXPECT_NEAR(g.x, 87.74, 0.01);
    EXPECT_NEAR(b.z, -107.86, 0.01);
    auto hunt = [](glm::dvec3 lab) {
        return glm::dvec3(lab.x, 0.01 * lab.x * lab.y, 0.01 * lab.x * lab.z);
    };
    const glm::dvec3 hg = hunt(g), hb = hunt(b);
    const double distance = std::abs(hg.x - hb.x) + std::hypot(hg.y - hb.y, hg.z - hb.z);
    EXPECT_NEAR(distance, 203.30, 0.02);
    EXPECT_NEAR(flipColorMax(), std::pow(distance, 0.7), 1e-3 * flipColorMax());
    EXPECT_NEAR(flipColorMax(), 41.3, 0.05);
}

// HPG 2020 §4.2: [0, p_c c_max] -> [0, p_t] and [p_c c_max, c_max] -> [p_t, 1], p_c 0.4, p_t 0.95.
TEST(Flip, ColorCompressionKnee) {
    const double cmax = flipColorMax();
    EXPECT_DOUBLE_EQ(flipCompressColor(0.0), 0.0);
    EXPECT_NEAR(flipCompressColor(0.2 * cmax), 0.475, 1e-12);
    EXPECT_NEAR(flipCompressColor(0.4 * cmax), 0.95, 1e-12);
    EXPECT_NEAR(flipCompressColor(0.7 * cmax), 0.975, 1e-12);
    EXPECT_NEAR(flipCompressColor(cmax), 1.0, 1e-12);
}

TEST(Flip, IdenticalImagesAreZero) {
    const auto img = noise(64, 48, 1);
    const LdrFlipParts parts = ldrFlipParts(img, img, 64, 48);
    ASSERT_EQ(parts.error.size(), img.size());
    for (size_t p = 0; p < img.size(); ++p) {
        ASSERT_EQ(parts.color[p], 0.0f);
        ASSERT_EQ(parts.feature[p], 0.0f);
        ASSERT_EQ(parts.error[p], 0.0f);
    }
}

// The c_max normalisation: a uniform green image against a uniform blue one is the largest colour
// difference, 1, with no feature difference (neither has an edge), so FLIP is 1 everywhere.
TEST(Flip, GreenAgainstBlueIsTheMaximumColorError) {
    const auto green = uniform(48, 32, {0, 1, 0}), blue = uniform(48, 32, {0, 0, 1});
    const LdrFlipParts parts = ldrFlipParts(green, blue, 48, 32);
    for (size_t p = 0; p < green.size(); ++p) {
        ASSERT_NEAR(parts.color[p], 1.0, 1e-4) << p;
        ASSERT_NEAR(parts.feature[p], 0.0, 1e-3) << p;
        ASSERT_NEAR(parts.error[p], 1.0, 1e-3) << p;
    }
    // Black against white is far but not the farthest: HyAB 100, (100/203.4)^0.7 of the way.
    const auto black = uniform(48, 32, {0, 0, 0}), white = uniform(48, 32, {1, 1, 1});
    const double expected = flipCompressColor(std::pow(100.0, 0.7));
    EXPECT_NEAR(mean(ldrFlip(black, white, 48, 32)), expected, 1e-3);
    EXPECT_NEAR(expected, 0.967,
                1e-3); // above the knee: 0.95 + (25.12 - 16.51) / (41.28 - 16.51) * 0.05
}

// Out-of-range inputs are clamped and NaN reads as black, so one bad pixel cannot poison the map.
TEST(Flip, NonFiniteAndOutOfRangeInputsStayLocal) {
    auto img = noise(32, 32, 6), bad = img;
    bad[100] = glm::vec3(std::numeric_limits<float>::quiet_NaN());
    bad[200] = glm::vec3(std::numeric_limits<float>::infinity(), -3.0f, 7.0f);
    const auto map = ldrFlip(bad, img, 32, 32);
    auto zeroed = img;
    zeroed[100] = glm::vec3(0.0f);
    zeroed[200] = glm::vec3(1.0f, 0.0f, 1.0f);
    const auto expected = ldrFlip(zeroed, img, 32, 32);
    for (size_t p = 0; p < map.size(); ++p)
        ASSERT_EQ(map[p], expected[p]) << p;
    EXPECT_EQ(map[500], 0.0f); // far from both
}

// Every term is symmetric (HyAB, |edge_t - edge_r|, ...), so LDR-FLIP does not care which image
// is the reference (HDR-FLIP does: its exposures come from the reference; see flip_hdr_test).
TEST(Flip, LdrFlipIsSymmetricAndInUnitRange) {
    const auto a = noise(64, 40, 2), b = noise(64, 40, 3);
    const auto ab = ldrFlip(a, b, 64, 40), ba = ldrFlip(b, a, 64, 40);
    for (size_t p = 0; p < ab.size(); ++p) {
        ASSERT_NEAR(ab[p], ba[p], 1e-5);
        ASSERT_GE(ab[p], 0.0f);
        ASSERT_LE(ab[p], 1.0f);
    }
    EXPECT_GT(mean(ab), 0.2); // two unrelated noise images are far apart
}

// The feature detectors' weights sum to zero, so a change of flat grey has no feature error,
// while moving an edge by one pixel has one, along the edge only.
TEST(Flip, FeaturesSeeEdgesNotFlatShifts) {
    const uint32_t w = 64, h = 32;
    const LdrFlipParts flat =
        ldrFlipParts(uniform(w, h, glm::vec3(0.3f)), uniform(w, h, glm::vec3(0.5f)), w, h);
    for (float f : flat.feature)
        ASSERT_LT(f, 2e-3);
    EXPECT_GT(mean(flat.color), 0.05);

    auto edgeAt = [&](uint32_t column) {
        std::vector<glm::vec3> img(size_t(w) * h);
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x)
                img[size_t(y) * w + x] = glm::vec3(x < column ? 0.1f : 0.8f);
        return img;
    };
    // Pixel 32 lies half a pixel from both edges (responses equal); its neighbours do not.
    const LdrFlipParts moved = ldrFlipParts(edgeAt(32), edgeAt(33), w, h);
    const size_t row = 16 * w;
    EXPECT_GT(moved.feature[row + 31], 0.3);
    EXPECT_GT(moved.feature[row + 33], 0.3);
    EXPECT_LT(moved.feature[row + 5], 1e-3);
    EXPECT_LT(moved.feature[row + 60], 1e-3);
    EXPECT_GT(moved.error[row + 31],
              moved.color[row + 31] + 0.05); // the feature lifts the colour error
}

// The same light added as one bright speck or spread smoothly over a Gaussian blob (equal sum of
// differences): the speck's error is far higher where it is. The map's mean goes the other way
// (documented in REFERENCE.md): q_c = 0.7 < 1 makes the colour error concave, so the blob's many
// faint pixels add up to more than the one strong one; the mean counts how much of the image
// differs, the peak and the weighted quartiles how strongly. At equal squared error
// (equal MSE) it goes the other way: the blob is then 4 sqrt(pi) = 7x the speck's energy, and a
// one-pixel speck is 0.015 degrees at 67 ppd, which the achromatic CSF blurs to a fraction of its
// contrast; FLIP says what is seen, which MSE does not.
TEST(Flip, OnePixelSpeckAgainstTheSameLightSpreadSmoothly) {
    const uint32_t w = 64, h = 64;
    const auto grey = uniform(w, h, glm::vec3(0.2f));
    auto speck = grey;
    const float peak = 0.6f;
    speck[size_t(32) * w + 32] += glm::vec3(peak);
    // d = A exp(-r^2 / (2 s^2)): sum d = A 2 pi s^2, sum d^2 = A^2 pi s^2.
    const double s = 4.0;
    auto blob = [&](double amplitude) {
        auto img = grey;
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                const double r2 =
                    (double(x) - 32) * (double(x) - 32) + (double(y) - 32) * (double(y) - 32);
                img[size_t(y) * w + x] += glm::vec3(float(amplitude * std::exp(-r2 / (2 * s * s))));
            }
        return img;
    };
    const auto sameLight = blob(peak / (2.0 * std::numbers::pi * s * s));
    const auto sameMse = blob(peak / (std::sqrt(std::numbers::pi) * s));
    auto sums = [&](const std::vector<glm::vec3>& img) {
        double l1 = 0, l2 = 0;
        for (size_t p = 0; p < img.size(); ++p) {
            l1 += img[p].x - grey[p].x;
            l2 += std::pow(img[p].x - grey[p].x, 2.0);
        }
        return std::pair{l1, l2};
    };
    ASSERT_NEAR(sums(sameLight).first / sums(speck).first, 1.0, 0.01);
    ASSERT_NEAR(sums(sameMse).second / sums(speck).second, 1.0, 0.01);
    const auto flipSpeck = summarizeError(ldrFlip(speck, grey, w, h));
    const auto flipLight = summarizeError(ldrFlip(sameLight, grey, w, h));
    const auto flipMse = summarizeError(ldrFlip(sameMse, grey, w, h));
    std::printf(
        "speck: mean %.5f max %.4f; same light: mean %.5f max %.4f; same MSE: mean %.5f max %.4f\n",
        flipSpeck.mean, flipSpeck.max, flipLight.mean, flipLight.max, flipMse.mean, flipMse.max);
    EXPECT_GT(flipSpeck.max, 3.0 * flipLight.max);
    EXPECT_GT(flipLight.mean, flipSpeck.mean);
    EXPECT_GT(flipMse.mean, 5.0 * flipSpeck.mean);
}

// The CSFs are sized in degrees: seen from twice as far (twice the pixels per degree) a one-pixel
// speck is blurred over more pixels and its error falls.
TEST(Flip, FartherObserverSeesLessOfASpeck) {
    const uint32_t w = 64, h = 64;
    const auto grey = uniform(w, h, glm::vec3(0.2f));
    auto speck = grey;
    speck[size_t(32) * w + 32] = glm::vec3(0.2f, 0.6f, 0.2f);
    const double near = summarizeError(ldrFlip(speck, grey, w, h, 67.0)).max;
    const double far = summarizeError(ldrFlip(speck, grey, w, h, 134.0)).max;
    EXPECT_LT(far, 0.8 * near);
}

TEST(Flip, SrgbTransferRoundTrips) {
    for (float v : {0.0f, 0.002f, 0.04f, 0.2f, 0.5f, 1.0f})
        EXPECT_NEAR(srgbToLinear(linearToSrgb(v)), v, 1e-6);
    EXPECT_NEAR(srgbToLinear(0.5f), 0.21404, 1e-5); // IEC 61966-2-1
}

// The player's displayed image, shaders/tonemap.frag: the same formula (the shader file is read to
// catch a coefficient changed on one side only) and its fixed points.
TEST(Flip, PlayerToneMapIsTonemapFrag) {
    std::ifstream shader(std::string(PNB_SHADER_DIR) + "/tonemap.frag");
    ASSERT_TRUE(shader) << PNB_SHADER_DIR;
    std::stringstream text;
    text << shader.rdbuf();
    for (const char* term : {"(x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0)",
                             "texture(uHdr, vUv).rgb * uExposure, vec3(65504.0))"})
        EXPECT_NE(text.str().find(term), std::string::npos)
            << "tonemap.frag no longer has: " << term;
    const double x = 0.18 * 2.0;
    EXPECT_NEAR(playerToneMap(glm::vec3(0.18f), 2.0).x,
                x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 1e-6);
    EXPECT_EQ(playerToneMap(glm::vec3(0.0f), 1.0), glm::vec3(0.0f));
    EXPECT_EQ(playerToneMap(glm::vec3(1e30f), 1.0), glm::vec3(1.0f));
    EXPECT_EQ(playerToneMap(glm::vec3(std::numeric_limits<float>::infinity()), 1.0),
              glm::vec3(1.0f));
}

// frame_flip_ldr's behaviour: two different HDR frames both burnt to white by a high exposure look
// the same; at a normal exposure they differ.
TEST(Flip, PlayerLdrFlipSeesWhatTheExposureShows) {
    const uint32_t w = 32, h = 32;
    const auto a = uniform(w, h, glm::vec3(100.0f)), b = uniform(w, h, glm::vec3(200.0f));
    EXPECT_LT(mean(playerLdrFlip(a, b, w, h, 1000.0)), 1e-4);
    EXPECT_GT(mean(playerLdrFlip(a, b, w, h, 0.005)), 0.05);
    // The same as LDR-FLIP of the tone-mapped images, sRGB encoding being undone by FLIP itself.
    std::vector<glm::vec3> ta, tb;
    for (size_t p = 0; p < a.size(); ++p) {
        ta.push_back(playerToneMap(a[p], 0.005));
        tb.push_back(playerToneMap(b[p], 0.005));
    }
    EXPECT_NEAR(mean(playerLdrFlip(a, b, w, h, 0.005)), mean(ldrFlip(ta, tb, w, h)), 1e-7);
}

// Issue 40's budget: a 480x270 frame well under a second (separable filters). Printed for the
// record; the bound only catches a non-separable regression (and leaves room for sanitizers).
TEST(Flip, Frame480x270IsFast) {
    const auto a = noise(480, 270, 4), b = noise(480, 270, 5);
    const auto start = std::chrono::steady_clock::now();
    const auto map = ldrFlip(a, b, 480, 270);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("LDR-FLIP 480x270: %.3f s\n", seconds);
    ASSERT_EQ(map.size(), size_t(480) * 270);
    EXPECT_LT(seconds, 5.0);
}

} // namespace pnb::reference::test
