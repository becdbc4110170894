// pnb_assets/procedural_scenes.h — procedural *source* test scenes, built as glTF documents.
//
// The rendering work (cascaded shadow maps, deferred shading, GI) needs scenes that provoke
// specific problems; these generators build them at build time (pnb-make-scene) so nothing large
// is committed. Each returns a gltf::Document (gltf_writer.h) that encodeGlb() turns into a .glb
// for the converter.
//
//   street-canyon  low sun across a street of tall buildings; two very tall towers outside the
//                  street camera's frustum whose shadows land in view (seed 000's Sehir case)
//   flat-city      ~0.5 M rendered triangles of instanced buildings on a 2 km ground, sun at 45°
//   box-room       the Cornell-style room of box_room.h, as a glTF source
//   terrain        fractal heightfield with floating slabs and arches, far plane kilometres away
//   grazing-plane  a large plane with poles and boxes under a 3° sun (shadow acne and
//                  peter-panning)
//   load-test      ~1 M triangles in 50 separate rock meshes with ten 1024² textures (base
//                  colour + normal maps): the player's load-time benchmark (scripts/bench-load)
//   light-field    a floor with a grid of boxes lit by N point lights with ranges: deferred vs
//                  forward shading cost against the light count (scripts/bench-lights)
//   one-triangle,  the degenerate ends of the ground-truth extremes matrix (scripts/bench-extremes)
//   wide-flat
//   lamp-room      a closed room lit by one spot and one point light and no sun: the shadows of
//                  local lights (issue 29) and their ray-traced truth
//   colour-room    an open-topped room with a red and a green wall and two blocks, sunlit from
//                  above: inter-reflection (multi-bounce indirect light, issue 40)
//   window         a closed room lit only through glass: a sun through a coloured roof pane and
//                  a spot through two overlapping panes (issue 43's translucent shadows; the
//                  layout and its analytic values are in window_scene.h)
//   crowd          N skinned walkers (--count N, 1..1000, default 100) circling a plinth in an
//                  open-roofed room with pillars, a sun and two point lights: one shared walker
//                  mesh, a skin per walker, one looping clip (issue 42's animated benchmark)
//   moving-light   a room whose point light circles under the ceiling, whose box slides and
//                  turns through the sun and whose ball squashes (a morph target): moving
//                  lights, rigid motion and morphs (issue 42's GI/shadow benchmark)
//
// load-test, light-field and crowd exist for benchmarks: they are not generated at build time (not in
// assets_src/CMakeLists.txt's PNB_PROCEDURAL_SCENES), the benchmark scripts make them.
//
// Conventions: glTF's (metres, +Y up, right-handed, cameras and lights look along local -Z).
// Every scene's first camera is the intended view. Every scene but lamp-room has one directional
// light on a node named "sun" with intensity 3: the artist-scale value box_room.cpp uses, not
// physical daylight (~100 000 lux), so all bundled scenes share one exposure. Scenes with a "seed"
// use a seeded PCG32 generator with our own integer-to-float mapping (never std::random_device or
// std::* distributions, whose outputs differ between standard libraries), so the same options give
// the same Document and the same .glb bytes with a given build. (Across libm versions, sin/cos/pow
// may differ in the last bit; the layouts do not depend on that.)
//
// Does NOT do: write files (see gltf_writer.h), animation outside crowd and moving-light,
// textures beyond small checkers
// (except load-test's procedural noise textures).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "pnb_assets/gltf_writer.h"

namespace pnb::assets {

// street-canyon: a straight street along -Z between two rows of boxes, and a street-level camera
// at the origin looking down it (identity rotation). The sun travels across the street (+X),
// tilted `sunAzimuthDegrees` towards -Z, so the left row's shadows cover the street and climb
// the right row's facades. Each off-screen caster is a tower far out on the sun side whose top
// casts its shadow onto the middle of the street inside the camera frustum; the left row leaves
// an empty lot in front of that spot so the spot is otherwise sunlit. Caster 0 stands behind the
// camera; caster 1 stands ahead of it but outside the left frustum plane (for any aspect ratio up
// to 2.4). Node names: "street-camera", "sun", "building-L<n>"/"building-R<n>",
// "offscreen-tower-<n>", "ground".
struct StreetCanyonOptions {
    uint64_t seed = 1;
    uint64_t targetTriangles = 10000;  // facades are subdivided to get close. Default 10 000.
    float streetLengthMeters = 400.0f; // in front of the camera. Default 400.
    float streetWidthMeters = 20.0f;   // asphalt, kerb to kerb. Default 20.
    float sidewalkMeters = 3.0f;       // between the kerb and the facades. Default 3.
    float minHeightMeters = 20.0f;     // row buildings. Default 20.
    float maxHeightMeters = 120.0f;    // row buildings. Default 120.
    float sunElevationDegrees = 15.0f; // low sun. Default 15.
    float sunAzimuthDegrees = 25.0f;   // 0 = straight across the street. Default 25.
    uint32_t offscreenCasters = 2;     // 0, 1 or 2 towers. Default 2.
    float cameraYFovDegrees = 60.0f;   // Default 60.
    float cameraAspect = 16.0f / 9.0f; // written into the camera. Default 16:9.
};
gltf::Document buildStreetCanyon(const StreetCanyonOptions& options = {});

// flat-city: a square grid of blocks (3 x 3 lots each) separated by streets, with building
// archetypes instanced across the lots (taller towards the centre), pavement, asphalt and a
// grass ring out to the ground size; a sun at 45°, and a camera overlooking the city from a
// corner. Blocks are nodes ("block-<i>-<j>") whose children are the buildings, so the hierarchy
// is exercised. Facades are subdivided so the *rendered* triangle count (every instance counted)
// is close to targetTriangles (within 1 % for targets from 50 000 up).
struct FlatCityOptions {
    uint64_t seed = 1;
    uint64_t targetTriangles = 500000; // rendered triangles. Default 500 000.
    float groundSizeMeters = 2000.0f;  // edge of the square ground. Default 2000.
    float citySizeMeters = 1600.0f;    // edge of the built-up square (<= ground). Default 1600.
    float blockMeters = 100.0f;        // edge of a block. Default 100.
    float streetMeters = 20.0f;        // street width between blocks. Default 20.
    uint32_t archetypes = 24;          // distinct building meshes. Default 24.
    bool instancing = true;            // false: one mesh per building (a big file). Default on.
    float sunElevationDegrees = 45.0f; // Default 45.
};
gltf::Document buildFlatCity(const FlatCityOptions& options = {});

// box-room: the layout of box_room.h (a closed room open towards +Z, red left wall, green right
// wall, white floor/ceiling/back, a tall and a short box, a translucent BLEND double-sided pane),
// with an embedded checker PNG on the floor, a ceiling point light, a sun shining in through the
// open side and a camera looking in. No randomness.
struct BoxRoomGltfOptions {
    float roomSize = 10.0f;    // metres, edge of the cubic room. Default 10.
    uint32_t subdivisions = 1; // quads per face edge (walls and boxes). Default 1.
    uint32_t textureSize = 64; // checker edge in texels. Default 64.
};
gltf::Document buildBoxRoomGltf(const BoxRoomGltfOptions& options = {});

// terrain: a fractal value-noise heightfield (our own lattice hash and quintic interpolation) in
// square tiles (one mesh and node per tile, for culling), floating rock slabs and arches above it
// (the overhangs), and a camera 2 m above the ground at one corner looking across to the far
// corner with a far plane several kilometres away.
struct TerrainOptions {
    uint64_t seed = 1;
    uint32_t quadsPerSide = 512;       // grid resolution; 2 triangles per quad. Default 512.
    uint32_t tileQuads = 64;           // quads per tile edge. Default 64.
    float sizeMeters = 4096.0f;        // edge of the square terrain. Default 4096.
    float heightMeters = 320.0f;       // highest possible elevation. Default 320.
    uint32_t octaves = 6;              // fBm octaves. Default 6.
    uint32_t slabs = 6;                // floating rock slabs. Default 6.
    uint32_t arches = 3;               // rock arches (one instanced mesh). Default 3.
    float sunElevationDegrees = 35.0f; // Default 35.
};
gltf::Document buildTerrain(const TerrainOptions& options = {});

// grazing-plane: a large checkered plane with thin poles, boxes resting on it, a box floating
// 2 cm above it (peter-panning makes it look like the resting ones or worse), a thin wall and a
// slightly tilted ramp, under a sun just above the horizon so shadows are very long and every
// surface is lit at a grazing angle (shadow acne). The camera stands at eye height looking along
// -Z; the sun shines across the view (+X).
struct GrazingPlaneOptions {
    uint64_t seed = 1;
    float sunElevationDegrees = 3.0f; // meant for 2..5. Default 3.
    float planeSizeMeters = 2000.0f;  // Default 2000.
    uint32_t planeSubdivisions = 1;   // quads per plane edge. Default 1.
    uint32_t poles = 12;              // Default 12.
    uint32_t textureSize = 64;        // checker edge in texels. Default 64.
};
gltf::Document buildGrazingPlane(const GrazingPlaneOptions& options = {});

// load-test: a big, texture-heavy scene for load-time measurements. `objects` rocks (UV spheres
// displaced by 3D value noise, so seamless; analytic-gradient normals; spherical UVs repeating
// 4 x 2 times), each its own mesh and node (no instancing: every triangle is stored), on a grid
// ("rock-<n>"), with ~targetTriangles in total. `materials` materials ("rock-material-<k>"),
// each with its own base-colour texture (RGB noise in a per-material palette) and tangent-space
// normal map (from a noise heightfield); both tile seamlessly. Rock n uses material n % materials.
// Images: base colours first, then normal maps, `textureSize`² RGB PNGs (png_writer.h: zlib
// level 6, ~0.6 MiB for a base colour and ~2 MiB for a normal map at 1024²). A camera
// overlooking the grid and a sun at 45°.
struct LoadTestOptions {
    uint64_t seed = 1;
    uint64_t targetTriangles = 1000000; // stored = rendered. Default 1 000 000.
    uint32_t objects = 50;              // Default 50.
    uint32_t materials = 5;             // each with 2 textures. Default 5 (10 textures).
    uint32_t textureSize = 1024;        // texels a side. Default 1024.
};
gltf::Document buildLoadTest(const LoadTestOptions& options = {});

// light-field: a square floor with a `boxesPerSide`² grid of boxes (footprint 30-60 % of a
// cell, heights 1-4 m; one unit-box mesh per colour, scaled by each node: "box-<i>-<j>"), lit
// by `lights` point lights ("point-light-<n>") on a jittered ceil(sqrt(lights))² grid, 4.5-6 m
// above the floor (above every box), each with a finite range (2.5 light-grid cells, at least
// 6 m) and a colour from a fixed palette; intensity falls with sqrt(lights) so the image stays
// in range. A dim sun (intensity 0.3; every scene has a "sun") and a camera looking across the
// field at a low angle, so boxes hide each other (overdraw for forward shading). Every material
// is OPAQUE (the converter places them deferred; a sidecar can move them forward). Geometry and
// its layout do not depend on `lights` (the lights draw from their own random stream).
struct LightFieldOptions {
    uint64_t seed = 1;
    uint32_t lights = 8;             // point lights, 0..4096. Default 8.
    uint32_t boxesPerSide = 8;       // Default 8 (64 boxes, 12 triangles each).
    float sizeMeters = 64.0f;        // floor edge. Default 64.
    uint32_t floorSubdivisions = 16; // floor quads per edge. Default 16.
};
gltf::Document buildLightField(const LightFieldOptions& options = {});

// one-triangle: one 10 m triangle on y = 0 facing up, a camera above looking at it and a sun at
// 40 degrees: the smallest scene there is (nothing casts a shadow on it).
gltf::Document buildOneTriangle();

// wide-flat: a single square ground quad `widthMeters` across and a 5 x 5 field of blocks
// (0.5 m x 0.5 m, `heightMeters` tall) in front of a camera 2.5 m above the ground, sun at 30
// degrees: a scene far wider than it is tall, for shadow fitting and ray-origin precision.
struct WideFlatOptions {
    float widthMeters = 100000.0f; // Default 100 km.
    float heightMeters = 1.0f;     // Default 1 m (10^5 x narrower than wide).
};
gltf::Document buildWideFlat(const WideFlatOptions& options = {});

// atrium: a 24 m x 24 m courtyard walled 14 m high and open to the sky (sun at 55 degrees), a
// ground-floor arcade of columns and arches (five-stone voussoirs) on all four sides carrying an
// upper gallery with a parapet, a red banner in the sun (colour bleeding) and a 0.1 m thin
// partition between sunlit and shaded floor (light leaking through thin walls). For GI: light
// reaches the arcade and the gallery's underside only by bouncing. Camera on the gallery.
gltf::Document buildAtrium();

// lamp-room: a closed 8 x 3 x 6 m room (x in [-4, 4], y in [0, 3], z in [-3, 3]; floor,
// ceiling, four walls facing in, no opening), a crate, a tall box, a floor-to-ceiling pillar and
// a table on four legs, lit by light 0, a spot ("spot-lamp": 60 cd, range 10 m, cone 25/38
// degrees, near the ceiling by the left wall aimed down at the boxes) and light 1, a point light
// ("bulb": 12 cd, range 8 m, 2.2 m up in front of the pillar). No directional light: the converter
// adds its generated default-sun, which cannot enter. One camera ("corner-camera") in the front
// right corner looking across at the boxes. Lit floor and walls reach radiances of ~0.1-0.6 at
// lighting.exposure 1. No randomness.
gltf::Document buildLampRoom();

// colour-room: an open-topped 6 x 3 x 6 m room (x, z in [-3, 3], y in [0, 3]; no ceiling) with a
// red left wall (x = -3), a green right wall (x = 3), white floor, back and front walls, a white
// block and a tall grey one, lit by a sun (60 degrees up, travelling towards +X and a little
// -Z) through the open top onto the floor and the green wall: light that bounces between
// bright walls, where the second and later diffuse bounces add about half again to the first
// (issue 40's held-out-style room, for the multi-bounce indirect truth). One camera
// ("room-camera") above the front wall looking down into the room. No randomness.
gltf::Document buildColourRoom();

// crowd: `count` walkers (a low-poly humanoid of welded tapered tubes, ~1000 triangles, 12 joints:
// hips, spine, chest, head, upper arm and forearm, thigh and shin a side; every vertex weighted
// over one or two joints, blending across each joint) in an 18 x 18 m room (x, z in [-9, 9]) with
// 3.5 m walls and no roof, four corner pillars ("pillars", with the 1.6 m plinth in the middle),
// a sun at 55 degrees ("sun") and two point lights ("lamp-west", "lamp-east", 3 m up).
// Walker i is node "walker-<i>" (its root: translation, rotation, a height scale of 0.92-1.08)
// with joint nodes "walker-<i>/<joint>" and a skinned node "walker-<i>/body"; every body draws the
// one mesh "walker" with its own skin (skin i). Walkers walk 13 circular lanes (radius 1.5 to 7.5
// m, neighbouring lanes in opposite directions; walker i on lane i % 13, spread along it with a
// seeded jitter), one lap in the clip's 24 s, so the clip loops seamlessly. The one clip ("walk",
// linear keys) holds every walker's 12 joint rotations (a 1 s walk cycle in one of 8 seeded
// phases, 8 keys a cycle; walkers of one phase share those samplers) and its root's translation
// and rotation (48 keys a lap). At rest (no clip) each walker stands in its bind pose at its
// start. Cameras: "overview-camera" above the south wall looking down across the room, and
// "floor-camera" at eye level by the west wall.
struct CrowdOptions {
    uint32_t count = 100; // walkers, 1..1000 (clamped). Default 100.
    uint64_t seed = 1;
};
gltf::Document buildCrowd(const CrowdOptions& options = {});

// moving-light: an 8 x 4 x 8 m room (x, z in [-4, 4], y in [0, 4]) open towards +Z, red left and
// green right walls, a static block, lit by a sun at 35 degrees coming in through the open side
// and by "moving-lamp", a point light (20 cd, range 10 m) circling 3.2 m up once per clip. One
// clip ("motion", 4 s, linear keys) also slides "moving-box" (a 0.8 m cube, the node at its base
// centre) from x = -2 to 2 and back through the sun while it turns once about +Y, and squashes
// "morph-ball" (a 0.6 m UV sphere with one morph target flattening it onto its base) twice.
// At rest the lamp, the box and the ball are where the clip starts them. Camera "room-camera"
// outside the open side looking in. No randomness.
gltf::Document buildMovingLight();

// --- Registry (what pnb-make-scene lists) -----------------------------------------------------

struct ProceduralScene {
    std::string_view name;    // e.g. "street-canyon"
    std::string_view summary; // one line
};
// All scenes, in a fixed order.
std::span<const ProceduralScene> proceduralScenes();

struct SceneRequest {
    uint64_t targetTriangles = 0;   // 0 = the scene's default detail
    uint64_t seed = 1;              // ignored by box-room
    std::optional<uint32_t> lights; // point lights; light-field only (others ignore it)
    std::optional<uint32_t> textureSize; // texels a side; load-test only (others ignore it)
    std::optional<uint32_t> count;       // walkers; crowd only (others ignore it)
};
// Builds the named scene. targetTriangles maps onto each scene's detail knob (facade cells,
// grid resolution or subdivisions); the result is as close as that knob allows. Returns nullopt
// for an unknown name.
std::optional<gltf::Document> buildProceduralScene(std::string_view name,
                                                   const SceneRequest& request);

} // namespace pnb::assets
