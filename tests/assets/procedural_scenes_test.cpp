// Procedural source scenes: every .glb parses back as valid glTF (checked by glb_check, not by
// the writer), is deterministic, meets its triangle target, and has the property it exists for
// (off-screen casters in the canyon, a grazing sun, floating overhangs, ...).

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <utility>
#include <vector>

#include "glb_check.h"
#include "pnb/scene_builder.h"
#include "pnb_assets/box_room.h"
#include "pnb_assets/procedural_scenes.h"
#include "pnb_assets/scene_transform.h"

namespace {

using namespace pnb;
using assets::gltf::Document;
using test::Aabb;
using test::Frustum;
using test::ParsedGlb;
using test::Vec3;

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

struct Encoded {
    std::vector<uint8_t> bytes;
    assets::gltf::GlbStats stats;
    ParsedGlb glb;
    std::vector<test::Mat4> world;
};

Encoded encodeAndCheck(const Document& doc) {
    Encoded e;
    EXPECT_EQ(assets::gltf::validateDocument(doc), "");
    e.bytes = assets::gltf::encodeGlb(doc, &e.stats);
    std::string error = test::parseGlb(e.bytes, e.glb);
    EXPECT_EQ(error, "");
    if (error.empty()) error = test::validateGltf(e.glb);
    EXPECT_EQ(error, "");
    if (error.empty()) e.world = test::worldMatrices(e.glb);
    return e;
}

// Default-option scenes are built once per test run (terrain and flat-city take a moment in
// debug builds).
const Encoded& defaultScene(const std::string& name) {
    static std::map<std::string, Encoded> cache;
    auto it = cache.find(name);
    if (it == cache.end()) {
        std::optional<Document> doc = assets::buildProceduralScene(name, {});
        EXPECT_TRUE(doc.has_value()) << name;
        it = cache.emplace(name, encodeAndCheck(doc ? *doc : Document{})).first;
    }
    return it->second;
}

const nlohmann::json& nodeJson(const Encoded& e, int node) {
    return e.glb.json["nodes"][node];
}

// The frustum of the camera on node `node`, with an optional aspect override.
Frustum frustumOf(const Encoded& e, int node, double aspect = 0) {
    const nlohmann::json& p =
        e.glb.json["cameras"][nodeJson(e, node)["camera"].get<size_t>()]["perspective"];
    return {e.world[size_t(node)], p["yfov"].get<double>(),
            aspect > 0 ? aspect : p["aspectRatio"].get<double>(), p["znear"].get<double>(),
            p.value("zfar", 1e9)};
}

// Direction the sun's light travels (its node's -Z in world space), normalised.
Vec3 sunDirection(const Encoded& e) {
    int sun = test::findNode(e.glb, "sun");
    EXPECT_GE(sun, 0);
    Vec3 d = test::transformDirection(e.world[size_t(sun)], {0, 0, -1});
    double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return {d[0] / len, d[1] / len, d[2] / len};
}

double sunElevationDegrees(const Encoded& e) {
    return std::asin(-sunDirection(e)[1]) * kRadToDeg;
}

// World-space bounds of every mesh node whose name starts with one of `prefixes`.
std::vector<std::pair<std::string, Aabb>> boundsOf(const Encoded& e,
                                                   std::initializer_list<std::string> prefixes) {
    std::vector<std::pair<std::string, Aabb>> out;
    const nlohmann::json& nodes = e.glb.json["nodes"];
    for (size_t i = 0; i < nodes.size(); ++i) {
        std::string name = nodes[i].value("name", "");
        for (const std::string& p : prefixes)
            if (nodes[i].contains("mesh") && name.rfind(p, 0) == 0)
                out.push_back({name, test::worldBounds(e.glb, e.world, i)});
    }
    return out;
}

// World positions of every vertex of nodes whose name starts with `prefix`.
std::vector<Vec3> worldVertices(const Encoded& e, const std::string& prefix) {
    std::vector<Vec3> out;
    const nlohmann::json& j = e.glb.json;
    for (size_t i = 0; i < j["nodes"].size(); ++i) {
        if (j["nodes"][i].value("name", "").rfind(prefix, 0) != 0) continue;
        for (const auto& prim : j["meshes"][j["nodes"][i]["mesh"].get<size_t>()]["primitives"]) {
            std::vector<double> p = test::readAccessor(e.glb, prim["attributes"]["POSITION"]);
            for (size_t k = 0; k < p.size(); k += 3)
                out.push_back(test::transformPoint(e.world[i], {p[k], p[k + 1], p[k + 2]}));
        }
    }
    return out;
}

std::vector<std::string> allSceneNames() {
    std::vector<std::string> names;
    for (const assets::ProceduralScene& s : assets::proceduralScenes())
        names.emplace_back(s.name);
    return names;
}

// The scenes the every-scene tests build with default options: all but load-test, whose default
// (~1 M triangles, ten 1024² textures) is benchmark-sized; it is tested with small options below.
std::vector<std::string> sceneNames() {
    std::vector<std::string> names = allSceneNames();
    std::erase(names, "load-test");
    return names;
}

// --- Every scene ------------------------------------------------------------------------------

class ProceduralScenes : public testing::TestWithParam<std::string> {};

TEST_P(ProceduralScenes, ParsesBackAsValidGltf) {
    const Encoded& e = defaultScene(GetParam());
    ASSERT_FALSE(e.world.empty());
    EXPECT_EQ(e.stats.sizeBytes, e.bytes.size());
    EXPECT_EQ(test::renderedTriangles(e.glb), e.stats.renderedTriangles)
        << "the writer's count and the file disagree";
    EXPECT_GT(e.stats.renderedTriangles, 0u);
    // Every scene has a camera to look through and a sun to cast shadows, but lamp-room, which
    // is lit by local lights alone (ProceduralLampRoom below).
    ASSERT_TRUE(e.glb.json.contains("cameras"));
    if (GetParam() != "lamp-room") {
        EXPECT_GE(sunElevationDegrees(e), 1.0);
    }
    EXPECT_EQ(e.glb.json["scenes"][0].value("name", ""), GetParam());
}

TEST_P(ProceduralScenes, SameOptionsGiveIdenticalBytes) {
    std::optional<Document> a = assets::buildProceduralScene(GetParam(), {});
    std::optional<Document> b = assets::buildProceduralScene(GetParam(), {});
    ASSERT_TRUE(a && b);
    std::vector<uint8_t> ba = assets::gltf::encodeGlb(*a), bb = assets::gltf::encodeGlb(*b);
    EXPECT_EQ(ba.size(), bb.size());
    EXPECT_TRUE(ba == bb);
    EXPECT_TRUE(ba == defaultScene(GetParam()).bytes);
}

INSTANTIATE_TEST_SUITE_P(All, ProceduralScenes, testing::ValuesIn(sceneNames()),
                         [](const testing::TestParamInfo<std::string>& param) {
                             std::string n = param.param;
                             std::replace(n.begin(), n.end(), '-', '_');
                             return n;
                         });

TEST(ProceduralScenesRegistry, ListsEverySceneAndRejectsUnknownNames) {
    std::vector<std::string> names = allSceneNames();
    EXPECT_EQ(names,
              (std::vector<std::string>{"street-canyon", "flat-city", "box-room", "terrain",
                                        "grazing-plane", "load-test", "light-field", "one-triangle",
                                        "wide-flat", "atrium", "lamp-room", "colour-room", "window",
                                        "crowd", "moving-light"}));
    for (const assets::ProceduralScene& s : assets::proceduralScenes())
        EXPECT_FALSE(s.summary.empty());
    EXPECT_FALSE(assets::buildProceduralScene("no-such-scene", {}).has_value());
}

TEST(ProceduralScenesRegistry, SeedChangesTheLayout) {
    for (const char* name : {"street-canyon", "flat-city", "terrain", "grazing-plane", "light-field"}) {
        assets::SceneRequest other;
        other.seed = 2;
        std::optional<Document> doc = assets::buildProceduralScene(name, other);
        ASSERT_TRUE(doc);
        EXPECT_FALSE(assets::gltf::encodeGlb(*doc) == defaultScene(name).bytes) << name;
    }
}

TEST(ProceduralScenesRegistry, TriangleTargetsAreMet) {
    struct Case {
        const char* name;
        uint64_t target;
        double tolerance;
    };
    // Scenes with a continuous knob (facade cell size) meet 5 %; grid-based ones land on the
    // nearest square of their subdivision, which is coarser for small targets.
    const Case cases[] = {{"street-canyon", 10000, 0.05}, {"street-canyon", 40000, 0.05},
                          {"flat-city", 100000, 0.05},    {"flat-city", 2000000, 0.05},
                          {"terrain", 200000, 0.05},      {"box-room", 5000, 0.10},
                          {"grazing-plane", 20000, 0.10}, {"light-field", 20000, 0.05}};
    for (const Case& c : cases) {
        assets::SceneRequest r;
        r.targetTriangles = c.target;
        std::optional<Document> doc = assets::buildProceduralScene(c.name, r);
        ASSERT_TRUE(doc);
        double n = double(assets::gltf::countRenderedTriangles(*doc));
        EXPECT_NEAR(n, double(c.target), c.tolerance * double(c.target))
            << c.name << " at " << c.target;
    }
}

// --- street-canyon ----------------------------------------------------------------------------

TEST(ProceduralStreetCanyon, AboutTenThousandTriangles) {
    EXPECT_NEAR(double(defaultScene("street-canyon").stats.renderedTriangles), 10000.0, 500.0);
}

TEST(ProceduralStreetCanyon, LowSunShinesAcrossTheStreet) {
    const Encoded& e = defaultScene("street-canyon");
    double elevation = sunElevationDegrees(e);
    EXPECT_GT(elevation, 10.0);
    EXPECT_LT(elevation, 20.0);
    Vec3 d = sunDirection(e);
    // Across (+X, from the left row to the right row) more than along the street.
    EXPECT_GT(d[0], 0.0);
    EXPECT_GT(std::fabs(d[0]), 2 * std::fabs(d[2]));
}

TEST(ProceduralStreetCanyon, CameraStandsInTheStreetLookingAlongIt) {
    const Encoded& e = defaultScene("street-canyon");
    int cam = test::findNode(e.glb, "street-camera");
    ASSERT_GE(cam, 0);
    EXPECT_EQ(e.glb.json["nodes"][0].value("name", ""), "street-camera") << "the default view";
    Vec3 eye = test::transformPoint(e.world[size_t(cam)], {0, 0, 0});
    Vec3 forward = test::transformDirection(e.world[size_t(cam)], {0, 0, -1});
    EXPECT_LT(eye[1], 2.5);
    EXPECT_LT(std::fabs(eye[0]), 10.0);
    EXPECT_LT(forward[2], -0.99);
    // Rows on both sides of the street, 20 to 120 m high, none standing in the street.
    auto rows = boundsOf(e, {"building-"});
    EXPECT_GT(rows.size(), 20u);
    for (const auto& [name, box] : rows) {
        EXPECT_GE(box.max[1], 20.0 - 1e-3) << name;
        EXPECT_LE(box.max[1], 120.0 + 1e-3) << name;
        EXPECT_TRUE(box.min[0] >= 10.0 || box.max[0] <= -10.0) << name << " blocks the street";
    }
}

TEST(ProceduralStreetCanyon, OffscreenTowersAreOutsideTheFrustumButShadowASunlitSpotInView) {
    const Encoded& e = defaultScene("street-canyon");
    const int cam = test::findNode(e.glb, "street-camera");
    ASSERT_GE(cam, 0);
    const Frustum view = frustumOf(e, cam);
    EXPECT_NEAR(view.aspect, 16.0 / 9.0, 1e-6);
    const Vec3 eye = test::transformPoint(e.world[size_t(cam)], {0, 0, 0});
    const Vec3 d = sunDirection(e);
    const Vec3 toSun{-d[0], -d[1], -d[2]};
    auto towers = boundsOf(e, {"offscreen-tower-"});
    auto everything = boundsOf(e, {"building-", "offscreen-tower-"});
    ASSERT_EQ(towers.size(), 2u);
    double tallestRow = 0;
    for (const auto& [name, box] : boundsOf(e, {"building-"}))
        tallestRow = std::max(tallestRow, box.max[1]);

    bool behind = false, beside = false;
    for (const auto& [name, tower] : towers) {
        SCOPED_TRACE(name);
        EXPECT_GT(tower.max[1], tallestRow + 50) << "a very tall building";
        // Outside the frustum at the file's aspect and at anything from 1:1 to 2.4:1.
        for (double aspect : {0.0, 1.0, 2.4})
            EXPECT_TRUE(frustumOf(e, cam, aspect).boxOutside(tower));
        behind |= tower.min[2] > eye[2];
        beside |= tower.max[2] < eye[2];

        // Shadow of the top onto the ground (y = 0) along the sun direction: the top centre
        // and all four top corners land inside the frustum.
        auto shadowOf = [&](Vec3 p) {
            double t = p[1] / -d[1];
            return Vec3{p[0] + t * d[0], 0.0, p[2] + t * d[2]};
        };
        const double cx = (tower.min[0] + tower.max[0]) / 2, cz = (tower.min[2] + tower.max[2]) / 2;
        const Vec3 tip = shadowOf({cx, tower.max[1], cz});
        EXPECT_TRUE(view.contains(tip)) << "tip at " << tip[0] << ", " << tip[2];
        EXPECT_TRUE(frustumOf(e, cam, 1.0).contains(tip));
        for (int k = 0; k < 4; ++k) {
            Vec3 corner{k & 1 ? tower.max[0] : tower.min[0], tower.max[1],
                        k & 2 ? tower.max[2] : tower.min[2]};
            EXPECT_TRUE(view.contains(shadowOf(corner)));
        }
        // The tip falls on the asphalt, in view of the camera...
        EXPECT_LT(std::fabs(tip[0]), 10.0);
        const Vec3 toTip{tip[0] - eye[0], tip[1] - eye[1], tip[2] - eye[2]};
        for (const auto& [other, box] : everything)
            EXPECT_FALSE(test::rayHitsBox(eye, toTip, box, 0.0, 0.999)) << other << " hides it";
        // ...and a spot just short of the tip is shadowed by this tower and by nothing else,
        // so the shadow is visible against sunlit ground.
        const Vec3 nearTip = shadowOf({cx, tower.max[1] - 2.0, cz});
        for (const auto& [other, box] : everything) {
            bool hit = test::rayHitsBox(nearTip, toSun, box, 1e-3, 1e9);
            EXPECT_EQ(hit, other == name) << other;
        }
    }
    EXPECT_TRUE(behind) << "one tower stands behind the camera";
    EXPECT_TRUE(beside) << "one tower stands ahead of the camera, outside a side plane";
}

// --- flat-city --------------------------------------------------------------------------------

TEST(ProceduralFlatCity, RenderedTrianglesWithinFivePercentOfTarget) {
    const Encoded& e = defaultScene("flat-city");
    EXPECT_NEAR(double(e.stats.renderedTriangles), 500000.0, 25000.0);
    // Instancing: far fewer triangles stored than drawn.
    EXPECT_LT(e.stats.uniqueTriangles * 10, e.stats.renderedTriangles);
}

TEST(ProceduralFlatCity, ManyBuildingsFewMeshesSeveralColours) {
    const Encoded& e = defaultScene("flat-city");
    auto buildings = boundsOf(e, {"building-"});
    EXPECT_GT(buildings.size(), 1000u);
    std::set<size_t> meshes;
    for (const auto& n : e.glb.json["nodes"])
        if (n.value("name", "").rfind("building-", 0) == 0) meshes.insert(n["mesh"].get<size_t>());
    EXPECT_LE(meshes.size(), 24u);
    std::set<std::vector<double>> colours;
    for (const auto& m : e.glb.json["materials"])
        colours.insert(m["pbrMetallicRoughness"]["baseColorFactor"].get<std::vector<double>>());
    EXPECT_GE(colours.size(), 4u);
    EXPECT_NEAR(sunElevationDegrees(e), 45.0, 0.5);
    // Heights vary widely.
    double lo = 1e9, hi = 0;
    for (const auto& [name, box] : buildings) {
        lo = std::min(lo, box.max[1]);
        hi = std::max(hi, box.max[1]);
    }
    EXPECT_LT(lo, 20.0);
    EXPECT_GT(hi, 100.0);
}

TEST(ProceduralFlatCity, GroundIsTwoKilometresAndBuildingsNeverOverlap) {
    const Encoded& e = defaultScene("flat-city");
    auto ground = boundsOf(e, {"ground"});
    ASSERT_EQ(ground.size(), 1u);
    EXPECT_NEAR(ground[0].second.max[0] - ground[0].second.min[0], 2000.0, 1.0);
    EXPECT_NEAR(ground[0].second.max[2] - ground[0].second.min[2], 2000.0, 1.0);
    auto buildings = boundsOf(e, {"building-"});
    std::sort(buildings.begin(), buildings.end(),
              [](const auto& a, const auto& b) { return a.second.min[0] < b.second.min[0]; });
    for (size_t i = 0; i < buildings.size(); ++i) {
        const Aabb& a = buildings[i].second;
        EXPECT_NEAR(a.min[1], 0.0, 1e-4) << buildings[i].first << " stands on the ground";
        for (size_t k = i + 1; k < buildings.size(); ++k) {
            const Aabb& b = buildings[k].second;
            if (b.min[0] >= a.max[0]) break; // sorted by min x: no later box overlaps in x
            bool overlap = a.min[2] < b.max[2] && b.min[2] < a.max[2];
            EXPECT_FALSE(overlap) << buildings[i].first << " and " << buildings[k].first;
        }
    }
}

TEST(ProceduralFlatCity, WithoutInstancingTheSameTrianglesAreStoredPerBuilding) {
    assets::FlatCityOptions o;
    o.targetTriangles = 60000;
    Document instanced = assets::buildFlatCity(o);
    o.instancing = false;
    Document unique = assets::buildFlatCity(o);
    Encoded e = encodeAndCheck(unique);
    EXPECT_EQ(e.stats.renderedTriangles, assets::gltf::countRenderedTriangles(instanced));
    EXPECT_EQ(e.stats.uniqueTriangles, e.stats.renderedTriangles);
}

// --- lamp-room --------------------------------------------------------------------------------

// Where the ray from `light` through `p` meets the plane axis = value (p between them).
Vec3 projectFrom(Vec3 light, Vec3 p, int axis, double value) {
    const double t = (value - light[size_t(axis)]) / (p[size_t(axis)] - light[size_t(axis)]);
    return {light[0] + (p[0] - light[0]) * t, light[1] + (p[1] - light[1]) * t,
            light[2] + (p[2] - light[2]) * t};
}

TEST(ProceduralLampRoom, OneSpotOnePointNoSunAndTheirShadowsInView) {
    const Encoded& e = defaultScene("lamp-room");
    ASSERT_FALSE(e.world.empty());
    // Exactly one spot and one point light, both with a finite range; no directional light.
    const nlohmann::json& lights = e.glb.json["extensions"]["KHR_lights_punctual"]["lights"];
    ASSERT_EQ(lights.size(), 2u);
    EXPECT_EQ(lights[0]["type"], "spot");
    EXPECT_EQ(lights[1]["type"], "point");
    EXPECT_EQ(test::findNode(e.glb, "sun"), -1);
    const double inner = lights[0]["spot"]["innerConeAngle"].get<double>() * kRadToDeg;
    const double outer = lights[0]["spot"]["outerConeAngle"].get<double>() * kRadToDeg;
    EXPECT_NEAR(inner, 25.0, 1e-3);
    EXPECT_NEAR(outer, 38.0, 1e-3);
    for (const nlohmann::json& l : lights)
        EXPECT_GT(l.value("range", 0.0), 0.0) << l;

    // The room is closed: six faces spanning 8 x 3 x 6 m, the camera and both lights inside.
    const int room = test::findNode(e.glb, "room");
    ASSERT_GE(room, 0);
    const Aabb box = test::worldBounds(e.glb, e.world, size_t(room));
    EXPECT_EQ(box.min, (Vec3{-4, 0, -3}));
    EXPECT_EQ(box.max, (Vec3{4, 3, 3}));
    EXPECT_EQ(e.glb.json["meshes"][nodeJson(e, room)["mesh"].get<size_t>()]["primitives"].size(),
              6u);
    auto inside = [&](Vec3 p) {
        for (int a = 0; a < 3; ++a)
            if (!(p[size_t(a)] > box.min[size_t(a)] && p[size_t(a)] < box.max[size_t(a)]))
                return false;
        return true;
    };
    const int cam = test::findNode(e.glb, "corner-camera"),
              spot = test::findNode(e.glb, "spot-lamp"), bulb = test::findNode(e.glb, "bulb");
    ASSERT_GE(cam, 0);
    ASSERT_GE(spot, 0);
    ASSERT_GE(bulb, 0);
    EXPECT_EQ(nodeJson(e, spot)["extensions"]["KHR_lights_punctual"]["light"], 0);
    EXPECT_EQ(nodeJson(e, bulb)["extensions"]["KHR_lights_punctual"]["light"], 1);
    const Vec3 eye = test::transformPoint(e.world[size_t(cam)], {0, 0, 0});
    const Vec3 spotAt = test::transformPoint(e.world[size_t(spot)], {0, 0, 0});
    const Vec3 bulbAt = test::transformPoint(e.world[size_t(bulb)], {0, 0, 0});
    EXPECT_TRUE(inside(eye));
    EXPECT_TRUE(inside(spotAt));
    EXPECT_TRUE(inside(bulbAt));

    // Shadows the camera sees — in its frustum and not hidden behind a caster: some of the
    // crate's top corners cast on the floor by each light (inside the spot's full beam for the
    // spot), and the pillar cast on the back wall by the bulb.
    const Frustum view = frustumOf(e, cam);
    const auto casters = boundsOf(e, {"crate", "tall-box", "pillar", "table"});
    ASSERT_EQ(casters.size(), 4u);
    auto seen = [&](Vec3 q) {
        if (!view.contains(q)) return false;
        const Vec3 d{q[0] - eye[0], q[1] - eye[1], q[2] - eye[2]};
        for (const auto& [name, b] : casters)
            if (test::rayHitsBox(eye, d, b, 0.0, 0.999)) return false;
        return true;
    };
    const Vec3 axis = test::transformDirection(e.world[size_t(spot)], {0, 0, -1});
    const double axisLength = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    EXPECT_LT(axis[1] / axisLength, -0.5) << "the spot points down";
    auto degreesFromAxis = [&](Vec3 q) {
        const Vec3 v{q[0] - spotAt[0], q[1] - spotAt[1], q[2] - spotAt[2]};
        const double cosine = (v[0] * axis[0] + v[1] * axis[1] + v[2] * axis[2]) /
                              (axisLength * std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
        return std::acos(cosine) * kRadToDeg;
    };
    const int crate = test::findNode(e.glb, "crate"), pillar = test::findNode(e.glb, "pillar");
    ASSERT_GE(crate, 0);
    ASSERT_GE(pillar, 0);
    const Aabb c = test::worldBounds(e.glb, e.world, size_t(crate));
    for (Vec3 light : {spotAt, bulbAt}) {
        int visible = 0;
        for (double x : {c.min[0], c.max[0]})
            for (double z : {c.min[2], c.max[2]}) {
                const Vec3 shadow = projectFrom(light, {x, c.max[1], z}, 1, 0.0);
                visible += inside({shadow[0], 0.5, shadow[2]}) && seen(shadow) &&
                           (light != spotAt || degreesFromAxis(shadow) < inner);
            }
        EXPECT_GE(visible, 1) << (light == spotAt ? "spot" : "bulb");
    }
    const Aabb p = test::worldBounds(e.glb, e.world, size_t(pillar));
    const Vec3 onWall =
        projectFrom(bulbAt, {(p.min[0] + p.max[0]) / 2, 2.0, (p.min[2] + p.max[2]) / 2}, 2, -3.0);
    EXPECT_GT(onWall[1], 0.0);
    EXPECT_LT(onWall[1], 3.0);
    EXPECT_GT(onWall[0], -4.0);
    EXPECT_TRUE(seen(onWall));
}

// --- box-room ---------------------------------------------------------------------------------

TEST(ProceduralBoxRoom, MatchesTheBundledBoxRoomLayout) {
    const Encoded& e = defaultScene("box-room");
    // Same bounds as the .pnb box room built by box_room.cpp.
    SceneBuilder builder;
    assets::buildBoxRoom(builder);
    const pnb::Aabb& expected = builder.scene.info.bounds;
    Aabb got;
    for (const auto& [name, box] : boundsOf(e, {""})) {
        got.grow(box.min);
        got.grow(box.max);
    }
    EXPECT_NEAR(got.min[0], expected.min.x, 1e-5);
    EXPECT_NEAR(got.min[1], expected.min.y, 1e-5);
    EXPECT_NEAR(got.min[2], expected.min.z, 1e-5);
    EXPECT_NEAR(got.max[0], expected.max.x, 1e-5);
    EXPECT_NEAR(got.max[1], expected.max.y, 1e-5);
    EXPECT_NEAR(got.max[2], expected.max.z, 1e-5);
    EXPECT_EQ(e.stats.renderedTriangles, 36u); // 5 walls, 2 boxes of 6 faces, 1 pane

    std::map<std::string, nlohmann::json> materials;
    for (const auto& m : e.glb.json["materials"])
        materials[m["name"]] = m;
    ASSERT_TRUE(materials.count("red-wall") && materials.count("green-wall") &&
                materials.count("white-wall") && materials.count("tinted-glass"));
    const auto& glass = materials["tinted-glass"];
    EXPECT_EQ(glass["alphaMode"], "BLEND");
    EXPECT_EQ(glass["doubleSided"], true);
    EXPECT_LT(glass["pbrMetallicRoughness"]["baseColorFactor"][3].get<double>(), 1.0);
    EXPECT_TRUE(materials["checker-floor"]["pbrMetallicRoughness"].contains("baseColorTexture"));

    std::multiset<std::string> lightTypes;
    for (const auto& l : e.glb.json["extensions"]["KHR_lights_punctual"]["lights"])
        lightTypes.insert(l["type"].get<std::string>());
    EXPECT_EQ(lightTypes, (std::multiset<std::string>{"directional", "point"}));
    // The sun shines down and into the room through the open +Z side.
    Vec3 d = sunDirection(e);
    EXPECT_LT(d[1], -0.5);
    EXPECT_LT(d[2], -0.2);
}

// --- terrain ----------------------------------------------------------------------------------

TEST(ProceduralTerrain, GridCameraAndFarPlane) {
    const Encoded& e = defaultScene("terrain");
    const uint64_t grid = 2ull * 512 * 512;
    EXPECT_GE(e.stats.renderedTriangles, grid);
    EXPECT_LT(e.stats.renderedTriangles, grid + 5000);
    const int cam = test::findNode(e.glb, "ground-camera");
    ASSERT_GE(cam, 0);
    const Frustum view = frustumOf(e, cam);
    EXPECT_GE(view.zfar, 5000.0);
    const Vec3 eye = test::transformPoint(e.world[size_t(cam)], {0, 0, 0});
    std::vector<Vec3> ground = worldVertices(e, "terrain-");
    ASSERT_EQ(ground.size(), 8u * 8 * 65 * 65);
    // Near the ground: 2 m above the closest terrain vertex.
    const Vec3* closest = &ground[0];
    double farthestInView = 0;
    for (const Vec3& p : ground) {
        double dx = p[0] - eye[0], dz = p[2] - eye[2];
        if (dx * dx + dz * dz <
            std::pow((*closest)[0] - eye[0], 2) + std::pow((*closest)[2] - eye[2], 2))
            closest = &p;
        if (view.contains(p))
            farthestInView = std::max(farthestInView, std::sqrt(dx * dx + dz * dz));
    }
    EXPECT_NEAR(eye[1] - (*closest)[1], 2.0, 1e-3);
    EXPECT_GT(farthestInView, 4000.0) << "the view reaches kilometres across the terrain";
}

TEST(ProceduralTerrain, OverhangsFloatAboveTheGround) {
    const Encoded& e = defaultScene("terrain");
    std::vector<Vec3> ground = worldVertices(e, "terrain-");
    auto highestUnder = [&](double x0, double z0, double x1, double z1) {
        double h = -1e9;
        for (const Vec3& p : ground)
            if (p[0] >= x0 && p[0] <= x1 && p[2] >= z0 && p[2] <= z1) h = std::max(h, p[1]);
        return h;
    };
    auto lowestUnder = [&](double x0, double z0, double x1, double z1) {
        double h = 1e9;
        for (const Vec3& p : ground)
            if (p[0] >= x0 && p[0] <= x1 && p[2] >= z0 && p[2] <= z1) h = std::min(h, p[1]);
        return h;
    };
    auto slabs = boundsOf(e, {"rock-slab-"});
    EXPECT_EQ(slabs.size(), 6u);
    for (const auto& [name, box] : slabs) {
        double below = highestUnder(box.min[0], box.min[2], box.max[0], box.max[2]);
        EXPECT_GT(box.min[1] - below, 5.0) << name << " must leave a gap under it";
    }
    // Arches: an open gap under the lintel's centre (above the highest ground near it), pillars'
    // feet buried (below the lowest ground near them).
    int arches = 0;
    for (size_t i = 0; i < e.world.size(); ++i) {
        std::string name = e.glb.json["nodes"][i].value("name", "");
        if (name.rfind("rock-arch-", 0) != 0) continue;
        ++arches;
        auto groundAt = [&](Vec3 p) {
            return highestUnder(p[0] - 6, p[2] - 6, p[0] + 6, p[2] + 6);
        };
        Vec3 lintel = test::transformPoint(e.world[i], {0, 30, 0});
        EXPECT_GT(lintel[1] - groundAt(lintel), 5.0) << name;
        for (double side : {-25.0, 25.0}) {
            Vec3 foot = test::transformPoint(e.world[i], {side, -40, 0});
            EXPECT_LT(foot[1],
                      lowestUnder(foot[0] - 6, foot[2] - 6, foot[0] + 6, foot[2] + 6) - 5.0)
                << name;
        }
    }
    EXPECT_EQ(arches, 3);
}

// --- grazing-plane ----------------------------------------------------------------------------

TEST(ProceduralGrazingPlane, SunGrazesAndTheFloatingBoxHovers) {
    const Encoded& e = defaultScene("grazing-plane");
    double elevation = sunElevationDegrees(e);
    EXPECT_GE(elevation, 2.0);
    EXPECT_LE(elevation, 5.0);
    auto plane = boundsOf(e, {"plane"});
    ASSERT_EQ(plane.size(), 1u);
    EXPECT_GE(plane[0].second.max[0] - plane[0].second.min[0], 1900.0);
    EXPECT_EQ(plane[0].second.max[1], 0.0);
    auto floating = boundsOf(e, {"floating-box"});
    ASSERT_EQ(floating.size(), 1u);
    EXPECT_NEAR(floating[0].second.min[1], 0.02, 1e-5);
    auto resting = boundsOf(e, {"resting-boxes", "poles", "thin-wall"});
    for (const auto& [name, box] : resting)
        EXPECT_NEAR(box.min[1], 0.0, 1e-6) << name;
    // The thin poles' shadows are more than 50 m long.
    auto poles = boundsOf(e, {"poles"});
    EXPECT_GT(poles[0].second.max[1] / std::tan(elevation / kRadToDeg), 50.0);
}

// --- load-test (small options: the default is benchmark-sized) ---------------------------------

assets::LoadTestOptions smallLoadTest() {
    assets::LoadTestOptions o;
    o.targetTriangles = 24000;
    o.objects = 6;
    o.materials = 2;
    o.textureSize = 32;
    return o;
}

// Width and height from a PNG's IHDR chunk.
std::pair<uint32_t, uint32_t> pngSize(const ParsedGlb& g, const nlohmann::json& image) {
    const nlohmann::json& v = g.json["bufferViews"][image["bufferView"].get<size_t>()];
    const uint8_t* p = g.bin.data() + v.value("byteOffset", size_t(0)) + 16;
    auto be32 = [](const uint8_t* b) {
        return uint32_t(b[0]) << 24 | uint32_t(b[1]) << 16 | uint32_t(b[2]) << 8 | b[3];
    };
    return {be32(p), be32(p + 4)};
}

TEST(ProceduralLoadTest, SeparateMeshesTexturedMaterialsAndTheTriangleTarget) {
    const assets::LoadTestOptions o = smallLoadTest();
    const Encoded e = encodeAndCheck(assets::buildLoadTest(o));
    ASSERT_FALSE(e.world.empty());
    EXPECT_EQ(e.stats.renderedTriangles, e.stats.uniqueTriangles) << "no instancing";
    EXPECT_NEAR(double(e.stats.renderedTriangles), double(o.targetTriangles),
                0.05 * double(o.targetTriangles));
    const nlohmann::json& j = e.glb.json;
    std::set<size_t> meshes;
    for (const auto& n : j["nodes"])
        if (n.value("name", "").rfind("rock-", 0) == 0) meshes.insert(n["mesh"].get<size_t>());
    EXPECT_EQ(meshes.size(), o.objects) << "one mesh per rock";
    ASSERT_EQ(j["images"].size(), 2 * o.materials);
    for (const auto& im : j["images"])
        EXPECT_EQ(pngSize(e.glb, im), (std::pair{o.textureSize, o.textureSize}));
    ASSERT_EQ(j["materials"].size(), o.materials);
    std::set<int> used;
    for (const auto& m : j["materials"]) {
        used.insert(m["pbrMetallicRoughness"]["baseColorTexture"]["index"].get<int>());
        used.insert(m["normalTexture"]["index"].get<int>());
    }
    EXPECT_EQ(used.size(), 2 * o.materials) << "every texture is used, once";
    for (const auto& mesh : j["meshes"])
        for (const auto& prim : mesh["primitives"])
            EXPECT_TRUE(prim["attributes"].contains("TEXCOORD_0")) << "normal maps need UVs";
    EXPECT_NEAR(sunElevationDegrees(e), 45.0, 1e-3);
}

TEST(ProceduralLoadTest, DeterministicAndSeeded) {
    const std::vector<uint8_t> a = assets::gltf::encodeGlb(assets::buildLoadTest(smallLoadTest()));
    EXPECT_TRUE(a == assets::gltf::encodeGlb(assets::buildLoadTest(smallLoadTest())));
    assets::LoadTestOptions other = smallLoadTest();
    other.seed = 2;
    EXPECT_FALSE(a == assets::gltf::encodeGlb(assets::buildLoadTest(other)));
}

// --- light-field --------------------------------------------------------------------------------

TEST(ProceduralLightField, PointLightsWithRangesAboveTheBoxesAndTheSameGeometryForAnyCount) {
    assets::SceneRequest r;
    r.lights = 64;
    std::optional<Document> many = assets::buildProceduralScene("light-field", r);
    ASSERT_TRUE(many);
    const Encoded e = encodeAndCheck(*many);
    const Encoded& few = defaultScene("light-field");
    const nlohmann::json& lights = e.glb.json["extensions"]["KHR_lights_punctual"]["lights"];
    size_t points = 0;
    for (const auto& l : lights)
        if (l["type"] == "point") {
            ++points;
            EXPECT_GT(l["range"].get<double>(), 0.0);
        }
    EXPECT_EQ(points, 64u);
    EXPECT_EQ(lights.size(), 65u) << "and the sun";
    size_t defaultLights = few.glb.json["extensions"]["KHR_lights_punctual"]["lights"].size();
    EXPECT_EQ(defaultLights, 9u) << "8 point lights by default, and the sun";

    auto boxes = boundsOf(e, {"box-"});
    ASSERT_EQ(boxes.size(), 64u);
    double tallest = 0;
    for (const auto& [name, box] : boxes)
        tallest = std::max(tallest, box.max[1]);
    auto floor = boundsOf(e, {"floor"});
    ASSERT_EQ(floor.size(), 1u);
    const nlohmann::json& nodes = e.glb.json["nodes"];
    for (size_t i = 0; i < nodes.size(); ++i) {
        if (nodes[i].value("name", "").rfind("point-light-", 0) != 0) continue;
        Vec3 p = test::transformPoint(e.world[i], {0, 0, 0});
        EXPECT_GT(p[1], tallest) << "above every box";
        EXPECT_TRUE(p[0] >= floor[0].second.min[0] && p[0] <= floor[0].second.max[0] &&
                    p[2] >= floor[0].second.min[2] && p[2] <= floor[0].second.max[2]);
    }
    // The light count does not move or change the geometry.
    auto fewBoxes = boundsOf(few, {"box-", "floor"});
    auto manyBoxes = boundsOf(e, {"box-", "floor"});
    ASSERT_EQ(fewBoxes.size(), manyBoxes.size());
    for (size_t i = 0; i < fewBoxes.size(); ++i) {
        EXPECT_EQ(fewBoxes[i].first, manyBoxes[i].first);
        EXPECT_EQ(fewBoxes[i].second.min, manyBoxes[i].second.min);
        EXPECT_EQ(fewBoxes[i].second.max, manyBoxes[i].second.max);
    }
}

} // namespace

namespace pnb::assets {
namespace {

// --- Scene transforms (the extremes matrix's inputs) ------------------------------------------

TEST(SceneTransform, WrapsTheRootsAndScalesWhatNodesDoNotReach) {
    gltf::Document doc = buildBoxRoomGltf();
    const size_t nodes = doc.nodes.size();
    std::vector<uint32_t> roots;
    std::vector<bool> child(nodes, false);
    for (const gltf::Node& n : doc.nodes)
        for (uint32_t c : n.children) child[c] = true;
    for (size_t i = 0; i < nodes; ++i)
        if (!child[i]) roots.push_back(uint32_t(i));
    const gltf::Document before = doc;
    SceneTransform t;
    t.unitScale = 1e-3;
    t.origin = {1e7f, 0, -5};
    ASSERT_EQ(applySceneTransform(doc, t), "");
    ASSERT_EQ(doc.nodes.size(), nodes + 1);
    const gltf::Node& root = doc.nodes.back();
    EXPECT_EQ(root.name, "unit-root");
    EXPECT_EQ(root.children, roots);
    EXPECT_EQ(root.scale, (gltf::Float3{1e-3f, 1e-3f, 1e-3f}));
    EXPECT_EQ(root.translation, t.origin);
    for (size_t i = 0; i < doc.cameras.size(); ++i)
        EXPECT_FLOAT_EQ(doc.cameras[i].znear, before.cameras[i].znear * 1e-3f);
    for (size_t i = 0; i < doc.lights.size(); ++i) {
        if (doc.lights[i].type == gltf::LightType::Point) {
            EXPECT_FLOAT_EQ(doc.lights[i].intensity, before.lights[i].intensity * 1e-6f);
        }
    }
    EXPECT_EQ(gltf::validateDocument(doc), "");
}

TEST(SceneTransform, TurnsTheSunAndRejectsBadValuesWithoutChangingTheScene) {
    gltf::Document doc = buildStreetCanyon();
    SceneTransform t;
    t.sunElevationDegrees = 90.0f;
    ASSERT_EQ(applySceneTransform(doc, t), "");
    EXPECT_EQ(doc.nodes.size(), buildStreetCanyon().nodes.size()); // unit scale: no new root
    for (const gltf::Node& n : doc.nodes)
        if (n.name == "sun") {
            gltf::Float3 d = gltf::rotate(n.rotation, {0, 0, -1});
            EXPECT_NEAR(d[1], -1.0f, 1e-6f); // straight down
        }
    t.sunElevationDegrees = 0.5f;
    t.sunAzimuthDegrees = 90.0f;
    ASSERT_EQ(applySceneTransform(doc, t), "");
    for (const gltf::Node& n : doc.nodes)
        if (n.name == "sun") {
            gltf::Float3 d = gltf::rotate(n.rotation, {0, 0, -1});
            EXPECT_NEAR(d[1], -std::sin(0.5 * std::numbers::pi / 180), 1e-6);
            EXPECT_NEAR(d[2], -std::cos(0.5 * std::numbers::pi / 180), 1e-5); // towards -Z
        }

    const gltf::Document unchanged = doc;
    for (SceneTransform bad : {SceneTransform{.unitScale = 0}, SceneTransform{.unitScale = -1},
                               SceneTransform{.sunElevationDegrees = 91.0f},
                               SceneTransform{.cameraNear = 0.0f}}) {
        EXPECT_NE(applySceneTransform(doc, bad), "");
        EXPECT_EQ(doc.nodes.size(), unchanged.nodes.size());
    }
    gltf::Document noSun;
    EXPECT_NE(applySceneTransform(noSun, SceneTransform{.sunElevationDegrees = 10.0f}).find("sun"),
              std::string::npos);
}

} // namespace
} // namespace pnb::assets
