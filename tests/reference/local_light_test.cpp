// Point and spot lights in the truth: the falloff against hand-computed values (lights.glsl's),
// placing a light with its node, the exact shadow of a box under a point light, a lamp set into
// a ceiling, and the binary metric counting only what a spot's cone reaches.
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>

#include "pnb_reference/local_light.h"
#include "pnb_reference/shadow_tracer.h"
#include "reference_test_util.h"

namespace pnb::reference::test {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A light node of `doc` at `translation` (rotation: the light shines down -Z turned by it).
void addLight(gltf::Document& doc, gltf::Light light, gltf::Float3 translation,
              gltf::Float4 rotation = {0, 0, 0, 1}, int32_t parent = -1) {
    doc.lights.push_back(std::move(light));
    gltf::Node n;
    n.name = doc.lights.back().name;
    n.translation = translation;
    n.rotation = rotation;
    n.light = int32_t(doc.lights.size() - 1);
    doc.nodes.push_back(n);
    if (parent >= 0) doc.nodes[size_t(parent)].children.push_back(uint32_t(doc.nodes.size() - 1));
}

// The index in the container of the light named `name` (the converter orders them by node).
uint32_t lightIndex(const Scene& scene, const std::string& name) {
    for (uint32_t i = 0; i < scene.lights.lights.size(); ++i)
        if (scene.strings.strings[scene.lights.lights[i].name] == name) return i;
    ADD_FAILURE() << "no light " << name;
    return 0;
}

// Ray (origin, towards `to`) against the box x, z in [-1, 1], y in [2, 4] grown by `grow`: does
// the open segment meet it? (Slabs, in double.)
bool segmentHitsBox(glm::dvec3 from, glm::dvec3 to, double grow) {
    const glm::dvec3 lo(-1 - grow, 2 - grow, -1 - grow), hi(1 + grow, 4 + grow, 1 + grow);
    double t0 = 0, t1 = 1;
    const glm::dvec3 d = to - from;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0) {
            if (from[a] < lo[a] || from[a] > hi[a]) return false;
            continue;
        }
        double ta = (lo[a] - from[a]) / d[a], tb = (hi[a] - from[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 < t1;
}

class LocalLightTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        sDir = new TempDir("local-light");
        // groundAndBox with a point light above the box, a spot pointing straight down placed
        // through a parent node (the world transform composes), and the converter's default-sun.
        gltf::Document doc = groundAndBox();
        addLight(doc,
                 {.name = "bulb", .type = gltf::LightType::Point, .intensity = 50, .range = 20},
                 {0, 6, 0});
        gltf::Node parent;
        parent.name = "rig";
        parent.translation = {0, 1, 0};
        doc.nodes.push_back(parent);
        addLight(doc,
                 {.name = "spot",
                  .type = gltf::LightType::Spot,
                  .intensity = 80,
                  .range = 0,
                  .innerConeRadians = float(20 * kDeg),
                  .outerConeRadians = float(30 * kDeg)},
                 {0, 5, 0}, kFaceUp, int32_t(doc.nodes.size() - 1)); // -Z turned to -Y
        sLit = loadPnb(pnb::test::convertDocument(sDir->str(), doc, "lit", "", false)).release();

        // A ceiling quad at y = 6 facing down, and a light 2e-4 above its plane, within its error
        // band (2^-16 of its distance from the eye, 19 away: 2.9e-4): set into it.
        gltf::Document lamp = groundAndBox();
        pnb::test::addObject(lamp, "ceiling", pnb::test::quad(40, 40, 0), {0, 6, 0},
                             {0.70710678f, 0, 0, 0.70710678f});
        addLight(lamp,
                 {.name = "recessed", .type = gltf::LightType::Point, .intensity = 50, .range = 30},
                 {0, 6.0002f, 0});
        sCeiling =
            loadPnb(pnb::test::convertDocument(sDir->str(), lamp, "ceiling", "", false)).release();
    }
    static void TearDownTestSuite() {
        delete sLit;
        delete sCeiling;
        delete sDir;
    }
    static TempDir* sDir;
    static LoadedScene* sLit;
    static LoadedScene* sCeiling;
};
TempDir* LocalLightTest::sDir = nullptr;
LoadedScene* LocalLightTest::sLit = nullptr;
LoadedScene* LocalLightTest::sCeiling = nullptr;

// Ground points on a grid (spacing 0.25, never within 0.125 of a multiple of 0.25).
std::vector<glm::dvec3> groundGrid(double half) {
    std::vector<glm::dvec3> points;
    for (double x = -half + 0.125; x < half; x += 0.25)
        for (double z = -half + 0.125; z < half; z += 0.25)
            points.push_back({x, 0, z});
    return points;
}

std::vector<float> traceToPoint(const ShadowTracer& tracer, const std::vector<glm::dvec3>& points,
                                glm::dvec3 light) {
    std::vector<glm::vec3> relative;
    for (const glm::dvec3& p : points)
        relative.push_back(glm::vec3(p - tracer.origin()));
    std::vector<float> out(points.size(), -7.0f);
    tracer.visibilityToPoint(relative, glm::vec3(light - tracer.origin()), out);
    return out;
}

} // namespace

TEST(LocalLightFalloff, EqualsHandComputedValuesOfLightsGlsl) {
    // window = 1 - (4/16)^2 = 0.9375; 0.9375^2 / 4 (all exact in binary).
    EXPECT_DOUBLE_EQ(rangeAttenuation(4.0, 4.0), 0.87890625 / 4.0);
    EXPECT_DOUBLE_EQ(rangeAttenuation(4.0, 0.0), 0.25);         // no range: the inverse square
    EXPECT_DOUBLE_EQ(rangeAttenuation(100.0, 10.0), 0.0);       // at the range
    EXPECT_DOUBLE_EQ(rangeAttenuation(150.0, 10.0), 0.0);       // past it
    EXPECT_NEAR(rangeAttenuation(1e-6, 10.0), 1e4, 1e-6);       // 1 cm^2 clamp
    EXPECT_NEAR(spotConeFactor(0.8, 0.7, 0.9), 0.25, 1e-12);    // t = 0.5
    EXPECT_DOUBLE_EQ(spotConeFactor(0.95, 0.7, 0.9), 1.0);      // inside the inner cone
    EXPECT_DOUBLE_EQ(spotConeFactor(0.6, 0.7, 0.9), 0.0);       // outside the outer cone
    EXPECT_NEAR(spotConeFactor(0.70005, 0.7, 0.7), 0.25, 1e-9); // inner = outer: 1e-4 wide edge

    // A point light 5 m away from a floor point, 3 up and 4 across: d^2 = 25, n.l = 0.6,
    // window = (1 - (25/100)^2)^2 = 0.87890625; E = 50 x 0.6 x 0.87890625 / 25.
    LocalLight point;
    point.type = LightType::Point;
    point.intensity = 50;
    point.range = 10;
    point.cosOuter = -1;
    const glm::dvec3 toLight(0, 3, 4), up(0, 1, 0);
    EXPECT_NEAR(localLightIrradiance(point, toLight, up), 1.0546875, 1e-12);
    EXPECT_TRUE(localLightReaches(point, toLight, up));
    // A spot there pointing straight down: cos from the axis 0.6, cone 0.5 .. 0.7: t = 0.5.
    LocalLight spot = point;
    spot.type = LightType::Spot;
    spot.direction = {0, -1, 0};
    spot.cosOuter = 0.5f;
    spot.cosInner = 0.7f;
    EXPECT_NEAR(localLightIrradiance(spot, toLight, up), 1.0546875 * 0.25, 1e-6); // float cones
    EXPECT_TRUE(localLightReaches(spot, toLight, up));
    // Not reached, and no light there either: past the range, facing away, outside the cone.
    for (auto [what, l, d, n] : {std::tuple{"range", point, glm::dvec3(0, 6, 8), up},
                                 std::tuple{"facing away", point, toLight, -up},
                                 std::tuple{"edge-on", point, glm::dvec3(0, 0, 4), up},
                                 std::tuple{"cone", spot, glm::dvec3(0, 3, 6), up}}) {
        SCOPED_TRACE(what);
        EXPECT_FALSE(localLightReaches(l, d, n));
        EXPECT_EQ(localLightIrradiance(l, d, n), 0.0);
    }
}

TEST_F(LocalLightTest, PlacesLightsWithTheirNodesAndNamesBadIndices) {
    ASSERT_TRUE(sLit);
    const Scene& scene = sLit->scene;
    ASSERT_EQ(scene.lights.lights.size(), 3u) << "bulb, spot and the converter's default-sun";
    auto bulb = placeLocalLight(scene, lightIndex(scene, "bulb"));
    ASSERT_TRUE(bulb.ok()) << bulb.error().message;
    EXPECT_EQ(bulb->type, LightType::Point);
    EXPECT_EQ(bulb->position, glm::dvec3(0, 6, 0));
    EXPECT_EQ(bulb->range, 20.0f);
    EXPECT_TRUE(bulb->ownRange);
    EXPECT_EQ(bulb->placementNodes, 1u);
    auto spot = placeLocalLight(scene, lightIndex(scene, "spot"));
    ASSERT_TRUE(spot.ok()) << spot.error().message;
    EXPECT_EQ(spot->type, LightType::Spot);
    EXPECT_NEAR(glm::length(spot->position - glm::dvec3(0, 6, 0)), 0.0, 1e-6) << "parent + child";
    EXPECT_NEAR(glm::length(spot->direction - glm::dvec3(0, -1, 0)), 0.0, 1e-6);
    // No range in the glTF: pnb-convert writes the 0.01 lux cut-off's, sqrt(80 / 0.01), into
    // LGHT, so the container's light has a range of its own.
    EXPECT_TRUE(spot->ownRange);
    EXPECT_NEAR(spot->range, std::sqrt(80.0 / 0.01), 1e-2);
    EXPECT_NEAR(spot->cosOuter, std::cos(30 * kDeg), 1e-6);
    EXPECT_NEAR(spot->cosInner, std::cos(20 * kDeg), 1e-6);

    auto none = placeLocalLight(scene, 3);
    ASSERT_FALSE(none.ok());
    EXPECT_EQ(none.error().kind, TracerErrorKind::Input);
    EXPECT_NE(none.error().message.find("light 3 does not exist"), std::string::npos)
        << none.error().message;
    auto sun = placeLocalLight(scene, lightIndex(scene, "default-sun"));
    ASSERT_FALSE(sun.ok());
    EXPECT_NE(sun.error().message.find("directional"), std::string::npos) << sun.error().message;
    auto unplaced = loadPnb(sDir->str() + "/lit.pnb"); // a copy whose bulb no node refers to
    ASSERT_TRUE(unplaced);
    for (Node& n : unplaced->scene.nodes.nodes)
        if (n.light == bulb->index) n.light = kNone;
    auto orphan = placeLocalLight(unplaced->scene, bulb->index);
    ASSERT_FALSE(orphan.ok());
    EXPECT_NE(orphan.error().message.find("'bulb' is placed by no node"), std::string::npos)
        << orphan.error().message;
}

// A point light 2 units above the box's top (y = 6): the box (x, z in [-1, 1], y in [2, 4]) hides
// exactly the ground square max(|x|, |z|) < 1 x 6 / (6 - 4) = 3, and its own underside.
TEST_F(LocalLightTest, PointLightAboveTheBoxShadowsExactlyTheProjectedSquare) {
    ASSERT_TRUE(sLit);
    auto tracer = ShadowTracer::build(sLit->scene, {0, 10, 10});
    ASSERT_TRUE(tracer.ok());
    const std::vector<glm::dvec3> points = groundGrid(6.0);
    const std::vector<float> vis = traceToPoint(**tracer, points, {0, 6, 0});
    size_t shadowed = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        SCOPED_TRACE(testing::Message() << "x " << points[i].x << " z " << points[i].z);
        const bool inside = std::max(std::fabs(points[i].x), std::fabs(points[i].z)) < 3;
        ASSERT_EQ(vis[i], inside ? 0.0f : 1.0f);
        shadowed += vis[i] == 0.0f;
    }
    EXPECT_EQ(shadowed, 24u * 24u); // 6 x 6 units at 0.25 spacing
    // The box's top is lit, its underside and the faces away from a light beside it are not.
    std::vector<glm::dvec3> top, bottom, side;
    for (double u = -0.875; u < 1; u += 0.25)
        for (double v = -0.875; v < 1; v += 0.25) {
            top.push_back({u, 4, v});
            bottom.push_back({u, 2, v});
            side.push_back({-1, 3 + u, v}); // normal -X
        }
    for (float v : traceToPoint(**tracer, top, {0, 6, 0}))
        ASSERT_EQ(v, 1.0f);
    for (float v : traceToPoint(**tracer, bottom, {0, 6, 0}))
        ASSERT_EQ(v, 0.0f);
    for (float v : traceToPoint(**tracer, side, {5, 3, 0}))
        ASSERT_EQ(v, 0.0f);
    for (float v : traceToPoint(**tracer, side, {-5, 3, 0}))
        ASSERT_EQ(v, 1.0f);
}

// Off the axis the footprint is no square: every ground point against a segment-box test in
// double (points within 10^-4 of the boundary, where float positions may go either way, skipped).
TEST_F(LocalLightTest, PointLightBesideTheBoxMatchesASegmentBoxTest) {
    ASSERT_TRUE(sLit);
    auto tracer = ShadowTracer::build(sLit->scene, {0, 10, 10});
    ASSERT_TRUE(tracer.ok());
    const glm::dvec3 light(3.3, 5.1, 1.7);
    const std::vector<glm::dvec3> points = groundGrid(8.0);
    const std::vector<float> vis = traceToPoint(**tracer, points, light);
    size_t shadowed = 0, judged = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        const bool inner = segmentHitsBox(points[i], light, -1e-4),
                   outer = segmentHitsBox(points[i], light, 1e-4);
        if (inner != outer) continue;
        ++judged;
        SCOPED_TRACE(testing::Message() << "x " << points[i].x << " z " << points[i].z);
        ASSERT_EQ(vis[i], inner ? 0.0f : 1.0f);
        shadowed += inner;
    }
    EXPECT_GT(judged, points.size() * 99 / 100);
    EXPECT_GT(shadowed, 100u);
}

// A lamp set into the ceiling (its position 2e-4 above the ceiling's plane, within the light's
// error band: rounding, not an occluder) lights the floor out to a grazing angle. Near the lamp
// the segment crosses the plane within the band of the light (tfar stops short of it); past
// ~6 units out it crosses farther than that (2e-4 / sin of the angle), and only the plane test
// at the light's end (self_intersection.h) keeps the ceiling from hiding the floor. The box
// still does.
TEST_F(LocalLightTest, ALampSetIntoTheCeilingIsNotHiddenByIt) {
    ASSERT_TRUE(sCeiling);
    auto tracer = ShadowTracer::build(sCeiling->scene, {0, 3, 19});
    ASSERT_TRUE(tracer.ok());
    const glm::dvec3 lamp(0, double(6.0002f), 0);
    const std::vector<glm::dvec3> points = groundGrid(19.5);
    const std::vector<float> vis = traceToPoint(**tracer, points, lamp);
    for (size_t i = 0; i < points.size(); ++i) {
        SCOPED_TRACE(testing::Message() << "x " << points[i].x << " z " << points[i].z);
        const bool behindBox = std::max(std::fabs(points[i].x), std::fabs(points[i].z)) < 3;
        ASSERT_EQ(vis[i], behindBox ? 0.0f : 1.0f);
    }
}

// A spot 5 above the floor pointing down with a 30-degree outer cone reaches the disc r < 5 tan 30;
// the player's errors outside it do not count, one inside does, with its irradiance as weight.
TEST(LocalLightMetrics, TheBinaryMetricCountsOnlyWhatTheSpotReaches) {
    LocalLight spot;
    spot.type = LightType::Spot;
    spot.intensity = 100;
    spot.range = 50;
    spot.direction = {0, -1, 0};
    spot.cosOuter = float(std::cos(30 * kDeg));
    spot.cosInner = float(std::cos(20 * kDeg));
    const glm::dvec3 light(0, 5, 0);
    std::vector<glm::vec3> positions, normals;
    for (double x = -5.875; x < 6; x += 0.25)
        for (double z = -5.875; z < 6; z += 0.25) {
            positions.push_back(glm::vec3(float(x), 0.0f, float(z)));
            normals.push_back({0, 1, 0});
        }
    positions.push_back(glm::vec3(NAN)); // no geometry
    normals.push_back({0, 0, 0});
    const LocalLightWeights w = localLightWeights(spot, light, positions, normals, {});
    const double radius = 5 * std::tan(30 * kDeg);
    uint64_t inCone = 0;
    size_t wrongInside = SIZE_MAX;
    std::vector<float> truth(positions.size(), 1.0f), player(positions.size(), 1.0f);
    truth.back() = NAN;
    player.back() = -1.0f;
    for (size_t i = 0; i + 1 < positions.size(); ++i) {
        const bool reached = std::hypot(positions[i].x, positions[i].z) < radius;
        ASSERT_EQ(w.reached[i], reached) << positions[i].x << " " << positions[i].z;
        ASSERT_EQ(w.irradiance[i] > 0.0f, reached);
        inCone += reached;
        if (!reached)
            player[i] = 0.0f; // wrong everywhere outside: not judged
        else if (wrongInside == SIZE_MAX)
            wrongInside = i, player[i] = 0.0f;
    }
    EXPECT_EQ(w.reachedCount, inCone);
    EXPECT_FALSE(w.reached.back());
    ASSERT_NE(wrongInside, SIZE_MAX);
    const ShadowErrorMetrics m = compareLocalShadow(player, truth, w);
    EXPECT_EQ(m.pixels, inCone);
    EXPECT_DOUBLE_EQ(m.misclassifiedPercent, 100.0 / double(inCone));
    EXPECT_DOUBLE_EQ(m.falseShadowPercent, 100.0 / double(inCone));
    EXPECT_EQ(m.coverageMismatch, 0u);
    double sum = 0;
    for (float e : w.irradiance)
        sum += e;
    EXPECT_NEAR(m.weightedErrorPercent, 100.0 * w.irradiance[wrongInside] / sum, 1e-9);
    EXPECT_NEAR(m.weightedFalseShadowPercent, m.weightedErrorPercent, 1e-12);
    // Without the reach, compareShadow would have counted every error outside the cone.
    EXPECT_GT(compareShadow(player, truth).misclassifiedPercent, 50.0);
}

} // namespace pnb::reference::test
