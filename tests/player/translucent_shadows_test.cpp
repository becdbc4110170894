// Light through glass (issue 43): a blended caster lets the sun or a lamp through, tinted by
// T = baseColor.rgb x (1 - alpha). A red pane (1, 0, 0) at alpha 0.5 over a floor: the floor's
// colour visibility behind it is (0.5, 0, 0), beside it 1; an opaque caster above the pane makes
// it 0; the pane is not tinted by its own map; the companion maps exist only with a blended caster.
#include <gtest/gtest.h>

#include <cmath>

#include "pnb_player/gpu_scene.h"
#include "render_fixture.h"

namespace pnb::player::test {
namespace {

const gltf::Float4 kFlat{-0.70710678f, 0, 0, 0.70710678f}; // a quad's +Z turned up

// Floor 8 x 8 at y = 0, a red half-transparent pane 1 x 1 at y = 1.5 (and an opaque grey lid
// above it at y = 2.5 with `lid`), lit by a sun straight down or by a point light at (0, 3, 0).
std::string glassScene(const std::string& name, bool lid, bool lamp, bool glassCasts = true) {
    gltf::Document doc;
    gltf::Material floor, glass, grey;
    floor.name = "floor";
    glass.name = "glass";
    glass.baseColorFactor = {1, 0, 0, 0.5f};
    glass.alphaMode = gltf::AlphaMode::Blend;
    glass.doubleSided = true;
    grey.name = "lid";
    doc.materials = {floor, glass, grey};
    addObject(doc, "floor", quad(8, 8, 0), {0, 0, 0}, kFlat);
    addObject(doc, "pane", quad(1, 1, 1), {0, 1.5f, 0}, kFlat);
    if (lid) addObject(doc, "lid", quad(1.4f, 1.4f, 2), {0, 2.5f, 0}, kFlat);
    if (lamp) {
        gltf::Light bulb;
        bulb.name = "bulb";
        bulb.type = gltf::LightType::Point;
        bulb.intensity = 20.0f;
        bulb.range = 12.0f;
        doc.lights.push_back(bulb);
        gltf::Node n;
        n.name = "bulb";
        n.light = 0;
        n.translation = {0, 3, 0};
        doc.nodes.push_back(n);
    } else {
        addSun(doc, 3.0f, kFlat); // -Z turned down: straight down
    }
    return convert(doc, name, glassCasts ? "" : R"({"materials": {"glass": {"casts_shadows": false}}})");
}

struct Captured {
    CapturedImage color, position, hdr;
    TargetMemory memory;
};

Captured captureColorVisibility(const std::string& file, const CameraState& camera, const RenderSettings& s) {
    Captured c;
    auto scene = loadScene(file);
    EXPECT_TRUE(scene.ok());
    if (!scene.ok()) return c;
    auto renderer = Renderer::create(**scene, s);
    EXPECT_TRUE(renderer.ok());
    if (!renderer.ok()) return c;
    EXPECT_TRUE((*renderer)->render(camera, 128, 96).ok());
    auto color = (*renderer)->capture(CaptureBuffer::ShadowColor);
    auto position = (*renderer)->capture(CaptureBuffer::Position);
    auto hdr = (*renderer)->capture(CaptureBuffer::Hdr);
    EXPECT_TRUE(color.ok() && position.ok() && hdr.ok());
    if (!color.ok() || !position.ok() || !hdr.ok()) return c;
    c.color = std::move(*color);
    c.position = std::move(*position);
    c.hdr = std::move(*hdr);
    c.memory = (*renderer)->targetMemory();
    return c;
}

// Floor pixels whose world position (camera-relative + the camera's) lies within `inner` of the
// axis (|x|, |z| < inner) must show `behind`; those beyond `outer` (and within `far`) show 1.
struct FloorCheck {
    int behindCount = 0, besideCount = 0, behindWrong = 0, besideWrong = 0;
};
FloorCheck checkFloor(const Captured& c, glm::dvec3 eye, double inner, double outer, double far, glm::vec3 behind) {
    FloorCheck f;
    const size_t n = size_t(c.color.width) * c.color.height;
    for (size_t i = 0; i < n && c.position.f32.size() == n * 3; ++i) {
        glm::dvec3 p(c.position.f32[i * 3], c.position.f32[i * 3 + 1], c.position.f32[i * 3 + 2]);
        if (!std::isfinite(p.x)) continue;
        p += eye;
        if (std::abs(p.y) > 0.01) continue; // not the floor
        const glm::vec3 v(c.color.f32[i * 4], c.color.f32[i * 4 + 1], c.color.f32[i * 4 + 2]);
        const double r = std::max(std::abs(p.x), std::abs(p.z));
        auto near = [](glm::vec3 a, glm::vec3 b) { return glm::all(glm::lessThan(glm::abs(a - b), glm::vec3(0.04f))); };
        if (r < inner) {
            ++f.behindCount;
            f.behindWrong += !near(v, behind);
        } else if (r > outer && r < far) {
            ++f.besideCount;
            f.besideWrong += !near(v, glm::vec3(1.0f));
        }
    }
    return f;
}

RenderSettings sunSettings() {
    RenderSettings s;
    s.shadowTechnique = ShadowTechnique::Pssm;
    s.shadowResolution = 1024;
    s.shadowLocal = false;
    return s;
}

const glm::dvec3 kEye{0, 6, 4};

TEST(TranslucentShadows, TheFloorBehindARedPaneGetsHalfItsRed) {
    const std::string file = glassScene("red-pane", false, false);
    struct Variant {
        const char* name;
        ShadowTechnique technique;
        ShadowRender render;
    } variants[] = {{"pssm layered", ShadowTechnique::Pssm, ShadowRender::Layered},
                    {"pssm multipass", ShadowTechnique::Pssm, ShadowRender::MultiPass},
                    {"sdsm layered", ShadowTechnique::Sdsm, ShadowRender::Layered},
                    {"single", ShadowTechnique::Single, ShadowRender::Layered}};
    for (const Variant& v : variants) {
        SCOPED_TRACE(v.name);
        RenderSettings s = sunSettings();
        s.shadowTechnique = v.technique;
        s.shadowRender = v.render;
        Captured c = captureColorVisibility(file, lookAt(kEye, {0, 0, 0}), s);
        FloorCheck f = checkFloor(c, kEye, 0.4, 0.6, 3.5, {0.5f, 0, 0});
        EXPECT_GT(f.behindCount, 40);
        EXPECT_GT(f.besideCount, 400);
        EXPECT_EQ(f.behindWrong, 0) << "of " << f.behindCount;
        EXPECT_EQ(f.besideWrong, 0) << "of " << f.besideCount;
        // Two cascade companions, 8 B a texel, at 1/4 of the depth array's side (the default
        // shadows.translucent_divisor): 8 / 16 of its 4 B a texel.
        EXPECT_EQ(c.memory.shadowTranslucentBytes, c.memory.shadowMapBytes / 8);
    }
    // Every companion size: the same verdict away from the pane's shadow edge, memory / d^2.
    for (uint32_t log2 : {0u, 1u, 3u}) {
        SCOPED_TRACE("shadows.translucent_divisor " + std::to_string(1u << log2));
        RenderSettings s = sunSettings();
        s.shadowTranslucentDivisorLog2 = log2;
        Captured c = captureColorVisibility(file, lookAt(kEye, {0, 0, 0}), s);
        FloorCheck f = checkFloor(c, kEye, 0.4, 0.6, 3.5, {0.5f, 0, 0});
        EXPECT_GT(f.behindCount, 40);
        EXPECT_EQ(f.behindWrong, 0) << "of " << f.behindCount;
        EXPECT_EQ(f.besideWrong, 0) << "of " << f.besideCount;
        EXPECT_EQ(c.memory.shadowTranslucentBytes, c.memory.shadowMapBytes * 2 >> (2 * log2));
    }
    // shadows.translucent = false: the pane casts nothing, as before issue 43; no companions.
    RenderSettings off = sunSettings();
    off.shadowTranslucent = false;
    Captured c = captureColorVisibility(file, lookAt(kEye, {0, 0, 0}), off);
    FloorCheck f = checkFloor(c, kEye, 0.4, 0.6, 3.5, {1, 1, 1});
    EXPECT_EQ(f.behindWrong, 0);
    EXPECT_EQ(c.memory.shadowTranslucentBytes, 0u);
}

TEST(TranslucentShadows, AnOpaqueCasterAboveThePaneBlocksTheLight) {
    const std::string file = glassScene("lidded-pane", true, false);
    Captured c = captureColorVisibility(file, lookAt(kEye, {0, 0, 0}), sunSettings());
    FloorCheck f = checkFloor(c, kEye, 0.4, 0.8, 3.5, {0, 0, 0});
    EXPECT_GT(f.behindCount, 40);
    EXPECT_EQ(f.behindWrong, 0) << "of " << f.behindCount;
    EXPECT_EQ(f.besideWrong, 0) << "of " << f.besideCount;
}

TEST(TranslucentShadows, ThePaneIsNotTintedByItsOwnMap) {
    // Seen at 45 degrees from the sun's side, the floor through the pane lies 1.5 m beyond its
    // shadow: only the pane's own lighting could differ between translucent shadows on and off.
    const std::string file = glassScene("self-pane", false, false);
    const glm::dvec3 eye{0, 4.5, 3};
    RenderSettings on = sunSettings(), off = sunSettings();
    off.shadowTranslucent = false;
    Captured a = captureColorVisibility(file, lookAt(eye, {0, 1.5, 0}), on);
    Captured b = captureColorVisibility(file, lookAt(eye, {0, 1.5, 0}), off);
    ASSERT_EQ(a.hdr.f32.size(), b.hdr.f32.size());
    size_t compared = 0, differ = 0;
    for (size_t i = 0; i * 4 < a.hdr.f32.size(); ++i) {
        glm::dvec3 p(a.position.f32[i * 3], a.position.f32[i * 3 + 1], a.position.f32[i * 3 + 2]);
        if (std::isfinite(p.x) && std::max(std::abs(p.x + eye.x), std::abs(p.z + eye.z)) < 0.8) continue; // the shadow
        ++compared;
        for (int k = 0; k < 3; ++k)
            if (std::abs(a.hdr.f32[i * 4 + k] - b.hdr.f32[i * 4 + k]) > 1e-3f * (1.0f + std::abs(b.hdr.f32[i * 4 + k]))) {
                ++differ;
                break;
            }
    }
    EXPECT_GT(compared, 5000u);
    EXPECT_EQ(differ, 0u);
}

TEST(TranslucentShadows, APointLightThroughThePaneTintsViaTheAtlas) {
    const std::string file = glassScene("lamp-pane", false, true);
    RenderSettings s;
    s.shadowTechnique = ShadowTechnique::Off;
    s.shadowJudgedLight = 0;
    Captured c = captureColorVisibility(file, lookAt(kEye, {0, 0, 0}), s);
    // The lamp 1.5 m above the pane and 3 m above the floor: the pane's shadow is 2 x 2.
    FloorCheck f = checkFloor(c, kEye, 0.8, 1.2, 3.0, {0.5f, 0, 0});
    EXPECT_GT(f.behindCount, 100);
    EXPECT_GT(f.besideCount, 200);
    EXPECT_EQ(f.behindWrong, 0) << "of " << f.behindCount;
    EXPECT_EQ(f.besideWrong, 0) << "of " << f.besideCount;
    EXPECT_EQ(c.memory.shadowTranslucentBytes, c.memory.localShadowBytes * 2);
}

TEST(TranslucentShadows, NoBlendedCasterNoCompanionsNoVariant) {
    const std::string file = glassScene("glass-casts-nothing", false, false, false);
    auto scene = loadScene(file);
    ASSERT_TRUE(scene.ok());
    EXPECT_FALSE((*scene)->shadowTranslucentProgram.has_value());
    EXPECT_FALSE((*scene)->translucentLighting);
    Captured c = captureColorVisibility(file, lookAt(kEye, {0, 0, 0}), sunSettings());
    EXPECT_GT(c.memory.shadowMapBytes, 0u);
    EXPECT_EQ(c.memory.shadowTranslucentBytes, 0u);
    FloorCheck f = checkFloor(c, kEye, 0.4, 0.6, 3.5, {1, 1, 1});
    EXPECT_EQ(f.behindWrong, 0) << "a glass that casts nothing lets all light through";
}

} // namespace
} // namespace pnb::player::test
