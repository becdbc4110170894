// pnb_lighting/brdf.h (the twin of shaders/include/brdf.glsl) and tonemap.h (the twin of
// shaders/tonemap.frag): the BRDF reflects no more than it receives (its directional albedo,
// integrated by Monte Carlo, is <= 1 for metals and views within 45 degrees, about 1 for a white
// dielectric seen head-on; above 1 for dielectrics at grazing views, pinned), is reciprocal, and peaks where GGX says; the tone map's fixed points.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "pnb_lighting/brdf.h"
#include "pnb_lighting/tonemap.h"

namespace pnb::lighting {
namespace {

constexpr double kPi = std::numbers::pi;

// A small, seeded generator: the tests give the same numbers on every run.
struct Random {
    uint64_t state;
    double next() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) * (1.0 / 9007199254740992.0);
    }
};

glm::vec3 unitFromAngles(double cosTheta, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    return glm::vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(cosTheta));
}

struct Albedo {
    double mean, standardError;
};

// The directional albedo rho(v) = integral of f(l, v) (n.l) dl over the hemisphere (n = +Z),
// estimated with a 50/50 mix of GGX half-vector sampling and cosine sampling (the combined pdf:
// low variance from the diffuse floor to a 0.03-rough mirror), first channel.
Albedo directionalAlbedo(glm::vec3 base, float metallic, float roughness, glm::vec3 v, int samples, uint64_t seed) {
    Random rng{seed};
    const glm::vec3 n(0, 0, 1);
    const double alpha = double(roughness) * roughness, a2 = alpha * alpha;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < samples; ++i) {
        glm::vec3 l;
        const double u1 = rng.next(), u2 = rng.next(), phi = 2 * kPi * rng.next();
        if (u1 < 0.5) {
            const double cosH = std::sqrt((1 - u2) / (1 + (a2 - 1) * u2));
            const glm::vec3 h = unitFromAngles(cosH, phi);
            l = glm::normalize(2.0f * glm::dot(v, h) * h - v);
        } else {
            l = unitFromAngles(std::sqrt(u2), phi);
        }
        double value = 0;
        if (l.z > 0) {
            const glm::vec3 h = glm::normalize(v + l);
            const double pdfGgx = distributionGgx(h.z, float(alpha)) * h.z / (4.0 * std::max(double(glm::dot(v, h)), 1e-9));
            const double pdf = 0.5 * pdfGgx + 0.5 * l.z / kPi;
            value = double(evaluateBrdf(base, metallic, roughness, n, v, l).x) * l.z / pdf;
        }
        sum += value;
        sum2 += value * value;
    }
    const double m = sum / samples;
    return {m, std::sqrt(std::max(0.0, sum2 / samples - m * m) / (samples - 1))};
}

// Metals (the GGX lobe alone) never reflect more than they receive, and neither does anything
// seen within 45 degrees of the normal. Dielectrics seen at grazing angles DO: glTF's (1 - F(v.h))
// weighting of the diffuse lobe takes back less than the specular lobe, which is large there,
// adds; the albedo of a white, smooth dielectric at cos(view) = 0.05 is about 1.7. The player and
// the truth share this BRDF, so the whole-frame truth inherits it (docs/REFERENCE.md "The whole
// frame"); the test pins where it happens and how far, so a change to the formulas shows.
TEST(Brdf, ReflectsNoMoreThanItReceivesExceptDielectricsAtGrazingViews) {
    double worstGrazing = 0;
    for (float roughness : {0.03f, 0.1f, 0.3f, 0.6f, 1.0f})
        for (float metallic : {0.0f, 0.5f, 1.0f})
            for (double cosView : {1.0, 0.7, 0.3, 0.05}) {
                const glm::vec3 v = unitFromAngles(cosView, 0.4);
                const Albedo a = directionalAlbedo(glm::vec3(1.0f), metallic, roughness, v, 20000,
                                                   uint64_t(roughness * 1000) * 7 + uint64_t(metallic * 10) * 3 +
                                                       uint64_t(cosView * 100));
                const bool conserves = metallic == 1.0f || cosView >= 0.7;
                if (conserves)
                    EXPECT_LE(a.mean, 1.0 + 4.0 * a.standardError + 1e-3)
                        << "roughness " << roughness << " metallic " << metallic << " cos(view) " << cosView;
                else
                    worstGrazing = std::max(worstGrazing, a.mean);
                // Single-scattering GGX loses energy, at most 1 - (1 - ln 2) (alpha = 1, head-on).
                EXPECT_GT(a.mean, 0.25) << "roughness " << roughness << " metallic " << metallic << " cos(view) "
                                        << cosView;
            }
    EXPECT_GT(worstGrazing, 1.3); // the excess is real...
    EXPECT_LT(worstGrazing, 2.0); // ...and bounded
}

TEST(Brdf, AWhiteDielectricSeenHeadOnReflectsAlmostEverythingAndBaseColourScalesTheDiffuseLobe) {
    // (1 - F) Lambert + F GGX with F0 = 0.04: what the diffuse part loses to Fresnel the specular
    // part takes back, up to the single-scattering GGX's loss (a few per cent when rough).
    const Albedo white = directionalAlbedo(glm::vec3(1.0f), 0.0f, 1.0f, glm::vec3(0, 0, 1), 100000, 5);
    EXPECT_GT(white.mean, 0.95);
    EXPECT_LT(white.mean, 1.0 + 4.0 * white.standardError);
    // The closed form at alpha = 1, head-on: the specular lobe alone (a black dielectric) is
    // about 0.04 x (1 - ln 2); F there varies little, so well under 0.02.
    const Albedo black = directionalAlbedo(glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(0, 0, 1), 100000, 5);
    EXPECT_GT(black.mean, 0.005);
    EXPECT_LT(black.mean, 0.02);
    // Linear in the base colour (the same directions: the same seed).
    const Albedo grey = directionalAlbedo(glm::vec3(0.5f), 0.0f, 1.0f, glm::vec3(0, 0, 1), 100000, 5);
    EXPECT_NEAR(grey.mean, 0.5 * (white.mean + black.mean), 1e-6);
}

TEST(Brdf, IsReciprocal) {
    Random rng{42};
    const glm::vec3 n(0, 0, 1);
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 l = unitFromAngles(0.02 + 0.98 * rng.next(), 2 * kPi * rng.next());
        const glm::vec3 v = unitFromAngles(0.02 + 0.98 * rng.next(), 2 * kPi * rng.next());
        const glm::vec3 base(float(rng.next()), float(rng.next()), float(rng.next()));
        const float metallic = float(rng.next()), roughness = float(0.03 + 0.97 * rng.next());
        const glm::vec3 a = evaluateBrdf(base, metallic, roughness, n, v, l);
        const glm::vec3 b = evaluateBrdf(base, metallic, roughness, n, l, v);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 2e-5f * std::max(1.0f, a[c])) << i;
    }
}

TEST(Brdf, ShadeBrdfIsTheBrdfTimesLightTimesCosineAndZeroBelowTheSurface) {
    const glm::vec3 n(0, 0, 1), v = glm::normalize(glm::vec3(0.3f, 0.1f, 1.0f));
    const glm::vec3 l = glm::normalize(glm::vec3(-0.5f, 0.2f, 0.8f)), light(2.0f, 1.0f, 0.5f);
    const glm::vec3 f = evaluateBrdf(glm::vec3(0.8f, 0.5f, 0.2f), 0.3f, 0.4f, n, v, l);
    const glm::vec3 shaded = shadeBrdf(glm::vec3(0.8f, 0.5f, 0.2f), 0.3f, 0.4f, n, v, l, light);
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(shaded[c], f[c] * light[c] * l.z);
    EXPECT_EQ(evaluateBrdf(glm::vec3(1.0f), 0.0f, 0.5f, n, v, glm::vec3(0, 0.6f, -0.8f)), glm::vec3(0.0f));
    // GGX's peak: a mirror-like metal reflects most along the mirror direction.
    const glm::vec3 mirror(-v.x, -v.y, v.z);
    EXPECT_GT(evaluateBrdf(glm::vec3(1.0f), 1.0f, 0.1f, n, v, mirror).x,
              50.0f * evaluateBrdf(glm::vec3(1.0f), 1.0f, 0.1f, n, v, l).x);
}

TEST(Tonemap, MatchesTheShadersFixedPoints) {
    EXPECT_EQ(acesFitted(0.0f), 0.0f);
    EXPECT_EQ(acesFitted(1e6f), 1.0f);
    EXPECT_NEAR(acesFitted(1.0f), 2.54f / (2.43f + 0.59f + 0.14f), 1e-6f); // (2.51 + 0.03) / (3.16)
    EXPECT_NEAR(srgbEncode(0.5f), 0.735357f, 1e-5f);
    EXPECT_NEAR(srgbEncode(0.002f), 0.02584f, 1e-5f); // the linear segment
    EXPECT_NEAR(srgbEncode(2.0f), 1.0f, 1e-6f);
    // Exposure scales before the curve; infinity is white, NaN black.
    EXPECT_EQ(displayColor(glm::vec3(0.25f), 4.0f), displayColor(glm::vec3(1.0f), 1.0f));
    EXPECT_NEAR(displayColor(glm::vec3(INFINITY), 1.0f).x, 1.0f, 1e-6f);
    EXPECT_EQ(displayColor(glm::vec3(NAN), 1.0f), glm::vec3(0.0f));
}

} // namespace
} // namespace pnb::lighting
