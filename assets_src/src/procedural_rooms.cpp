// assets_src/src/procedural_rooms.cpp — the enclosed scenes: box-room (the Cornell-style room of
// box_room.h as a glTF source), atrium (a courtyard with arcade and gallery for GI) and lamp-room
// (a closed room lit only by a spot and a point light), colour-room (an open-topped room of
// coloured walls for multi-bounce GI). One file for rooms whose light comes from
// inside or through one opening (procedural_scenes.h documents each scene).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "procedural_scenes_internal.h"

namespace pnb::assets {

using namespace procedural_detail;

// [SECTION] box-room ----------------------------------------------------------------------------

gltf::Document buildBoxRoomGltf(const BoxRoomGltfOptions& o) {
    Document doc;
    doc.sceneName = "box-room";
    const float r = o.roomSize;
    const uint32_t n = std::max(1u, o.subdivisions);
    const uint32_t texture = std::max(2u, o.textureSize);

    // Same colours as box_room.cpp.
    doc.images.push_back({"checker", checkerPng(texture, std::max(1u, texture / 8),
                                                {230 / 255.0f, 220 / 255.0f, 200 / 255.0f},
                                                {60 / 255.0f, 70 / 255.0f, 90 / 255.0f})});
    const uint32_t white =
        addMaterial(doc, makeMaterial("white-wall", {0.73f, 0.73f, 0.73f}, 0.8f));
    const uint32_t red = addMaterial(doc, makeMaterial("red-wall", {0.63f, 0.065f, 0.05f}, 0.8f));
    const uint32_t green =
        addMaterial(doc, makeMaterial("green-wall", {0.14f, 0.45f, 0.091f}, 0.8f));
    Material floorMat = makeMaterial("checker-floor", {1, 1, 1}, 0.8f);
    floorMat.baseColorImage = 0;
    const uint32_t floorMaterial = addMaterial(doc, std::move(floorMat));
    Material glassMat = makeMaterial("tinted-glass", {0.2f, 0.4f, 0.9f}, 0.1f);
    glassMat.baseColorFactor[3] = 0.35f;
    glassMat.alphaMode = gltf::AlphaMode::Blend;
    glassMat.doubleSided = true;
    const uint32_t glass = addMaterial(doc, std::move(glassMat));

    // Room: inward-facing walls, open towards +Z (the camera side).
    Mesh room;
    room.name = "room";
    const Float3 X{r, 0, 0}, Y{0, r, 0}, Z{0, 0, r}, lo{-r / 2, 0, -r / 2};
    struct Wall {
        uint32_t material;
        Float3 origin, u, v;
    };
    const Wall walls[] = {
        {floorMaterial, lo, Z, X}, // floor, normal +Y
        {white, lo + Y, X, Z},     // ceiling, normal -Y
        {white, lo, X, Y},         // back, normal +Z
        {red, lo, Y, Z},           // left, normal +X
        {green, lo + X, Z, Y},     // right, normal -X
    };
    for (const Wall& w : walls) {
        Primitive p;
        p.material = w.material;
        // UVs only where a texture reads them (validators flag unused TEXCOORD_0).
        addGrid(p, w.origin, w.u, w.v, n, n, w.material == floorMaterial);
        room.primitives.push_back(std::move(p));
    }

    Mesh boxes;
    boxes.name = "boxes";
    boxes.primitives.resize(1);
    Primitive& bp = boxes.primitives[0];
    bp.material = white;
    addBox(bp, bp, {-0.35f * r, 0, -0.3f * r}, {-0.05f * r, 0.6f * r, 0.0f}, {n, n, n}, false);
    addBox(bp, bp, {0.05f * r, 0, -0.1f * r}, {0.35f * r, 0.3f * r, 0.2f * r}, {n, n, n}, false);

    Mesh pane;
    pane.name = "glass-pane";
    pane.primitives.resize(1);
    pane.primitives[0].material = glass;
    addGrid(pane.primitives[0], {-0.3f * r, 0.05f * r, 0.3f * r}, {0.6f * r, 0, 0},
            {0, 0.5f * r, 0}, 1, 1, false);

    Node root;
    root.name = "box-room";
    const uint32_t rootNode = addNode(doc, std::move(root));
    std::vector<uint32_t> children = {
        addNode(doc, meshNode("room", addMesh(doc, std::move(room)))),
        addNode(doc, meshNode("boxes", addMesh(doc, std::move(boxes)))),
        addNode(doc, meshNode("glass-pane", addMesh(doc, std::move(pane)))),
        // The sun of box_room.cpp: -Z turned 60 degrees down, from above the open side.
        addSun(doc, {0, -0.8660254f, -0.5f}, {0, 2 * r, 2 * r}, 0.0f, {1.0f, 0.95f, 0.85f}, 3.0f),
    };
    doc.lights.push_back({.name = "ceiling-lamp",
                          .type = gltf::LightType::Point,
                          .color = {1, 1, 1},
                          .intensity = 40.0f,
                          .range = 2 * r});
    Node lamp;
    lamp.name = "ceiling-lamp";
    lamp.translation = {0, 0.9f * r, 0};
    lamp.light = int32_t(doc.lights.size() - 1);
    children.push_back(addNode(doc, std::move(lamp)));
    children.push_back(
        addCamera(doc, "camera", {0, 0.5f * r, 1.4f * r}, {0, 0, -1}, 0.9f, 0.0f, 0.05f, 0.0f));
    doc.nodes[rootNode].children = std::move(children);
    return doc;
}

// [SECTION] atrium ------------------------------------------------------------------------------

gltf::Document buildAtrium() {
    Document doc;
    doc.sceneName = "atrium";
    constexpr float kHalf = 12.0f, kWallHeight = 14.0f, kWall = 0.6f;
    constexpr float kArcade = 3.0f;      // depth of the arcade and gallery from the walls
    constexpr float kGallery = 5.0f;     // gallery floor height (slab 5.0 .. 5.4)
    constexpr float kColumn = 0.7f;      // column side
    constexpr float kPitch = 4.0f;       // column spacing
    const uint32_t stone = addMaterial(doc, makeMaterial("floor-stone", {0.55f, 0.5f, 0.45f}, 0.85f));
    const uint32_t ochre = addMaterial(doc, makeMaterial("ochre-wall", {0.7f, 0.55f, 0.35f}, 0.9f));
    const uint32_t marble = addMaterial(doc, makeMaterial("white-marble", {0.8f, 0.8f, 0.78f}, 0.5f));
    const uint32_t red = addMaterial(doc, makeMaterial("red-banner", {0.7f, 0.06f, 0.05f}, 0.9f));
    const uint32_t plaster = addMaterial(doc, makeMaterial("partition", {0.75f, 0.75f, 0.75f}, 0.9f));

    Mesh floor;
    floor.name = "floor";
    floor.primitives.resize(1);
    floor.primitives[0].material = stone;
    addGrid(floor.primitives[0], {-kHalf, 0, -kHalf}, {0, 0, 2 * kHalf}, {2 * kHalf, 0, 0}, 12, 12, false);
    addNode(doc, meshNode("floor", addMesh(doc, std::move(floor))));

    // Enclosing walls (closed boxes) and the gallery slabs with their parapets.
    std::vector<Box> walls = {
        {{-kHalf - kWall, 0, -kHalf - kWall}, {kHalf + kWall, kWallHeight, -kHalf}},
        {{-kHalf - kWall, 0, kHalf}, {kHalf + kWall, kWallHeight, kHalf + kWall}},
        {{-kHalf - kWall, 0, -kHalf}, {-kHalf, kWallHeight, kHalf}},
        {{kHalf, 0, -kHalf}, {kHalf + kWall, kWallHeight, kHalf}},
    };
    addNode(doc, meshNode("walls", addMesh(doc, boxesMesh("walls", walls, 2.0f, ochre, ochre))));
    const float inner = kHalf - kArcade; // |x| or |z| of the arcade's open edge
    std::vector<Box> gallery = {
        {{-kHalf, kGallery, -kHalf}, {kHalf, kGallery + 0.4f, -inner}},
        {{-kHalf, kGallery, inner}, {kHalf, kGallery + 0.4f, kHalf}},
        {{-kHalf, kGallery, -inner}, {-inner, kGallery + 0.4f, inner}},
        {{inner, kGallery, -inner}, {kHalf, kGallery + 0.4f, inner}},
        // parapets, 1 m high and 0.2 m thick, on the open edges
        {{-inner, kGallery + 0.4f, -inner - 0.2f}, {inner, kGallery + 1.4f, -inner}},
        {{-inner, kGallery + 0.4f, inner}, {inner, kGallery + 1.4f, inner + 0.2f}},
        {{-inner - 0.2f, kGallery + 0.4f, -inner}, {-inner, kGallery + 1.4f, inner}},
        {{inner, kGallery + 0.4f, -inner}, {inner + 0.2f, kGallery + 1.4f, inner}},
    };
    addNode(doc, meshNode("gallery", addMesh(doc, boxesMesh("gallery", gallery, 2.0f, marble, marble))));

    // Columns along the arcade's open edge and, between neighbours, an arch of five voussoirs on
    // a semicircle springing at 3.8 m whose crown meets the slab.
    std::vector<Box> columns, arches;
    const float springing = 3.8f;
    for (int side = 0; side < 4; ++side) {
        for (float t = -inner; t <= inner + 1e-3f; t += kPitch) {
            float x = side < 2 ? t : (side == 2 ? -inner : inner);
            float z = side < 2 ? (side == 0 ? -inner : inner) : t;
            if (side >= 2 && std::fabs(t) > inner - 1e-3f) continue; // corners once
            columns.push_back({{x - kColumn / 2, 0, z - kColumn / 2}, {x + kColumn / 2, kGallery, z + kColumn / 2}});
            if (t + kPitch > inner + 1e-3f) continue;
            const float radius = (kPitch - kColumn) / 2, centre = t + kPitch / 2;
            for (int k = 0; k < 5; ++k) {
                float angle = float(std::numbers::pi) * (float(k) + 0.5f) / 5.0f;
                float u = centre - radius * std::cos(angle), h = springing + radius * std::sin(angle);
                float top = std::min(kGallery, h + 0.35f);
                Box b = side < 2 ? Box{{u - 0.3f, h - 0.2f, z - 0.2f}, {u + 0.3f, top, z + 0.2f}}
                                 : Box{{x - 0.2f, h - 0.2f, u - 0.3f}, {x + 0.2f, top, u + 0.3f}};
                arches.push_back(b);
            }
        }
    }
    addNode(doc, meshNode("columns", addMesh(doc, boxesMesh("columns", columns, 2.0f, marble, marble))));
    addNode(doc, meshNode("arches", addMesh(doc, boxesMesh("arches", arches, 2.0f, marble, marble))));
    std::vector<Box> banner = {{{-3.0f, 6.0f, -kHalf + 0.02f}, {3.0f, 12.0f, -kHalf + 0.07f}}};
    addNode(doc, meshNode("red-banner", addMesh(doc, boxesMesh("red-banner", banner, 2.0f, red, red))));
    std::vector<Box> partition = {{{-4.0f, 0, 2.0f}, {4.0f, 4.0f, 2.1f}}};
    addNode(doc, meshNode("thin-partition", addMesh(doc, boxesMesh("thin-partition", partition, 2.0f, plaster, plaster))));

    addCamera(doc, "gallery-camera", {-9.5f, kGallery + 2.2f, 9.5f}, {12.0f, -6.0f, -12.0f}, radians(60),
              16.0f / 9.0f, 0.05f, 0.0f);
    addSun(doc, sunDirection(radians(55), radians(30)), {0, 0, 0}, 40.0f, {1.0f, 0.97f, 0.9f}, 3.0f);
    return doc;
}

// [SECTION] lamp-room ---------------------------------------------------------------------------

gltf::Document buildLampRoom() {
    Document doc;
    doc.sceneName = "lamp-room";
    // A closed 8 x 3 x 6 m room (x in [-4, 4], y in [0, 3], z in [-3, 3]): no opening, so no sun
    // can enter (the converter's generated default-sun lights the outside only) and every lit
    // pixel is lit by the two local lights.
    const uint32_t wall = addMaterial(doc, makeMaterial("plaster", {0.72f, 0.72f, 0.70f}, 0.9f));
    const uint32_t floorMaterial =
        addMaterial(doc, makeMaterial("floorboards", {0.55f, 0.50f, 0.45f}, 0.8f));
    const uint32_t crate = addMaterial(doc, makeMaterial("crate", {0.70f, 0.45f, 0.25f}, 0.7f));
    const uint32_t blue = addMaterial(doc, makeMaterial("blue-box", {0.30f, 0.42f, 0.70f}, 0.6f));
    const uint32_t stone = addMaterial(doc, makeMaterial("pillar", {0.65f, 0.65f, 0.62f}, 0.8f));
    const uint32_t wood = addMaterial(doc, makeMaterial("table-wood", {0.45f, 0.30f, 0.18f}, 0.6f));

    Mesh room;
    room.name = "room";
    const Float3 X{8, 0, 0}, Y{0, 3, 0}, Z{0, 0, 6}, lo{-4, 0, -3};
    struct Wall {
        uint32_t material;
        Float3 origin, u, v; // inward normal u x v
    };
    const Wall walls[] = {
        {floorMaterial, lo, Z, X}, // floor, +Y
        {wall, lo + Y, X, Z},      // ceiling, -Y
        {wall, lo, X, Y},          // back (z = -3), +Z
        {wall, lo + Z, Y, X},      // front (z = 3), -Z
        {wall, lo, Y, Z},          // left (x = -4), +X
        {wall, lo + X, Z, Y},      // right (x = 4), -X
    };
    for (const Wall& w : walls) {
        Primitive p;
        p.material = w.material;
        addGrid(p, w.origin, w.u, w.v, 1, 1, false);
        room.primitives.push_back(std::move(p));
    }

    const auto boxMesh = solidBoxesMesh;
    // Table: a 1.2 x 0.8 m top at 0.72-0.78 m on four 6 cm legs, in the back right corner.
    const float tx0 = 1.6f, tx1 = 2.8f, tz0 = -2.4f, tz1 = -1.6f, leg = 0.06f, inset = 0.05f;
    std::vector<Box> table = {{{tx0, 0.72f, tz0}, {tx1, 0.78f, tz1}}};
    for (float x : {tx0 + inset, tx1 - inset - leg})
        for (float z : {tz0 + inset, tz1 - inset - leg})
            table.push_back({{x, 0, z}, {x + leg, 0.72f, z + leg}});

    Node root;
    root.name = "lamp-room";
    const uint32_t rootNode = addNode(doc, std::move(root));
    std::vector<uint32_t> children = {
        addNode(doc, meshNode("room", addMesh(doc, std::move(room)))),
        addNode(doc, meshNode("crate",
                              addMesh(doc, boxMesh("crate", crate,
                                                   {{{-1.4f, 0, -1.2f}, {-0.6f, 0.8f, -0.4f}}})))),
        addNode(doc, meshNode("tall-box",
                              addMesh(doc, boxMesh("tall-box", blue,
                                                   {{{0.3f, 0, -0.7f}, {0.9f, 1.3f, -0.1f}}})))),
        addNode(doc, meshNode("pillar",
                              addMesh(doc, boxMesh("pillar", stone,
                                                   {{{-2.65f, 0, 0.85f}, {-2.35f, 3, 1.15f}}})))),
        addNode(doc, meshNode("table", addMesh(doc, boxMesh("table", wood, table)))),
    };

    // The spot: near the ceiling by the left wall, aimed down at the boxes at about 40 degrees
    // below the horizontal, so their shadows fall across the camera's view (towards +X), not
    // behind them; cone 25/38 degrees. Where its axis meets the floor (3.8 m) it gives ~2 lux:
    // a radiance of ~0.35 on 0.55 albedo at exposure 1 (albedo / pi x E).
    // Light indices follow the nodes: the spot is light 0, the point light 1 (in the .glb, and in
    // the container, where the converter appends its default-sun after them).
    doc.lights.push_back({.name = "spot-lamp",
                          .type = gltf::LightType::Spot,
                          .color = {1.0f, 0.92f, 0.80f},
                          .intensity = 60.0f,
                          .range = 10.0f,
                          .innerConeRadians = radians(25),
                          .outerConeRadians = radians(38)});
    Node spot;
    spot.name = "spot-lamp";
    spot.translation = {-3.0f, 2.85f, -0.5f};
    spot.rotation = gltf::lookRotation(Float3{-0.2f, 0.3f, -0.6f} - spot.translation);
    spot.light = int32_t(doc.lights.size() - 1);
    children.push_back(addNode(doc, std::move(spot)));
    // The point light: 2.2 m up in front of the pillar, so the pillar's shadow runs across the
    // floor and up the back wall and the boxes' towards the back right (~2.5 lux straight below
    // it; its 8 m range leaves the far right corner unlit).
    doc.lights.push_back({.name = "bulb",
                          .type = gltf::LightType::Point,
                          .color = {1.0f, 0.85f, 0.65f},
                          .intensity = 12.0f,
                          .range = 8.0f});
    Node bulb;
    bulb.name = "bulb";
    bulb.translation = {-2.2f, 2.2f, 2.4f};
    bulb.light = int32_t(doc.lights.size() - 1);
    children.push_back(addNode(doc, std::move(bulb)));
    // From the front right corner, looking across the room at the boxes.
    children.push_back(addCamera(doc, "corner-camera", {3.6f, 2.1f, 2.6f},
                                 Float3{-0.8f, 0.6f, -0.8f} - Float3{3.6f, 2.1f, 2.6f}, radians(70),
                                 16.0f / 9.0f, 0.05f, 50.0f));
    doc.nodes[rootNode].children = std::move(children);
    return doc;
}

// [SECTION] colour-room -------------------------------------------------------------------------

gltf::Document buildColourRoom() {
    Document doc;
    doc.sceneName = "colour-room";
    // Bright walls (albedo 0.75-0.8 in their own colour) so that inter-reflection matters: the
    // sunlit floor and green wall light the rest, which light each other again.
    const uint32_t white = addMaterial(doc, makeMaterial("white-plaster", {0.80f, 0.80f, 0.78f}, 0.9f));
    const uint32_t red = addMaterial(doc, makeMaterial("red-plaster", {0.75f, 0.12f, 0.10f}, 0.9f));
    const uint32_t green = addMaterial(doc, makeMaterial("green-plaster", {0.12f, 0.65f, 0.15f}, 0.9f));
    const uint32_t grey = addMaterial(doc, makeMaterial("grey-block", {0.55f, 0.55f, 0.55f}, 0.8f));

    Mesh room;
    room.name = "room";
    const Float3 X{6, 0, 0}, Y{0, 3, 0}, Z{0, 0, 6}, lo{-3, 0, -3};
    struct Wall {
        uint32_t material;
        Float3 origin, u, v; // inward normal u x v
    };
    const Wall walls[] = {
        {white, lo, Z, X},      // floor, +Y
        {white, lo, X, Y},      // back (z = -3), +Z
        {white, lo + Z, Y, X},  // front (z = 3), -Z
        {red, lo, Y, Z},        // left (x = -3), +X
        {green, lo + X, Z, Y},  // right (x = 3), -X
    };
    for (const Wall& w : walls) {
        Primitive p;
        p.material = w.material;
        addGrid(p, w.origin, w.u, w.v, 4, 4, false);
        room.primitives.push_back(std::move(p));
    }
    Node root;
    root.name = "colour-room";
    const uint32_t rootNode = addNode(doc, std::move(root));
    std::vector<uint32_t> children = {
        addNode(doc, meshNode("room", addMesh(doc, std::move(room)))),
        addNode(doc, meshNode("white-block",
                              addMesh(doc, solidBoxesMesh("white-block", white, {{{-1.6f, 0, -1.4f}, {-0.4f, 1.0f, -0.2f}}})))),
        addNode(doc, meshNode("tall-block",
                              addMesh(doc, solidBoxesMesh("tall-block", grey, {{{0.7f, 0, -2.2f}, {1.5f, 2.0f, -1.4f}}})))),
    };
    // Above the front wall, looking down and in at the blocks and both coloured walls.
    children.push_back(addCamera(doc, "room-camera", {0.0f, 5.2f, 5.6f}, Float3{0.0f, 0.6f, -1.0f} - Float3{0.0f, 5.2f, 5.6f},
                                 radians(65), 16.0f / 9.0f, 0.05f, 60.0f));
    doc.nodes[rootNode].children = std::move(children);
    // 60 degrees up, travelling +X turned 20 degrees towards -Z: the sun falls on the floor's
    // right half and the green wall; the red wall's shadow covers the floor's left edge.
    addSun(doc, sunDirection(radians(60), radians(20)), {0, 0, 0}, 30.0f, {1.0f, 0.97f, 0.9f}, 3.0f);
    return doc;
}

} // namespace pnb::assets
