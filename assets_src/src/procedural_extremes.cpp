// assets_src/src/procedural_extremes.cpp — the shadow-test extremes: grazing-plane (a large plane
// under a 3-degree sun: acne and peter-panning), one-triangle and wide-flat (the degenerate ends
// of the ground-truth extremes matrix). Small scenes of one purpose each, kept together
// (procedural_scenes.h documents each scene).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "procedural_scenes_internal.h"

namespace pnb::assets {

using namespace procedural_detail;

// [SECTION] grazing-plane -----------------------------------------------------------------------

gltf::Document buildGrazingPlane(const GrazingPlaneOptions& o) {
    Document doc;
    doc.sceneName = "grazing-plane";
    const float size = o.planeSizeMeters;
    const uint32_t texture = std::max(2u, o.textureSize);
    constexpr float kTileMeters = 8.0f; // one checker texture repeat

    doc.images.push_back({"checker", checkerPng(texture, std::max(1u, texture / 8),
                                                {0.85f, 0.85f, 0.85f}, {0.55f, 0.55f, 0.55f})});
    Material planeMat = makeMaterial("checker-plane", {1, 1, 1}, 0.9f);
    planeMat.baseColorImage = 0;
    const uint32_t plane = addMaterial(doc, std::move(planeMat));
    const uint32_t pole = addMaterial(doc, makeMaterial("pole", {0.8f, 0.8f, 0.8f}, 0.6f));
    const uint32_t box = addMaterial(doc, makeMaterial("box", {0.7f, 0.3f, 0.2f}, 0.7f));
    const uint32_t wall = addMaterial(doc, makeMaterial("wall", {0.3f, 0.4f, 0.7f}, 0.7f));

    // The plane reaches 100 m behind the camera and size - 100 m ahead of it.
    Mesh planeMesh;
    planeMesh.name = "plane";
    planeMesh.primitives.resize(1);
    planeMesh.primitives[0].material = plane;
    const uint32_t n = std::max(1u, o.planeSubdivisions);
    addGrid(planeMesh.primitives[0], {-size / 2, 0, 100 - size}, {0, 0, size}, {size, 0, 0}, n, n,
            true, {size / kTileMeters, size / kTileMeters});

    Pcg32 rng(o.seed, kStreamGrazingProps);
    Mesh poles;
    poles.name = "poles";
    poles.primitives.resize(1);
    poles.primitives[0].material = pole;
    for (uint32_t k = 0; k < o.poles; ++k) {
        // Alternating sides of the view, 10 m to ~190 m away; 15 cm thick, 4-10 m tall.
        const float z = -(10.0f + 15.0f * float(k) + rng.uniform(0, 5));
        const float x = (k % 2 == 0 ? -1.0f : 1.0f) * rng.uniform(2, 12);
        const float h = rng.uniform(4, 10);
        addBox(poles.primitives[0], poles.primitives[0], {x - 0.075f, 0, z - 0.075f},
               {x + 0.075f, h, z + 0.075f}, {1, 4, 1}, false);
    }

    Mesh boxes;
    boxes.name = "resting-boxes";
    boxes.primitives.resize(1);
    boxes.primitives[0].material = box;
    for (int k = 0; k < 4; ++k) {
        const float s = rng.uniform(1, 3), x = (k % 2 == 0 ? -6.0f : 6.0f) + rng.uniform(-1, 1);
        const float z = -20.0f - 20.0f * float(k);
        addBox(boxes.primitives[0], boxes.primitives[0], {x - s / 2, 0, z - s / 2},
               {x + s / 2, s, z + s / 2}, {1, 1, 1}, false);
    }
    Mesh floating;
    floating.name = "floating-box";
    floating.primitives.resize(1);
    floating.primitives[0].material = box;
    addBox(floating.primitives[0], floating.primitives[0], {-1, 0.02f, -1}, {1, 2.02f, 1},
           {1, 1, 1}, false);

    // A thin wall along the view (it blocks the sun, which shines across), and a ramp tilted 2
    // degrees: nearly parallel to the light, the hardest case for a constant depth bias.
    Mesh thinWall;
    thinWall.name = "thin-wall";
    thinWall.primitives.resize(1);
    thinWall.primitives[0].material = wall;
    addBox(thinWall.primitives[0], thinWall.primitives[0], {-10.05f, 0, -52}, {-9.95f, 4, -40},
           {1, 1, 3}, false);
    Mesh ramp;
    ramp.name = "ramp";
    ramp.primitives.resize(1);
    ramp.primitives[0].material = wall;
    addBox(ramp.primitives[0], ramp.primitives[0], {-3, 0, -10}, {3, 0.3f, 10}, {1, 1, 4}, false);

    const float elevation = radians(o.sunElevationDegrees);
    addCamera(doc, "eye-camera", {0, 1.7f, 0}, {0, -std::sin(radians(4)), -std::cos(radians(4))},
              radians(55), 16.0f / 9.0f, 0.1f, 3000.0f);
    addSun(doc, sunDirection(elevation, radians(10)), {0, 0, -60}, 500.0f, {1.0f, 0.8f, 0.6f},
           3.0f);
    addNode(doc, meshNode("plane", addMesh(doc, std::move(planeMesh))));
    addNode(doc, meshNode("poles", addMesh(doc, std::move(poles))));
    addNode(doc, meshNode("resting-boxes", addMesh(doc, std::move(boxes))));
    addNode(doc, meshNode("floating-box", addMesh(doc, std::move(floating)), {3, 0, -25}));
    addNode(doc, meshNode("thin-wall", addMesh(doc, std::move(thinWall))));
    // Rotation about +X by 2 degrees lifts the ramp's far (-Z) end; its near end stays at y=0.
    const float tilt = radians(2);
    addNode(doc, meshNode("ramp", addMesh(doc, std::move(ramp)), {12, 0, -40},
                          {std::sin(tilt / 2), 0, 0, std::cos(tilt / 2)}));
    return doc;
}

// [SECTION] one-triangle and wide-flat: extremes of the ground-truth matrix ---------------------

gltf::Document buildOneTriangle() {
    Document doc;
    doc.sceneName = "one-triangle";
    const uint32_t stone = addMaterial(doc, makeMaterial("stone", {0.6f, 0.6f, 0.6f}, 0.8f));
    Mesh mesh;
    mesh.name = "triangle";
    Primitive& p = mesh.primitives.emplace_back();
    p.material = stone;
    p.positions = {{-5, 0, 5}, {5, 0, 5}, {0, 0, -5}};
    p.normals.assign(3, Float3{0, 1, 0});
    p.indices = {0, 1, 2};
    addNode(doc, meshNode("triangle", addMesh(doc, std::move(mesh))));
    addCamera(doc, "camera", {0, 6, 12}, {0, -6, -12}, radians(60), 16.0f / 9.0f, 0.1f, 0.0f);
    addSun(doc, sunDirection(radians(40), radians(30)), {0, 0, 0}, 50.0f, {1, 1, 1}, 3.0f);
    return doc;
}

gltf::Document buildWideFlat(const WideFlatOptions& o) {
    Document doc;
    doc.sceneName = "wide-flat";
    const float half = o.widthMeters / 2;
    const uint32_t ground = addMaterial(doc, makeMaterial("ground", {0.5f, 0.5f, 0.45f}, 0.9f));
    const uint32_t block = addMaterial(doc, makeMaterial("block", {0.7f, 0.35f, 0.25f}, 0.7f));
    Mesh groundMesh;
    groundMesh.name = "ground";
    groundMesh.primitives.resize(1);
    groundMesh.primitives[0].material = ground;
    addGrid(groundMesh.primitives[0], {-half, 0, -half}, {0, 0, o.widthMeters},
            {o.widthMeters, 0, 0}, 1, 1, false);
    Mesh blocks;
    blocks.name = "blocks";
    blocks.primitives.resize(1);
    blocks.primitives[0].material = block;
    // A 5 x 5 field of 0.5 m x 0.5 m blocks at 2 m pitch, as tall as the scene.
    for (int i = -2; i <= 2; ++i)
        for (int j = 0; j < 5; ++j) {
            const float x = 2.0f * float(i), z = -4.0f - 2.0f * float(j);
            addBox(blocks.primitives[0], blocks.primitives[0], {x - 0.25f, 0, z - 0.25f},
                   {x + 0.25f, o.heightMeters, z + 0.25f}, {1, 1, 1}, false);
        }
    addNode(doc, meshNode("ground", addMesh(doc, std::move(groundMesh))));
    addNode(doc, meshNode("blocks", addMesh(doc, std::move(blocks))));
    addCamera(doc, "camera", {0, 2.5f, 2}, {0, -2.5f, -9}, radians(60), 16.0f / 9.0f, 0.05f, 0.0f);
    addSun(doc, sunDirection(radians(30), radians(20)), {0, 0, -8}, 50.0f, {1, 1, 1}, 3.0f);
    return doc;
}

} // namespace pnb::assets
