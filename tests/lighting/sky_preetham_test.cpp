// Preetham 1999 daylight sky: hand-computed values, sun-side brightening, range, below-horizon
// fade.
#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "pnb_lighting/sh9.h"
#include "pnb_lighting/sky_preetham.h"

namespace pnb::lighting {
namespace {

constexpr double kPi = std::numbers::pi;

double deg(double d) {
    return d * kPi / 180.0;
}
glm::dvec3 dirAt(double elevationDeg, double azimuthDeg) { // azimuth from +X towards +Z
    double e = deg(elevationDeg), a = deg(azimuthDeg);
    return {std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a)};
}
double rec709Luminance(const glm::dvec3& rgb) {
    return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z;
}

TEST(SkyPreetham, MatchesValuesComputedFromThePaperByHand) {
    // T = 3, sun at elevation 30 degrees (theta_s = 60 deg = 1.047198 rad), azimuth +X.
    //   chi = (4/9 - 3/120)(pi - 2 theta_s) = 0.419444 * 1.047198 = 0.439241, tan chi = 0.469854
    //   Y_z = (4.0453*3 - 4.9710) 0.469854 - 0.2155*3 + 2.4192 = 7.1649 * 0.469854 + 1.7727
    //       = 5.139156 kcd/m^2 -> 5139.16 nits
    //   x_z = 0.244929, y_z = 0.252573 (the cubic tables at theta_s = 1.047198)
    //   Y coefficients: A = -0.9269, B = -0.6387, C = 5.2570, D = -2.2153, E = 0.1693
    //   F(0, theta_s) = (1 + A e^B)(1 + C e^{D theta_s} + E cos^2 theta_s) = 0.796064
    //   elevation 10, towards the sun (gamma = 20 deg): F = 3.491821 -> Y = 22542.18 nits
    //   elevation 10, away (gamma = 140 deg):           F = 1.096487 -> Y = 7078.60 nits
    //   elevation 30, azimuth 90 (gamma = 75.52 deg):   F = 0.959729 -> Y = 6195.73 nits
    PreethamSky sky({.turbidity = 3.0, .sunDirection = dirAt(30, 0)});
    EXPECT_NEAR(sky.zenithLuminance(), 5139.156, 0.01);
    EXPECT_NEAR(sky.zenithChromaticity().x, 0.244929, 1e-6);
    EXPECT_NEAR(sky.zenithChromaticity().y, 0.252573, 1e-6);
    EXPECT_NEAR(sky.luminance({0, 1, 0}), 5139.156, 0.01);
    EXPECT_NEAR(sky.luminance(dirAt(10, 0)), 22542.18, 0.05);
    EXPECT_NEAR(sky.luminance(dirAt(10, 180)), 7078.60, 0.05);
    EXPECT_NEAR(sky.luminance(dirAt(30, 90)), 6195.73, 0.05);
    // The colour conversion keeps the luminance (no clipping for a clear sky) and is blue.
    glm::dvec3 zenith = sky.radiance({0, 1, 0});
    EXPECT_NEAR(rec709Luminance(zenith), 5139.156, 0.5);
    EXPECT_GT(zenith.b, zenith.r);
}

TEST(SkyPreetham, BrighterOnTheSunSideAndTowardsTheSun) {
    for (double t : {2.0, 4.0, 7.0, 10.0})
        for (double elev : {5.0, 30.0, 60.0}) {
            PreethamSky sky({.turbidity = t, .sunDirection = dirAt(elev, 40)});
            for (double viewElev : {5.0, 20.0, 45.0}) {
                EXPECT_GT(sky.luminance(dirAt(viewElev, 40)), sky.luminance(dirAt(viewElev, 220)))
                    << "T=" << t << " sun " << elev << " view " << viewElev;
                EXPECT_GT(rec709Luminance(sky.radiance(dirAt(viewElev, 40))),
                          rec709Luminance(sky.radiance(dirAt(viewElev, 220))));
            }
            // Circumsolar: 5 degrees from the sun is brighter than 30 degrees from it.
            EXPECT_GT(sky.luminance(dirAt(elev + 5.0, 40)), sky.luminance(dirAt(elev + 30.0, 40)));
        }
    // A higher sun gives a brighter zenith.
    EXPECT_GT(PreethamSky({.sunDirection = dirAt(60, 0)}).zenithLuminance(),
              PreethamSky({.sunDirection = dirAt(20, 0)}).zenithLuminance());
}

TEST(SkyPreetham, FiniteAndNonNegativeForEveryTurbidityAndSunElevation) {
    const glm::dvec3 views[] = {{0, 1, 0},       dirAt(0, 0),     dirAt(0, 180),
                                dirAt(0.01, 90), dirAt(-0.01, 0), {0, -1, 0},
                                dirAt(45, 0),    dirAt(45, 135),  dirAt(80, 300)};
    for (double t = 2.0; t <= 10.0; t += 1.0)
        for (double elev = -10.0; elev <= 90.0; elev += 1.0) {
            PreethamSky sky({.turbidity = t,
                             .sunDirection = dirAt(elev, 0),
                             .sunIlluminance = glm::dvec3(1e5)});
            ASSERT_TRUE(std::isfinite(sky.zenithLuminance()));
            EXPECT_GE(sky.zenithLuminance(), 0.0);
            for (const glm::dvec3& v : views) {
                glm::dvec3 r = sky.radiance(v);
                for (int c = 0; c < 3; ++c) {
                    ASSERT_TRUE(std::isfinite(r[c])) << t << " " << elev;
                    EXPECT_GE(r[c], 0.0);
                }
                ASSERT_TRUE(std::isfinite(sky.luminance(v)));
            }
            // Looking straight at the sun (where exp(D gamma) peaks) stays finite too.
            if (elev >= 0.0) {
                ASSERT_TRUE(std::isfinite(sky.radiance(dirAt(elev, 0)).g));
            }
        }
}

TEST(SkyPreetham, BelowTheHorizonTheSkyFadesToBlackBySixDegrees) {
    PreethamSky horizon({.sunDirection = dirAt(0, 70)});
    PreethamSky dusk({.sunDirection = dirAt(-3, 70)});
    PreethamSky night({.sunDirection = dirAt(-6, 70), .sunIlluminance = glm::dvec3(1e5)});
    PreethamSky deep({.sunDirection = dirAt(-10, 70)});
    EXPECT_DOUBLE_EQ(horizon.fade(), 1.0);
    EXPECT_NEAR(dusk.fade(), 0.5, 1e-12);
    EXPECT_NEAR(dusk.modelSunDirection().y, 0.0, 1e-12);
    for (const glm::dvec3& v : {glm::dvec3(0, 1, 0), dirAt(10, 70), dirAt(30, 200)}) {
        EXPECT_NEAR(dusk.luminance(v), 0.5 * horizon.luminance(v), 1e-9 * horizon.luminance(v));
        EXPECT_EQ(night.radiance(v), glm::dvec3(0.0));
        EXPECT_EQ(deep.radiance(v), glm::dvec3(0.0));
    }
    EXPECT_EQ(night.groundRadiance(), glm::dvec3(0.0)); // no sky and the sun is below the ground
    // Continuous through sunset.
    PreethamSky above({.sunDirection = dirAt(0.001, 70)}),
        below({.sunDirection = dirAt(-0.001, 70)});
    EXPECT_NEAR(above.luminance(dirAt(20, 10)), below.luminance(dirAt(20, 10)),
                1e-3 * above.luminance(dirAt(20, 10)));
}

TEST(SkyPreetham, GroundIsTheAlbedoLitConstantAndTheShProjectionAgrees) {
    const glm::dvec3 sunLux(1e5, 0.95e5, 0.9e5);
    PreethamSky sky({.turbidity = 2.5,
                     .sunDirection = dirAt(40, 30),
                     .groundAlbedo = glm::dvec3(0.3, 0.2, 0.1),
                     .sunIlluminance = sunLux});
    // Independent midpoint quadrature of the sky's horizontal irradiance.
    glm::dvec3 e(0.0);
    const int n = 400, nPhi = 800;
    for (int i = 0; i < n; ++i) {
        double mu = (i + 0.5) / n, s = std::sqrt(1.0 - mu * mu);
        for (int j = 0; j < nPhi; ++j) {
            double phi = 2.0 * kPi * (j + 0.5) / nPhi;
            e += sky.radiance({s * std::cos(phi), mu, s * std::sin(phi)}) * mu;
        }
    }
    e *= (1.0 / n) * (2.0 * kPi / nPhi);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(sky.skyHorizontalIlluminance()[c] / e[c], 1.0, 2e-3);
    // Daylight magnitudes: a clear sky gives ~1e4 lux on the ground.
    EXPECT_GT(rec709Luminance(e), 5e3);
    EXPECT_LT(rec709Luminance(e), 5e4);
    glm::dvec3 expected = glm::dvec3(0.3, 0.2, 0.1) *
                          (sky.skyHorizontalIlluminance() + sunLux * std::sin(deg(40))) / kPi;
    for (const glm::dvec3& v : {glm::dvec3(0, -1, 0), dirAt(-0.5, 10), dirAt(-60, 200)})
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(sky.radiance(v)[c], expected[c], 1e-9 * expected[c]);
    // The diffuse IBL path: project the sky (ground included) on SH; the irradiance of an upward
    // surface is the sky's horizontal illuminance within the order-2 truncation (2%).
    Sh9Rgb sh = sh9ProjectFunction([&](const glm::dvec3& w) { return sky.radiance(w); }, 32);
    glm::dvec3 up = sh9Irradiance(sh, {0, 1, 0}, ShWindow::None);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(up[c] / sky.skyHorizontalIlluminance()[c], 1.0, 0.02); // measured <= 0.7%
}

TEST(SkyPreetham, GarbageInputsStayFinite) {
    const double nan = std::numeric_limits<double>::quiet_NaN(),
                 inf = std::numeric_limits<double>::infinity();
    PreethamSky a({.turbidity = nan,
                   .sunDirection = glm::dvec3(0.0),
                   .groundAlbedo = glm::dvec3(nan),
                   .sunIlluminance = glm::dvec3(inf)});
    EXPECT_DOUBLE_EQ(a.turbidity(), 3.0);
    EXPECT_EQ(a.modelSunDirection(), glm::dvec3(0, 1, 0));
    PreethamSky b({.turbidity = 1e9, .sunDirection = glm::dvec3(nan, 1, 0)});
    EXPECT_DOUBLE_EQ(b.turbidity(), 10.0);
    for (const PreethamSky* s : {&a, &b}) {
        for (const glm::dvec3& v : {glm::dvec3(0.0), glm::dvec3(nan), glm::dvec3(0, -1, 0),
                                    glm::dvec3(1e300, 1e300, 0)}) {
            glm::dvec3 r = s->radiance(v);
            for (int c = 0; c < 3; ++c)
                EXPECT_TRUE(std::isfinite(r[c]) && r[c] >= 0.0);
            EXPECT_TRUE(std::isfinite(s->luminance(v)));
        }
    }
    EXPECT_EQ(xyYToLinearRec709(0.3, 0.0, 1.0), glm::dvec3(0.0));
    EXPECT_TRUE(std::isfinite(perezF(preethamCoefficients(2.0)[0], 0.0, nan)));
}

} // namespace
} // namespace pnb::lighting
