// Camera math without a GL context: reversed-Z projection, frustum planes, path evaluation.
#include <cmath>

#include <gtest/gtest.h>

#include "pnb_player/camera.h"
#include "pnb_player/camera_path.h"

namespace pnb::player {

namespace {

float depthOf(const ViewMatrices& v, glm::vec3 relative) {
    glm::vec4 clip = v.viewProjection * glm::vec4(relative, 1);
    return clip.z / clip.w;
}

CameraPath straightPath(bool loop, Interpolation interpolation) {
    CameraPath p;
    p.loop = loop;
    p.interpolation = interpolation;
    for (int i = 0; i < 5; ++i) {
        CameraKey k;
        k.timeSeconds = i < 3 ? float(i) : 2.0f + 2.0f * float(i - 2); // 0 1 2 4 6: uneven
        k.position = {float(i) * 10.0f, 1.0f, 0.0f};
        k.yfovRadians = 0.8f;
        glm::quat q = glm::angleAxis(0.3f * float(i), glm::vec3(0, 1, 0));
        k.rotation = {q.x, q.y, q.z, q.w};
        p.keys.push_back(k);
    }
    return p;
}

} // namespace

TEST(Camera, ReversedZMapsNearToOneAndFarToZero) {
    CameraState c;
    c.znear = 0.5f;
    ViewMatrices inf = makeViewMatrices(c, 1.5f);
    EXPECT_NEAR(depthOf(inf, {0, 0, -0.5f}), 1.0f, 1e-6);
    EXPECT_NEAR(depthOf(inf, {0, 0, -1e7f}), 0.0f, 1e-6);
    EXPECT_GT(depthOf(inf, {0, 0, -1.0f}), depthOf(inf, {0, 0, -1.001f})); // nearer = larger
    c.zfar = 100.0f;
    ViewMatrices fin = makeViewMatrices(c, 1.5f);
    EXPECT_NEAR(depthOf(fin, {0, 0, -0.5f}), 1.0f, 1e-6);
    EXPECT_NEAR(depthOf(fin, {0, 0, -100.0f}), 0.0f, 1e-6);
}

TEST(Camera, FrustumKeepsVisibleBoxesAndDropsOthers) {
    CameraState c;
    c.position = {1.0e6, 0, 0}; // far from the origin: the test is camera-relative
    c.znear = 0.1f;
    ViewMatrices v = makeViewMatrices(c, 1.0f);
    glm::dvec3 p = c.position;
    EXPECT_TRUE(intersectsFrustum(v, p + glm::dvec3(-1, -1, -11), p + glm::dvec3(1, 1, -9)));
    EXPECT_FALSE(intersectsFrustum(v, p + glm::dvec3(-1, -1, 9), p + glm::dvec3(1, 1, 11)));   // behind
    EXPECT_FALSE(intersectsFrustum(v, p + glm::dvec3(50, -1, -11), p + glm::dvec3(52, 1, -9))); // right
    EXPECT_TRUE(intersectsFrustum(v, p + glm::dvec3(-1, -1, -1e9), p + glm::dvec3(1, 1, -1e9 + 1))); // infinite far
    EXPECT_TRUE(intersectsFrustum(v, p + glm::dvec3(-100, -100, -100), p + glm::dvec3(100, 100, 100))); // contains camera
}

TEST(CameraPath, PassesThroughKeysAndIsContinuous) {
    for (Interpolation interp : {Interpolation::Linear, Interpolation::CatmullRom}) {
        CameraPath path = straightPath(false, interp);
        EXPECT_DOUBLE_EQ(pathDuration(path), 6.0);
        for (const CameraKey& k : path.keys) {
            CameraState c;
            evaluatePath(path, k.timeSeconds, c);
            EXPECT_NEAR(c.position.x, k.position.x, 1e-9);
            EXPECT_NEAR(std::abs(glm::dot(glm::dvec4(c.rotation.x, c.rotation.y, c.rotation.z, c.rotation.w),
                                          glm::dvec4(k.rotation.x, k.rotation.y, k.rotation.z, k.rotation.w))),
                        1.0, 1e-6); // keys are float quaternions, unit to float precision
        }
        // Small time steps give small moves everywhere, also across keys with uneven spacing.
        CameraState prev;
        evaluatePath(path, 0.0, prev);
        for (double t = 0.001; t <= 6.0; t += 0.001) {
            CameraState c;
            evaluatePath(path, t, c);
            ASSERT_LT(glm::length(c.position - prev.position), 0.05) << "t " << t;
            ASSERT_NEAR(glm::length(glm::dvec4(c.rotation.x, c.rotation.y, c.rotation.z, c.rotation.w)), 1.0, 1e-6);
            prev = c;
        }
        CameraState before, after;
        evaluatePath(path, -5.0, before);
        evaluatePath(path, 50.0, after);
        EXPECT_NEAR(before.position.x, 0.0, 1e-9); // clamped
        EXPECT_NEAR(after.position.x, 40.0, 1e-9);
    }
}

TEST(CameraPath, CatmullRomIsSmoothAtKeys) {
    CameraPath path = straightPath(false, Interpolation::CatmullRom);
    // Velocity just before and after the key at t = 2 agrees (C1), where linear has a kink.
    auto velocity = [&](double t0, double t1) {
        CameraState a, b;
        evaluatePath(path, t0, a);
        evaluatePath(path, t1, b);
        return (b.position.x - a.position.x) / (t1 - t0);
    };
    double h = 1e-4;
    EXPECT_NEAR(velocity(2 - h, 2), velocity(2, 2 + h), 0.01);
}

TEST(CameraPath, LoopWrapsAndClosesSmoothly) {
    CameraPath path = straightPath(true, Interpolation::CatmullRom);
    double period = pathDuration(path);
    EXPECT_DOUBLE_EQ(period, 6.0 + 1.5); // the closing segment takes the mean spacing
    CameraState a, b;
    evaluatePath(path, 1.25, a);
    evaluatePath(path, 1.25 + 3 * period, b);
    EXPECT_NEAR(glm::length(a.position - b.position), 0.0, 1e-6);
    CameraState end, start;
    evaluatePath(path, period - 1e-6, end);
    evaluatePath(path, 0.0, start);
    EXPECT_LT(glm::length(end.position - start.position), 1e-3);
}

} // namespace pnb::player
