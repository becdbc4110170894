// The window scene (pnb_assets/window_scene.h, issue 43): its analytic expectations are the
// contract's numbers (written out here by hand), and the .glb the generator writes really gives
// them: every path from the floor to a light is traced through the file's own triangles (parsed
// back by glb_check, not taken from the generator), its panes' transmittances multiplied from the
// file's materials and its irradiance computed from the file's lights.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "glb_check.h"
#include "pnb_assets/procedural_scenes.h"
#include "pnb_assets/window_scene.h"

namespace {

using namespace pnb;
using test::Vec3;

Vec3 sub(Vec3 a, Vec3 b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vec3 crossV(Vec3 a, Vec3 b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dotV(Vec3 a, Vec3 b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3 unit(Vec3 v) {
    const double len = std::sqrt(dotV(v, v));
    return {v[0] / len, v[1] / len, v[2] / len};
}

// A world-space triangle of the file and what its material does to light.
struct Triangle {
    Vec3 a, b, c;
    std::string material;
    bool blend = false;
    assets::Rgb transmittance{0, 0, 0}; // colour * (1 - alpha) for BLEND, 0 for opaque
};

// The file parsed back, its triangles in world space, and its two lights.
struct WindowGlb {
    test::ParsedGlb glb;
    std::vector<test::Mat4> world;
    std::vector<Triangle> triangles;
};

const WindowGlb& windowGlb() {
    static const WindowGlb parsed = [] {
        WindowGlb w;
        std::optional<assets::gltf::Document> doc = assets::buildProceduralScene("window", {});
        EXPECT_TRUE(doc.has_value());
        if (!doc) return w;
        EXPECT_EQ(assets::gltf::validateDocument(*doc), "");
        const std::vector<uint8_t> bytes = assets::gltf::encodeGlb(*doc);
        EXPECT_EQ(test::parseGlb(bytes, w.glb), "");
        EXPECT_EQ(test::validateGltf(w.glb), "");
        w.world = test::worldMatrices(w.glb);
        const nlohmann::json& j = w.glb.json;
        for (size_t n = 0; n < j["nodes"].size(); ++n) {
            if (!j["nodes"][n].contains("mesh")) continue;
            for (const auto& prim : j["meshes"][j["nodes"][n]["mesh"].get<size_t>()]["primitives"]) {
                const nlohmann::json& m = j["materials"][prim["material"].get<size_t>()];
                Triangle proto;
                proto.material = m.value("name", "");
                proto.blend = m.value("alphaMode", "OPAQUE") == "BLEND";
                if (proto.blend) {
                    const auto f = m["pbrMetallicRoughness"]["baseColorFactor"];
                    for (size_t c = 0; c < 3; ++c)
                        proto.transmittance[c] = f[c].get<double>() * (1 - f[3].get<double>());
                }
                const std::vector<double> p =
                    test::readAccessor(w.glb, prim["attributes"]["POSITION"]);
                const std::vector<double> idx = test::readAccessor(w.glb, prim["indices"]);
                auto vertex = [&](double i) {
                    const size_t k = size_t(i) * 3;
                    return test::transformPoint(w.world[n], {p[k], p[k + 1], p[k + 2]});
                };
                for (size_t i = 0; i + 2 < idx.size(); i += 3) {
                    Triangle t = proto;
                    t.a = vertex(idx[i]);
                    t.b = vertex(idx[i + 1]);
                    t.c = vertex(idx[i + 2]);
                    w.triangles.push_back(t);
                }
            }
        }
        return w;
    }();
    return parsed;
}

// Möller–Trumbore, both faces: whether the segment from `from` to `to` crosses the triangle
// strictly between its ends.
bool segmentHits(Vec3 from, Vec3 to, const Triangle& t) {
    const Vec3 d = sub(to, from), e1 = sub(t.b, t.a), e2 = sub(t.c, t.a);
    const Vec3 p = crossV(d, e2);
    const double det = dotV(e1, p);
    if (std::fabs(det) < 1e-12) return false;
    const Vec3 s = sub(from, t.a);
    const double u = dotV(s, p) / det;
    if (u < 0 || u > 1) return false;
    const Vec3 q = crossV(s, e1);
    const double v = dotV(d, q) / det;
    if (v < 0 || u + v > 1) return false;
    const double along = dotV(e2, q) / det;
    return along > 1e-9 && along < 1 - 1e-9;
}

// What the file's geometry does to the path from `from` to `to`: opaque visibility, the product
// of the blended surfaces' transmittances and the names of those surfaces (a pane is one quad, two
// triangles: a path through its diagonal counts once).
struct Path {
    double visibility = 1;
    assets::Rgb transmittance{1, 1, 1};
    std::set<std::string> panes;
};

Path tracePath(Vec3 from, Vec3 to) {
    Path path;
    for (const Triangle& t : windowGlb().triangles) {
        if (!segmentHits(from, to, t)) continue;
        if (!t.blend) {
            path.visibility = 0;
            continue;
        }
        if (!path.panes.insert(t.material).second) continue;
        for (size_t c = 0; c < 3; ++c)
            path.transmittance[c] *= t.transmittance[c];
    }
    return path;
}

const nlohmann::json& lightsJson() {
    return windowGlb().glb.json["extensions"]["KHR_lights_punctual"]["lights"];
}

size_t nodeOf(const std::string& name) {
    const int n = test::findNode(windowGlb().glb, name);
    EXPECT_GE(n, 0) << name;
    return size_t(std::max(n, 0));
}

// The light's position (the spot's node) and the direction it shines along (its node's -Z).
Vec3 lightPosition(const std::string& node) {
    return test::transformPoint(windowGlb().world[nodeOf(node)], {0, 0, 0});
}
Vec3 lightAxis(const std::string& node) {
    return unit(test::transformDirection(windowGlb().world[nodeOf(node)], {0, 0, -1}));
}

// Where the path from floor point `p` to the probe's light ends: the spot, or 100 m up-sun.
Vec3 lightEnd(const assets::WindowProbe& probe, Vec3 p) {
    if (probe.lightNode == "spot-lamp") return lightPosition("spot-lamp");
    const Vec3 d = lightAxis("sun");
    return {p[0] - d[0] * 100, p[1] - d[1] * 100, p[2] - d[2] * 100};
}

// A floor point lifted off the floor slab's top face, so the path does not start on it.
Vec3 onFloor(double x, double z) {
    return {x, 1e-6, z};
}

// The unshadowed irradiance of a floor point (normal +Y) from the file's light `index`.
double fileIrradiance(size_t index, Vec3 p) {
    const nlohmann::json& l = lightsJson()[index];
    const double intensity = l.value("intensity", 1.0);
    if (l["type"] == "directional") return intensity * std::max(0.0, -lightAxis("sun")[1]);
    const Vec3 toLight = sub(lightPosition("spot-lamp"), p);
    const double d2 = dotV(toLight, toLight), range = l["range"].get<double>();
    const Vec3 dir = unit(toLight);
    const double window = std::pow(std::clamp(1 - (d2 / (range * range)) * (d2 / (range * range)), 0.0, 1.0), 2);
    const double cosInner = std::cos(l["spot"]["innerConeAngle"].get<double>());
    const double cosOuter = std::cos(l["spot"]["outerConeAngle"].get<double>());
    const double cosAxis = -dotV(dir, lightAxis("spot-lamp"));
    const double cone =
        std::pow(std::clamp((cosAxis - cosOuter) / (cosInner - cosOuter), 0.0, 1.0), 2);
    return intensity * std::max(0.0, dir[1]) / d2 * window * cone;
}

const assets::WindowProbe& probe(const std::string& name) {
    static const std::vector<assets::WindowProbe> probes = assets::windowSceneProbes();
    for (const assets::WindowProbe& p : probes)
        if (p.name == name) return p;
    ADD_FAILURE() << "no probe " << name;
    return probes.front();
}

void expectRgb(const assets::Rgb& actual, const assets::Rgb& expected, double tolerance,
               const std::string& what) {
    for (size_t c = 0; c < 3; ++c)
        EXPECT_NEAR(actual[c], expected[c], tolerance) << what << " channel " << c;
}

// --- The expectations: issue 43's contract, by hand ---------------------------------------------

TEST(WindowScene, ProbesCarryTheContractsNumbers) {
    const std::vector<assets::WindowProbe> probes = assets::windowSceneProbes();
    std::vector<std::string> names;
    for (const auto& p : probes)
        names.emplace_back(p.name);
    EXPECT_EQ(names, (std::vector<std::string>{"sun-pane", "sun-roof-shadow", "spot-clear",
                                               "spot-green", "spot-both", "spot-blue"}));

    // The sun: 3 lux at 53.13 degrees (cos 0.8) through (0.9, 0.3, 0.1) at alpha 0.5.
    const auto& sun = probe("sun-pane");
    EXPECT_EQ(sun.lightIndex, 0u);
    EXPECT_EQ(sun.position, (std::array<double, 3>{-3, 0, 0}));
    EXPECT_EQ(sun.panes, (std::vector<std::string_view>{"sun-pane"}));
    EXPECT_EQ(sun.opaqueVisibility, 1.0);
    expectRgb(sun.transmittance, {0.45, 0.15, 0.05}, 1e-12, "sun-pane T");
    EXPECT_NEAR(sun.unshadowedIrradiance, 2.4, 1e-12);
    expectRgb(sun.irradiance, {1.08, 0.36, 0.12}, 1e-12, "sun-pane E");
    const auto& roofShadow = probe("sun-roof-shadow");
    EXPECT_EQ(roofShadow.opaqueVisibility, 0.0);
    expectRgb(roofShadow.colorVisibility, {0, 0, 0}, 0, "sun-roof-shadow V");
    expectRgb(roofShadow.irradiance, {0, 0, 0}, 0, "sun-roof-shadow E");

    // The spot: 20 cd at (3, 2.5, 0) pointing down; E = 20 cos / d^2 * (1 - (d^2/400)^2)^2,
    // green pane (0.2, 0.8, 0.3) at alpha 0.4, blue (0.3, 0.3, 0.9) at alpha 0.6.
    struct Spot {
        const char* name;
        std::vector<std::string_view> panes;
        assets::Rgb t;
        double e; // unshadowed
    };
    const Spot spots[] = {
        {"spot-clear", {}, {1, 1, 1}, 1.910225711921135},                 // d^2 8.81
        {"spot-green", {"green-pane"}, {0.12, 0.48, 0.18}, 2.559632421759977}, // d^2 7.25
        {"spot-both", {"green-pane", "blue-pane"}, {0.0144, 0.0576, 0.0648}, 3.1984376907348633},
        {"spot-blue", {"blue-pane"}, {0.12, 0.12, 0.36}, 2.559632421759977},
    };
    for (const Spot& s : spots) {
        const auto& p = probe(s.name);
        EXPECT_EQ(p.lightIndex, 1u) << s.name;
        EXPECT_EQ(p.lightNode, "spot-lamp") << s.name;
        EXPECT_EQ(p.panes, s.panes) << s.name;
        EXPECT_EQ(p.opaqueVisibility, 1.0) << s.name;
        expectRgb(p.transmittance, s.t, 1e-12, std::string(s.name) + " T");
        EXPECT_NEAR(p.unshadowedIrradiance, s.e, 1e-9) << s.name;
        expectRgb(p.irradiance, {s.e * s.t[0], s.e * s.t[1], s.e * s.t[2]}, 1e-9,
                  std::string(s.name) + " E");
    }
}

// --- The file gives them ------------------------------------------------------------------------

TEST(WindowScene, FileHasTheSunTheSpotAndThreeBlendedPanes) {
    const WindowGlb& w = windowGlb();
    ASSERT_FALSE(w.triangles.empty());
    const nlohmann::json& lights = lightsJson();
    ASSERT_EQ(lights.size(), 2u);
    EXPECT_EQ(lights[0]["type"], "directional");
    EXPECT_EQ(lights[1]["type"], "spot");
    EXPECT_EQ(w.glb.json["nodes"][nodeOf("sun")]["extensions"]["KHR_lights_punctual"]["light"], 0);
    EXPECT_EQ(w.glb.json["nodes"][nodeOf("spot-lamp")]["extensions"]["KHR_lights_punctual"]["light"],
              1);
    EXPECT_NEAR(lightAxis("spot-lamp")[1], -1.0, 1e-6) << "the spot points straight down";

    // Each pane: one double-sided BLEND quad, horizontal, with the layout's colour and alpha.
    for (const assets::WindowPane& pane : assets::windowScenePanes()) {
        int triangles = 0;
        for (const Triangle& t : w.triangles) {
            if (t.material != pane.name) continue;
            ++triangles;
            EXPECT_TRUE(t.blend) << pane.name;
            for (const Vec3& v : {t.a, t.b, t.c})
                EXPECT_NEAR(v[1], pane.height, 1e-6) << pane.name;
            expectRgb(t.transmittance, assets::paneTransmittance(pane), 1e-6,
                      std::string(pane.name));
        }
        EXPECT_EQ(triangles, 2) << pane.name;
        for (const auto& m : w.glb.json["materials"])
            if (m.value("name", "") == pane.name) {
                EXPECT_TRUE(m.value("doubleSided", false)) << pane.name;
            }
    }
    // Everything else is opaque.
    for (const Triangle& t : w.triangles)
        if (t.material.find("-pane") == std::string::npos) {
            EXPECT_FALSE(t.blend) << t.material;
        }
}

TEST(WindowScene, EveryProbesPathThroughTheFileMatchesItsExpectation) {
    for (const assets::WindowProbe& p : assets::windowSceneProbes()) {
        const Vec3 from = onFloor(p.position[0], p.position[2]);
        const Path path = tracePath(from, lightEnd(p, from));
        EXPECT_EQ(path.visibility, p.opaqueVisibility) << p.name;
        std::set<std::string> expectedPanes(p.panes.begin(), p.panes.end());
        EXPECT_EQ(path.panes, expectedPanes) << p.name;
        expectRgb(path.transmittance, p.transmittance, 1e-6, std::string(p.name) + " T");
        const double e = fileIrradiance(p.lightIndex, from);
        EXPECT_NEAR(e, p.unshadowedIrradiance, 1e-5 * p.unshadowedIrradiance) << p.name;
        for (size_t c = 0; c < 3; ++c)
            EXPECT_NEAR(e * path.visibility * path.transmittance[c], p.irradiance[c], 1e-5)
                << p.name << " channel " << c;
    }
}

// The sun reaches the floor exactly on the patch x in [-4, -2], z in [-1, 1], and there only
// through the roof pane: no wall or roof edge cuts into it, nothing else lets it in.
TEST(WindowScene, SunLightsThePatchThroughThePaneAndNothingElse) {
    const assets::WindowSceneLayout& l = assets::windowSceneLayout();
    const assets::WindowProbe& sun = probe("sun-pane");
    int lit = 0;
    for (double x = l.x0 + 0.05; x < l.x1; x += 0.1)
        for (double z = l.z0 + 0.05; z < l.z1; z += 0.1) {
            const bool inside = x > l.patchX0 && x < l.patchX1 && z > l.patchZ0 && z < l.patchZ1;
            const Vec3 from = onFloor(x, z);
            const Path path = tracePath(from, lightEnd(sun, from));
            if (inside) {
                ++lit;
                EXPECT_EQ(path.visibility, 1.0) << x << ", " << z;
                EXPECT_EQ(path.panes, std::set<std::string>{"sun-pane"}) << x << ", " << z;
            } else {
                EXPECT_EQ(path.visibility, 0.0) << x << ", " << z << " is lit outside the patch";
            }
        }
    EXPECT_EQ(lit, 20 * 20);
}

// Under the spot, the floor is behind no pane, the green one, both or the blue one, in the bands
// the layout states; nothing opaque is in the way within the spot's inner cone.
TEST(WindowScene, SpotFloorIsBehindNoneOneOrBothPanes) {
    const assets::WindowSceneLayout& l = assets::windowSceneLayout();
    const Vec3 spot = lightPosition("spot-lamp");
    const double tanInner = std::tan(l.spotInnerDegrees * std::numbers::pi / 180);
    std::map<std::set<std::string>, int> regions;
    for (double x = 0.15; x < l.x1; x += 0.1)
        for (double z = -2.95; z < 3; z += 0.1) {
            const double r = std::hypot(x - spot[0], z - spot[2]);
            if (r > spot[1] * tanInner) continue; // outside the inner cone
            const bool inZ = z > l.paneFloorZ0 && z < l.paneFloorZ1;
            std::set<std::string> expected;
            if (inZ && x > l.greenFloorX0 && x < l.greenFloorX1) expected.insert("green-pane");
            if (inZ && x > l.blueFloorX0 && x < l.blueFloorX1) expected.insert("blue-pane");
            const Path path = tracePath(onFloor(x, z), spot);
            EXPECT_EQ(path.visibility, 1.0) << x << ", " << z;
            EXPECT_EQ(path.panes, expected) << x << ", " << z;
            ++regions[expected];
        }
    // Each of the four regions is a good size (at 0.1 m spacing: 0.01 m^2 a sample).
    EXPECT_EQ(regions.size(), 4u);
    for (const auto& [panes, samples] : regions)
        EXPECT_GE(samples, 100) << panes.size() << " panes";
}

// The camera sees every probe: inside its frustum, and nothing opaque between (it may look
// through a pane).
TEST(WindowScene, CameraSeesEveryProbe) {
    const WindowGlb& w = windowGlb();
    const size_t cam = nodeOf("window-camera");
    const nlohmann::json& persp =
        w.glb.json["cameras"][w.glb.json["nodes"][cam]["camera"].get<size_t>()]["perspective"];
    const test::Frustum view{w.world[cam], persp["yfov"].get<double>(),
                             persp["aspectRatio"].get<double>(), persp["znear"].get<double>(),
                             persp.value("zfar", 1e9)};
    const Vec3 eye = test::transformPoint(w.world[cam], {0, 0, 0});
    for (const assets::WindowProbe& p : assets::windowSceneProbes()) {
        const Vec3 at = onFloor(p.position[0], p.position[2]);
        EXPECT_TRUE(view.contains(at)) << p.name;
        EXPECT_EQ(tracePath(eye, at).visibility, 1.0) << p.name << " is hidden from the camera";
    }
}

} // namespace
