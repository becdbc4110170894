// The whole-frame truth (FrameTracer) checks itself against closed forms and the other truths:
// the white furnace (albedo 1 under a uniform sky: L everywhere, whatever the bounces), a convex
// grey object (a L), the emissive box's geometric series E (1 + a + ... + a^(N+1)); the
// reduction of its one-bounce indirect light to IndirectTracer's irradiance; the same image at
// scales 1e-4 and 1e4 and 1e6 from the origin; empty scenes and a camera inside geometry;
// determinism across seeds and thread counts; the noise falling as 1/N. Scenes are built by hand
// (pnb::SceneBuilder), images are tiny. Also: direct light is exactly the player's shading of
// point and spot lights; alpha modes, sides and unlit materials as the player draws them; the
// environment's importance sampling agrees with BSDF sampling.
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "pnb/light_range.h"
#include "pnb/scene_builder.h"
#include "pnb_lighting/brdf.h"
#include "pnb_reference/frame_tracer.h"
#include "pnb_reference/indirect_tracer.h"
#include "pnb_reference/local_light.h"

namespace pnb::reference::test {
namespace {

constexpr double kPi = std::numbers::pi;

struct Geometry {
    std::vector<glm::vec3> positions, normals;
    std::vector<uint32_t> indices;
    std::vector<glm::vec2> uv0, uv1;  // optional
    std::vector<glm::vec4> tangents;  // optional
};

// Each triangle wound counter-clockwise seen from the side `outward(centroid)` points to.
void orient(Geometry& g, const std::function<glm::vec3(glm::vec3)>& outward) {
    for (size_t t = 0; t + 2 < g.indices.size(); t += 3) {
        const glm::vec3 a = g.positions[g.indices[t]], b = g.positions[g.indices[t + 1]], c = g.positions[g.indices[t + 2]];
        if (glm::dot(glm::cross(b - a, c - a), outward((a + b + c) / 3.0f)) < 0.0f)
            std::swap(g.indices[t + 1], g.indices[t + 2]);
    }
}

Geometry sphere(float radius, int rings = 16, int segments = 32) {
    Geometry g;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= segments; ++j) {
            const double theta = kPi * i / rings, phi = 2.0 * kPi * j / segments;
            const glm::vec3 n(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                              float(std::sin(theta) * std::sin(phi)));
            g.positions.push_back(n * radius);
            g.normals.push_back(n);
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const uint32_t a = uint32_t(i * (segments + 1) + j), b = a + 1, c = a + uint32_t(segments + 1), d = c + 1;
            if (i > 0) g.indices.insert(g.indices.end(), {a, c, b});
            if (i + 1 < rings) g.indices.insert(g.indices.end(), {b, c, d});
        }
    orient(g, [](glm::vec3 p) { return p; });
    return g;
}

// The six faces of the cube [-h, h]^3, facing inwards.
Geometry insideOfCube(float h) {
    Geometry g;
    for (int axis = 0; axis < 3; ++axis)
        for (float side : {-1.0f, 1.0f}) {
            const uint32_t base = uint32_t(g.positions.size());
            glm::vec3 n(0.0f);
            n[axis] = -side;
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            for (auto [su, sv] : {std::pair{-1.0f, -1.0f}, {1.0f, -1.0f}, {1.0f, 1.0f}, {-1.0f, 1.0f}}) {
                glm::vec3 p(0.0f);
                p[axis] = side * h, p[u] = su * h, p[v] = sv * h;
                g.positions.push_back(p);
                g.normals.push_back(n);
            }
            g.indices.insert(g.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        }
    orient(g, [](glm::vec3 p) { return -p; });
    return g;
}

// A horizontal square of half size h at y = 0, facing +Y.
Geometry ground(float h) {
    Geometry g;
    g.positions = {{-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}};
    g.normals.assign(4, glm::vec3(0, 1, 0));
    g.indices = {0, 1, 2, 0, 2, 3};
    orient(g, [](glm::vec3) { return glm::vec3(0, 1, 0); });
    return g;
}

Geometry box(glm::vec3 lo, glm::vec3 hi) {
    Geometry g = insideOfCube(1.0f);
    const glm::vec3 centre = (lo + hi) * 0.5f, half = (hi - lo) * 0.5f;
    for (glm::vec3& p : g.positions) p = centre + p * half;
    for (glm::vec3& n : g.normals) n = -n;
    orient(g, [centre](glm::vec3 p) { return p - centre; });
    return g;
}

uint32_t addMaterial(SceneBuilder& b, glm::vec3 base, glm::vec3 emissive = glm::vec3(0.0f)) {
    Material m;
    m.baseColorFactor = {base.x, base.y, base.z, 1};
    m.emissiveFactor = {emissive.x, emissive.y, emissive.z};
    m.metallicFactor = 0;
    m.roughnessFactor = 1;
    m.doubleSided = true;
    b.scene.materials.push_back(m);
    return uint32_t(b.scene.materials.size() - 1);
}

// `g` as its own mesh and node, scaled by `scale` then moved by `translation`.
void addObject(SceneBuilder& b, const Geometry& g, uint32_t material, glm::dvec3 translation = glm::dvec3(0.0),
               double scale = 1.0) {
    Mesh m;
    m.vertexCount = uint32_t(g.positions.size());
    for (VertexSemantic semantic : {VertexSemantic::Position, VertexSemantic::Normal}) {
        std::vector<float> xyz;
        for (const glm::vec3& v : semantic == VertexSemantic::Position ? g.positions : g.normals)
            xyz.insert(xyz.end(), {v.x, v.y, v.z});
        VertexStream s;
        s.semantic = semantic;
        s.data = b.keep(xyz);
        m.streams.push_back(s);
    }
    auto addStream = [&](VertexSemantic semantic, const std::vector<float>& values, uint8_t components) {
        VertexStream st;
        st.semantic = semantic;
        st.componentCount = components;
        st.data = b.keep(values);
        m.streams.push_back(st);
    };
    for (auto [semantic, uv] : {std::pair{VertexSemantic::TexCoord0, &g.uv0}, {VertexSemantic::TexCoord1, &g.uv1}}) {
        std::vector<float> values;
        for (const glm::vec2& v : *uv) values.insert(values.end(), {v.x, v.y});
        if (!values.empty()) addStream(semantic, values, 2);
    }
    std::vector<float> tangents;
    for (const glm::vec4& t : g.tangents) tangents.insert(tangents.end(), {t.x, t.y, t.z, t.w});
    if (!tangents.empty()) addStream(VertexSemantic::Tangent, tangents, 4);
    m.indexType = IndexType::U32;
    m.indices = b.keep(g.indices);
    Submesh sm;
    sm.material = material;
    sm.indexCount = uint32_t(g.indices.size());
    m.submeshes.push_back(sm);
    Node n;
    n.mesh = uint32_t(b.scene.meshes.size());
    n.translation = {float(translation.x), float(translation.y), float(translation.z)};
    n.scale = {float(scale), float(scale), float(scale)};
    b.scene.meshes.push_back(m);
    b.scene.nodes.nodes.push_back(n);
}

// An ENVM of width x height texels, texel (i, j) = radiance(i, j) (row 0 the top, +Y).
void addSky(SceneBuilder& b, uint32_t width, uint32_t height, const std::function<glm::vec3(uint32_t, uint32_t)>& radiance) {
    TextureDesc t;
    t.format = TextureFormat::RGBA32F;
    t.colorSpace = ColorSpace::Linear;
    t.width = width, t.height = height, t.mipCount = 1;
    TextureMip mip;
    mip.texture = uint32_t(b.scene.textures.size());
    mip.width = width, mip.height = height;
    std::vector<float> texels;
    for (uint32_t j = 0; j < height; ++j)
        for (uint32_t i = 0; i < width; ++i) {
            const glm::vec3 l = radiance(i, j);
            texels.insert(texels.end(), {l.x, l.y, l.z, 1.0f});
        }
    mip.data = b.keep(texels);
    b.scene.textures.push_back(t);
    b.scene.textureMips.push_back(mip);
    Environment e;
    e.radiance = mip.texture;
    b.scene.environment = e;
}

void addUniformSky(SceneBuilder& b, glm::vec3 l) {
    addSky(b, 4, 2, [l](uint32_t, uint32_t) { return l; });
}

// A light of `type` at `position`, shining along -toward (directional, spot).
void addLight(SceneBuilder& b, Light l, glm::vec3 position, glm::vec3 toward) {
    b.scene.lights.lights.push_back(l);
    // A directional light shines along its node's -Z: turn -Z onto -toward.
    const glm::dvec3 from(0, 0, -1), to = -glm::normalize(glm::dvec3(toward));
    const glm::dvec3 axis = glm::cross(from, to);
    const double c = glm::dot(from, to);
    glm::dvec4 q = glm::length(axis) < 1e-9 ? glm::dvec4(1, 0, 0, 0)
                                             : glm::dvec4(glm::normalize(axis) * std::sin(std::acos(c) / 2), std::cos(std::acos(c) / 2));
    Node n;
    n.light = uint32_t(b.scene.lights.lights.size() - 1);
    n.rotation = {float(q.x), float(q.y), float(q.z), float(q.w)};
    n.translation = {position.x, position.y, position.z};
    b.scene.nodes.nodes.push_back(n);
}

void addSun(SceneBuilder& b, glm::vec3 toward, float lux) {
    Light l;
    l.type = LightType::Directional;
    l.intensity = lux;
    addLight(b, l, glm::vec3(0.0f), toward);
}

// An orthographic camera looking straight down (-Y) from height 5 over (x, z), view +Y = world -Z:
// pixel (i, j) of a size x size image sees the ground at groundPoint(i, j).
struct DownCamera {
    FrameCamera camera;
    glm::dvec3 groundPoint(int i, int j) const {
        const double nx = (i + 0.5) / camera.width * 2 - 1, ny = 1 - (j + 0.5) / camera.height * 2;
        return {camera.position.x + nx * camera.xmag, 0.0, camera.position.z - ny * camera.ymag};
    }
};
DownCamera lookDown(double x, double z, double halfSize, int size) {
    DownCamera d;
    d.camera.position = {x, 5, z};
    d.camera.worldFromView = glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
    d.camera.orthographic = true;
    d.camera.xmag = d.camera.ymag = halfSize;
    d.camera.width = d.camera.height = size;
    return d;
}

// A camera at `eye` looking at `target`, +Y up.
FrameCamera lookAt(glm::dvec3 eye, glm::dvec3 target, int size, double yfovDegrees = 40) {
    FrameCamera c;
    c.position = eye;
    const glm::dvec3 z = glm::normalize(eye - target);
    const glm::dvec3 x = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), z));
    c.worldFromView = glm::dmat3(x, glm::cross(z, x), z);
    c.yfovRadians = yfovDegrees * kPi / 180.0;
    c.aspect = 1.0;
    c.width = c.height = size;
    return c;
}

std::unique_ptr<FrameTracer> build(const SceneBuilder& b, glm::dvec3 origin = glm::dvec3(0.0)) {
    auto t = FrameTracer::build(b.scene, origin);
    EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.error().message);
    return t.ok() ? std::move(*t) : nullptr;
}

FrameTraceSettings fixedSamples(uint32_t samples, uint32_t bounces = 16) {
    FrameTraceSettings s;
    s.maxBounces = bounces;
    s.samplesPerPass = samples;
    s.maxSamples = samples;
    s.noiseTarget = 0;
    s.timeLimitSeconds = 0;
    s.lambertianOnly = true;
    return s;
}

// Every pixel of `image` within 4 standard errors (and a float's rounding) of `expected(p)`.
void expectEverywhere(const FrameImage& image, const std::function<glm::vec3(size_t)>& expected) {
    ASSERT_EQ(image.mean.size(), size_t(image.width) * size_t(image.height));
    size_t off = 0;
    for (size_t p = 0; p < image.mean.size(); ++p)
        for (int c = 0; c < 3; ++c) {
            const double truth = expected(p)[c];
            const double error = std::abs(double(image.mean[p][c]) - truth);
            if (error > 4.0 * image.standardError[p][c] + 1e-5 * std::abs(truth) + 1e-7 && off++ < 5)
                ADD_FAILURE() << "pixel " << p << " channel " << c << ": " << image.mean[p][c] << " +- "
                              << image.standardError[p][c] << ", expected " << truth;
        }
}

TEST(FrameTracer, WhiteFurnaceIsTheSkyEverywhereWhateverTheBounces) {
    SceneBuilder b;
    const glm::vec3 l(1.5f, 0.75f, 3.0f);
    const uint32_t white = addMaterial(b, glm::vec3(1.0f));
    addObject(b, sphere(1.0f), white, {0, 1, 0});
    addObject(b, ground(3.0f), white); // concave with the sphere: light bounces between them
    addUniformSky(b, l);
    auto tracer = build(b);
    ASSERT_TRUE(tracer);
    const FrameImage image = tracer->render(lookAt({0, 2.5, 5}, {0, 0.8, 0}, 24), fixedSamples(16, 64));
    EXPECT_EQ(image.stats.nonFiniteSamples, 0u);
    expectEverywhere(image, [&](size_t) { return l; });
}

TEST(FrameTracer, AGreyConvexObjectUnderAUniformSkyIsAlbedoTimesSky) {
    SceneBuilder b;
    const glm::vec3 l(2.0f), albedo(0.5f, 0.25f, 0.75f);
    addObject(b, sphere(1.0f), addMaterial(b, albedo));
    addUniformSky(b, l);
    auto tracer = build(b);
    ASSERT_TRUE(tracer);
    const FrameCamera camera = lookAt({0, 0, 4}, {0, 0, 0}, 24);
    for (uint32_t bounces : {0u, 8u}) {
        const FrameImage image = tracer->render(camera, fixedSamples(32, bounces));
        // The sphere covers the pixels whose ray passes within 1 of the centre.
        int sphereCovered = 0;
        expectEverywhere(image, [&](size_t p) {
            const int x = int(p % 24), y = int(p / 24);
            const double t = std::tan(camera.yfovRadians / 2);
            const glm::dvec3 d = glm::normalize(glm::dvec3(((x + 0.5) / 12 - 1) * t, (1 - (y + 0.5) / 12) * t, -1));
            const double miss = glm::length(glm::cross(d, glm::dvec3(0, 0, -4)));
            if (std::abs(miss - 1.0) < 0.02) return glm::vec3(image.mean[p]); // the silhouette: either
            sphereCovered += miss < 1.0;
            return miss < 1.0 ? albedo * l : l;
        });
        EXPECT_GT(sphereCovered, 100);
    }
}

TEST(FrameTracer, AnEmissiveGreyBoxSeenFromInsideSumsTheGeometricSeries) {
    SceneBuilder b;
    const float a = 0.5f;
    const glm::vec3 e(1.0f, 2.0f, 0.5f);
    addObject(b, insideOfCube(1.0f), addMaterial(b, glm::vec3(a), e));
    auto tracer = build(b);
    ASSERT_TRUE(tracer);
    const FrameCamera camera = lookAt({0.1, -0.2, 0.3}, {1, 0.3, -0.5}, 16, 80);
    for (uint32_t bounces : {0u, 2u, 40u}) {
        double series = 0; // E (1 + a + ... + a^(N+1)): the emission seen after 0 ... N+1 reflections
        for (uint32_t k = 0; k <= bounces + 1; ++k) series += std::pow(double(a), double(k));
        // Enough samples that Russian roulette's rare long paths show in every pixel's error.
        const FrameImage image = tracer->render(camera, fixedSamples(512, bounces));
        expectEverywhere(image, [&](size_t) { return glm::vec3(glm::dvec3(e) * series); });
        if (bounces == 0) { // no randomness can change E (1 + a): every path's value is that
            for (const glm::vec3& se : image.standardError) EXPECT_LT(se.x, 1e-5f);
        }
    }
}

// The reduction to the one-bounce truth: radiance(1 bounce) - radiance(0 bounces) at a pixel is
// the light that reached its surface after exactly one reflection, albedo / pi x IndirectTracer's
// irradiance at that point. An orthographic camera straight down on the ground beside a box:
// pixel (x, y) sees the ground at a known point.
TEST(FrameTracer, OneBounceIsTheIndirectTracersIrradianceTimesAlbedoOverPi) {
    SceneBuilder b;
    const glm::vec3 albedo(0.8f, 0.6f, 0.4f);
    const uint32_t grey = addMaterial(b, albedo);
    addObject(b, ground(20.0f), grey);
    addObject(b, box({-1, 0, -1}, {1, 2, 1}), grey);
    addSun(b, glm::vec3(-1, 2, 0.5f), 3.0f); // lights the box's face towards the pixels' ground
    auto frame = build(b);
    auto indirect = IndirectTracer::build(b.scene, glm::dvec3(0.0));
    ASSERT_TRUE(frame);
    ASSERT_TRUE(indirect.ok()) << indirect.error().message;
    FrameCamera camera;
    camera.position = {-2.5, 10, 0};
    camera.worldFromView = glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
    camera.orthographic = true;
    camera.xmag = camera.ymag = 1.2; // x in [-3.7, -1.3], z in [-1.2, 1.2]: the ground beside the box
    camera.width = camera.height = 8;
    const FrameImage direct = frame->render(camera, fixedSamples(256, 0));
    const FrameImage once = frame->render(camera, fixedSamples(256, 1));
    std::vector<glm::vec3> points, normals(64, glm::vec3(0, 1, 0));
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            points.emplace_back(float(-2.5 + ((x + 0.5) / 4 - 1) * 1.2), 0.0f, float(-(1 - (y + 0.5) / 4) * 1.2));
    std::vector<glm::vec3> irradiance(64), irradianceError(64);
    IndirectSettings settings;
    settings.samples = 4096;
    (*indirect)->irradiance(points, normals, settings, irradiance, irradianceError, camera.position);
    glm::dvec3 frameSum(0.0), truthSum(0.0), variance(0.0), directSum(0.0);
    for (size_t p = 0; p < 64; ++p) {
        const glm::dvec3 bounce = glm::dvec3(once.mean[p]) - glm::dvec3(direct.mean[p]);
        const glm::dvec3 truth = glm::dvec3(albedo) / kPi * glm::dvec3(irradiance[p]);
        frameSum += bounce;
        directSum += glm::dvec3(direct.mean[p]);
        truthSum += truth;
        const glm::dvec3 se = glm::dvec3(once.standardError[p]) + glm::dvec3(direct.standardError[p]); // correlated: bound
        const glm::dvec3 te = glm::dvec3(albedo) / kPi * glm::dvec3(irradianceError[p]);
        variance += se * se + te * te;
    }
    for (int c = 0; c < 3; ++c) {
        EXPECT_GT(truthSum[c], 0.02 * directSum[c]) << "the box must reflect light onto the ground";
        EXPECT_NEAR(frameSum[c], truthSum[c], 4.0 * std::sqrt(variance[c]) + 1e-4 * truthSum[c]) << "channel " << c;
        EXPECT_NEAR(frameSum[c], truthSum[c], 0.05 * truthSum[c]) << "channel " << c;
    }
}

// A sphere on the ground under sky and sun, built at `scale` around `offset`, seen by a camera
// scaled and moved with it (the tracer's origin at the camera).
FrameImage scaledScene(double scale, glm::dvec3 offset) {
    SceneBuilder b;
    const uint32_t grey = addMaterial(b, glm::vec3(0.6f));
    addObject(b, sphere(1.0f), grey, offset + glm::dvec3(0, 1, 0) * scale, scale);
    addObject(b, ground(4.0f), grey, offset, scale);
    addUniformSky(b, glm::vec3(0.5f, 0.6f, 0.8f));
    addSun(b, glm::vec3(1, 2, 0.5f), 2.0f);
    const FrameCamera camera = lookAt(offset + glm::dvec3(0, 2.5, 5) * scale, offset + glm::dvec3(0, 0.8, 0) * scale, 16);
    auto tracer = build(b, camera.position);
    if (!tracer) return {};
    return tracer->render(camera, fixedSamples(64, 4));
}

TEST(FrameTracer, TheSameImageAtAnyScaleAndFarFromTheOrigin) {
    const FrameImage unit = scaledScene(1.0, glm::dvec3(0.0));
    ASSERT_EQ(unit.mean.size(), 256u);
    for (auto [scale, offset] : {std::pair{1e-4, glm::dvec3(0.0)}, {1e4, glm::dvec3(0.0)}, {1.0, glm::dvec3(1e6, 0, -1e6)}}) {
        const FrameImage other = scaledScene(scale, offset);
        ASSERT_EQ(other.mean.size(), 256u);
        EXPECT_EQ(other.stats.nonFiniteSamples, 0u);
        double sumA = 0, sumB = 0, variance = 0;
        size_t outliers = 0;
        for (size_t p = 0; p < 256; ++p)
            for (int c = 0; c < 3; ++c) {
                const double se = std::hypot(unit.standardError[p][c], other.standardError[p][c]);
                outliers += std::abs(unit.mean[p][c] - other.mean[p][c]) > 5.0 * se + 1e-4;
                sumA += unit.mean[p][c], sumB += other.mean[p][c], variance += se * se;
            }
        EXPECT_LE(outliers, 8u) << "scale " << scale << ", offset " << offset.x; // silhouette pixels may differ
        EXPECT_NEAR(sumA, sumB, 4.0 * std::sqrt(variance) + 1e-4 * sumA) << "scale " << scale;
    }
}

// A sky with one small, bright patch (a sun of ~0.5 % of the sphere) over a dim blue: drawing
// directions from the environment's map and weighting them against BSDF sampling converges to
// what BSDF sampling alone does, with far less noise, on rough and smooth surfaces alike.
TEST(FrameTracer, EnvironmentSamplingAgreesWithBsdfSamplingAndIsLessNoisy) {
    SceneBuilder b;
    addObject(b, sphere(1.0f), addMaterial(b, glm::vec3(0.7f)), {0, 1, 0});
    Material metal;
    metal.baseColorFactor = {0.9f, 0.8f, 0.6f, 1};
    metal.metallicFactor = 1;
    metal.roughnessFactor = 0.35f;
    metal.doubleSided = true;
    b.scene.materials.push_back(metal);
    addObject(b, ground(4.0f), uint32_t(b.scene.materials.size() - 1));
    addSky(b, 64, 32, [](uint32_t i, uint32_t j) {
        return i >= 40 && i < 43 && j >= 9 && j < 12 ? glm::vec3(400.0f, 380.0f, 300.0f) : glm::vec3(0.2f, 0.3f, 0.5f);
    });
    auto tracer = build(b);
    ASSERT_TRUE(tracer);
    const FrameCamera camera = lookAt({0, 2.5, 5}, {0, 0.8, 0}, 12);
    FrameTraceSettings s = fixedSamples(256, 4);
    s.lambertianOnly = false;
    s.iblRotationRadians = 0.7;
    const FrameImage drawn = tracer->render(camera, s);
    s.sampleEnvironment = false;
    s.samplesPerPass = s.maxSamples = 1024;
    const FrameImage bsdf = tracer->render(camera, s);
    // Image-wide: a pixel's BSDF-only error estimate is unreliable (most of its 1024 paths miss
    // the patch; a pixel whose paths all missed it reports a small error and a low mean).
    double sumDrawn = 0, sumBsdf = 0, variance = 0;
    for (size_t p = 0; p < drawn.mean.size(); ++p)
        for (int c = 0; c < 3; ++c) {
            sumDrawn += drawn.mean[p][c], sumBsdf += bsdf.mean[p][c];
            variance += std::pow(drawn.standardError[p][c], 2) + std::pow(bsdf.standardError[p][c], 2);
        }
    EXPECT_NEAR(sumDrawn, sumBsdf, 4.0 * std::sqrt(variance) + 0.01 * sumBsdf);
    EXPECT_LT(drawn.relativeNoise, 0.5 * bsdf.relativeNoise) << "with 4x fewer samples";
}

// Direct light only and no sky: every pixel is exactly the player's shading (brdf.h's shadeBrdf,
// lights.glsl's range window and spot cone), no randomness left. A point light and a spot
// pointing down, 2 above a rough grey dielectric; pixels inside, across and outside the cone.
TEST(FrameTracer, DirectLightIsThePlayersShadingOfPointAndSpotLights) {
    for (LightType type : {LightType::Point, LightType::Spot}) {
        SceneBuilder b;
        Material grey;
        grey.baseColorFactor = {0.6f, 0.5f, 0.4f, 1};
        grey.metallicFactor = 0.2f;
        grey.roughnessFactor = 0.5f;
        b.scene.materials.push_back(grey);
        addObject(b, ground(10.0f), 0);
        Light l;
        l.type = type;
        l.color = {1.0f, 0.9f, 0.8f};
        l.intensity = 40;
        l.innerConeRadians = 0.2f, l.outerConeRadians = 0.4f;
        addLight(b, l, {0.1f, 2.0f, -0.2f}, {0, 1, 0});
        auto tracer = build(b);
        ASSERT_TRUE(tracer);
        const DownCamera view = lookDown(0.3, 0.1, 1.5, 8);
        FrameTraceSettings s = fixedSamples(4, 0);
        s.lambertianOnly = false;
        const FrameImage image = tracer->render(view.camera, s);
        const double range = pnb::effectiveLightRange(l);
        int inside = 0, outside = 0;
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 8; ++i) {
                const glm::dvec3 p = view.groundPoint(i, j), toLight = glm::dvec3(0.1, 2.0, -0.2) - p;
                double attenuation = rangeAttenuation(glm::dot(toLight, toLight), range);
                if (type == LightType::Spot) {
                    const double cone = spotConeFactor(glm::normalize(toLight).y, std::cos(0.4), std::cos(0.2));
                    attenuation *= cone;
                    inside += cone == 1.0;
                    outside += cone == 0.0;
                }
                const glm::vec3 truth = lighting::shadeBrdf(glm::vec3(0.6f, 0.5f, 0.4f), 0.2f, 0.5f, {0, 1, 0}, {0, 1, 0},
                                                            glm::vec3(glm::normalize(toLight)),
                                                            glm::vec3(1.0f, 0.9f, 0.8f) * float(40 * attenuation));
                const glm::vec3 got = image.mean[size_t(j) * 8 + size_t(i)];
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], truth[c], 1e-5f + 1e-5f * truth[c]) << i << "," << j;
            }
        if (type == LightType::Spot) {
            EXPECT_GT(inside, 0);
            EXPECT_GT(outside, 0);
        }
    }
}

// Alpha, sides and unlit materials, one quad at y = 1 over nothing, a uniform sky L behind it,
// seen from above: MASK below its cut-off is absent, at or above it there; BLEND shows alpha x
// surface + (1 - alpha) x what is behind; a single-sided surface seen from behind is absent;
// unlit radiance is base colour + emissive x strength.
TEST(FrameTracer, AlphaModesSidesAndUnlitMaterialsAsThePlayerDrawsThem) {
    const glm::vec3 sky(0.2f, 0.4f, 0.6f), base(0.9f, 0.5f, 0.1f), emissive(0.1f, 0.2f, 0.3f);
    struct Case {
        const char* name;
        AlphaMode mode;
        float alpha;
        bool facingUp, doubleSided;
        float emissiveStrength;
        glm::vec3 expected;
    };
    const Case cases[] = {
        {"mask below cut-off", AlphaMode::Mask, 0.3f, true, false, 0, sky},
        {"mask above cut-off", AlphaMode::Mask, 0.7f, true, false, 0, base},
        {"blend", AlphaMode::Blend, 0.25f, true, false, 0, 0.25f * base + 0.75f * sky},
        {"single-sided from behind", AlphaMode::Opaque, 1, false, false, 0, sky},
        {"double-sided from behind", AlphaMode::Opaque, 1, false, true, 0, base},
        {"emissive strength", AlphaMode::Opaque, 1, true, false, 4, base + 4.0f * emissive},
    };
    for (const Case& k : cases) {
        SceneBuilder b;
        Material m;
        m.baseColorFactor = {base.x, base.y, base.z, k.alpha};
        m.alphaMode = k.mode;
        m.unlit = true;
        m.doubleSided = k.doubleSided;
        m.emissiveFactor = {emissive.x, emissive.y, emissive.z};
        m.emissiveStrength = k.emissiveStrength;
        b.scene.materials.push_back(m);
        Geometry quad = ground(2.0f);
        if (!k.facingUp) orient(quad, [](glm::vec3) { return glm::vec3(0, -1, 0); });
        addObject(b, quad, 0, {0, 1, 0});
        addUniformSky(b, sky);
        auto tracer = build(b);
        ASSERT_TRUE(tracer);
        const FrameImage image = tracer->render(lookDown(0, 0, 1, 6).camera, fixedSamples(256, 2));
        expectEverywhere(image, [&](size_t) { return k.expected; });
        if (k.mode == AlphaMode::Blend) {
            EXPECT_GT(image.standardError[0].x, 0.0f) << k.name; // stochastic: some paths pass
        }
        if (testing::Test::HasFailure()) {
            ADD_FAILURE() << "case: " << k.name;
        }
    }
}

// A linear RGBA32F texture of width x 1 texels.
uint32_t addTexture(SceneBuilder& b, const std::vector<glm::vec4>& texels) {
    TextureDesc t;
    t.format = TextureFormat::RGBA32F;
    t.colorSpace = ColorSpace::Linear;
    t.width = uint32_t(texels.size()), t.height = 1, t.mipCount = 1;
    TextureMip mip;
    mip.texture = uint32_t(b.scene.textures.size());
    mip.width = t.width, mip.height = 1;
    std::vector<float> values;
    for (const glm::vec4& v : texels) values.insert(values.end(), {v.x, v.y, v.z, v.w});
    mip.data = b.keep(values);
    b.scene.textures.push_back(t);
    b.scene.textureMips.push_back(mip);
    return mip.texture;
}

// The base colour texture read with the slot's UV set and KHR_texture_transform: a 2-texel
// texture (red | green), UV set 0 at u = 0.75 and set 1 at u = 0.25 on every vertex, an unlit
// quad seen from above. Texel centres are at u = 0.25 and 0.75, so each case is exact.
TEST(FrameTracer, TexturesAreReadWithTheSlotsUvSetAndTransform) {
    const glm::vec3 red(1, 0, 0), green(0, 1, 0);
    struct Case {
        uint8_t texCoord;
        float offset, scale;
        glm::vec3 expected;
    };
    for (const Case& k : {Case{0, 0, 1, green}, Case{1, 0, 1, red}, Case{1, 0.5f, 1, green}, Case{1, 0, 2, 0.5f * (red + green)}}) {
        SceneBuilder b;
        const uint32_t texture = addTexture(b, {glm::vec4(red, 1), glm::vec4(green, 1)});
        Material m;
        m.unlit = true;
        m.textures[size_t(TextureSlotKind::BaseColor)].texture = texture;
        m.textures[size_t(TextureSlotKind::BaseColor)].texCoord = k.texCoord;
        m.textures[size_t(TextureSlotKind::BaseColor)].offset = {k.offset, 0};
        m.textures[size_t(TextureSlotKind::BaseColor)].scale = {k.scale, 1};
        b.scene.materials.push_back(m);
        Geometry quad = ground(2.0f);
        quad.uv0.assign(4, glm::vec2(0.75f, 0.5f));
        quad.uv1.assign(4, glm::vec2(0.25f, 0.5f));
        addObject(b, quad, 0);
        auto tracer = build(b);
        ASSERT_TRUE(tracer);
        const FrameImage image = tracer->render(lookDown(0, 0, 1, 4).camera, fixedSamples(1, 0));
        for (const glm::vec3& v : image.mean)
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[c], k.expected[c], 1e-6f) << "set " << int(k.texCoord) << " offset " << k.offset << " scale " << k.scale;
    }
}

// A normal map tilts the shading normal along the stored tangent (+X): texel (0.8, 0.5, 0.9)
// is the tangent-space normal (0.6, 0, 0.8), so the sun straight above lights the ground with
// cos = 0.8 and a sun along (0.6, 0.8, 0) with cos = 1. And the sun's light through a glass pane
// (Blend, casting shadows) above the ground is attenuated by T = rgb x (1 - alpha); the pane,
// single-sided and facing down, is not seen from above. Direct light, no sky: exact.
TEST(FrameTracer, NormalMapsTiltTheNormalAndGlassTintsTheSun) {
    const float albedo = 0.5f, lux = 3.0f;
    for (glm::vec3 sun : {glm::vec3(0, 1, 0), glm::vec3(0.6f, 0.8f, 0)}) {
        SceneBuilder b;
        Material m;
        m.baseColorFactor = {albedo, albedo, albedo, 1};
        m.metallicFactor = 0;
        m.textures[size_t(TextureSlotKind::Normal)].texture = addTexture(b, {glm::vec4(0.8f, 0.5f, 0.9f, 1)});
        b.scene.materials.push_back(m);
        Geometry floor = ground(3.0f);
        floor.uv0.assign(4, glm::vec2(0.5f));
        floor.tangents.assign(4, glm::vec4(1, 0, 0, 1));
        addObject(b, floor, 0);
        addSun(b, sun, lux);
        auto tracer = build(b);
        ASSERT_TRUE(tracer);
        FrameTraceSettings s = fixedSamples(1, 0);
        const FrameImage image = tracer->render(lookDown(0, 0, 1, 4).camera, s);
        const double cosine = glm::dot(glm::normalize(glm::dvec3(0.6, 0, 0.8)).x * glm::dvec3(1, 0, 0) +
                                           glm::normalize(glm::dvec3(0.6, 0, 0.8)).z * glm::dvec3(0, 1, 0),
                                       glm::dvec3(sun));
        for (const glm::vec3& v : image.mean) EXPECT_NEAR(v.x, albedo / kPi * lux * cosine, 1e-4) << sun.x;
    }
    SceneBuilder b;
    addObject(b, ground(3.0f), addMaterial(b, glm::vec3(albedo)));
    Material glass;
    glass.baseColorFactor = {0.5f, 1.0f, 0.8f, 0.4f};
    glass.alphaMode = AlphaMode::Blend;
    b.scene.materials.push_back(glass);
    Geometry pane = ground(2.0f);
    orient(pane, [](glm::vec3) { return glm::vec3(0, -1, 0); });
    addObject(b, pane, uint32_t(b.scene.materials.size() - 1), {0, 1, 0});
    addSun(b, glm::vec3(0, 1, 0), lux);
    auto tracer = build(b);
    ASSERT_TRUE(tracer);
    const FrameImage image = tracer->render(lookDown(0, 0, 1, 4).camera, fixedSamples(1, 0));
    const glm::vec3 transmitted = glm::vec3(0.5f, 1.0f, 0.8f) * 0.6f;
    for (const glm::vec3& v : image.mean)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[c], albedo / kPi * lux * transmitted[c], 1e-4);
}

TEST(FrameTracer, EmptyScenesAndACameraInsideGeometryGiveFiniteImages) {
    SceneBuilder empty;
    auto black = build(empty);
    ASSERT_TRUE(black);
    const FrameImage none = black->render(lookAt({0, 0, 0}, {0, 0, -1}, 8), fixedSamples(2));
    for (const glm::vec3& v : none.mean) EXPECT_EQ(v, glm::vec3(0.0f));
    SceneBuilder sky;
    addUniformSky(sky, glm::vec3(0.25f));
    auto skyOnly = build(sky);
    ASSERT_TRUE(skyOnly);
    for (const glm::vec3& v : skyOnly->render(lookAt({0, 0, 0}, {0, 0, -1}, 8), fixedSamples(2)).mean)
        EXPECT_EQ(v, glm::vec3(0.25f));
    // Inside a closed sphere under a sky: no light gets in; and a camera inside a solid's wall.
    SceneBuilder inside;
    addObject(inside, sphere(1.0f), addMaterial(inside, glm::vec3(0.9f)));
    addUniformSky(inside, glm::vec3(1.0f));
    addSun(inside, glm::vec3(0, 1, 0), 5.0f);
    auto tracer = build(inside);
    ASSERT_TRUE(tracer);
    for (glm::dvec3 eye : {glm::dvec3(0.0), glm::dvec3(0, 0, 1.0)}) {
        FrameTraceSettings s = fixedSamples(4);
        s.lambertianOnly = false;
        const FrameImage image = tracer->render(lookAt(eye, eye + glm::dvec3(0.3, 0.2, -1), 8), s);
        EXPECT_EQ(image.stats.nonFiniteSamples, 0u);
        for (const glm::vec3& v : image.mean) EXPECT_TRUE(std::isfinite(v.x + v.y + v.z));
        if (eye == glm::dvec3(0.0)) {
            for (const glm::vec3& v : image.mean) EXPECT_EQ(v, glm::vec3(0.0f));
        }
    }
}

SceneBuilder& metalAndWallScene(SceneBuilder& b) {
    Material metal;
    metal.baseColorFactor = {0.9f, 0.7f, 0.3f, 1};
    metal.metallicFactor = 1;
    metal.roughnessFactor = 0.2f;
    b.scene.materials.push_back(metal);
    addObject(b, sphere(1.0f), 0, {0, 1, 0});
    addObject(b, ground(4.0f), addMaterial(b, glm::vec3(0.7f)));
    addUniformSky(b, glm::vec3(0.4f, 0.5f, 0.7f));
    addSun(b, glm::vec3(1, 2, 0.5f), 3.0f);
    return b;
}

TEST(FrameTracer, DeterministicForASeedOnAnyNumberOfThreads) {
    SceneBuilder b;
    auto tracer = build(metalAndWallScene(b));
    ASSERT_TRUE(tracer);
    const FrameCamera camera = lookAt({0, 2.5, 5}, {0, 0.8, 0}, 12);
    FrameTraceSettings s = fixedSamples(8);
    s.lambertianOnly = false;
    s.samplesPerPass = 3; // passes of 3, 3, 2
    s.threads = 1;
    const FrameImage one = tracer->render(camera, s);
    EXPECT_EQ(one.passes, 3u);
    EXPECT_EQ(one.samples, 8u);
    for (unsigned threads : {2u, 3u}) {
        s.threads = threads;
        const FrameImage many = tracer->render(camera, s);
        EXPECT_EQ(many.mean, one.mean) << threads << " threads";
        EXPECT_EQ(many.standardError, one.standardError) << threads << " threads";
        EXPECT_EQ(many.rays, one.rays);
    }
    s.seed = 2;
    EXPECT_NE(tracer->render(camera, s).mean, one.mean);
}

TEST(FrameTracer, NoiseFallsAsOneOverTheSampleCountAndStopsAtTheTarget) {
    SceneBuilder b;
    auto tracer = build(metalAndWallScene(b));
    ASSERT_TRUE(tracer);
    const FrameCamera camera = lookAt({0, 2.5, 5}, {0, 0.8, 0}, 12);
    FrameTraceSettings s = fixedSamples(16);
    s.lambertianOnly = false;
    const double few = tracer->render(camera, s).relativeNoise;
    s.samplesPerPass = s.maxSamples = 64;
    const FrameImage more = tracer->render(camera, s);
    // relativeNoise is a mean of squared standard errors: 4x the samples, a quarter of it.
    EXPECT_GT(few / more.relativeNoise, 2.0);
    EXPECT_LT(few / more.relativeNoise, 6.0);
    // Progressive: stops at the first pass whose noise is below the target.
    s.samplesPerPass = 4;
    s.maxSamples = 4096;
    s.minSamples = 8;
    s.noiseTarget = more.relativeNoise;
    const FrameImage target = tracer->render(camera, s);
    EXPECT_LE(target.relativeNoise, s.noiseTarget);
    EXPECT_GT(target.samples, 16u);
    EXPECT_LT(target.samples, 160u);
}

} // namespace
} // namespace pnb::reference::test
