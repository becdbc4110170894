// Light-matrix fitting (player/math/shadow_fit): coverage, stabilisation and the extremes of
// issue 5, on the CPU.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "shadow_fit.h"

namespace {

using namespace pnb::player;

FitCamera cameraLooking(glm::dvec3 forward, glm::dvec3 position = glm::dvec3(0.0)) {
    FitCamera c;
    c.forward = glm::normalize(forward);
    glm::dvec3 helper = std::abs(c.forward.y) < 0.999 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
    c.right = glm::normalize(glm::cross(c.forward, helper));
    c.up = glm::cross(c.right, c.forward);
    c.tanHalfFovY = std::tan(0.4);
    c.aspect = 16.0 / 9.0;
    c.position = position;
    return c;
}

FitBox sceneBox(glm::dvec3 cameraPosition) {
    return {glm::dvec3(-200, -1, -200) - cameraPosition, glm::dvec3(200, 60, 200) - cameraPosition};
}

bool finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// Every point of the slice where a receiver can be (the slice clipped to the scene) lands inside
// the map: x, y in [-1, 1], z in [0, 1].
void expectSliceInside(const ShadowFit& fit, const FitCamera& cam, double a, double b,
                       const FitBox& scene) {
    ASSERT_TRUE(finite(fit.matrix));
    for (const glm::dvec3& c : clipSliceToBox(cam, a, b, scene)) {
        glm::dvec3 s = toShadow(fit, c);
        EXPECT_LE(std::abs(s.x), 1.0 + 1e-9) << s.x;
        EXPECT_LE(std::abs(s.y), 1.0 + 1e-9) << s.y;
        EXPECT_GE(s.z, -1e-9);
        EXPECT_LE(s.z, 1.0 + 1e-9);
    }
}

const glm::dvec3 kSun = glm::normalize(glm::dvec3(0.4, -0.8, 0.3));

TEST(ShadowFit, LightRotationIsOrthonormalForEveryDirection) {
    for (glm::dvec3 d : {kSun, glm::dvec3(0, -1, 0), glm::dvec3(0, 1, 0), glm::dvec3(1, 0, 0),
                         glm::dvec3(0, -0.99999, 0.0001)}) {
        glm::dmat3 r = lightRotation(d);
        glm::dmat3 identity = r * glm::transpose(r);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) EXPECT_NEAR(identity[i][j], i == j ? 1.0 : 0.0, 1e-12);
        EXPECT_NEAR(glm::dot(glm::transpose(r)[2], -glm::normalize(d)), 1.0, 1e-12); // +z toward light
    }
}

TEST(ShadowFit, CascadesCoverTheirSliceInBothModes) {
    FitCamera cam = cameraLooking({1, -0.2, 0.3});
    FitBox scene = sceneBox(cam.position);
    for (FitMode mode : {FitMode::Sphere, FitMode::Tight})
        expectSliceInside(fitCascade(cam, 5, 40, lightRotation(kSun), scene, 1024, mode), cam, 5, 40, scene);
}

TEST(ShadowFit, CastersAboveTheSliceAreInsideTheDepthRange) {
    // The map's depth reaches the top of the scene toward the light (pancaking by extent): a
    // caster at the scene's highest point above a receiver in the slice is not clipped.
    FitCamera cam = cameraLooking({1, -0.1, 0});
    FitBox scene = sceneBox(cam.position);
    ShadowFit fit = fitCascade(cam, 1, 20, lightRotation(kSun), scene, 1024, FitMode::Tight);
    glm::dvec3 receiver = cam.forward * 10.0;
    glm::dvec3 caster = receiver - kSun * ((scene.max.y - receiver.y) / -kSun.y * 0.999);
    glm::dvec3 s = toShadow(fit, caster), r = toShadow(fit, receiver);
    EXPECT_GE(s.z, 0.0);
    EXPECT_LT(s.z, r.z); // nearer the light
    EXPECT_NEAR(s.x, r.x, 1e-9);
    EXPECT_NEAR(s.y, r.y, 1e-9);
}

TEST(ShadowFit, SphereExtentIsInvariantUnderRotation) {
    FitBox scene = sceneBox(glm::dvec3(0.0));
    glm::dmat3 light = lightRotation(kSun);
    ShadowFit first = fitCascade(cameraLooking({1, 0, 0}), 3, 30, light, scene, 1024, FitMode::Sphere);
    for (int i = 1; i < 24; ++i) {
        double yaw = i * 0.27, pitch = std::sin(i * 1.3) * 0.6;
        FitCamera cam = cameraLooking({std::cos(yaw) * std::cos(pitch), std::sin(pitch), std::sin(yaw) * std::cos(pitch)});
        ShadowFit fit = fitCascade(cam, 3, 30, light, scene, 1024, FitMode::Sphere);
        EXPECT_EQ(fit.texelWorld, first.texelWorld);
        EXPECT_EQ(fit.matrix[0][0], first.matrix[0][0]); // x scale: the extent
        EXPECT_EQ(fit.matrix[1][1], first.matrix[1][1]);
        expectSliceInside(fit, cam, 3, 30, scene);
    }
}

TEST(ShadowFit, SphereOriginMovesInWholeTexelsUnderTranslation) {
    glm::dmat3 light = lightRotation(kSun);
    for (glm::dvec3 base : {glm::dvec3(0.0), glm::dvec3(1e6, 30, -1e6)}) {
        for (int i = 0; i < 16; ++i) {
            glm::dvec3 position = base + glm::dvec3(i * 0.0137, i * 0.003, -i * 0.021);
            FitCamera cam = cameraLooking({1, -0.3, 0.2}, position);
            ShadowFit fit = fitCascade(cam, 2, 25, light, sceneBox(position), 1024, FitMode::Sphere);
            // The map centre in absolute light space: shadow x = 0 <=> light x = centre.
            double sx = 2.0 / (fit.texelWorld * 1024.0);
            double centreX = -fit.matrix[3][0] / sx + (light * position).x;
            double centreY = -fit.matrix[3][1] / sx + (light * position).y;
            EXPECT_NEAR(centreX / fit.texelWorld, std::round(centreX / fit.texelWorld), 1e-4);
            EXPECT_NEAR(centreY / fit.texelWorld, std::round(centreY / fit.texelWorld), 1e-4);
        }
    }
}

TEST(ShadowFit, ClippingTheSliceToTheSceneKeepsOnlyItsInside) {
    FitCamera cam = cameraLooking({1, -0.2, 0});
    FitBox scene{{-1, -1, -1}, {30, 0.5, 1}};
    std::vector<glm::dvec3> points = clipSliceToBox(cam, 0.5, 20, scene);
    ASSERT_GE(points.size(), 4u);
    for (const glm::dvec3& p : points) {
        EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, scene.min - 1e-6)) && glm::all(glm::lessThanEqual(p, scene.max + 1e-6)));
        double d = glm::dot(p, cam.forward);
        EXPECT_GE(d, 0.5 - 1e-6);
        EXPECT_LE(d, 20 + 1e-6);
    }
    // A scene behind the camera does not meet the slice.
    EXPECT_TRUE(clipSliceToBox(cam, 0.5, 20, FitBox{{-50, -1, -1}, {-10, 1, 1}}).empty());
}

TEST(ShadowFit, TightIsSmallerThanSphere) {
    FitCamera cam = cameraLooking({1, -0.2, 0});
    glm::dmat3 light = lightRotation(kSun);
    FitBox scene = sceneBox(cam.position);
    EXPECT_LT(fitCascade(cam, 1, 10, light, scene, 1024, FitMode::Tight).texelWorld,
              fitCascade(cam, 1, 10, light, scene, 1024, FitMode::Sphere).texelWorld);
}

TEST(ShadowFit, ExtremeLightAndViewDirectionsStayFiniteAndCovering) {
    FitBox scene = sceneBox(glm::dvec3(0.0));
    double t = 89.9 * M_PI / 180.0;
    glm::dvec3 grazing = glm::normalize(glm::dvec3(std::sin(t), -std::cos(t), 0));
    struct Case { glm::dvec3 light, view; };
    for (Case c : {Case{{0, -1, 0}, {1, -0.3, 0}},      // straight down
                   Case{{0, -1, 0}, {0, -1, 0}},        // looking along the light
                   Case{{0, -1, 0}, {0, 1, 0}},         // looking into the light
                   Case{grazing, {1, 0, 0}}, Case{grazing, {-1, 0, 0}}, Case{grazing, {0, 0, 1}}}) {
        FitCamera cam = cameraLooking(c.view);
        for (FitMode mode : {FitMode::Sphere, FitMode::Tight})
            expectSliceInside(fitCascade(cam, 0.1, 100, lightRotation(c.light), scene, 512, mode), cam, 0.1, 100, scene);
        expectSliceInside(fitLispsm(cam, 0.1, 100, c.light, scene, 512), cam, 0.1, 100, scene);
    }
}

TEST(ShadowFit, TinyNearPlaneStaysFinite) {
    FitCamera cam = cameraLooking({1, -0.2, 0});
    FitBox scene = sceneBox(cam.position);
    ShadowFit fit = fitCascade(cam, 1e-5, 1e-5 * 1e5, lightRotation(kSun), scene, 1024, FitMode::Sphere);
    expectSliceInside(fit, cam, 1e-5, 1.0, scene);
    expectSliceInside(fitLispsm(cam, 1e-5, 1.0, kSun, scene, 1024), cam, 1e-5, 1.0, scene);
}

TEST(ShadowFit, LispsmWarpsWhenPerpendicularAndFallsBackWhenAligned) {
    FitBox scene = sceneBox(glm::dvec3(0.0));
    glm::dvec3 light{0, -1, 0};
    FitCamera side = cameraLooking({1, 0, 0});
    ShadowFit warped = fitLispsm(side, 0.5, 150, light, scene, 1024);
    EXPECT_TRUE(warped.warped);
    // Near the viewer a warped texel is smaller than a uniform one over the same body.
    ShadowFit uniform = fitCascade(side, 0.5, 150, lightRotation(light), scene, 1024, FitMode::Tight);
    EXPECT_LT(warped.texelWorld, uniform.texelWorld);
    // Sweep towards the light direction: always covering, warp fading out.
    for (double angle : {60.0, 20.0, 5.0, 1.0, 0.1, 0.001, 0.0}) {
        double r = angle * M_PI / 180.0;
        FitCamera cam = cameraLooking({std::sin(r), -std::cos(r), 0.0001 * (angle == 0)});
        ShadowFit fit = fitLispsm(cam, 0.5, 150, light, scene, 1024);
        expectSliceInside(fit, cam, 0.5, 150, scene);
    }
    EXPECT_FALSE(fitLispsm(cameraLooking({0, -1, 1e-9}), 0.5, 150, light, scene, 1024).warped);
}

TEST(ShadowFit, SceneFitCoversTheScene) {
    FitBox scene = sceneBox(glm::dvec3(0.0));
    ShadowFit fit = fitScene(lightRotation(kSun), scene, 2048);
    for (int c = 0; c < 8; ++c) {
        glm::dvec3 p{(c & 1) ? scene.max.x : scene.min.x, (c & 2) ? scene.max.y : scene.min.y,
                     (c & 4) ? scene.max.z : scene.min.z};
        glm::dvec3 s = toShadow(fit, p);
        EXPECT_LE(std::abs(s.x), 1 + 1e-9);
        EXPECT_LE(std::abs(s.y), 1 + 1e-9);
        EXPECT_GE(s.z, 0);
        EXPECT_LE(s.z, 1);
    }
}

} // namespace
