// LPV numbers: SH constants, the projected cosine lobe, face solid angles, cascade placement.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "lpv_math.h"

namespace pnb::player {
namespace {

// Midpoint quadrature over the sphere in (cos theta, phi): exact enough for degree <= 2 integrands.
template <typename F>
double integrateSphere(F f, int n = 400) {
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        double z = -1.0 + (i + 0.5) * 2.0 / n, r = std::sqrt(1.0 - z * z);
        for (int j = 0; j < 2 * n; ++j) {
            double phi = (j + 0.5) * kPi / n;
            sum += f(glm::dvec3(r * std::cos(phi), r * std::sin(phi), z));
        }
    }
    return sum * (2.0 / n) * (kPi / n);
}

TEST(LpvMath, ShConstantsAreTheClosedForms) {
    EXPECT_NEAR(kShY0, 0.5 / std::sqrt(kPi), 1e-15);
    EXPECT_NEAR(kShY1, std::sqrt(3.0) / (2.0 * std::sqrt(kPi)), 1e-15);
    EXPECT_NEAR(kLobeC0, std::sqrt(kPi) / 2.0, 1e-15);
    EXPECT_NEAR(kLobeC1, std::sqrt(kPi / 3.0), 1e-15);
    EXPECT_NEAR(kShY0, 0.282095, 1e-6);
    EXPECT_NEAR(kShY1, 0.488603, 1e-6);
    EXPECT_NEAR(kLobeC0, 0.886227, 1e-6);
    EXPECT_NEAR(kLobeC1, 1.023327, 1e-6);
}

TEST(LpvMath, BasisIsOrthonormal) {
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
            double v = integrateSphere([&](glm::dvec3 w) { return shBasis(w)[a] * shBasis(w)[b]; });
            EXPECT_NEAR(v, a == b ? 1.0 : 0.0, 1e-4) << a << "," << b;
        }
}

TEST(LpvMath, CosineLobeIsTheProjectionOfTheClampedCosineAndIntegratesToPi) {
    const glm::dvec3 normals[] = {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}, glm::normalize(glm::dvec3(1, 2, -3))};
    for (glm::dvec3 n : normals) {
        Sh4 lobe = cosineLobe(n);
        EXPECT_NEAR(shIntegral(lobe), kPi, 1e-12);
        // Projection coefficient k = integral of max(0, n.w) * y_k(w).
        for (int k = 0; k < 4; ++k) {
            double proj = integrateSphere([&](glm::dvec3 w) { return std::max(0.0, glm::dot(n, w)) * shBasis(w)[k]; });
            EXPECT_NEAR(lobe[k], proj, 2e-4) << k;
        }
        // The lobe peaks along n and is lowest opposite it.
        EXPECT_GT(shEvaluate(lobe, n), shEvaluate(lobe, -n));
        EXPECT_NEAR(shEvaluate(lobe, n), kLobeC0 * kShY0 + kLobeC1 * kShY1, 1e-12);
    }
}

TEST(LpvMath, FaceSolidAnglesAreTheExactRectangleAngles) {
    // Unit cells; source centre at the origin, destination centre at (0, 0, 1).
    double farFace = rectangleSolidAngle(-0.5, 0.5, -0.5, 0.5, 1.5);
    double sideFace = rectangleSolidAngle(-0.5, 0.5, 0.5, 1.5, 0.5); // plane x = 0.5: (y, z)
    double nearFace = rectangleSolidAngle(-0.5, 0.5, -0.5, 0.5, 0.5);
    EXPECT_NEAR(farFace, kFarFaceSolidAngle, 1e-12);
    EXPECT_NEAR(sideFace, kSideFaceSolidAngle, 1e-12);
    EXPECT_NEAR(nearFace, 2.0 * kPi / 3.0, 1e-12);
    EXPECT_NEAR(kFarFaceSolidAngle + 4 * kSideFaceSolidAngle, 2.0 * kPi / 3.0, 1e-12);
    // The widely copied 0.4234413544 is a typo: it is off by 1e-5.
    EXPECT_GT(std::abs(0.4234413544 - kSideFaceSolidAngle), 9e-6);
}

TEST(LpvMath, FollowingCascadesMoveInWholeCellsOnly) {
    glm::dvec3 lo(-50), hi(50), fwd(0, 0, -1);
    auto a = placeCascades(3, 32, 0.5, lo, hi, {1.02, 2.0, 3.0}, fwd);
    auto b = placeCascades(3, 32, 0.5, lo, hi, {1.02 + 0.3, 2.0 - 0.2, 3.0 + 0.1}, fwd);
    ASSERT_EQ(a.size(), 3u);
    for (size_t k = 0; k < 3; ++k) {
        EXPECT_DOUBLE_EQ(a[k].cellSize, 0.5 * std::ldexp(1.0, int(k)));
        glm::dvec3 moved = (b[k].origin - a[k].origin) / a[k].cellSize;
        for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(moved[i], std::round(moved[i])) << k;
        EXPECT_TRUE(a[k].contains({1.02, 2.0, 3.0})) << k; // the camera is inside every cascade
    }
    // Finer cascades lie inside coarser ones up to one coarse cell of snapping.
    EXPECT_LE(a[2].origin.x, a[1].origin.x + a[2].cellSize);
}

TEST(LpvMath, AutoOuterCascadeHoldsTheSceneAndStaysPut) {
    glm::dvec3 lo(1e7, 0, 0), hi(1e7 + 40, 10, 20);
    auto a = placeCascades(2, 32, 0, lo, hi, {1e7 + 5, 1, 1}, {1, 0, 0});
    auto b = placeCascades(2, 32, 0, lo, hi, {1e7 + 25, 8, 3}, {0, 1, 0});
    ASSERT_EQ(a.size(), 2u);
    EXPECT_EQ(a[1].origin, b[1].origin);
    // A cell of margin: a surface on the boundary shifted half a cell outwards stays inside.
    EXPECT_TRUE(a[1].contains(lo - a[1].cellSize * 0.99));
    EXPECT_TRUE(a[1].contains(hi + a[1].cellSize * 0.99));
    EXPECT_DOUBLE_EQ(a[0].cellSize, 0.5 * a[1].cellSize);
    // A single auto cascade is the scene's grid.
    auto one = placeCascades(1, 16, 0, lo, hi, {0, 0, 0}, {1, 0, 0});
    ASSERT_EQ(one.size(), 1u);
    EXPECT_TRUE(one[0].contains(0.5 * (lo + hi)));
}

TEST(LpvMath, ProbesFollowTheCameraOnlyWhereTheScenesCubeSpacesThemTooWide) {
    // A 12 m room at 20 probes: 0.67 m apart, the fixed grid.
    EXPECT_EQ(probeCellSize(20, 8.0, glm::dvec3(0), glm::dvec3(12, 4, 8)), 0.0);
    // A 2 km street scene: 111 m apart, so they follow the camera 8 m apart.
    EXPECT_EQ(probeCellSize(20, 8.0, glm::dvec3(-1000, 0, -1000), glm::dvec3(1000, 60, 1000)), 8.0);
    // Exactly at the limit stays fixed; 0 (or a non-finite limit) never follows.
    EXPECT_EQ(probeCellSize(10, 1.0, glm::dvec3(0), glm::dvec3(8)), 0.0);
    EXPECT_EQ(probeCellSize(20, 0.0, glm::dvec3(-1000), glm::dvec3(1000)), 0.0);
    EXPECT_EQ(probeCellSize(20, std::numeric_limits<double>::infinity(), glm::dvec3(-1000), glm::dvec3(1000)), 0.0);
    // Degenerate scene bounds: no spacing to compare, placeCascades' auto decides (no cascades).
    EXPECT_EQ(probeCellSize(20, 8.0, glm::dvec3(std::nan("")), glm::dvec3(1)), 0.0);
}

TEST(LpvMath, DegenerateInputsGiveNoCascades) {
    double inf = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(placeCascades(1, 32, 0, glm::dvec3(0), glm::dvec3(0), {}, {0, 0, -1}).empty());
    EXPECT_TRUE(placeCascades(1, 32, 0, glm::dvec3(-inf), glm::dvec3(inf), {}, {0, 0, -1}).empty());
    EXPECT_TRUE(placeCascades(2, 32, inf, glm::dvec3(0), glm::dvec3(1), {}, {0, 0, -1}).empty());
    EXPECT_TRUE(placeCascades(0, 32, 1, glm::dvec3(0), glm::dvec3(1), {}, {0, 0, -1}).empty());
}

} // namespace
} // namespace pnb::player
