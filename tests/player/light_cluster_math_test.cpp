// The light clusters' CPU math (player/src/light_clusters.h): bounding spheres that hold what a
// light reaches, the slice mapping, and when the frame clusters.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "lights/light_clusters.h"

namespace pnb::player {
namespace {

GpuLight spot(glm::vec3 position, glm::vec3 direction, float range, float outerRadians) {
    GpuLight g;
    g.positionRange = glm::vec4(position, range);
    g.directionType = glm::vec4(glm::normalize(direction), float(int(LightType::Spot)));
    g.cone = {std::cos(outerRadians), 1.0f, 0, 0};
    return g;
}

// Points of the spherical sector a spot light of `range` and half-angle `outer` lights (apex at
// the origin, axis +z): apex, rim, axis tip and a spread of interior directions at full range.
bool sphereHoldsSector(glm::vec4 s, float range, float outer) {
    const glm::vec3 c(s);
    for (int i = 0; i <= 16; ++i)
        for (int j = 0; j < 16; ++j) {
            const float theta = outer * float(i) / 16.0f, phi = 6.2831853f * float(j) / 16.0f;
            const glm::vec3 dir(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
            for (float t : {0.0f, 0.5f, 1.0f})
                if (glm::length(dir * range * t - c) > s.w * (1.0f + 1e-5f) + 1e-6f) return false;
        }
    return true;
}

TEST(LightClusterMath, PointLightSphereIsItsRangeInViewSpace) {
    GpuLight g;
    g.positionRange = {1, 2, 3, 4.5f};
    g.directionType = {0, 0, -1, float(int(LightType::Point))};
    const glm::mat4 view = glm::rotate(glm::mat4(1.0f), 0.7f, glm::vec3(0, 1, 0));
    const glm::vec4 s = lightBoundingSphere(g, view);
    EXPECT_FLOAT_EQ(s.w, 4.5f);
    const glm::vec3 expected(view * glm::vec4(1, 2, 3, 1));
    EXPECT_NEAR(glm::length(glm::vec3(s) - expected), 0.0f, 1e-5f);
}

TEST(LightClusterMath, DirectionalLightsReachEverything) {
    GpuLight g;
    g.directionType = {0, -1, 0, float(int(LightType::Directional))};
    EXPECT_LT(lightBoundingSphere(g, glm::mat4(1.0f)).w, 0.0f);
}

TEST(LightClusterMath, SpotSphereHoldsItsSectorAndIsTighterWhenNarrow) {
    for (float degrees : {1.0f, 20.0f, 45.0f, 59.0f, 61.0f, 80.0f, 90.0f}) {
        const float outer = glm::radians(degrees);
        const glm::vec4 s = lightBoundingSphere(spot({0, 0, 0}, {0, 0, 1}, 10.0f, outer), glm::mat4(1.0f));
        EXPECT_TRUE(sphereHoldsSector(s, 10.0f, outer)) << degrees << " degrees";
        EXPECT_LE(s.w, 10.0f + 1e-4f) << degrees;
        if (degrees < 45.0f) {
            EXPECT_LT(s.w, 7.1f) << degrees; // range / (2 cos 45°) = 7.07
        }
    }
    // 10 degrees: the sector's sphere is about half the range sphere.
    EXPECT_NEAR(lightBoundingSphere(spot({0, 0, 0}, {0, 0, 1}, 10.0f, glm::radians(10.0f)), glm::mat4(1.0f)).w,
                10.0f / (2.0f * std::cos(glm::radians(10.0f))), 1e-4f);
}

TEST(LightClusterMath, SlicesMapNearToZeroAndFarToTheSliceCount) {
    const LightClusterGrid g = lightClusterGrid(1280, 720, 32, 24, 1024, 0.5f, 200.0f);
    EXPECT_EQ(g.tilesX, 40u);
    EXPECT_EQ(g.tilesY, 23u); // 720 / 32 = 22.5: the last row is partial
    EXPECT_EQ(g.words, 32u);
    EXPECT_NEAR(std::log(0.5f) * g.sliceScale + g.sliceBias, 0.0f, 1e-4f);
    EXPECT_NEAR(std::log(200.0f) * g.sliceScale + g.sliceBias, 24.0f, 1e-3f);
    EXPECT_EQ(g.maskBytes(), 32u + uint64_t(40 * 23 + 24) * 32u * 4u);
    // 33 lights need two words; a far plane not beyond the near one is moved out.
    const LightClusterGrid h = lightClusterGrid(1, 1, 32, 1, 33, 2.0f, 1.0f);
    EXPECT_EQ(h.words, 2u);
    EXPECT_EQ(h.tilesX, 1u);
    EXPECT_TRUE(std::isfinite(h.sliceScale) && h.sliceScale > 0.0f);
}

TEST(LightClusterMath, ExtremeDepthRangesStayFinite) {
    for (auto [n, f] : {std::pair{1e-6f, 1e9f}, std::pair{1e6f, 1e6f}, std::pair{0.1f, 0.1f}}) {
        const LightClusterGrid g = lightClusterGrid(512, 288, 32, 64, 4096, n, f);
        EXPECT_TRUE(std::isfinite(g.sliceScale) && g.sliceScale > 0.0f) << n << " " << f;
        EXPECT_TRUE(std::isfinite(g.sliceBias)) << n << " " << f;
    }
}

TEST(LightClusterMath, AutoClustersFromTheMeasuredLightCount) {
    RenderSettings s;
    EXPECT_FALSE(clustersWanted(s, 0));
    EXPECT_FALSE(clustersWanted(s, s.lightClusterMin - 1));
    EXPECT_TRUE(clustersWanted(s, s.lightClusterMin));
    s.lightCulling = LightCulling::Clusters;
    EXPECT_TRUE(clustersWanted(s, 1));
    EXPECT_FALSE(clustersWanted(s, 0)); // only directional lights: nothing to cull
    s.lightCulling = LightCulling::Off;
    EXPECT_FALSE(clustersWanted(s, 4096));
}

} // namespace
} // namespace pnb::player
