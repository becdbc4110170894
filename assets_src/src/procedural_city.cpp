// assets_src/src/procedural_city.cpp — the city scenes: street-canyon (a street between rows of
// boxes, off-screen towers shadowing the view) and flat-city (instanced building archetypes on a
// grid of blocks). One file for the two because they share their facade materials and the facade
// cell-size search (procedural_scenes.h documents each scene).
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "procedural_scenes_internal.h"

namespace pnb::assets {

using namespace procedural_detail;

// [SECTION] street-canyon -----------------------------------------------------------------------

gltf::Document buildStreetCanyon(const StreetCanyonOptions& o) {
    Document doc;
    doc.sceneName = "street-canyon";
    const float halfStreet = o.streetWidthMeters / 2;
    const float rowInner = halfStreet + o.sidewalkMeters; // |x| of the street-side facades
    const float elevation = radians(o.sunElevationDegrees);
    const float azimuth = radians(o.sunAzimuthDegrees);
    const Float3 sun = sunDirection(elevation, azimuth);
    constexpr float kBehind = 40.0f;     // the rows start this far behind the camera
    constexpr float kMaxDepth = 30.0f;   // row building depth (x extent) is 18..30 m
    constexpr float kPatch = 15.0f;      // half-length of the sunlit street patch at each spot
    constexpr float kTowerWidth = 24.0f; // top-corner shadows stay within the sidewalks

    const uint32_t asphalt = addMaterial(doc, makeMaterial("asphalt", {0.08f, 0.08f, 0.09f}, 0.9f));
    const uint32_t pavement =
        addMaterial(doc, makeMaterial("pavement", {0.45f, 0.44f, 0.42f}, 0.85f));
    const uint32_t roof = addMaterial(doc, makeMaterial("roof", {0.2f, 0.2f, 0.22f}, 0.8f));
    const uint32_t facades[4] = {
        addMaterial(doc, makeMaterial("brick", {0.5f, 0.22f, 0.15f}, 0.85f)),
        addMaterial(doc, makeMaterial("sandstone", {0.65f, 0.55f, 0.4f}, 0.8f)),
        addMaterial(doc, makeMaterial("concrete", {0.55f, 0.55f, 0.55f}, 0.9f)),
        addMaterial(doc, makeMaterial("stucco", {0.8f, 0.78f, 0.72f}, 0.75f)),
    };
    const uint32_t glass =
        addMaterial(doc, makeMaterial("tower-glass", {0.25f, 0.35f, 0.45f}, 0.3f, 0.4f));

    // Along-street coordinate s = -z (the camera looks towards +s). Buildings as base-centred
    // boxes; `name`, centre (x, s), footprint and height.
    struct Building {
        std::string name;
        float x, s, wx, ws, h;
        uint32_t wall;
    };
    std::vector<Building> buildings;
    struct Lot {
        float s0, s1;
    };
    std::vector<Lot> lots;

    // Off-screen casters. A tower of height h at horizontal distance reach = h / tan(elevation)
    // up-sun of a street spot casts its top's shadow exactly onto that spot. The left row keeps
    // an empty lot wherever a sun ray from the patch around the spot crosses it, so the patch
    // is sunlit apart from the tower's shadow: rays from street points (x0 in +-halfStreet)
    // cross the row's x range at s = s0 - (x0 - x) tan(azimuth).
    const float tanAz = std::tan(azimuth);
    const uint32_t casters = std::min(o.offscreenCasters, 2u);
    for (uint32_t i = 0; i < casters; ++i) {
        const float height = i == 0 ? 180.0f : 200.0f;
        const float reach = height / std::tan(elevation);
        // Caster 0: its spot is 30 m ahead (close enough to cover ~40 pixel rows of a 540p
        // view from eye height), so the tower lands far behind the camera. Caster 1: the spot
        // is chosen so the tower lands ~45 m ahead of the camera but hundreds of metres to the
        // left, i.e. outside the left frustum plane instead; its shadow tip is far down the
        // street (a far-cascade case).
        float spot =
            i == 0 ? std::min(30.0f, 0.5f * o.streetLengthMeters)
                   : std::min(o.streetLengthMeters - 25.0f, reach * std::sin(azimuth) + 45.0f);
        buildings.push_back({"offscreen-tower-" + std::to_string(i), -reach * std::cos(azimuth),
                             spot - reach * std::sin(azimuth), kTowerWidth, kTowerWidth, height,
                             glass});
        lots.push_back(
            {spot - kPatch - (o.streetWidthMeters + o.sidewalkMeters + kMaxDepth) * tanAz - 3.0f,
             spot + kPatch + 3.0f});
    }

    // Rows. Widths 15..40 m along the street, depths 18..30 m, alleys 1..6 m, heights skewed
    // towards the low end (h = min + range * u^1.5) so a few tall ones stand out.
    Pcg32 rng(o.seed, kStreamCanyonRows);
    for (int side = -1; side <= 1; side += 2) {
        float s = -kBehind;
        for (uint32_t n = 0;; ++n) {
            float width = rng.uniform(15, 40), depth = rng.uniform(18, kMaxDepth);
            float u = rng.unit(), gap = rng.uniform(1, 6);
            uint32_t wall = facades[rng.below(4)];
            if (side < 0) {
                for (bool moved = true; moved;) {
                    moved = false;
                    for (const Lot& lot : lots)
                        if (s < lot.s1 && s + width > lot.s0) {
                            s = lot.s1;
                            moved = true;
                        }
                }
            }
            if (s + width > o.streetLengthMeters) break;
            float h =
                o.minHeightMeters + (o.maxHeightMeters - o.minHeightMeters) * u * std::sqrt(u);
            buildings.push_back(
                {std::string("building-") + (side < 0 ? "L" : "R") + std::to_string(n),
                 float(side) * (rowInner + depth / 2), s + width / 2, depth, width, h, wall});
            s += width + gap;
        }
    }

    auto localBox = [](const Building& b) {
        return std::vector<Box>{{{-b.wx / 2, 0, -b.ws / 2}, {b.wx / 2, b.h, b.ws / 2}}};
    };
    constexpr uint64_t kGroundTriangles = 6;
    uint64_t budget =
        o.targetTriangles > kGroundTriangles ? o.targetTriangles - kGroundTriangles : 0;
    float cell = cellSizeForTarget(budget, [&](float c) {
        uint64_t n = 0;
        for (const Building& b : buildings)
            n += trianglesFor(localBox(b), c);
        return n;
    });

    // Ground: street and the ground either side as three non-overlapping quads (no coplanar
    // z-fighting), large enough to hold the towers' bases.
    const float groundHalfWidth = 1000.0f, sBack = -500.0f, sFront = o.streetLengthMeters + 600;
    Mesh ground;
    ground.name = "ground";
    auto groundStrip = [&](float x0, float x1, uint32_t material) {
        Primitive p;
        p.material = material;
        // u along +z, v along +x: u x v = +Y.
        addGrid(p, {x0, 0, -sFront}, {0, 0, sFront - sBack}, {x1 - x0, 0, 0}, 1, 1, false);
        ground.primitives.push_back(std::move(p));
    };
    groundStrip(-groundHalfWidth, -halfStreet, pavement);
    groundStrip(-halfStreet, halfStreet, asphalt);
    groundStrip(halfStreet, groundHalfWidth, pavement);
    const Float3 streetCentre{0, 0, -o.streetLengthMeters / 2};

    addCamera(doc, "street-camera", {0, 1.7f, 0}, {0, 0, -1}, radians(o.cameraYFovDegrees),
              o.cameraAspect, 0.5f, 2000.0f);
    addCamera(doc, "overview-camera", {150, 220, 120}, streetCentre - Float3{150, 220, 120},
              radians(50), o.cameraAspect, 1.0f, 5000.0f);
    addSun(doc, sun, streetCentre, 800.0f, {1.0f, 0.85f, 0.7f}, 3.0f);
    addNode(doc, meshNode("ground", addMesh(doc, std::move(ground))));
    for (const Building& b : buildings) {
        int32_t mesh = addMesh(doc, boxesMesh(b.name, localBox(b), cell, b.wall, roof));
        addNode(doc, meshNode(b.name, mesh, {b.x, 0, -b.s}));
    }
    return doc;
}

// [SECTION] flat-city ---------------------------------------------------------------------------

namespace {

// The city's grid: `blocks` × `blocks` blocks of 3 × 3 lots, streets between them, centred on
// the origin, on a ground at least `groundSizeMeters` wide.
struct CityGrid {
    float pitch = 0; // block plus street
    uint32_t blocks = 0;
    float span = 0;  // edge of the built area
    float start = 0; // its west and north edge
    float halfGround = 0;
    float lotSize = 0;
};

CityGrid cityGrid(const FlatCityOptions& o) {
    CityGrid g;
    g.pitch = o.blockMeters + o.streetMeters;
    g.blocks = uint32_t(std::max(1.0f, std::floor((o.citySizeMeters + o.streetMeters) / g.pitch)));
    g.span = float(g.blocks) * g.pitch - o.streetMeters;
    g.start = -g.span / 2;
    g.halfGround = std::max(o.groundSizeMeters, g.span) / 2;
    g.lotSize = o.blockMeters / 3;
    return g;
}

struct CityMaterials {
    uint32_t asphalt, pavement, grass, roof;
    uint32_t facades[5];
};

CityMaterials addCityMaterials(Document& doc) {
    CityMaterials m;
    m.asphalt = addMaterial(doc, makeMaterial("asphalt", {0.08f, 0.08f, 0.09f}, 0.9f));
    m.pavement = addMaterial(doc, makeMaterial("pavement", {0.45f, 0.44f, 0.42f}, 0.85f));
    m.grass = addMaterial(doc, makeMaterial("grass", {0.16f, 0.32f, 0.1f}, 0.95f));
    m.roof = addMaterial(doc, makeMaterial("roof", {0.2f, 0.2f, 0.22f}, 0.8f));
    m.facades[0] = addMaterial(doc, makeMaterial("brick", {0.5f, 0.22f, 0.15f}, 0.85f));
    m.facades[1] = addMaterial(doc, makeMaterial("sandstone", {0.65f, 0.55f, 0.4f}, 0.8f));
    m.facades[2] = addMaterial(doc, makeMaterial("concrete", {0.55f, 0.55f, 0.55f}, 0.9f));
    m.facades[3] = addMaterial(doc, makeMaterial("stucco", {0.8f, 0.78f, 0.72f}, 0.75f));
    m.facades[4] = addMaterial(doc, makeMaterial("blue-glass", {0.2f, 0.3f, 0.42f}, 0.25f, 0.5f));
    return m;
}

struct Archetype {
    std::vector<Box> boxes;
    uint32_t wall;
    uint64_t instances = 0;
};

// Archetypes: a third each low (8-20 m), mid (20-60 m) and high (60-180 m); styles plain box,
// setback tower (upper third narrower) and box with a rooftop plant room.
std::vector<Archetype> makeArchetypes(const FlatCityOptions& o, const CityGrid& g,
                                      const CityMaterials& materials) {
    // Footprints up to 0.84 lot: rotated by any multiple of 90 degrees they still fit.
    const float maxFootprint = 0.84f * g.lotSize;
    const uint32_t archetypeCount = std::max(3u, o.archetypes);
    std::vector<Archetype> archetypes(archetypeCount);
    Pcg32 arng(o.seed, kStreamCityArchetypes);
    for (uint32_t k = 0; k < archetypeCount; ++k) {
        const uint32_t cls = k * 3 / archetypeCount;
        const float w = arng.uniform(0.55f, 1.0f) * maxFootprint;
        const float d = arng.uniform(0.55f, 1.0f) * maxFootprint;
        const float h = cls == 0   ? arng.uniform(8, 20)
                        : cls == 1 ? arng.uniform(20, 60)
                                   : arng.uniform(60, 180);
        const uint32_t style = arng.below(3);
        Archetype& a = archetypes[k];
        a.wall = materials.facades[arng.below(5)];
        if (style == 1 && cls > 0) {
            const float split = 0.65f * h, iw = 0.65f * w, id = 0.65f * d;
            a.boxes.push_back({{-w / 2, 0, -d / 2}, {w / 2, split, d / 2}});
            a.boxes.push_back({{-iw / 2, split, -id / 2}, {iw / 2, h, id / 2}});
        } else {
            a.boxes.push_back({{-w / 2, 0, -d / 2}, {w / 2, h, d / 2}});
            if (style == 2) {
                const float pw = 0.3f * w, pd = 0.3f * d;
                a.boxes.push_back({{-pw / 2, h, -pd / 2}, {pw / 2, h + 4, pd / 2}});
            }
        }
    }
    return archetypes;
}

// A building on a lot: block (i, j), lot (a, b) in it, which archetype, turned how often.
struct Placement {
    uint32_t blockI, blockJ, lotA, lotB, archetype, quarterTurns;
};

// Lots: 3 x 3 per block; downtown (near the centre) favours the high class. Counts each
// archetype's instances.
std::vector<Placement> placeBuildings(const FlatCityOptions& o, const CityGrid& g,
                                      std::vector<Archetype>& archetypes) {
    const auto archetypeCount = uint32_t(archetypes.size());
    auto classRange = [&](uint32_t cls) {
        uint32_t first = (cls * archetypeCount + 2) / 3,
                 last = ((cls + 1) * archetypeCount + 2) / 3;
        return std::pair{first, std::max(first + 1, last)};
    };
    std::vector<Placement> placements;
    Pcg32 rng(o.seed, kStreamCityLayout);
    const float downtownRadius = 0.3f * g.span;
    for (uint32_t j = 0; j < g.blocks; ++j)
        for (uint32_t i = 0; i < g.blocks; ++i)
            for (uint32_t b = 0; b < 3; ++b)
                for (uint32_t a = 0; a < 3; ++a) {
                    const float x = g.start + float(i) * g.pitch + (float(a) + 0.5f) * g.lotSize;
                    const float z = g.start + float(j) * g.pitch + (float(b) + 0.5f) * g.lotSize;
                    const float r = std::sqrt(x * x + z * z) / downtownRadius;
                    const float f = std::exp(-r * r);
                    const bool empty = rng.chance(0.06f);
                    const float u = rng.unit();
                    const uint32_t cls = u < 0.75f * f ? 2 : u < 0.25f + 0.95f * f ? 1 : 0;
                    auto [first, last] = classRange(cls);
                    const uint32_t archetype = first + rng.below(last - first);
                    const uint32_t turns = rng.below(4);
                    if (empty) continue; // a plaza: the block's pavement shows through
                    placements.push_back({i, j, a, b, archetype, turns});
                    ++archetypes[archetype].instances;
                }
    return placements;
}

// Ground: block quads (pavement), street quads (asphalt) and a grass ring, none
// overlapping. Horizontal streets run the full span; vertical ones sit between blocks.
Mesh cityGround(const FlatCityOptions& o, const CityGrid& g, const CityMaterials& materials) {
    Mesh ground;
    ground.name = "ground";
    ground.primitives.resize(3);
    ground.primitives[0].material = materials.pavement;
    ground.primitives[1].material = materials.asphalt;
    ground.primitives[2].material = materials.grass;
    auto quad = [&](uint32_t prim, float x0, float z0, float x1, float z1) {
        addGrid(ground.primitives[prim], {x0, 0, z0}, {0, 0, z1 - z0}, {x1 - x0, 0, 0}, 1, 1,
                false);
    };
    const float start = g.start, span = g.span, halfGround = g.halfGround;
    for (uint32_t j = 0; j < g.blocks; ++j) {
        const float z0 = start + float(j) * g.pitch, z1 = z0 + o.blockMeters;
        for (uint32_t i = 0; i < g.blocks; ++i) {
            const float x0 = start + float(i) * g.pitch, x1 = x0 + o.blockMeters;
            quad(0, x0, z0, x1, z1);
            if (i + 1 < g.blocks) quad(1, x1, z0, x1 + o.streetMeters, z1);
        }
        if (j + 1 < g.blocks) quad(1, start, z1, start + span, z1 + o.streetMeters);
    }
    quad(2, -halfGround, -halfGround, start, halfGround);       // west
    quad(2, start + span, -halfGround, halfGround, halfGround); // east
    quad(2, start, -halfGround, start + span, start);           // north
    quad(2, start, start + span, start + span, halfGround);     // south
    return ground;
}

// One cell size for every facade, chosen so the rendered total (ground included) meets the
// target.
float facadeCellSize(const FlatCityOptions& o, const Mesh& ground,
                     const std::vector<Archetype>& archetypes) {
    uint64_t groundTriangles = 0;
    for (const Primitive& p : ground.primitives)
        groundTriangles += p.triangleCount();
    const uint64_t budget =
        o.targetTriangles > groundTriangles ? o.targetTriangles - groundTriangles : 0;
    return cellSizeForTarget(budget, [&](float c) {
        uint64_t n = 0;
        for (const Archetype& a : archetypes)
            n += a.instances * trianglesFor(a.boxes, c);
        return n;
    });
}

// A node per block under the city node, indexed j * blocks + i.
std::vector<uint32_t> addBlockNodes(Document& doc, const FlatCityOptions& o, const CityGrid& g,
                                    uint32_t cityNode) {
    std::vector<uint32_t> blockNode(size_t(g.blocks) * g.blocks, 0);
    for (uint32_t j = 0; j < g.blocks; ++j)
        for (uint32_t i = 0; i < g.blocks; ++i) {
            Node block;
            block.name = "block-" + std::to_string(i) + "-" + std::to_string(j);
            block.translation = {g.start + float(i) * g.pitch + o.blockMeters / 2, 0,
                                 g.start + float(j) * g.pitch + o.blockMeters / 2};
            blockNode[size_t(j) * g.blocks + i] = addNode(doc, std::move(block));
            doc.nodes[cityNode].children.push_back(blockNode[size_t(j) * g.blocks + i]);
        }
    return blockNode;
}

// The buildings: with instancing one mesh per used archetype that every placement shares,
// else a mesh of its own per placement; each a node under its block.
void addBuildings(Document& doc, const FlatCityOptions& o, const CityGrid& g,
                  const std::vector<Archetype>& archetypes,
                  const std::vector<Placement>& placements, float cell, uint32_t roof,
                  const std::vector<uint32_t>& blockNode) {
    std::vector<int32_t> archetypeMesh(archetypes.size(), kNone);
    if (o.instancing)
        for (size_t k = 0; k < archetypes.size(); ++k)
            if (archetypes[k].instances > 0)
                archetypeMesh[k] =
                    addMesh(doc, boxesMesh("building-archetype-" + std::to_string(k),
                                           archetypes[k].boxes, cell, archetypes[k].wall, roof));
    for (const Placement& p : placements) {
        const std::string name = "building-" + std::to_string(p.blockI) + "-" +
                                 std::to_string(p.blockJ) + "-" + std::to_string(p.lotA) +
                                 std::to_string(p.lotB);
        int32_t mesh = archetypeMesh[p.archetype];
        if (!o.instancing) {
            const Archetype& a = archetypes[p.archetype];
            mesh = addMesh(doc, boxesMesh(name, a.boxes, cell, a.wall, roof));
        }
        const Float3 local{(float(p.lotA) - 1.0f) * g.lotSize, 0,
                           (float(p.lotB) - 1.0f) * g.lotSize};
        const uint32_t node = addNode(
            doc, meshNode(name, mesh, local, gltf::rotationY(float(p.quarterTurns) * kPi / 2)));
        doc.nodes[blockNode[size_t(p.blockJ) * g.blocks + p.blockI]].children.push_back(node);
    }
}

} // namespace

gltf::Document buildFlatCity(const FlatCityOptions& o) {
    Document doc;
    doc.sceneName = "flat-city";
    const CityGrid grid = cityGrid(o);
    const CityMaterials materials = addCityMaterials(doc);
    std::vector<Archetype> archetypes = makeArchetypes(o, grid, materials);
    const std::vector<Placement> placements = placeBuildings(o, grid, archetypes);
    Mesh ground = cityGround(o, grid, materials);
    const float cell = facadeCellSize(o, ground, archetypes);

    const float halfGround = grid.halfGround;
    const float elevation = radians(o.sunElevationDegrees);
    addCamera(doc, "overview-camera",
              {-0.45f * halfGround * 2, 0.22f * halfGround * 2, 0.45f * halfGround * 2},
              {0.45f, -0.22f, -0.45f}, radians(50), 16.0f / 9.0f, 1.0f, 6000.0f);
    addSun(doc, sunDirection(elevation, radians(30)), {0, 0, 0}, 1500.0f, {1.0f, 0.96f, 0.9f},
           3.0f);
    Node city;
    city.name = "city";
    const uint32_t cityNode = addNode(doc, std::move(city));
    doc.nodes[cityNode].children.push_back(
        addNode(doc, meshNode("ground", addMesh(doc, std::move(ground)))));
    const std::vector<uint32_t> blockNode = addBlockNodes(doc, o, grid, cityNode);
    addBuildings(doc, o, grid, archetypes, placements, cell, materials.roof, blockNode);
    return doc;
}

} // namespace pnb::assets
