// The sky-light truth checks itself against closed forms: an open plane under a constant sky
// receives pi L; the floor of a long street canyon receives pi L times the view factor of the
// strip of sky between the walls; with visibility off, the Sh source reproduces the player's SH
// irradiance (and its rotation); a 1 x 1 image is a constant sky; no ENVM is an error; seeds
// reproduce. Scenes are built by hand (pnb::SceneBuilder): a few quads and an environment.
#include <cmath>
#include <cstring>
#include <functional>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>
#include <gtest/gtest.h>

#include "pnb/scene_builder.h"
#include "pnb_reference/sky_tracer.h"
#include "pnb_lighting/sh9.h"

namespace pnb::reference::test {
namespace {

constexpr double kPi = std::numbers::pi;

// One opaque quad (two triangles) corner, corner + a, corner + a + b, corner + b, as its own
// mesh and node.
void addQuad(SceneBuilder& b, glm::vec3 corner, glm::vec3 a, glm::vec3 e) {
    if (b.scene.materials.empty()) b.scene.materials.push_back(Material{});
    const glm::vec3 p[4] = {corner, corner + a, corner + a + e, corner + e};
    std::vector<float> xyz;
    for (const glm::vec3& v : p) xyz.insert(xyz.end(), {v.x, v.y, v.z});
    Mesh m;
    m.vertexCount = 4;
    VertexStream s;
    s.semantic = VertexSemantic::Position;
    s.data = b.keep(xyz);
    m.streams.push_back(s);
    m.indexType = IndexType::U32;
    m.indices = b.keep(std::vector<uint32_t>{0, 1, 2, 0, 2, 3});
    Submesh sm;
    sm.material = 0;
    sm.indexCount = 6;
    m.submeshes.push_back(sm);
    Node n;
    n.mesh = uint32_t(b.scene.meshes.size());
    b.scene.meshes.push_back(m);
    b.scene.nodes.nodes.push_back(n);
}

// An ENVM whose radiance image is width x height texels of radiance(direction at the texel's
// centre), stored as RGBA32F or RGBA16F, and whose irradianceSh is `irradianceSh`.
void setEnvironment(SceneBuilder& b, uint32_t width, uint32_t height, TextureFormat format,
                    const std::function<glm::vec3(glm::dvec3)>& radiance, const lighting::Sh9Rgb& irradianceSh) {
    TextureDesc t;
    t.name = b.intern("sky");
    t.format = format;
    t.colorSpace = ColorSpace::Linear;
    t.width = width;
    t.height = height;
    t.mipCount = 1;
    TextureMip mip;
    mip.texture = uint32_t(b.scene.textures.size());
    mip.width = width;
    mip.height = height;
    std::vector<float> f32;
    std::vector<uint16_t> f16;
    for (uint32_t j = 0; j < height; ++j)
        for (uint32_t i = 0; i < width; ++i) {
            glm::vec3 l = radiance(lighting::equirectDirection((i + 0.5) / width, (j + 0.5) / height));
            for (float c : {l.x, l.y, l.z, 1.0f}) {
                f32.push_back(c);
                f16.push_back(glm::packHalf1x16(c));
            }
        }
    mip.data = format == TextureFormat::RGBA16F ? b.keep(f16) : b.keep(f32);
    b.scene.textures.push_back(t);
    b.scene.textureMips.push_back(mip);
    Environment e;
    e.radiance = mip.texture;
    for (int k = 0; k < 9; ++k) {
        const glm::dvec3& c = irradianceSh.c[size_t(k)];
        e.irradianceSh[size_t(k)] = {float(c.x), float(c.y), float(c.z)};
    }
    b.scene.environment = e;
}

// The irradiance SH of a constant radiance L: pi L Y0 / Y0(any) = L sqrt(4 pi) pi in band 0.
lighting::Sh9Rgb constantIrradianceSh(glm::vec3 l) {
    lighting::Sh9Rgb sh;
    sh.c[0] = glm::dvec3(l) * (kPi / lighting::kSh9K0);
    return sh;
}

std::unique_ptr<SkyTracer> build(const SceneBuilder& b, glm::dvec3 origin = glm::dvec3(0.0)) {
    auto t = SkyTracer::build(b.scene, origin);
    EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.error().message);
    return t.ok() ? std::move(*t) : nullptr;
}

struct Estimate {
    std::vector<glm::vec3> mean, error;
};

Estimate trace(const SkyTracer& tracer, const std::vector<glm::vec3>& points, const std::vector<glm::vec3>& normals,
               const SkySettings& settings, glm::dvec3 eye = glm::dvec3(0.0)) {
    Estimate e;
    e.mean.resize(points.size());
    e.error.resize(points.size());
    tracer.irradiance(points, normals, settings, e.mean, e.error, eye);
    return e;
}

// A long street canyon: floor y = 0 for |x| <= w/2, walls of height h at x = +-w/2, length
// `length` along z; a constant sky of radiance l.
void buildCanyon(SceneBuilder& b, float w, float h, float length, glm::vec3 l) {
    addQuad(b, {-w / 2, 0, -length / 2}, {w, 0, 0}, {0, 0, length});
    addQuad(b, {-w / 2, 0, -length / 2}, {0, h, 0}, {0, 0, length});
    addQuad(b, {w / 2, 0, -length / 2}, {0, h, 0}, {0, 0, length});
    setEnvironment(b, 16, 8, TextureFormat::RGBA32F, [&](glm::dvec3) { return l; }, constantIrradianceSh(l));
}

TEST(SkyTracer, AnOpenPlaneUnderAConstantSkyReceivesPiL) {
    SceneBuilder b;
    const glm::vec3 l(1.5f, 0.75f, 3.0f);
    addQuad(b, {-50, 0, -50}, {100, 0, 0}, {0, 0, 100});      // the plane the point lies on
    addQuad(b, {-50, -1, -50}, {100, 0, 0}, {0, -3, 100});     // below the horizon: hides nothing
    setEnvironment(b, 16, 8, TextureFormat::RGBA32F, [&](glm::dvec3) { return l; }, constantIrradianceSh(l));
    auto tracer = build(b);
    ASSERT_TRUE(tracer);
    EXPECT_EQ(tracer->stats().triangles, 4u);
    SkySettings s;
    s.samples = 4096;
    // The point 4e-5 below its plane, as a depth-reconstructed position may be (within the point
    // band, 2^-16 x its distance 5.6 from the eye): the own-surface filter, not luck, lets its rays out.
    Estimate e = trace(*tracer, {{0.3f, -4e-5f, 0.2f}}, {{0, 1, 0}}, s, {0, 2, -5});
    for (int c = 0; c < 3; ++c) {
        const double truth = kPi * l[c];
        EXPECT_LE(std::abs(e.mean[0][c] - truth), 3.0 * e.error[0][c] + 1e-6 * truth) << "channel " << c;
        EXPECT_LE(std::abs(e.mean[0][c] - truth), 0.02 * truth) << "channel " << c;
    }
}

TEST(SkyTracer, TheFloorOfALongCanyonSeesTheStripOfSkyBetweenTheWalls) {
    SceneBuilder b;
    const float w = 2, h = 1, length = 400; // the open ends subtend ~1e-7 of the floor's view
    const glm::vec3 l(2.0f);
    buildCanyon(b, w, h, length, l);
    auto tracer = build(b);
    ASSERT_TRUE(tracer);
    SkySettings s;
    s.samples = 40000;
    // The middle, and a point 0.5 from the right wall: an infinitely long strip of sky between
    // the wall tops at angles phi1 < phi2 from the normal has view factor (sin phi2 - sin phi1) / 2.
    const std::vector<glm::vec3> points = {{0, 0, 3}, {0.5f, 0, -7}};
    const std::vector<glm::vec3> normals(2, glm::vec3(0, 1, 0));
    Estimate e = trace(*tracer, points, normals, s, {0, 1.5, -20});
    const double middle = std::sin(std::atan(w / (2.0 * h)));
    const double offCentre = 0.5 * (std::sin(std::atan(0.5 / h)) + std::sin(std::atan(1.5 / h)));
    const double factors[2] = {middle, offCentre};
    for (int i = 0; i < 2; ++i) {
        const double truth = kPi * l.x * factors[i], open = kPi * l.x;
        const double se = e.error[size_t(i)].x;
        EXPECT_GT(se, 0.0);
        EXPECT_NEAR(e.mean[size_t(i)].x, truth, 3.0 * se) << "point " << i;
        EXPECT_GT(open - truth, 30.0 * se) << "the walls must matter far beyond the tolerance";
    }
    // Visibility off: the open sky.
    s.visibility = false;
    Estimate open = trace(*tracer, points, normals, s, {0, 1.5, -20});
    EXPECT_NEAR(open.mean[0].x, kPi * l.x, 1e-5 * kPi * l.x);
}

// A directional environment: a bright lobe around +X over a dim, slightly blue sky.
glm::dvec3 lobeSky(const glm::dvec3& w) {
    const double c = std::max(0.0, w.x);
    return glm::dvec3(0.2, 0.25, 0.3) + glm::dvec3(8.0, 6.0, 4.0) * (c * c * c * c);
}

TEST(SkyTracer, ShSourceWithoutVisibilityIsThePlayersShIrradianceAndRotatesLikeIt) {
    SceneBuilder b;
    addQuad(b, {-5, 10, -5}, {10, 0, 0}, {0, 0, 10}); // a roof: must not matter with visibility off
    const lighting::Sh9Rgb irradiance = lighting::sh9IrradianceCoefficients(
        lighting::sh9ProjectFunction(lobeSky), lighting::ShWindow::NonNegative);
    setEnvironment(b, 64, 32, TextureFormat::RGBA32F, [](glm::dvec3 w) { return glm::vec3(lobeSky(w)); }, irradiance);
    auto tracer = build(b);
    ASSERT_TRUE(tracer);
    const std::vector<glm::vec3> normals = {{1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}, {0, 1, 0},
                                            glm::normalize(glm::vec3(1, 1, -1))};
    const std::vector<glm::vec3> points(normals.size(), glm::vec3(0, 0, 0));
    SkySettings s;
    s.samples = 20000;
    s.source = SkySource::Sh;
    s.visibility = false;
    s.intensity = 1.5f;
    for (double degrees : {0.0, 90.0, -37.0}) {
        s.rotationRadians = float(degrees * kPi / 180.0);
        const lighting::Sh9Rgb rotated = lighting::sh9RotateY(irradiance, double(s.rotationRadians));
        Estimate e = trace(*tracer, points, normals, s);
        for (size_t i = 0; i < normals.size(); ++i) {
            const glm::dvec3 truth = lighting::sh9Evaluate(rotated, glm::dvec3(normals[i])) * double(s.intensity);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(e.mean[i][c], truth[c], 4.0 * e.error[i][c] + 1e-5 * truth[c])
                    << degrees << " degrees, normal " << i << ", channel " << c;
        }
    }
    // Rotated by +90 degrees the bright side, +X, is seen towards -Z (sh9RotateY: +X turns
    // towards -Z): what faced +X before now faces -Z.
    s.rotationRadians = 0;
    Estimate before = trace(*tracer, points, normals, s);
    s.rotationRadians = float(kPi / 2);
    Estimate after = trace(*tracer, points, normals, s);
    EXPECT_NEAR(after.mean[3].x, before.mean[0].x, 4.0 * (after.error[3].x + before.error[0].x));
    EXPECT_LT(after.mean[0].x, 0.5 * before.mean[0].x);
    EXPECT_GT(after.mean[3].x, 2.0 * after.mean[2].x);
}

TEST(SkyTracer, ImageSourceRotatesInTheShSense) {
    SceneBuilder b;
    setEnvironment(b, 64, 32, TextureFormat::RGBA32F, [](glm::dvec3 w) { return glm::vec3(lobeSky(w)); },
                   lighting::Sh9Rgb{});
    auto tracer = build(b);
    ASSERT_TRUE(tracer);
    const std::vector<glm::vec3> normals = {{1, 0, 0}, {0, 0, 1}, {0, 0, -1}};
    const std::vector<glm::vec3> points(normals.size(), glm::vec3(0.0f));
    SkySettings s;
    s.samples = 20000;
    Estimate before = trace(*tracer, points, normals, s);
    // Against the closed form at +X: pi 0.2 from the dim sky plus 8 x the hemisphere integral
    // of cos^5 (2 pi / 6); the 64 x 32 image's bilinear reconstruction is within 2 % of it.
    const double exact = kPi * 0.2 + 8.0 * 2.0 * kPi / 6.0;
    EXPECT_NEAR(before.mean[0].x, exact, 0.02 * exact + 4.0 * before.error[0].x);
    s.rotationRadians = float(kPi / 2);
    Estimate after = trace(*tracer, points, normals, s);
    EXPECT_NEAR(after.mean[2].x, before.mean[0].x, 4.0 * (after.error[2].x + before.error[0].x));
    EXPECT_GT(after.mean[2].x, 2.0 * after.mean[1].x);
}

TEST(SkyTracer, AOneByOneImageIsAConstantSky) {
    SceneBuilder b;
    const glm::vec3 l(2.0f, 3.0f, 0.5f); // exact in half precision
    setEnvironment(b, 1, 1, TextureFormat::RGBA16F, [&](glm::dvec3) { return l; }, lighting::Sh9Rgb{});
    auto tracer = build(b);
    ASSERT_TRUE(tracer);
    EXPECT_EQ(tracer->stats().radianceWidth, 1u);
    SkySettings s;
    s.samples = 512;
    s.intensity = 2.0f;
    const std::vector<glm::vec3> normals = {{0, 1, 0}, {0, -1, 0}, glm::normalize(glm::vec3(0.3f, -0.2f, 0.9f))};
    Estimate e = trace(*tracer, std::vector<glm::vec3>(3, glm::vec3(1, 2, 3)), normals, s);
    for (size_t i = 0; i < normals.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(e.mean[i][c], kPi * 2.0 * l[c], 1e-5 * kPi * 2.0 * l[c]) << "normal " << i;
            EXPECT_LE(e.error[i][c], 1e-5 * l[c]);
        }
}

TEST(SkyTracer, ASceneWithoutEnvironmentIsAnErrorNamingIt) {
    SceneBuilder b;
    addQuad(b, {-1, 0, -1}, {2, 0, 0}, {0, 0, 2});
    auto t = SkyTracer::build(b.scene, glm::dvec3(0.0));
    ASSERT_FALSE(t.ok());
    EXPECT_EQ(t.error().kind, TracerErrorKind::Input);
    EXPECT_NE(t.error().message.find("ENVM"), std::string::npos) << t.error().message;
}

TEST(SkyTracer, TheSameSeedGivesTheSameAnswerAndPointsWithoutSurfaceGiveNaN) {
    SceneBuilder b;
    buildCanyon(b, 2, 1, 100, glm::vec3(1.0f));
    auto tracer = build(b);
    ASSERT_TRUE(tracer);
    std::vector<glm::vec3> points(2000, glm::vec3(0.2f, 0, 0));
    std::vector<glm::vec3> normals(points.size(), glm::vec3(0, 1, 0));
    points[7] = glm::vec3(NAN, 0, 0);
    normals[9] = glm::vec3(0.0f);
    SkySettings s;
    s.samples = 64;
    s.seed = 7;
    Estimate a = trace(*tracer, points, normals, s), again = trace(*tracer, points, normals, s);
    // Bit-identical on any interleaving of the threads (memcmp: NaN == NaN bitwise, not by ==).
    EXPECT_EQ(std::memcmp(a.mean.data(), again.mean.data(), a.mean.size() * sizeof(glm::vec3)), 0);
    EXPECT_EQ(std::memcmp(a.error.data(), again.error.data(), a.error.size() * sizeof(glm::vec3)), 0);
    EXPECT_TRUE(std::isnan(a.mean[7].x) && std::isnan(a.error[7].x));
    EXPECT_TRUE(std::isnan(a.mean[9].x));
    EXPECT_NE(a.mean[0], a.mean[1]) << "each point has its own samples";
    s.seed = 8;
    Estimate other = trace(*tracer, points, normals, s);
    EXPECT_NE(a.mean[0], other.mean[0]);
}

} // namespace
} // namespace pnb::reference::test
