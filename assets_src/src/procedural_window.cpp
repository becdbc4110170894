// assets_src/src/procedural_window.cpp — the window scene (pnb_assets/window_scene.h: issue 43's
// light through glass) and the analytic values at its named floor points. The generator and the
// expectations read the same WindowSceneLayout, so a change to the layout moves both.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "pnb_assets/window_scene.h"
#include "procedural_scenes_internal.h"

namespace pnb::assets {

using namespace procedural_detail;

namespace {

Float3 toFloat3(const std::array<double, 3>& v) {
    return {float(v[0]), float(v[1]), float(v[2])};
}

// How far a ray from the floor towards the sun has moved horizontally (x, z) on reaching height y.
std::array<double, 2> sunOffsetAt(const WindowSceneLayout& l, double y) {
    const double up = -l.sunTravel[1];
    return {-l.sunTravel[0] * y / up, -l.sunTravel[2] * y / up};
}

// The roof hole (x0, x1, z0, z1) through which the sun lights exactly the floor patch: a floor
// point is lit when its ray towards the sun is inside the hole at both faces of the roof slab
// (y = height and height + wall), so the hole is the patch grown by the smaller offset on the low
// side and the larger one on the high side.
std::array<double, 4> roofHole(const WindowSceneLayout& l) {
    const auto bottom = sunOffsetAt(l, l.height), top = sunOffsetAt(l, l.height + l.wall);
    return {l.patchX0 + std::min(bottom[0], top[0]), l.patchX1 + std::max(bottom[0], top[0]),
            l.patchZ0 + std::min(bottom[1], top[1]), l.patchZ1 + std::max(bottom[1], top[1])};
}

// A pane at `height` under the spot casting its shadow on the floor region x0..x1, z0..z1: the
// region scaled towards the point under the spot by (spot height - height) / spot height.
WindowPane paneUnderSpot(const WindowSceneLayout& l, std::string_view name, Rgb color, double alpha,
                         double height, double floorX0, double floorX1) {
    const auto& s = l.spotPosition;
    const double k = (s[1] - height) / s[1];
    return {name,
            color,
            alpha,
            height,
            s[0] + (floorX0 - s[0]) * k,
            s[0] + (floorX1 - s[0]) * k,
            s[2] + (l.paneFloorZ0 - s[2]) * k,
            s[2] + (l.paneFloorZ1 - s[2]) * k};
}

// Whether the segment from floor point `p` to `light` crosses pane `pane` (strictly inside it).
bool segmentCrossesPane(const std::array<double, 3>& p, const std::array<double, 3>& light,
                        const WindowPane& pane) {
    if ((pane.height - p[1]) * (pane.height - light[1]) >= 0) return false;
    const double t = (pane.height - p[1]) / (light[1] - p[1]);
    const double x = p[0] + (light[0] - p[0]) * t, z = p[2] + (light[2] - p[2]) * t;
    return x > pane.x0 && x < pane.x1 && z > pane.z0 && z < pane.z1;
}

// glTF's range window (shaders/include/lights.glsl rangeAttenuation without the 1/d^2).
double rangeWindow(double distanceSquared, double range) {
    const double r = distanceSquared / (range * range);
    const double w = std::clamp(1.0 - r * r, 0.0, 1.0);
    return w * w;
}

} // namespace

Rgb paneTransmittance(const WindowPane& pane) {
    return {pane.color[0] * (1 - pane.alpha), pane.color[1] * (1 - pane.alpha),
            pane.color[2] * (1 - pane.alpha)};
}

const WindowSceneLayout& windowSceneLayout() {
    static const WindowSceneLayout layout;
    return layout;
}

std::vector<WindowPane> windowScenePanes() {
    const WindowSceneLayout& l = windowSceneLayout();
    const auto hole = roofHole(l);
    return {
        {"sun-pane", l.sunPaneColor, l.sunPaneAlpha, l.roofPaneHeight, hole[0], hole[1], hole[2],
         hole[3]},
        paneUnderSpot(l, "green-pane", l.greenColor, l.greenAlpha, l.greenHeight, l.greenFloorX0,
                      l.greenFloorX1),
        paneUnderSpot(l, "blue-pane", l.blueColor, l.blueAlpha, l.blueHeight, l.blueFloorX0,
                      l.blueFloorX1),
    };
}

std::vector<WindowProbe> windowSceneProbes() {
    const WindowSceneLayout& l = windowSceneLayout();
    const std::vector<WindowPane> panes = windowScenePanes();
    const double sunCos = -l.sunTravel[1];
    struct Spec {
        std::string_view name;
        bool sun;
        std::array<double, 3> position;
    };
    const Spec specs[] = {
        {"sun-pane", true, {(l.patchX0 + l.patchX1) / 2, 0, (l.patchZ0 + l.patchZ1) / 2}},
        {"sun-roof-shadow", true, {(l.patchX0 + l.patchX1) / 2, 0, l.patchZ1 + 1.5}},
        {"spot-clear", false, {l.spotPosition[0], 0, l.paneFloorZ1 + 0.4}},
        {"spot-green", false, {(l.greenFloorX0 + l.blueFloorX0) / 2, 0, 0}},
        {"spot-both", false, {(l.blueFloorX0 + l.greenFloorX1) / 2, 0, 0}},
        {"spot-blue", false, {(l.greenFloorX1 + l.blueFloorX1) / 2, 0, 0}},
    };
    std::vector<WindowProbe> probes;
    for (const Spec& s : specs) {
        WindowProbe p{s.name, s.sun ? "sun" : "spot-lamp", s.sun ? 0u : 1u, s.position, {}, 1,
                      {1, 1, 1}, {}, 0, {}};
        // Where the path to the light leaves the room: a point far up-sun, or the spot itself.
        std::array<double, 3> light = l.spotPosition;
        if (s.sun) {
            const double far = 100.0;
            for (int k = 0; k < 3; ++k)
                light[size_t(k)] = s.position[size_t(k)] - l.sunTravel[size_t(k)] * far;
            // The roof is opaque but for the hole (the pane's extent), sides included.
            const auto bottom = sunOffsetAt(l, l.height), top = sunOffsetAt(l, l.height + l.wall);
            const WindowPane& roof = panes[0];
            for (const auto& o : {bottom, top}) {
                const double x = s.position[0] + o[0], z = s.position[2] + o[1];
                if (!(x > roof.x0 && x < roof.x1 && z > roof.z0 && z < roof.z1))
                    p.opaqueVisibility = 0;
            }
            p.unshadowedIrradiance = l.sunIntensity * sunCos;
        } else {
            std::array<double, 3> toLight{};
            double d2 = 0;
            for (int k = 0; k < 3; ++k) {
                toLight[size_t(k)] = l.spotPosition[size_t(k)] - s.position[size_t(k)];
                d2 += toLight[size_t(k)] * toLight[size_t(k)];
            }
            const double cosTheta = toLight[1] / std::sqrt(d2); // floor normal +Y; also the
                                                                // cosine from the spot's axis
            const double cosInner = std::cos(l.spotInnerDegrees * std::numbers::pi / 180);
            const double cosOuter = std::cos(l.spotOuterDegrees * std::numbers::pi / 180);
            const double t = std::clamp((cosTheta - cosOuter) / (cosInner - cosOuter), 0.0, 1.0);
            p.unshadowedIrradiance =
                l.spotIntensity * cosTheta / d2 * rangeWindow(d2, l.spotRange) * t * t;
        }
        for (const WindowPane& pane : panes) {
            if (!segmentCrossesPane(s.position, light, pane)) continue;
            p.panes.push_back(pane.name);
            const Rgb t = paneTransmittance(pane);
            for (int c = 0; c < 3; ++c)
                p.transmittance[size_t(c)] *= t[size_t(c)];
        }
        for (int c = 0; c < 3; ++c) {
            p.colorVisibility[size_t(c)] = p.opaqueVisibility * p.transmittance[size_t(c)];
            p.irradiance[size_t(c)] = p.unshadowedIrradiance * p.colorVisibility[size_t(c)];
        }
        probes.push_back(std::move(p));
    }
    return probes;
}

gltf::Document buildWindowScene() {
    const WindowSceneLayout& l = windowSceneLayout();
    Document doc;
    doc.sceneName = "window";
    const uint32_t plaster = addMaterial(doc, makeMaterial("plaster", {0.75f, 0.75f, 0.72f}, 0.9f));
    const uint32_t floorMaterial =
        addMaterial(doc, makeMaterial("floor", {0.7f, 0.7f, 0.7f}, 0.8f));
    const uint32_t partitionMaterial =
        addMaterial(doc, makeMaterial("partition", {0.55f, 0.5f, 0.45f}, 0.9f));

    auto boxMesh = [&](std::string name, uint32_t material, const std::vector<Box>& parts) {
        return addMesh(doc, solidBoxesMesh(std::move(name), material, parts));
    };
    const auto f = [](double v) { return float(v); };
    const float x0 = f(l.x0), x1 = f(l.x1), z0 = f(l.z0), z1 = f(l.z1), h = f(l.height),
                w = f(l.wall);
    // Closed slabs outside the interior: the sun sees the roof's outer faces and the room's
    // inner faces are the slabs' own, whatever faces a renderer culls.
    const std::vector<Box> walls = {
        {{x0 - w, 0, z0 - w}, {x1 + w, h, z0}}, // back
        {{x0 - w, 0, z1}, {x1 + w, h, z1 + w}}, // front
        {{x0 - w, 0, z0}, {x0, h, z1}},         // left (bay A)
        {{x1, 0, z0}, {x1 + w, h, z1}},         // right (bay B)
    };
    const auto hole = roofHole(l);
    const float hx0 = f(hole[0]), hx1 = f(hole[1]), hz0 = f(hole[2]), hz1 = f(hole[3]);
    const std::vector<Box> roof = {
        {{x0 - w, h, z0 - w}, {hx0, h + w, z1 + w}},
        {{hx1, h, z0 - w}, {x1 + w, h + w, z1 + w}},
        {{hx0, h, z0 - w}, {hx1, h + w, hz0}},
        {{hx0, h, hz1}, {hx1, h + w, z1 + w}},
    };
    Node root;
    root.name = "window";
    const uint32_t rootNode = addNode(doc, std::move(root));
    std::vector<uint32_t> children = {
        addNode(doc, meshNode("floor", boxMesh("floor", floorMaterial,
                                               {{{x0 - w, -w, z0 - w}, {x1 + w, 0, z1 + w}}}))),
        addNode(doc, meshNode("walls", boxMesh("walls", plaster, walls))),
        addNode(doc, meshNode("roof", boxMesh("roof", plaster, roof))),
        addNode(doc, meshNode("partition",
                              boxMesh("partition", partitionMaterial,
                                      {{{-0.1f, 0, z0}, {0.1f, h, f(l.partitionZ)}}}))),
    };

    // Each pane: one double-sided BLEND quad facing up (u x v = +Y).
    for (const WindowPane& pane : windowScenePanes()) {
        Material m = makeMaterial(std::string(pane.name),
                                  {f(pane.color[0]), f(pane.color[1]), f(pane.color[2])}, 0.05f);
        m.baseColorFactor[3] = f(pane.alpha);
        m.alphaMode = gltf::AlphaMode::Blend;
        m.doubleSided = true;
        Mesh mesh;
        mesh.name = std::string(pane.name);
        mesh.primitives.resize(1);
        mesh.primitives[0].material = addMaterial(doc, std::move(m));
        const float y = f(pane.height);
        addGrid(mesh.primitives[0], {f(pane.x0), y, f(pane.z0)}, {0, 0, f(pane.z1 - pane.z0)},
                {f(pane.x1 - pane.x0), 0, 0}, 1, 1, false);
        children.push_back(
            addNode(doc, meshNode(std::string(pane.name), addMesh(doc, std::move(mesh)))));
    }

    // Light 0: the sun; light 1: the spot (the converter keeps the .glb's order).
    children.push_back(addSun(doc, toFloat3(l.sunTravel), {f((l.patchX0 + l.patchX1) / 2), 0, 0},
                              20.0f, {1, 1, 1}, f(l.sunIntensity)));
    doc.lights.push_back({.name = "spot-lamp",
                          .type = gltf::LightType::Spot,
                          .color = {1, 1, 1},
                          .intensity = f(l.spotIntensity),
                          .range = f(l.spotRange),
                          .innerConeRadians = radians(f(l.spotInnerDegrees)),
                          .outerConeRadians = radians(f(l.spotOuterDegrees))});
    Node spot;
    spot.name = "spot-lamp";
    spot.translation = toFloat3(l.spotPosition);
    spot.rotation = gltf::lookRotation({0, -1, 0}, {0, 0, -1}); // straight down
    spot.light = int32_t(doc.lights.size() - 1);
    children.push_back(addNode(doc, std::move(spot)));
    children.push_back(addCamera(doc, "window-camera", toFloat3(l.cameraPosition),
                                 toFloat3(l.cameraTarget) - toFloat3(l.cameraPosition),
                                 radians(f(l.cameraYFovDegrees)), 16.0f / 9.0f, 0.05f, 50.0f));
    doc.nodes[rootNode].children = std::move(children);
    return doc;
}

} // namespace pnb::assets
