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

// Orthographic: x = xmag maps to NDC 1 at any depth (the viewport's aspect being xmag / ymag),
// depth is linear, reversed (near 1, far 0) and stays in [0, 1] between the planes.
TEST(Camera, OrthographicMapsMagnitudesToTheEdgesAtEveryDepth) {
    CameraState c;
    c.projection = Projection::Orthographic;
    c.ymag = 2.0f;
    c.znear = 0.5f;
    c.zfar = 40.0f;
    const float xmag = 3.0f, aspect = xmag / c.ymag;
    ViewMatrices v = makeViewMatrices(c, aspect);
    EXPECT_TRUE(v.orthographic);
    auto ndc = [&](glm::vec3 p) {
        glm::vec4 clip = v.viewProjection * glm::vec4(p, 1);
        return glm::vec3(clip) / clip.w;
    };
    float previous = 2.0f;
    for (float z : {0.5f, 1.0f, 3.0f, 10.0f, 39.0f, 40.0f}) {
        EXPECT_NEAR(ndc({xmag, 0, -z}).x, 1.0f, 1e-6) << z;
        EXPECT_NEAR(ndc({-xmag, c.ymag, -z}).x, -1.0f, 1e-6) << z;
        EXPECT_NEAR(ndc({-xmag, c.ymag, -z}).y, 1.0f, 1e-6) << z;
        EXPECT_NEAR(ndc({0.5f * xmag, 0, -z}).x, 0.5f, 1e-6) << z; // no perspective divide
        float d = ndc({0, 0, -z}).z;
        EXPECT_GE(d, 0.0f);
        EXPECT_LE(d, 1.0f);
        EXPECT_LT(d, previous) << z; // farther = smaller, strictly
        EXPECT_NEAR(d, (40.0f - z) / 39.5f, 1e-6) << z; // linear
        if (d > 0) { // 0 reads as nothing drawn
            EXPECT_NEAR(viewDepthFromBuffer(v, d), z, 1e-5 * z) << z;
        }
        previous = d;
    }
    EXPECT_NEAR(ndc({0, 0, -0.5f}).z, 1.0f, 1e-6);
    EXPECT_NEAR(ndc({0, 0, -40.0f}).z, 0.0f, 1e-6);
    // Another viewport keeps ymag and widens x (no stretching): x = ymag * aspect maps to 1.
    ViewMatrices wide = makeViewMatrices(c, 2.0f);
    glm::vec4 clip = wide.viewProjection * glm::vec4(4.0f, 2.0f, -7.0f, 1);
    EXPECT_NEAR(clip.x / clip.w, 1.0f, 1e-6);
    EXPECT_NEAR(clip.y / clip.w, 1.0f, 1e-6);
    // The pixel footprint is depth independent; the forward axis is the camera's -Z.
    EXPECT_DOUBLE_EQ(v.halfHeightAt(1.0), 2.0);
    EXPECT_DOUBLE_EQ(v.halfHeightAt(100.0), 2.0);
    EXPECT_NEAR(glm::length(v.forward() - glm::dvec3(0, 0, -1)), 0.0, 1e-12);
    // The inverse is exact enough to reconstruct positions from depth (the lighting passes do).
    glm::vec4 back = v.inverseViewProjection * glm::vec4(ndc({1.0f, -0.5f, -12.0f}), 1.0f);
    EXPECT_NEAR(glm::length(glm::vec3(back) / back.w - glm::vec3(1.0f, -0.5f, -12.0f)), 0.0f, 1e-4f);
}

TEST(Camera, PerspectiveDepthRoundTripsThroughViewDepthFromBuffer) {
    CameraState c;
    c.znear = 0.25f;
    for (float far : {0.0f, 80.0f}) {
        c.zfar = far;
        ViewMatrices v = makeViewMatrices(c, 1.0f);
        EXPECT_FALSE(v.orthographic);
        for (float z : {0.25f, 2.0f, 50.0f})
            EXPECT_NEAR(viewDepthFromBuffer(v, depthOf(v, {0, 0, -z})), z, 1e-4 * z) << far << " " << z;
        EXPECT_NEAR(v.halfHeightAt(2.0), 2.0 * std::tan(0.4), 1e-6);
    }
    EXPECT_TRUE(std::isinf(viewDepthFromBuffer(makeViewMatrices(c, 1.0f), 0.0)));
}

// Culling through the orthographic box: a box beside the view is culled at every depth (a
// perspective frustum would take it in far enough away), one inside is kept at every depth,
// and nothing behind the near plane or past the far plane is kept.
TEST(Camera, OrthographicFrustumIsABox) {
    CameraState c;
    c.position = {-2.0e6, 5, 3}; // camera-relative
    c.projection = Projection::Orthographic;
    c.ymag = 1.0f;
    c.znear = 0.1f;
    c.zfar = 500.0f;
    ViewMatrices v = makeViewMatrices(c, 1.0f);
    CameraState persp = c;
    persp.projection = Projection::Perspective;
    ViewMatrices pv = makeViewMatrices(persp, 1.0f);
    const glm::dvec3 p = c.position;
    for (double z : {1.0, 10.0, 100.0, 450.0}) {
        EXPECT_TRUE(intersectsFrustum(v, p + glm::dvec3(0.5, 0.5, -z - 0.1), p + glm::dvec3(0.9, 0.9, -z))) << z;
        EXPECT_FALSE(intersectsFrustum(v, p + glm::dvec3(1.2, -0.1, -z - 0.1), p + glm::dvec3(1.5, 0.1, -z))) << z;
        EXPECT_FALSE(intersectsFrustum(v, p + glm::dvec3(-0.1, -1.5, -z - 0.1), p + glm::dvec3(0.1, -1.2, -z))) << z;
    }
    // The same box beside the view is inside the perspective frustum far enough away: the test
    // above would pass with the wrong projection only if culling ignored it.
    EXPECT_TRUE(intersectsFrustum(pv, p + glm::dvec3(1.2, -0.1, -100.1), p + glm::dvec3(1.5, 0.1, -100)));
    EXPECT_FALSE(intersectsFrustum(v, p + glm::dvec3(-0.5, -0.5, 0.5), p + glm::dvec3(0.5, 0.5, 2)));   // behind
    EXPECT_FALSE(intersectsFrustum(v, p + glm::dvec3(-0.5, -0.5, -600), p + glm::dvec3(0.5, 0.5, -501))); // past far
    EXPECT_TRUE(intersectsFrustum(v, p + glm::dvec3(-9, -9, -600), p + glm::dvec3(9, 9, 9)));            // around it
}

TEST(Camera, ValidOrthographicSuppliesAFarPlaneAndAMagnitude) {
    Aabb bounds;
    bounds.min = {-1, -1, -20};
    bounds.max = {1, 1, -10};
    CameraState c;
    c.projection = Projection::Orthographic;
    c.ymag = -2.0f;
    c.zfar = 0.0f;
    CameraState v = validOrthographic(c, bounds);
    EXPECT_FLOAT_EQ(v.ymag, 2.0f);
    EXPECT_GE(v.zfar, 20.0f); // past the scene's far side
    c.ymag = 0.0f;
    c.zfar = 30.0f;
    v = validOrthographic(c, bounds);
    EXPECT_FLOAT_EQ(v.ymag, 1.0f);
    EXPECT_FLOAT_EQ(v.zfar, 30.0f); // its own far plane is kept
    CameraState persp;
    EXPECT_FLOAT_EQ(validOrthographic(persp, bounds).zfar, 0.0f); // perspective: untouched
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
