// ShadowTracer: analytically known shadow footprints, acne-free grazing light, precision 10^6
// units from the world origin, material rules (Mask opaque, Blend passed, non-casting skipped),
// every position encoding, node hierarchies, bad input, and every procedural scene.
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "pnb_converter/convert.h"
#include "pnb_reference/shadow_tracer.h"
#include "reference_test_util.h"

namespace pnb::reference::test {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

const glm::vec3 kUp{0, 1, 0};
const glm::vec3 kTilted = glm::normalize(glm::vec3(1, 2, 0)); // shadow x in [-3, 0]

std::unique_ptr<ShadowTracer> buildTracer(const Scene& scene, glm::dvec3 origin) {
    auto t = ShadowTracer::build(scene, origin);
    EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.error().message);
    return t.ok() ? std::move(*t) : nullptr;
}

// Visibility of world points (converted to origin-relative here, in double).
std::vector<float> trace(const ShadowTracer& tracer, const std::vector<glm::dvec3>& wsPoints,
                         glm::vec3 towardLight) {
    std::vector<glm::vec3> positions;
    for (const glm::dvec3& p : wsPoints) positions.push_back(glm::vec3(p - tracer.origin()));
    std::vector<float> out(wsPoints.size(), -7.0f);
    tracer.visibility(positions, towardLight, out);
    return out;
}

// Ground points on a grid (spacing 0.25, offset so no point is closer than 0.125 to x or z = k).
std::vector<glm::dvec3> groundGrid(glm::dvec3 offset = glm::dvec3(0.0), double half = 6.0) {
    std::vector<glm::dvec3> points;
    for (double x = -half + 0.125; x < half; x += 0.25)
        for (double z = -half + 0.125; z < half; z += 0.25) points.push_back(offset + glm::dvec3(x, 0, z));
    return points;
}

bool inOverheadShadow(glm::dvec3 p) { return std::fabs(p.x) < 1 && std::fabs(p.z) < 1; }
bool inTiltedShadow(glm::dvec3 p) { return p.x > -3 && p.x < 0 && std::fabs(p.z) < 1; }

class ShadowTracerTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        sDir = new TempDir("tracer");
        auto convert = [](const gltf::Document& doc, const std::string& name,
                          const std::string& sidecar = "") {
            return pnb::test::convertDocument(sDir->str(), doc, name, sidecar, false);
        };
        sGroundBox = loadPnb(convert(groundAndBox(), "ground-box")).release();
        sFarGroundBox = loadPnb(convert(groundAndBox({1e6f, 0, 1e6f}), "far-ground-box")).release();

        // The same scene with quantised positions (U16 normalized, dequantised by the mesh box).
        converter::ConvertSettings s;
        s.input = sDir->str() + "/ground-box.glb";
        s.output = sDir->str() + "/ground-box-quantized.pnb";
        s.noSidecar = true;
        s.jobs = 1;
        s.validateShaders = false;
        s.mesh.quantize = true;
        auto r = converter::convertScene(s);
        EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
        sQuantized = loadPnb(s.output).release();
    }
    static void TearDownTestSuite() {
        delete sGroundBox;
        delete sFarGroundBox;
        delete sQuantized;
        delete sDir;
    }

    static TempDir* sDir;
    static LoadedScene* sGroundBox;
    static LoadedScene* sFarGroundBox;
    static LoadedScene* sQuantized;
};
TempDir* ShadowTracerTest::sDir = nullptr;
LoadedScene* ShadowTracerTest::sGroundBox = nullptr;
LoadedScene* ShadowTracerTest::sFarGroundBox = nullptr;
LoadedScene* ShadowTracerTest::sQuantized = nullptr;

TEST_F(ShadowTracerTest, OverheadSunCastsTheBoxFootprint) {
    ASSERT_TRUE(sGroundBox);
    auto tracer = buildTracer(sGroundBox->scene, {0, 10, 10});
    ASSERT_TRUE(tracer);
    EXPECT_EQ(tracer->stats().triangles, 2u + 12u);
    EXPECT_EQ(tracer->stats().casterInstances, 2u);
    EXPECT_EQ(tracer->stats().maskedCastersTreatedOpaque, 0u);
    EXPECT_GT(tracer->stats().buildMs, 0.0);

    auto points = groundGrid();
    auto vis = trace(*tracer, points, kUp);
    size_t shadowed = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        SCOPED_TRACE(testing::Message() << "x " << points[i].x << " z " << points[i].z);
        ASSERT_EQ(vis[i], inOverheadShadow(points[i]) ? 0.0f : 1.0f);
        shadowed += vis[i] == 0.0f;
    }
    EXPECT_EQ(shadowed, 8u * 8u); // 2 x 2 units at 0.25 spacing
}

TEST_F(ShadowTracerTest, TiltedSunShiftsTheFootprint) {
    ASSERT_TRUE(sGroundBox);
    auto tracer = buildTracer(sGroundBox->scene, {0, 10, 10});
    ASSERT_TRUE(tracer);
    auto points = groundGrid();
    auto vis = trace(*tracer, points, kTilted);
    for (size_t i = 0; i < points.size(); ++i) {
        SCOPED_TRACE(testing::Message() << "x " << points[i].x << " z " << points[i].z);
        ASSERT_EQ(vis[i], inTiltedShadow(points[i]) ? 0.0f : 1.0f);
    }
}

TEST_F(ShadowTracerTest, BoxTopIsLitAndFacesAwayFromTheLightAreShadowed) {
    ASSERT_TRUE(sGroundBox);
    auto tracer = buildTracer(sGroundBox->scene, {0, 10, 10});
    ASSERT_TRUE(tracer);
    std::vector<glm::dvec3> top, awayFace, towardFace;
    for (double u = -0.875; u < 1; u += 0.25)
        for (double v = -0.875; v < 1; v += 0.25) {
            top.push_back({u, 4, v});
            awayFace.push_back({-1, 3 + u, v}); // normal -X, the light comes from +X
            towardFace.push_back({1, 3 + u, v});
        }
    for (glm::vec3 light : {kUp, kTilted}) {
        for (float v : trace(*tracer, top, light)) ASSERT_EQ(v, 1.0f);
    }
    for (float v : trace(*tracer, towardFace, kTilted)) ASSERT_EQ(v, 1.0f);
    for (float v : trace(*tracer, awayFace, kTilted)) ASSERT_EQ(v, 0.0f);
}

// A flat plane lit 89.9 degrees from the zenith, from eight azimuths, with query points jittered
// off the plane by one part in 10^6 of their distance (position reconstruction error): no acne.
void expectNoAcneOnGrazingPlane(const Scene& scene, glm::dvec3 planeCentre, glm::dvec3 origin) {
    auto tracer = buildTracer(scene, origin);
    ASSERT_TRUE(tracer);
    const double zenith = 89.9 * std::numbers::pi / 180.0;
    std::vector<glm::vec3> positions;
    for (double x = -90.3; x < 90; x += 1.7)
        for (double z = -90.1; z < 90; z += 1.3)
            for (double jitter : {-1e-6, 0.0, 1e-6}) {
                glm::dvec3 rel = planeCentre + glm::dvec3(x, 0, z) - origin;
                rel.y += jitter * glm::length(rel);
                positions.push_back(glm::vec3(rel));
            }
    std::vector<float> out(positions.size());
    for (int a = 0; a < 8; ++a) {
        const double azimuth = a * std::numbers::pi / 4 + 0.1;
        glm::vec3 light(float(std::sin(zenith) * std::cos(azimuth)), float(std::cos(zenith)),
                        float(std::sin(zenith) * std::sin(azimuth)));
        tracer->visibility(positions, light, out);
        size_t occluded = 0;
        for (float v : out) occluded += v != 1.0f;
        EXPECT_EQ(occluded, 0u) << "azimuth " << azimuth << " of " << out.size() << " points";
    }
}

TEST(ShadowTracerGrazing, FlatPlaneDoesNotShadowItselfAt89Point9Degrees) {
    TempDir dir("grazing");
    gltf::Document doc;
    doc.materials.push_back(material("ground"));
    pnb::test::addObject(doc, "plane", pnb::test::quad(200, 200, 0), {0, 0, 0}, kFaceUp);
    auto loaded = loadPnb(pnb::test::convertDocument(dir.str(), doc, "plane", "", false));
    ASSERT_TRUE(loaded);
    expectNoAcneOnGrazingPlane(loaded->scene, {0, 0, 0}, {0, 1.7, 0});

    gltf::Document far;
    far.materials.push_back(material("ground"));
    pnb::test::addObject(far, "plane", pnb::test::quad(200, 200, 0), {1e6f, 0, -1e6f}, kFaceUp);
    auto farLoaded = loadPnb(pnb::test::convertDocument(dir.str(), far, "far-plane", "", false));
    ASSERT_TRUE(farLoaded);
    expectNoAcneOnGrazingPlane(farLoaded->scene, {1e6, 0, -1e6}, {1e6 + 3, 1.7, -1e6 + 5});
}

TEST_F(ShadowTracerTest, SceneTranslatedByAMillionUnitsGivesIdenticalResults) {
    ASSERT_TRUE(sGroundBox && sFarGroundBox);
    const glm::dvec3 shift(1e6, 0, 1e6);
    auto near = buildTracer(sGroundBox->scene, {0, 10, 10});
    auto far = buildTracer(sFarGroundBox->scene, shift + glm::dvec3(0, 10, 10));
    ASSERT_TRUE(near && far);
    EXPECT_EQ(near->stats().triangles, far->stats().triangles);
    for (glm::vec3 light : {kUp, kTilted}) {
        auto points = groundGrid();
        std::vector<glm::dvec3> farPoints;
        for (const glm::dvec3& p : points) farPoints.push_back(p + shift);
        auto a = trace(*near, points, light);
        auto b = trace(*far, farPoints, light);
        ASSERT_EQ(a, b);
        for (size_t i = 0; i < points.size(); ++i)
            ASSERT_EQ(b[i], (light == kUp ? inOverheadShadow(points[i]) : inTiltedShadow(points[i]))
                                ? 0.0f
                                : 1.0f);
    }
}

TEST_F(ShadowTracerTest, QuantizedPositionsDecodeToTheSameShadow) {
    ASSERT_TRUE(sQuantized);
    bool quantized = false;
    for (const Mesh& m : sQuantized->scene.meshes)
        for (const VertexStream& s : m.streams)
            quantized |= s.semantic == VertexSemantic::Position && s.componentType == ComponentType::U16;
    ASSERT_TRUE(quantized) << "the converter did not quantise positions";
    auto tracer = buildTracer(sQuantized->scene, {0, 10, 10});
    ASSERT_TRUE(tracer);
    auto points = groundGrid();
    auto overhead = trace(*tracer, points, kUp);
    auto tilted = trace(*tracer, points, kTilted);
    for (size_t i = 0; i < points.size(); ++i) {
        ASSERT_EQ(overhead[i], inOverheadShadow(points[i]) ? 0.0f : 1.0f);
        ASSERT_EQ(tilted[i], inTiltedShadow(points[i]) ? 0.0f : 1.0f);
    }
}

// visibility() is the opaque part: the blended box (a translucent caster since issue 43, see
// translucency_test.cpp for what it lets through) does not block it.
TEST(ShadowTracerMaterials, MaskCastsAsOpaqueBlendAndNonCastingDoNot) {
    TempDir dir("materials");
    gltf::Document doc;
    doc.materials = {material("ground"), material("leaves", gltf::AlphaMode::Mask),
                     material("glass", gltf::AlphaMode::Blend), material("nocast")};
    pnb::test::addObject(doc, "ground", pnb::test::quad(40, 40, 0), {0, 0, 0}, kFaceUp);
    pnb::test::addObject(doc, "masked", pnb::test::box(2, 2, 2, 1), {-6, 3, 0});
    pnb::test::addObject(doc, "blended", pnb::test::box(2, 2, 2, 2), {0, 3, 0});
    pnb::test::addObject(doc, "hidden", pnb::test::box(2, 2, 2, 3), {6, 3, 0});
    auto loaded = loadPnb(pnb::test::convertDocument(
        dir.str(), doc, "materials", R"({"materials": {"nocast": {"casts_shadows": false}}})",
        false));
    ASSERT_TRUE(loaded);
    auto tracer = buildTracer(loaded->scene, {0, 10, 10});
    ASSERT_TRUE(tracer);
    EXPECT_EQ(tracer->stats().casterInstances, 3u); // ground + masked box + blended box
    EXPECT_EQ(tracer->stats().maskedCastersTreatedOpaque, 1u);
    EXPECT_EQ(tracer->stats().translucentCasters, 1u);
    EXPECT_EQ(tracer->stats().excludedInstances, 1u); // the box that casts nothing
    EXPECT_EQ(tracer->stats().triangles, 2u + 12u + 12u);
    auto vis = trace(*tracer, {{-6, 0, 0}, {0, 0, 0}, {6, 0, 0}, {-3, 0, 0}}, kUp);
    EXPECT_EQ(vis, (std::vector<float>{0.0f, 1.0f, 1.0f, 1.0f}));
}

TEST_F(ShadowTracerTest, NonFinitePositionsGiveNaNAndMisuseFillsNaN) {
    ASSERT_TRUE(sGroundBox);
    auto tracer = buildTracer(sGroundBox->scene, {0, 10, 10});
    ASSERT_TRUE(tracer);
    const glm::vec3 ground = glm::vec3(0, 0, 0) - glm::vec3(0, 10, 10); // shadowed
    const glm::vec3 open = glm::vec3(5, 0, 0) - glm::vec3(0, 10, 10);   // lit
    std::vector<glm::vec3> positions = {ground, {kNaN, 0, 0}, open, {0, kInf, 0}, {0, 0, -kInf},
                                        open};
    std::vector<float> out(positions.size());
    tracer->visibility(positions, kUp, out);
    EXPECT_EQ(out[0], 0.0f);
    EXPECT_TRUE(std::isnan(out[1]));
    EXPECT_EQ(out[2], 1.0f);
    EXPECT_TRUE(std::isnan(out[3]));
    EXPECT_TRUE(std::isnan(out[4]));
    EXPECT_EQ(out[5], 1.0f);

    // A light direction that is not unit length is normalised.
    tracer->visibility(positions, kUp * 3.0f, out);
    EXPECT_EQ(out[0], 0.0f);
    EXPECT_EQ(out[2], 1.0f);

    // Precondition violations: everything NaN, nothing traced.
    for (glm::vec3 light : {glm::vec3(0.0f), glm::vec3(kNaN, 1, 0)}) {
        tracer->visibility(positions, light, out);
        for (float v : out) EXPECT_TRUE(std::isnan(v));
    }
    tracer->visibility(positions, kUp, out, glm::dvec3(0, kInf, 0)); // non-finite eye
    for (float v : out) EXPECT_TRUE(std::isnan(v));
    std::vector<float> wrongSize(2, 5.0f);
    tracer->visibility(positions, kUp, wrongSize);
    for (float v : wrongSize) EXPECT_TRUE(std::isnan(v));
    tracer->visibility({}, kUp, std::span<float>()); // empty: nothing to do
}

TEST_F(ShadowTracerTest, ManyPointsOnAllThreadsMatchOnePointAtATime) {
    ASSERT_TRUE(sGroundBox);
    auto tracer = buildTracer(sGroundBox->scene, {0, 10, 10});
    ASSERT_TRUE(tracer);
    auto points = groundGrid(glm::dvec3(0.0), 12.0); // 9216 points: several chunks and packets
    points.push_back({0.5, 0, 0.5});                 // a partial last packet
    auto all = trace(*tracer, points, kTilted);
    for (size_t i = 0; i < points.size(); i += 97) {
        auto one = trace(*tracer, {points[i]}, kTilted);
        ASSERT_EQ(one[0], all[i]) << i;
    }
}

// [SECTION] hand-built scenes: every position encoding, node hierarchies, bad data

// One triangle in the plane y = 1 covering x + z <= 0 of the square [-5, 5]^2, stored as `type`.
struct TriangleScene {
    std::vector<std::byte> positions, indices;
    Scene scene;
};

template <class T> void append(std::vector<std::byte>& bytes, T v) {
    size_t at = bytes.size();
    bytes.resize(at + sizeof(T));
    std::memcpy(bytes.data() + at, &v, sizeof(T));
}

uint16_t toHalf(float f) { // exact for the small integers used here
    if (f == 0.0f) return 0;
    uint32_t bits;
    std::memcpy(&bits, &f, 4);
    uint32_t sign = (bits >> 16) & 0x8000u, exponent = ((bits >> 23) & 0xFF) - 127 + 15;
    return uint16_t(sign | (exponent << 10) | ((bits >> 13) & 0x3FF));
}

std::unique_ptr<TriangleScene> triangleScene(ComponentType type, bool normalized) {
    auto t = std::make_unique<TriangleScene>();
    // Corner coordinates in [0, 1] (u) for x and z; y is stored 0 and offset to 1.
    const float corners[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    VertexStream s;
    s.semantic = VertexSemantic::Position;
    s.componentType = type;
    s.componentCount = 3;
    s.normalized = normalized;
    bool isSigned = type == ComponentType::I8 || type == ComponentType::I16 || type == ComponentType::I32;
    for (const auto& c : corners) {
        for (int k = 0; k < 3; ++k) {
            if (k == 1) { // y: stored 0 (decodes to 0 in every type), dequantised to 1
                switch (componentSizeBytes(type)) {
                case 1: append(t->positions, uint8_t(0)); break;
                case 2: append(t->positions, uint16_t(0)); break;
                default: append(t->positions, uint32_t(0)); break;
                }
                continue;
            }
            float u = k == 0 ? c[0] : c[1];
            // Stored so that the decoded value d dequantises (d * scale + offset) to u * 10 - 5.
            switch (type) {
            case ComponentType::F32: append(t->positions, u * 10 - 5); break;
            case ComponentType::F16: append(t->positions, toHalf(u * 10 - 5)); break;
            case ComponentType::U8: append(t->positions, uint8_t(normalized ? u * 255 : u * 10)); break;
            case ComponentType::I8: append(t->positions, int8_t(normalized ? (2 * u - 1) * 127 : u * 10)); break;
            case ComponentType::U16: append(t->positions, uint16_t(normalized ? u * 65535 : u * 10)); break;
            case ComponentType::I16: append(t->positions, int16_t(normalized ? (2 * u - 1) * 32767 : u * 10)); break;
            case ComponentType::U32: append(t->positions, uint32_t(u * 10)); break;
            case ComponentType::I32: append(t->positions, int32_t(u * 10)); break;
            default: break;
            }
        }
    }
    const bool isFloat = type == ComponentType::F32 || type == ComponentType::F16;
    if (isFloat) {
        s.dequantScale = {1, 1, 1};
        s.dequantOffset = {0, 1, 0};
    } else if (normalized && isSigned) { // d in [-1, 1]
        s.dequantScale = {5, 1, 5};
        s.dequantOffset = {0, 1, 0};
    } else if (normalized) { // d in [0, 1]
        s.dequantScale = {10, 1, 10};
        s.dequantOffset = {-5, 1, -5};
    } else { // d in [0, 10]
        s.dequantScale = {1, 1, 1};
        s.dequantOffset = {-5, 1, -5};
    }
    for (uint16_t i : {0, 1, 2}) append(t->indices, i);
    s.data = t->positions;

    Mesh m;
    m.vertexCount = 3;
    m.indexType = IndexType::U16;
    m.streams = {s};
    m.indices = t->indices;
    Submesh sm;
    sm.material = 0;
    sm.indexCount = 3;
    m.submeshes = {sm};
    t->scene.meshes = {m};
    t->scene.materials = {Material{}};
    Node n;
    n.mesh = 0;
    t->scene.nodes.nodes = {n};
    return t;
}

std::vector<float> traceDown(const Scene& scene, const std::vector<glm::dvec3>& points,
                             glm::dvec3 origin = glm::dvec3(0.0)) {
    auto tracer = buildTracer(scene, origin);
    if (!tracer) return {};
    return trace(*tracer, points, kUp);
}

TEST(ShadowTracerEncodings, EveryComponentTypeDecodesAsTheGpuWould) {
    struct Case {
        ComponentType type;
        bool normalized;
    };
    const Case cases[] = {{ComponentType::F32, false}, {ComponentType::F16, false},
                          {ComponentType::U8, true},   {ComponentType::I8, true},
                          {ComponentType::U16, true},  {ComponentType::I16, true},
                          {ComponentType::U16, false}, {ComponentType::I16, false},
                          {ComponentType::U32, false}, {ComponentType::I32, false},
                          {ComponentType::U8, false},  {ComponentType::I8, false}};
    // Under the triangle (x + z < 0), outside it, and outside the square.
    const std::vector<glm::dvec3> points = {{-4.5, 0, -4.5}, {-2, 0, 1.5}, {4.4, 0, -4.6},
                                            {1, 0, 1},      {-4.5, 0, 4.0}, {-5.5, 0, -4.5},
                                            {-4.5, 0, -5.5}};
    const std::vector<float> expected = {0, 0, 0, 1, 0, 1, 1};
    for (const Case& c : cases) {
        SCOPED_TRACE(testing::Message() << "component type " << int(c.type) << " normalized "
                                        << c.normalized);
        auto t = triangleScene(c.type, c.normalized);
        EXPECT_EQ(traceDown(t->scene, points), expected);
    }
}

TEST(ShadowTracerGraph, WorldTransformsComposeParentsFirstInDouble) {
    auto t = triangleScene(ComponentType::F32, false);
    // parent: translate (100, 0, 0), scale (2, 1, 2); child: translate (0, 2, 0), the mesh.
    // World vertex = (100 + 2x, 2 + y, 2z): the triangle covers (x-100)/2 + z/2 <= 0 at y = 3.
    Node parent;
    parent.translation = {100, 0, 0};
    parent.scale = {2, 1, 2};
    Node child;
    child.parent = 0;
    child.translation = {0, 2, 0};
    child.mesh = 0;
    t->scene.nodes.nodes = {parent, child};
    EXPECT_EQ(traceDown(t->scene, {{94, 0, -6}, {106, 0, 6}, {91, 0, -9}, {-4.5, 0, -4.5}},
                        {100, 5, 0}),
              (std::vector<float>{0, 1, 0, 1}));

    // A 90-degree rotation about +Y maps (x, z) to (z, -x): the triangle covers x <= z.
    Node rotated;
    rotated.rotation = {0, 0.70710678f, 0, 0.70710678f};
    rotated.mesh = 0;
    t->scene.nodes.nodes = {rotated};
    EXPECT_EQ(traceDown(t->scene, {{-2, 0, 3}, {3, 0, -2}}), (std::vector<float>{0, 1}));
}

TEST(ShadowTracerGraph, LodLevelsNonTrianglesAndMaterialLessSubmeshesCastNothing) {
    auto t = triangleScene(ComponentType::F32, false);
    t->scene.meshes[0].submeshes[0].lod = 1;
    EXPECT_EQ(traceDown(t->scene, {{-4.5, 0, -4.5}}), std::vector<float>{1});
    t->scene.meshes[0].submeshes[0].lod = 0;
    t->scene.meshes[0].submeshes[0].material = kNone;
    EXPECT_EQ(traceDown(t->scene, {{-4.5, 0, -4.5}}), std::vector<float>{1});
    t->scene.meshes[0].submeshes[0].material = 0;
    t->scene.meshes[0].primitive = Primitive::Lines;
    EXPECT_EQ(traceDown(t->scene, {{-4.5, 0, -4.5}}), std::vector<float>{1});
    t->scene.meshes[0].primitive = Primitive::Triangles;
    EXPECT_EQ(traceDown(t->scene, {{-4.5, 0, -4.5}}), std::vector<float>{0});
    // An empty scene: everything lit.
    EXPECT_EQ(traceDown(Scene{}, {{0, 0, 0}}), std::vector<float>{1});
}

TEST(ShadowTracerErrors, BadSceneDataIsAnErrorNamingTheMesh) {
    auto expectError = [](const Scene& scene, TracerErrorKind kind, const char* needle) {
        auto r = ShadowTracer::build(scene, glm::dvec3(0.0));
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().kind, kind);
        EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
    };
    {
        auto t = triangleScene(ComponentType::I16, true);
        t->scene.meshes[0].streams[0].encoding = VertexEncoding::Octahedral;
        expectError(t->scene, TracerErrorKind::Unsupported, "octahedral");
    }
    {
        auto t = triangleScene(ComponentType::F32, false);
        t->scene.meshes[0].vertexCount = 4;
        expectError(t->scene, TracerErrorKind::Input, "position stream holds");
    }
    {
        auto t = triangleScene(ComponentType::F32, false);
        t->scene.meshes[0].vertexCount = 2;
        t->scene.meshes[0].streams[0].data = std::span(t->positions).first(24);
        expectError(t->scene, TracerErrorKind::Input, "is not below vertexCount");
    }
    {
        auto t = triangleScene(ComponentType::F32, false);
        t->scene.meshes[0].submeshes[0].indexCount = 6;
        expectError(t->scene, TracerErrorKind::Input, "run past");
    }
    {
        auto t = triangleScene(ComponentType::F32, false);
        t->scene.meshes[0].submeshes[0].material = 3;
        expectError(t->scene, TracerErrorKind::Input, "material 3");
    }
    {
        auto t = triangleScene(ComponentType::F32, false);
        t->scene.nodes.nodes[0].mesh = 1;
        expectError(t->scene, TracerErrorKind::Input, "mesh 1");
    }
    {
        auto t = triangleScene(ComponentType::F32, false);
        t->scene.nodes.nodes[0].parent = 0;
        expectError(t->scene, TracerErrorKind::Input, "does not precede");
    }
    {
        auto t = triangleScene(ComponentType::F32, false);
        t->scene.meshes[0].streams.clear();
        expectError(t->scene, TracerErrorKind::Input, "no position stream");
    }
}

// Every procedural scene the build converts: the tracer builds, and points above the scene
// looking straight up at the sky are lit (no caster hangs over everything).
TEST(ShadowTracerScenes, EveryProceduralSceneBuilds) {
    for (const char* name : {"box-room", "street-canyon", "flat-city", "terrain", "grazing-plane"}) {
        SCOPED_TRACE(name);
        auto loaded = loadPnb(std::string(PNB_SCENE_DIR) + "/" + name + ".pnb");
        ASSERT_TRUE(loaded);
        const Aabb& b = loaded->scene.info.bounds;
        ASSERT_FALSE(b.empty());
        glm::dvec3 centre((b.min.x + b.max.x) * 0.5, (b.min.y + b.max.y) * 0.5,
                          (b.min.z + b.max.z) * 0.5);
        auto tracer = buildTracer(loaded->scene, centre);
        ASSERT_TRUE(tracer);
        EXPECT_GT(tracer->stats().triangles, 0u);
        EXPECT_GT(tracer->stats().casterInstances, 0u);
        std::vector<glm::dvec3> above;
        for (int i = 0; i < 16; ++i)
            above.push_back({b.min.x + (b.max.x - b.min.x) * (i + 0.5) / 16.0, b.max.y + 1.0,
                             b.min.z + (b.max.z - b.min.z) * (i + 0.5) / 16.0});
        for (float v : trace(*tracer, above, kUp)) EXPECT_EQ(v, 1.0f);
    }
}

} // namespace

} // namespace pnb::reference::test
