#include "render_fixture.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "pnb_player/gl_context.h"
#include "pnb_player/benchmark.h"
#include "pnb_player/gpu_scene.h"

namespace pnb::player::test {

namespace {

std::unique_ptr<GlContext> gContext;

std::string tempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "global";
    auto dir = std::filesystem::temp_directory_path() /
               ("pnb-render-test-" + std::to_string(::getpid())) / name;
    std::filesystem::create_directories(dir);
    return dir.string();
}

} // namespace

void HeadlessEnvironment::SetUp() {
    auto c = createHeadlessContext(false);
    ASSERT_TRUE(c.ok()) << c.error().message;
    gContext = std::move(*c);
}

void HeadlessEnvironment::TearDown() {
    gContext.reset();
    std::filesystem::remove_all(std::filesystem::temp_directory_path() /
                                ("pnb-render-test-" + std::to_string(::getpid())));
}

void addLights(gltf::Document& doc, gltf::Float3 offset) {
    addSun(doc, 2.0f, gltf::lookRotation({0.4f, -1.0f, -0.6f}));
    gltf::Light point;
    point.name = "lamp";
    point.type = gltf::LightType::Point;
    point.color = {1.0f, 0.8f, 0.6f};
    point.intensity = 6.0f;
    doc.lights.push_back(point);
    gltf::Node lampNode;
    lampNode.name = "lamp";
    lampNode.light = 1;
    lampNode.translation = {offset[0] + 1.5f, offset[1] + 1.5f, offset[2] + 2.0f};
    doc.nodes.push_back(lampNode);
}

gltf::Primitive uvSphere(float radius, uint32_t rings, uint32_t segments, uint32_t material) {
    gltf::Primitive p;
    p.material = material;
    for (uint32_t r = 0; r <= rings; ++r) {
        float theta = float(std::numbers::pi) * float(r) / float(rings);
        for (uint32_t s = 0; s <= segments; ++s) {
            float phi = 2.0f * float(std::numbers::pi) * float(s) / float(segments);
            gltf::Float3 n{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
            p.normals.push_back(n);
            p.positions.push_back({n[0] * radius, n[1] * radius, n[2] * radius});
        }
    }
    for (uint32_t r = 0; r < rings; ++r)
        for (uint32_t s = 0; s < segments; ++s) {
            uint32_t a = r * (segments + 1) + s, b = a + segments + 1;
            // Counter-clockwise from outside (theta grows downward, phi toward -z... from +y).
            p.indices.insert(p.indices.end(), {a, a + 1, b, a + 1, b + 1, b});
        }
    return p;
}

std::string convert(const gltf::Document& doc, const std::string& name, const std::string& sidecarJson) {
    // The driver compiles every program in these tests, so glslang validation is skipped.
    return pnb::test::convertDocument(tempDir(), doc, name, sidecarJson, false);
}

Rendered render(const std::string& path, const CameraState& camera, uint32_t w, uint32_t h,
                const RenderSettings& settings) {
    Rendered out;
    auto scene = loadScene(path);
    EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().message);
    if (!scene.ok()) return out;
    auto renderer = Renderer::create(**scene, settings);
    EXPECT_TRUE(renderer.ok());
    if (!renderer.ok()) return out;
    auto r = (*renderer)->render(camera, w, h);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    out.stats = (*renderer)->lastFrame();
    out.memory = (*renderer)->targetMemory();
    out.deferredLayers = (*scene)->deferredLayers.size();
    out.lightingProgramCompiled = (*scene)->deferredLightingProgram.has_value() &&
                                  bool((*scene)->programs[*(*scene)->deferredLightingProgram]);
    out.color = std::move(*(*renderer)->capture(CaptureBuffer::Color));
    out.hdr = std::move(*(*renderer)->capture(CaptureBuffer::Hdr));
    out.depth = std::move(*(*renderer)->capture(CaptureBuffer::Depth));
    out.position = std::move(*(*renderer)->capture(CaptureBuffer::Position));
    // PNB_TEST_IMAGES=DIR keeps every rendered image, for looking at a failure.
    if (const char* dir = std::getenv("PNB_TEST_IMAGES")) {
        static int counter = 0;
        std::string file = std::string(dir) + "/" + std::filesystem::path(path).stem().string() + "_" +
                           std::to_string(counter++) + ".png";
        EXPECT_TRUE(saveCapture(file, out.color).ok());
    }
    return out;
}

CameraState lookAt(glm::dvec3 position, glm::dvec3 target, float znear, float zfar) {
    CameraState c;
    c.position = position;
    c.rotation = glm::quatLookAt(glm::normalize(target - position), glm::dvec3(0, 1, 0));
    c.yfovRadians = 0.8f;
    c.znear = znear;
    c.zfar = zfar;
    return c;
}

double ImageDiff::fractionOver(int threshold) const {
    if (perPixelMax.empty()) return 0;
    size_t n = 0;
    for (int d : perPixelMax) n += d > threshold;
    return double(n) / double(perPixelMax.size());
}

ImageDiff compareRgba8(const CapturedImage& a, const CapturedImage& b) {
    ImageDiff d;
    EXPECT_EQ(a.u8.size(), b.u8.size());
    if (a.u8.size() != b.u8.size() || a.u8.empty()) return d;
    double sum = 0;
    for (size_t i = 0; i < a.u8.size(); i += 4) {
        int m = 0;
        for (size_t c = 0; c < 3; ++c) {
            int diff = std::abs(int(a.u8[i + c]) - int(b.u8[i + c]));
            sum += diff;
            m = std::max(m, diff);
        }
        d.perPixelMax.push_back(m);
        d.maxAbs = std::max(d.maxAbs, m);
    }
    d.meanAbs = sum / double(a.u8.size() / 4 * 3);
    return d;
}

bool allFinite(const CapturedImage& image) {
    for (float f : image.f32)
        if (!std::isfinite(f)) return false;
    return true;
}

} // namespace pnb::player::test
