// Light through glass (issue 43) in the three tracers, against hand-computed transmittances:
// a pane of alpha 0.5 and colour (1, 0, 0) lets (0.5, 0, 0) through, two panes multiply, an
// opaque caster above a pane gives 0, a pane that casts no shadow lets everything through, a
// textured pane reads its texture (with its transform) at the hit, the same for a point light's
// segments; the verdict does not change with the unit of length; sky seen through a pane is
// tinted by the pane's share of the hemisphere; one-bounce light through a pane is the pane-free
// estimate times T twice (in and out), sample for sample. Scenes are built by hand
// (pnb::SceneBuilder): quads, materials, a texture, an environment, a sun.
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "pnb/scene_builder.h"
#include "pnb_lighting/sh9.h"
#include "pnb_reference/indirect_tracer.h"
#include "pnb_reference/shadow_tracer.h"
#include "pnb_reference/sky_tracer.h"

namespace pnb::reference::test {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A scene of quads, each its own mesh and node, every length multiplied by `unit`.
struct QuadScene {
    SceneBuilder b;
    float unit = 1.0f;

    uint32_t material(glm::vec4 color, AlphaMode mode = AlphaMode::Blend, bool castsShadows = true) {
        Material m;
        m.baseColorFactor = {color.r, color.g, color.b, color.a};
        m.alphaMode = mode;
        m.castsShadows = castsShadows;
        b.scene.materials.push_back(m);
        return uint32_t(b.scene.materials.size() - 1);
    }

    // A width x height RGBA32F texture (rows t = 0 first), clamped at its edges, as the
    // base-colour texture of `material` with the KHR_texture_transform `scale`.
    void texture(uint32_t material, uint32_t width, uint32_t height, const std::vector<glm::vec4>& texels,
                 glm::vec2 scale = glm::vec2(1.0f)) {
        TextureDesc t;
        t.format = TextureFormat::RGBA32F;
        t.width = width;
        t.height = height;
        t.wrapU = t.wrapV = Wrap::ClampToEdge;
        TextureMip mip;
        mip.texture = uint32_t(b.scene.textures.size());
        mip.width = width;
        mip.height = height;
        std::vector<float> data;
        for (const glm::vec4& c : texels) data.insert(data.end(), {c.r, c.g, c.b, c.a});
        mip.data = b.keep(data);
        b.scene.textures.push_back(t);
        b.scene.textureMips.push_back(mip);
        TextureSlot& slot = b.scene.materials[material].textures[size_t(TextureSlotKind::BaseColor)];
        slot.texture = mip.texture;
        slot.scale = {scale.x, scale.y};
    }

    // The quad corner, corner + a, corner + a + e, corner + e (texture coordinates (0, 0),
    // (1, 0), (1, 1), (0, 1)).
    void quad(glm::vec3 corner, glm::vec3 a, glm::vec3 e, uint32_t material) {
        const glm::vec3 p[4] = {corner * unit, (corner + a) * unit, (corner + a + e) * unit, (corner + e) * unit};
        std::vector<float> xyz, uv = {0, 0, 1, 0, 1, 1, 0, 1};
        for (const glm::vec3& v : p) xyz.insert(xyz.end(), {v.x, v.y, v.z});
        Mesh m;
        m.vertexCount = 4;
        VertexStream position;
        position.data = b.keep(xyz);
        VertexStream texCoord;
        texCoord.semantic = VertexSemantic::TexCoord0;
        texCoord.componentCount = 2;
        texCoord.data = b.keep(uv);
        m.streams = {position, texCoord};
        m.indexType = IndexType::U32;
        m.indices = b.keep(std::vector<uint32_t>{0, 1, 2, 0, 2, 3});
        Submesh sm;
        sm.material = material;
        sm.indexCount = 6;
        m.submeshes.push_back(sm);
        Node n;
        n.mesh = uint32_t(b.scene.meshes.size());
        b.scene.meshes.push_back(m);
        b.scene.nodes.nodes.push_back(n);
    }

    // A horizontal square of half-size `half` at height y, centred over (x, z).
    void square(float x, float y, float z, float half, uint32_t material) {
        quad({x - half, y, z - half}, {0, 0, 2 * half}, {2 * half, 0, 0}, material);
    }
};

// The floor every shadow test uses (40 x 40 at y = 0, opaque) and a red pane of alpha 0.5
// (T = (0.5, 0, 0)) over x, z in [-1, 1] at y = 2.
void floorAndRedPane(QuadScene& s) {
    s.square(0, 0, 0, 20, s.material(glm::vec4(1.0f), AlphaMode::Opaque));
    s.square(0, 2, 0, 1, s.material({1, 0, 0, 0.5f}));
}

std::unique_ptr<ShadowTracer> shadowTracer(const QuadScene& s, glm::dvec3 origin = glm::dvec3(0.0)) {
    auto t = ShadowTracer::build(s.b.scene, origin);
    EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.error().message);
    return t.ok() ? std::move(*t) : nullptr;
}

// Colour visibility of world points (times the scene's unit) towards the sun overhead.
std::vector<glm::vec3> sunThrough(const ShadowTracer& tracer, const std::vector<glm::vec3>& points, float unit = 1,
                                  glm::vec3 towardLight = {0, 1, 0}) {
    std::vector<glm::vec3> positions;
    for (const glm::vec3& p : points) positions.push_back(glm::vec3(glm::dvec3(p * unit) - tracer.origin()));
    std::vector<glm::vec3> out(points.size(), glm::vec3(-7.0f));
    tracer.colorVisibility(positions, towardLight, out, -tracer.origin());
    return out;
}

void expectNear(glm::vec3 actual, glm::vec3 expected, float tolerance = 1e-6f) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(actual[c], expected[c], tolerance) << "channel " << c;
}

TEST(Translucency, APaneOfAlphaHalfLetsHalfItsColourThroughAndNothingBeside) {
    QuadScene s;
    floorAndRedPane(s);
    auto tracer = shadowTracer(s);
    ASSERT_TRUE(tracer);
    EXPECT_EQ(tracer->stats().casterInstances, 2u);
    EXPECT_EQ(tracer->stats().translucentCasters, 1u);
    EXPECT_EQ(tracer->stats().excludedInstances, 0u);
    // (0, 0, 0) lies under the quad's diagonal: its ray crosses the pane through the edge both
    // triangles share, once.
    const std::vector<glm::vec3> points = {{0, 0, 0}, {0.9f, 0, -0.9f}, {5, 0, 0}, {1.1f, 0, 0}};
    auto v = sunThrough(*tracer, points);
    EXPECT_EQ(v[0], glm::vec3(0.5f, 0, 0));
    EXPECT_EQ(v[1], glm::vec3(0.5f, 0, 0));
    EXPECT_EQ(v[2], glm::vec3(1.0f));
    EXPECT_EQ(v[3], glm::vec3(1.0f));
    // The binary call is the opaque part: the pane blocks nothing.
    std::vector<glm::vec3> positions(points.begin(), points.end());
    std::vector<float> binary(points.size());
    tracer->visibility(positions, {0, 1, 0}, binary);
    EXPECT_EQ(binary, std::vector<float>(points.size(), 1.0f));
    // A point on the pane itself is not behind it (the own-surface rule), on either face.
    auto onPane = sunThrough(*tracer, {{0.3f, 2, 0.3f}});
    EXPECT_EQ(onPane[0], glm::vec3(1.0f));
    // A tilted sun moves the tinted footprint: towards (1, 2, 0) a ray from (x, 0, 0) meets
    // y = 2 at x + 1, inside the pane for x in [-2, 0].
    auto tilted = sunThrough(*tracer, {{-1, 0, 0}, {0.5f, 0, 0}}, 1, glm::normalize(glm::vec3(1, 2, 0)));
    EXPECT_EQ(tilted[0], glm::vec3(0.5f, 0, 0));
    EXPECT_EQ(tilted[1], glm::vec3(1.0f));
}

TEST(Translucency, TwoPanesMultiplyAndAnOpaqueCasterAboveAPaneGivesZero) {
    QuadScene s;
    s.square(0, 0, 0, 20, s.material(glm::vec4(1.0f), AlphaMode::Opaque));
    s.square(0, 2, 0, 1, s.material({1, 0.5f, 0.25f, 0.5f}));  // T = (0.5, 0.25, 0.125)
    s.square(1, 3, 0, 1, s.material({1, 1, 1, 0.2f}));         // T = 0.8, over x in [0, 2]
    s.square(-1, 4, 3, 1, s.material(glm::vec4(1.0f), AlphaMode::Opaque)); // over z in [2, 4]
    s.square(-1, 1, 3, 1, s.material({1, 1, 1, 0.5f}));         // a pane below it
    s.square(5, 4, 0, 1, s.material({1, 1, 1, 1}, AlphaMode::Mask)); // Mask: opaque
    auto tracer = shadowTracer(s);
    ASSERT_TRUE(tracer);
    EXPECT_EQ(tracer->stats().translucentCasters, 3u);
    EXPECT_EQ(tracer->stats().maskedCastersTreatedOpaque, 1u);
    auto v = sunThrough(*tracer, {{-0.5f, 0, 0}, {0.5f, 0, 0}, {1.5f, 0, 0}, {-1, 0, 3}, {5, 0, 0}});
    expectNear(v[0], {0.5f, 0.25f, 0.125f});
    expectNear(v[1], {0.4f, 0.2f, 0.1f}); // under both
    expectNear(v[2], glm::vec3(0.8f));
    EXPECT_EQ(v[3], glm::vec3(0.0f));
    EXPECT_EQ(v[4], glm::vec3(0.0f));
}

TEST(Translucency, APaneThatCastsNoShadowLetsEverythingThrough) {
    QuadScene s;
    s.square(0, 0, 0, 20, s.material(glm::vec4(1.0f), AlphaMode::Opaque));
    s.square(0, 2, 0, 1, s.material({1, 0, 0, 0.5f}, AlphaMode::Blend, false));
    auto tracer = shadowTracer(s);
    ASSERT_TRUE(tracer);
    EXPECT_EQ(tracer->stats().translucentCasters, 0u);
    EXPECT_EQ(tracer->stats().excludedInstances, 1u);
    EXPECT_EQ(sunThrough(*tracer, {{0, 0, 0}})[0], glm::vec3(1.0f));
}

TEST(Translucency, ATexturedPaneIsReadAtTheHitsTextureCoordinateWithItsTransform) {
    // Two texels across u, times the factor's alpha 0.5: yellow of alpha 0.5 x 0.5 (T = (0.75,
    // 0.75, 0)) and blue of alpha 1.5 x 0.5 (T = (0, 0, 0.25)), clamped at the edges: u < 0.25
    // reads the first alone, u > 0.75 the second.
    for (bool scaled : {false, true}) {
        SCOPED_TRACE(scaled ? "texture transform scale 0.25" : "no transform");
        QuadScene s;
        s.square(0, 0, 0, 20, s.material(glm::vec4(1.0f), AlphaMode::Opaque));
        const uint32_t glass = s.material({1, 1, 1, 0.5f});
        s.texture(glass, 2, 1, {{1, 1, 0, 0.5f}, {0, 0, 1, 1.5f}}, glm::vec2(scaled ? 0.25f : 1.0f, 1.0f));
        // u runs along +z on square(): the quad's first edge is (0, 0, 2 half).
        s.square(0, 2, 0, 1, glass);
        auto tracer = shadowTracer(s);
        ASSERT_TRUE(tracer);
        auto v = sunThrough(*tracer, {{0, 0, -0.8f}, {0, 0, 0.8f}});
        expectNear(v[0], {0.75f, 0.75f, 0.0f});
        // Scaled by 0.25, the whole pane reads u' <= 0.25: the first texel.
        expectNear(v[1], scaled ? glm::vec3(0.75f, 0.75f, 0.0f) : glm::vec3(0.0f, 0.0f, 0.25f));
    }
}

TEST(Translucency, APointLightsSegmentsCrossThePaneToo) {
    QuadScene s;
    floorAndRedPane(s);
    auto tracer = shadowTracer(s);
    ASSERT_TRUE(tracer);
    // A light at (0, 5, 0): the segment from (x, 0, 0) meets y = 2 at 0.6 x, inside the pane
    // for |x| < 1 / 0.6.
    std::vector<glm::vec3> points = {{0, 0, 0}, {1.5f, 0, 0}, {1.8f, 0, 0}, {0, 6, 0}, {0, 3, 0}};
    std::vector<glm::vec3> out(points.size());
    tracer->colorVisibilityToPoint(points, {0, 5, 0}, out);
    EXPECT_EQ(out[0], glm::vec3(0.5f, 0, 0));
    EXPECT_EQ(out[1], glm::vec3(0.5f, 0, 0));
    EXPECT_EQ(out[2], glm::vec3(1.0f));
    EXPECT_EQ(out[3], glm::vec3(1.0f)); // above the light: the pane is not between
    EXPECT_EQ(out[4], glm::vec3(1.0f)); // between the pane and the light
    // A light below the pane, a point above it: the same pane, the other way round.
    tracer->colorVisibilityToPoint(std::vector<glm::vec3>{{0, 4, 0}}, {0, 1, 0}, std::span(out).first(1));
    EXPECT_EQ(out[0], glm::vec3(0.5f, 0, 0));
}

TEST(Translucency, TheVerdictDoesNotDependOnTheUnitOfLength) {
    const std::vector<glm::vec3> points = {{0, 0, 0}, {0.99f, 0, 0.5f}, {1.01f, 0, 0}, {0.5f, 0, 0.5f},
                                           {-0.5f, 0, 0.25f}, {3, 0, 3}};
    std::vector<std::vector<glm::vec3>> verdicts;
    for (float unit : {1e-3f, 1.0f, 1e3f}) {
        QuadScene s;
        s.unit = unit;
        floorAndRedPane(s);
        s.square(0.5f, 3, 0.5f, 0.5f, s.material({0, 1, 1, 0.5f})); // T = (0, 0.5, 0.5) on top
        auto tracer = shadowTracer(s, glm::dvec3(0, 10, 10) * double(unit));
        ASSERT_TRUE(tracer);
        verdicts.push_back(sunThrough(*tracer, points, unit, glm::normalize(glm::vec3(0.1f, 1, 0.05f))));
    }
    for (size_t i = 0; i < points.size(); ++i) {
        SCOPED_TRACE(testing::Message() << "point " << i);
        EXPECT_EQ(verdicts[0][i], verdicts[1][i]);
        EXPECT_EQ(verdicts[2][i], verdicts[1][i]);
    }
    // Not all the same answer: the scene does test something.
    EXPECT_EQ(verdicts[1][4], glm::vec3(0.5f, 0, 0));
    EXPECT_EQ(verdicts[1][0], glm::vec3(0.0f)); // red through the red pane, then cyan
    EXPECT_EQ(verdicts[1][5], glm::vec3(1.0f));
}

TEST(Translucency, AClosedGlassBoxMultipliesTwiceAndManyThreadsMatchOnePoint) {
    QuadScene s;
    s.square(0, 0, 0, 20, s.material(glm::vec4(1.0f), AlphaMode::Opaque));
    const uint32_t glass = s.material({1, 0.5f, 1, 0.5f}); // T = (0.5, 0.25, 0.5) per face
    s.square(0, 2, 0, 1, glass);
    s.square(0, 3, 0, 1, glass); // the lid and the floor of a box: a ray crosses both
    auto tracer = shadowTracer(s);
    ASSERT_TRUE(tracer);
    std::vector<glm::vec3> points;
    for (float x = -3.05f; x < 3; x += 0.1f)
        for (float z = -3.05f; z < 3; z += 0.1f) points.push_back({x, 0, z});
    auto all = sunThrough(*tracer, points);
    for (size_t i = 0; i < points.size(); ++i) {
        const bool under = std::fabs(points[i].x) < 1 && std::fabs(points[i].z) < 1;
        ASSERT_EQ(all[i], under ? glm::vec3(0.25f, 0.0625f, 0.25f) : glm::vec3(1.0f)) << i;
        if (i % 37 == 0) {
            ASSERT_EQ(sunThrough(*tracer, {points[i]})[0], all[i]) << i;
        }
    }
}

TEST(Translucency, BadInputGivesNaNAsTheBinaryCallDoes) {
    QuadScene s;
    floorAndRedPane(s);
    auto tracer = shadowTracer(s);
    ASSERT_TRUE(tracer);
    std::vector<glm::vec3> points = {{0, 0, 0}, {kNaN, 0, 0}};
    std::vector<glm::vec3> out(2);
    tracer->colorVisibility(points, {0, 1, 0}, out);
    EXPECT_EQ(out[0], glm::vec3(0.5f, 0, 0));
    EXPECT_TRUE(std::isnan(out[1].x) && std::isnan(out[1].y) && std::isnan(out[1].z));
    tracer->colorVisibility(points, {0, 0, 0}, out); // no direction
    for (const glm::vec3& v : out) EXPECT_TRUE(std::isnan(v.x) && std::isnan(v.y) && std::isnan(v.z));
    std::vector<glm::vec3> wrongSize(3, glm::vec3(5.0f));
    tracer->colorVisibilityToPoint(points, {0, 5, 0}, wrongSize);
    for (const glm::vec3& v : wrongSize) EXPECT_TRUE(std::isnan(v.x));
}

// [SECTION] sky and one bounce

// A constant sky of radiance `l` (a 1 x 1 RGBA32F image).
void constantSky(QuadScene& s, glm::vec3 l) {
    TextureDesc t;
    t.format = TextureFormat::RGBA32F;
    t.width = t.height = 1;
    TextureMip mip;
    mip.texture = uint32_t(s.b.scene.textures.size());
    mip.width = mip.height = 1;
    mip.data = s.b.keep(std::vector<float>{l.x, l.y, l.z, 1.0f});
    s.b.scene.textures.push_back(t);
    s.b.scene.textureMips.push_back(mip);
    Environment e;
    e.radiance = mip.texture;
    s.b.scene.environment = e;
}

// View factor from a differential area facing a parallel square of half-size a, centred above
// it at distance h (Howell's catalogue, C-11: four a x a rectangles meeting over the point).
double squareViewFactor(double a, double h) {
    const double x = a / h;
    const double f = 2.0 * (x / std::sqrt(1 + x * x)) * std::atan(x / std::sqrt(1 + x * x));
    return 4.0 * f / (2.0 * kPi);
}

TEST(Translucency, SkySeenThroughAPaneIsTintedByThePanesViewFactor) {
    QuadScene s;
    constantSky(s, glm::vec3(2.0f));
    s.square(0, 1, 0, 1, s.material({1, 0.5f, 0, 0.5f})); // T = (0.5, 0.25, 0)
    auto built = SkyTracer::build(s.b.scene, glm::dvec3(0.0));
    ASSERT_TRUE(built.ok()) << (built.ok() ? "" : built.error().message);
    const SkyTracer& tracer = **built;
    EXPECT_EQ(tracer.stats().translucentInstances, 1u);
    std::vector<glm::vec3> points(16, glm::vec3(0.0f)), normals(16, glm::vec3(0, 1, 0)), mean(16), error(16);
    SkySettings settings;
    settings.samples = 4096;
    tracer.irradiance(points, normals, settings, mean, error);
    const double f = squareViewFactor(1.0, 1.0); // 0.554
    const glm::dvec3 t(0.5, 0.25, 0.0);
    glm::dvec3 m(0.0), se(0.0);
    for (size_t i = 0; i < points.size(); ++i) {
        m += glm::dvec3(mean[i]) / 16.0;
        se += glm::dvec3(error[i]) / 16.0;
    }
    for (int c = 0; c < 3; ++c) {
        const double truth = kPi * 2.0 * ((1.0 - f) + f * t[c]);
        // The mean of 16 independent estimates: its error is se / 4; allow 4 of those.
        EXPECT_NEAR(m[c], truth, 4.0 * se[c] / 4.0 + 1e-6) << "channel " << c;
    }
}

// Sun straight down onto a lit floor (half-size 5, albedo (0.8, 0.4, 0.2)); with `pane`, a pane
// of T = (0.5, 0.25, 1) at y = 0.5 covering everything a point at y = 1 sees of the floor and
// every sun ray to the floor below it.
std::unique_ptr<IndirectTracer> litFloor(QuadScene& s, bool pane) {
    s.square(0, 0, 0, 5, s.material({0.8f, 0.4f, 0.2f, 1}, AlphaMode::Opaque));
    s.b.scene.materials.back().metallicFactor = 0;
    if (pane) s.square(0, 0.5f, 0, 20, s.material({1, 0.5f, 2, 0.5f}));
    Light sun;
    sun.intensity = 3;
    s.b.scene.lights.lights.push_back(sun);
    Node n;
    n.light = 0;
    n.rotation = {-0.70710678f, 0, 0, 0.70710678f}; // -Z turned to -Y: shining straight down
    s.b.scene.nodes.nodes.push_back(n);
    auto t = IndirectTracer::build(s.b.scene, glm::dvec3(0.0));
    EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.error().message);
    return t.ok() ? std::move(*t) : nullptr;
}

TEST(Translucency, OneBounceThroughAPaneIsThePaneFreeEstimateTimesTTwice) {
    QuadScene open, glazed;
    auto without = litFloor(open, false), with = litFloor(glazed, true);
    ASSERT_TRUE(without && with);
    EXPECT_EQ(with->stats().translucentInstances, 1u);
    std::vector<glm::vec3> points(8, glm::vec3(0, 1, 0)), normals(8, glm::vec3(0, -1, 0));
    std::vector<glm::vec3> m0(8), e0(8), m1(8), e1(8);
    IndirectSettings settings;
    settings.samples = 512;
    without->irradiance(points, normals, settings, m0, e0);
    with->irradiance(points, normals, settings, m1, e1);
    // The same seed: the same rays hit the same floor points; each crosses the pane on its way
    // from the floor to the point and the sun's light crossed it on its way to the floor.
    const glm::vec3 t2(0.25f, 0.0625f, 1.0f);
    for (size_t i = 0; i < points.size(); ++i) {
        ASSERT_GT(m0[i].x, 0.1f);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(m1[i][c], m0[i][c] * t2[c], 1e-5f * m0[i][c]) << i << " " << c;
    }
}

} // namespace
} // namespace pnb::reference::test
