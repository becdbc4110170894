// Procedural source scenes (see procedural_scenes.h): the registry (names, descriptions, and
// the option mapping of buildProceduralScene).
//
// The scenes are one file each, or one per small family, over shared building helpers:
//   procedural_scenes_internal.h  the helpers' interface (procedural_helpers.cpp: random numbers
//                                 and noise, grids, boxes, materials, cameras, suns)
//   procedural_city.cpp           street-canyon, flat-city
//   procedural_rooms.cpp          box-room, atrium, lamp-room, colour-room
//   procedural_terrain.cpp        terrain
//   procedural_extremes.cpp       grazing-plane, one-triangle, wide-flat
//   procedural_load_test.cpp      load-test
//   procedural_light_field.cpp    light-field
//   procedural_window.cpp         window (and its analytic expectations, window_scene.h)
//   procedural_crowd.cpp          crowd (skinned walkers)
//   procedural_moving_light.cpp   moving-light (an animated light, rigid motion, a morph)

#include "pnb_assets/procedural_scenes.h"
#include "pnb_assets/window_scene.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace pnb::assets {

// [SECTION] Registry ----------------------------------------------------------------------------

namespace {

constexpr ProceduralScene kScenes[] = {
    {"street-canyon", "low sun across a street of tall boxes; off-screen towers shadow the view "
                      "(~10k triangles)"},
    {"flat-city", "~0.5M rendered triangles of instanced buildings on 2 km of ground, sun at 45 "
                  "degrees"},
    {"box-room", "Cornell-style room: red/green walls, two boxes, a BLEND pane, point light + sun"},
    {"terrain", "512x512 fractal heightfield with floating slabs and arches, far plane 8 km"},
    {"grazing-plane", "large plane with poles and boxes under a 3-degree sun (acne, "
                      "peter-panning)"},
    {"load-test", "~1M triangles in 50 rock meshes, ten 1024^2 textures (load benchmark; big)"},
    {"light-field", "floor and 64 boxes lit by N point lights (--lights N, default 8; "
                    "deferred vs forward benchmark)"},
    {"one-triangle", "a single triangle under a 40-degree sun (extremes of the ground truth)"},
    {"wide-flat", "a 100 km ground with 1 m blocks: 10^5 x wider than tall (extremes)"},
    {"atrium", "walled courtyard open to the sky: arcade of columns and arches, upper gallery, "
               "red banner, thin partition (GI: bounce light, bleeding, leaks)"},
    {"lamp-room",
     "closed 8x3x6 m room, boxes, pillar and table lit by one spot and one point light "
     "(no sun gets in): local-light shadows"},
    {"colour-room", "open-topped room, red and green walls, two blocks, sun from above (GI: "
                    "multiple bounces)"},
    {"window", "closed room lit only through glass: a sun through a coloured roof pane, a spot "
               "through two overlapping panes (translucent shadows)"},
    {"crowd", "N skinned walkers (--count N, default 100) circling a plinth in an open-roofed room "
              "(animation benchmark)"},
    {"moving-light", "room with a circling point light, a sliding box and a squashing morph ball "
                     "(moving GI and shadows)"},
};

uint32_t sqrtRound(double v) {
    return uint32_t(std::max(1.0, std::round(std::sqrt(v))));
}

} // namespace

std::span<const ProceduralScene> proceduralScenes() {
    return kScenes;
}

std::optional<gltf::Document> buildProceduralScene(std::string_view name,
                                                   const SceneRequest& request) {
    const uint64_t target = request.targetTriangles;
    if (name == "street-canyon") {
        StreetCanyonOptions o;
        o.seed = request.seed;
        if (target) o.targetTriangles = target;
        return buildStreetCanyon(o);
    }
    if (name == "flat-city") {
        FlatCityOptions o;
        o.seed = request.seed;
        if (target) o.targetTriangles = target;
        return buildFlatCity(o);
    }
    if (name == "box-room") {
        // Triangles: 5 walls of 2n^2, two boxes of 12n^2 each, and the 2-triangle pane.
        BoxRoomGltfOptions o;
        if (target) o.subdivisions = sqrtRound(double(target > 2 ? target - 2 : 0) / 34.0);
        return buildBoxRoomGltf(o);
    }
    if (name == "terrain") {
        // The overhangs add a few thousand triangles; the grid is 2 per quad.
        TerrainOptions o;
        o.seed = request.seed;
        if (target) o.quadsPerSide = sqrtRound(double(target) / 2.0);
        return buildTerrain(o);
    }
    if (name == "grazing-plane") {
        GrazingPlaneOptions o;
        o.seed = request.seed;
        if (target) {
            const uint64_t props = gltf::countRenderedTriangles(buildGrazingPlane(o)) - 2;
            o.planeSubdivisions = sqrtRound(double(target > props ? target - props : 0) / 2.0);
        }
        return buildGrazingPlane(o);
    }
    if (name == "load-test") {
        LoadTestOptions o;
        o.seed = request.seed;
        if (target) o.targetTriangles = target;
        if (request.textureSize) o.textureSize = *request.textureSize;
        return buildLoadTest(o);
    }
    if (name == "light-field") {
        // Boxes are 12 triangles each; the floor is 2 per quad.
        LightFieldOptions o;
        o.seed = request.seed;
        if (request.lights) o.lights = *request.lights;
        const uint64_t boxes = 12ull * o.boxesPerSide * o.boxesPerSide;
        if (target)
            o.floorSubdivisions = sqrtRound(double(target > boxes ? target - boxes : 0) / 2.0);
        return buildLightField(o);
    }
    if (name == "one-triangle") return buildOneTriangle();
    if (name == "wide-flat") return buildWideFlat({});
    if (name == "atrium") return buildAtrium();
    if (name == "lamp-room") return buildLampRoom();
    if (name == "window") return buildWindowScene();
    if (name == "colour-room") return buildColourRoom();
    if (name == "crowd") {
        CrowdOptions o;
        o.seed = request.seed;
        if (request.count) o.count = *request.count;
        return buildCrowd(o);
    }
    if (name == "moving-light") return buildMovingLight();
    return std::nullopt;
}

} // namespace pnb::assets
