// Orthographic cameras through the whole frame, headless: a glTF orthographic camera arrives in
// the container and the player draws through it (two identical cubes at different depths are the
// same size on screen, as they are not through a perspective camera), position and linear depth
// are reconstructed with the orthographic mapping, the view vector is the same at every pixel
// (a flat glossy plane under a sun is one colour), and the Khronos Cameras model's camera 1
// shows its square as a rectangle. Shadows: shadow_rendering_test.cpp; LOD:
// lod_rendering_test.cpp; the matrices: camera_test.cpp.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <unistd.h>

#include "render_fixture.h"

#include "pnb_player/benchmark.h"
#include "pnb_player/gpu_scene.h"

namespace pnb::player::test {
namespace {

constexpr uint32_t kW = 160, kH = 120;

// Two unit cubes facing the camera, at view depths 6.5 and 16.5 (front faces), left and right of
// the axis, a sun, and two cameras on +Z looking down -Z: 0 orthographic (ymag 3), 1 perspective.
std::string twoCubes() {
    gltf::Document doc;
    gltf::Material grey;
    grey.name = "grey";
    grey.baseColorFactor = {0.7f, 0.7f, 0.7f, 1};
    doc.materials.push_back(grey);
    addObject(doc, "nearCube", box(1, 1, 1, 0), {-1.5f, 0, -2});
    addObject(doc, "farCube", box(1, 1, 1, 0), {1.5f, 0, -12});
    addSun(doc, 2.0f, gltf::lookRotation({0.3f, -0.5f, -1.0f}));
    gltf::Camera ortho;
    ortho.name = "ortho";
    ortho.orthographic = true;
    ortho.xmag = 4.0f; // the viewport's 4:3 at ymag 3
    ortho.ymag = 3.0f;
    ortho.znear = 0.1f;
    ortho.zfar = 50.0f;
    gltf::Camera persp;
    persp.name = "persp";
    persp.yfovRadians = 0.8f;
    doc.cameras = {ortho, persp};
    for (int32_t c = 0; c < 2; ++c) {
        gltf::Node n;
        n.name = c == 0 ? "orthoCam" : "perspCam";
        n.camera = c;
        n.translation = {0, 0, 5};
        doc.nodes.push_back(n);
    }
    return convert(doc, "two-cubes");
}

struct Footprint {
    uint64_t left = 0, right = 0; // covered pixels left and right of the image's centre
};

Footprint footprint(const CapturedImage& depth) {
    Footprint f;
    for (uint32_t y = 0; y < depth.height; ++y)
        for (uint32_t x = 0; x < depth.width; ++x)
            if (depth.f32[size_t(y) * depth.width + x] > 0) (x < depth.width / 2 ? f.left : f.right) += 1;
    return f;
}

TEST(Orthographic, TheGltfCameraArrivesAndIdenticalCubesAreTheSameSizeAtAnyDepth) {
    const std::string file = twoCubes();
    auto scene = loadScene(file);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    ASSERT_EQ((*scene)->cameras.size(), 2u);
    CameraState ortho = sceneCamera(**scene, 0), persp = sceneCamera(**scene, 1);
    ASSERT_EQ(ortho.projection, Projection::Orthographic);
    EXPECT_FLOAT_EQ(ortho.ymag, 3.0f);
    EXPECT_FLOAT_EQ(ortho.zfar, 50.0f);
    ASSERT_EQ(persp.projection, Projection::Perspective);

    Rendered o = render(file, ortho, kW, kH);
    Rendered p = render(file, persp, kW, kH);
    Footprint fo = footprint(o.depth), fp = footprint(p.depth);
    // A unit face is 120 / 6 = 20 pixels tall through the orthographic camera, at any depth.
    EXPECT_NEAR(double(fo.left), 400.0, 45.0);
    EXPECT_NEAR(double(fo.right), double(fo.left), 0.03 * double(fo.left));
    // Through the perspective camera the far cube is much smaller (distance 16.5 against 6.5).
    EXPECT_GT(double(fp.left), 3.0 * double(fp.right));
    EXPECT_EQ(o.stats.culledItems, 0u); // both cubes inside the orthographic box
    EXPECT_TRUE(allFinite(o.hdr));

    // Position reconstruction from depth: the far cube's front face is at view depth 16.5 and the
    // near one's at 6.5, both lying exactly where the orthographic rays put them.
    ASSERT_FALSE(o.position.f32.empty());
    int nearHits = 0, farHits = 0;
    for (uint32_t y = 0; y < kH; ++y) {
        for (uint32_t x = 0; x < kW; ++x) {
            const size_t i = size_t(y) * kW + x;
            const float* q = &o.position.f32[i * 3];
            if (!std::isfinite(q[0])) continue;
            // The pixel centre's view-plane coordinates: x in [-4, 4], y in [-3, 3].
            const double vx = ((x + 0.5) / kW * 2 - 1) * 4.0, vy = ((y + 0.5) / kH * 2 - 1) * 3.0;
            EXPECT_NEAR(q[0], vx, 1e-3) << x << "," << y;
            EXPECT_NEAR(q[1], vy, 1e-3) << x << "," << y;
            if (std::abs(q[2] + 16.5f) < 2e-3f) ++farHits;
            if (std::abs(q[2] + 6.5f) < 2e-3f) ++nearHits;
        }
    }
    EXPECT_GT(farHits, 300);
    EXPECT_GT(nearHits, 300);
}

// The specular view vector: a sun, a flat glossy metal plane filling the view, and nothing else
// view dependent. With parallel view rays V is the same at every pixel, so is the colour; through
// a perspective camera V turns across the plane and the highlight shows. Deferred (left) and
// forward (right: blended at alpha 1) surfaces both.
TEST(Orthographic, TheViewVectorIsTheSameAtEveryPixel) {
    gltf::Document doc;
    gltf::Material gloss;
    gloss.name = "gloss";
    gloss.baseColorFactor = {0.9f, 0.8f, 0.6f, 1};
    gloss.metallicFactor = 1.0f;
    gloss.roughnessFactor = 0.3f;
    gltf::Material glossForward = gloss;
    glossForward.name = "glossForward";
    glossForward.alphaMode = gltf::AlphaMode::Blend;
    doc.materials = {gloss, glossForward};
    addObject(doc, "deferredHalf", quad(20, 40, 0), {-10, 0, 0});
    addObject(doc, "forwardHalf", quad(20, 40, 1), {10, 0, 0});
    // Its mirror image is near the view axis.
    addSun(doc, 3.0f, gltf::lookRotation({0.15f, -0.1f, -1.0f}));
    const std::string file = convert(doc, "gloss-plane");

    auto spread = [](const CapturedImage& hdr, bool left) {
        double lo = 1e30, hi = 0;
        for (uint32_t y = 4; y + 4 < hdr.height; ++y)
            for (uint32_t x = left ? 4 : hdr.width / 2 + 4; x + 4 < (left ? hdr.width / 2 : hdr.width); ++x) {
                const float* c = &hdr.f32[(size_t(y) * hdr.width + x) * 4];
                const double l = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
                lo = std::min(lo, l);
                hi = std::max(hi, l);
            }
        return hi > 0 ? (hi - lo) / hi : 1.0;
    };
    RenderSettings s;
    s.shadowTechnique = ShadowTechnique::Off; // a plane facing the sun: nothing to shadow
    CameraState ortho = lookAt({0, 0, 6}, {0, 0, 0}, 0.1f, 20.0f);
    ortho.projection = Projection::Orthographic;
    ortho.ymag = 4.0f;
    Rendered o = render(file, ortho, kW, kH, s);
    Rendered p = render(file, lookAt({0, 0, 6}, {0, 0, 0}), kW, kH, s);
    ASSERT_FALSE(o.hdr.f32.empty());
    ASSERT_FALSE(p.hdr.f32.empty());
    EXPECT_LT(spread(o.hdr, true), 0.01) << "deferred";
    EXPECT_LT(spread(o.hdr, false), 0.01) << "forward";
    EXPECT_GT(spread(p.hdr, true), 0.1) << "the perspective view sees the highlight move";
    EXPECT_GT(spread(p.hdr, false), 0.1);
}

// Khronos glTF sample model "Cameras": a unit square tilted 45 degrees away about x, seen by a
// perspective camera (0) and an orthographic one (1, xmag = ymag = 1) from (0.5, 0.5, 3). Through
// camera 1 the square is a rectangle 0.5 x 0.354 of the view (x in [0, 1] -> NDC [-0.5, 0.5],
// y in [0, 0.707] -> [-0.5, 0.207]); through camera 0 its far edge is narrower than its near one.
TEST(Orthographic, KhronosCamerasModelCamera1IsOrthographic) {
    std::filesystem::path model = PNB_KHRONOS_DIR "/Cameras/glTF/Cameras.gltf";
    if (const char* dir = std::getenv("PNB_KHRONOS_DIR")) model = std::filesystem::path(dir) / "Cameras/glTF/Cameras.gltf";
    if (!std::filesystem::exists(model)) GTEST_SKIP() << model << " not found (../shared/khronos): skipped";
    auto dir = std::filesystem::temp_directory_path() / ("pnb-render-test-" + std::to_string(::getpid())) / "khronos";
    std::filesystem::create_directories(dir);
    converter::ConvertSettings cs;
    cs.input = model.string();
    cs.output = (dir / "Cameras.pnb").string();
    cs.jobs = 1;
    cs.validateShaders = false;
    cs.noSidecar = true;
    auto converted = converter::convertScene(cs);
    ASSERT_TRUE(converted.ok()) << converted.error().message;
    auto scene = loadScene(cs.output);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    ASSERT_EQ((*scene)->cameras.size(), 2u);
    ASSERT_EQ(sceneCamera(**scene, 1).projection, Projection::Orthographic);

    constexpr uint32_t kSide = 256;
    struct Shape {
        int top = -1, bottom = -1;       // covered rows (GL: row 0 at the bottom)
        int topWidth = 0, bottomWidth = 0;
    };
    auto shape = [&](size_t camera) {
        Rendered r = render(cs.output, sceneCamera(**scene, camera), kSide, kSide);
        Shape s;
        for (uint32_t y = 0; y < r.depth.height; ++y) {
            int width = 0;
            for (uint32_t x = 0; x < r.depth.width; ++x) width += r.depth.f32[size_t(y) * kSide + x] > 0;
            if (width == 0) continue;
            if (s.bottom < 0) {
                s.bottom = int(y);
                s.bottomWidth = width;
            }
            s.top = int(y);
            s.topWidth = width;
        }
        return s;
    };
    Shape ortho = shape(1), persp = shape(0);
    ASSERT_GE(ortho.bottom, 0) << "camera 1 sees the square";
    EXPECT_NEAR(ortho.bottomWidth, 128, 2);
    EXPECT_NEAR(ortho.topWidth, 128, 2); // a rectangle: the far edge as wide as the near one
    EXPECT_NEAR(ortho.bottom, 64, 2);     // NDC y -0.5
    EXPECT_NEAR(ortho.top, 154, 2);       // NDC y 0.207
    ASSERT_GE(persp.bottom, 0);
    EXPECT_LT(double(persp.topWidth), 0.9 * double(persp.bottomWidth)); // a trapezoid
}

} // namespace
} // namespace pnb::player::test
