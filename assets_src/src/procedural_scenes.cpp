// Procedural source scenes (see procedural_scenes.h).
//
// Index of this file (grep for the markers):
//   [SECTION] Random numbers and noise
//   [SECTION] Geometry helpers
//   [SECTION] street-canyon
//   [SECTION] flat-city
//   [SECTION] box-room
//   [SECTION] terrain
//   [SECTION] grazing-plane
//   [SECTION] load-test
//   [SECTION] light-field
//   [SECTION] lamp-room
//   [SECTION] Registry
//
// Based on: M. E. O'Neill, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
// Algorithms for Random Number Generation" (2014) for Pcg32; D. Lemire, "Fast Random Integer
// Generation in an Interval" (2019) for bounded integers; K. Perlin, "Improving Noise" (2002) for
// the quintic fade; the murmur3 fmix32 finaliser for the lattice hash.

#include "pnb_assets/procedural_scenes.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "pnb_assets/png_writer.h"

namespace pnb::assets {

using gltf::Document;
using gltf::Float2;
using gltf::Float3;
using gltf::Float4;
using gltf::kNone;
using gltf::Material;
using gltf::Mesh;
using gltf::Node;
using gltf::Primitive;

namespace {

constexpr float kPi = std::numbers::pi_v<float>;
float radians(float degrees) {
    return degrees * (kPi / 180.0f);
}

// [SECTION] Random numbers and noise ------------------------------------------------------------

// PCG32 (XSH RR, 64-bit state). Each scene part draws from its own stream, so a change in one
// part (say, the triangle target) does not reshuffle another part's layout.
class Pcg32 {
public:
    Pcg32(uint64_t seed, uint64_t stream) : mInc((stream << 1) | 1) {
        next();
        mState += seed;
        next();
    }

    uint32_t next() {
        uint64_t old = mState;
        mState = old * 6364136223846793005ULL + mInc;
        auto xorshifted = uint32_t(((old >> 18) ^ old) >> 27);
        auto rot = uint32_t(old >> 59);
        return (xorshifted >> rot) | (xorshifted << ((32 - rot) & 31));
    }

    // [0, 1) with 24 bits of precision (every value exactly representable as a float).
    float unit() { return float(next() >> 8) * 0x1p-24f; }
    float uniform(float lo, float hi) { return lo + (hi - lo) * unit(); }
    bool chance(float p) { return unit() < p; }

    // Unbiased integer in [0, n), n >= 1 (Lemire's multiply-and-reject).
    uint32_t below(uint32_t n) {
        uint64_t m = uint64_t(next()) * n;
        if (uint32_t(m) < n) {
            uint32_t threshold = (0u - n) % n;
            while (uint32_t(m) < threshold)
                m = uint64_t(next()) * n;
        }
        return uint32_t(m >> 32);
    }

private:
    uint64_t mState = 0;
    uint64_t mInc;
};

// Stream ids, one per scene part (arbitrary distinct constants).
constexpr uint64_t kStreamCanyonRows = 11, kStreamCityLayout = 21, kStreamCityArchetypes = 22,
                   kStreamTerrainProps = 31, kStreamGrazingProps = 41, kStreamLoadTestRocks = 51,
                   kStreamLightFieldBoxes = 61, kStreamLightFieldLights = 62;

uint32_t fmix32(uint32_t h) {
    h ^= h >> 16;
    h *= 0x85EBCA6Bu;
    h ^= h >> 13;
    h *= 0xC2B2AE35u;
    h ^= h >> 16;
    return h;
}

uint32_t latticeHash(int32_t x, int32_t y, uint32_t seed) {
    return fmix32(uint32_t(x) * 0x8DA6B343u ^ fmix32(uint32_t(y) * 0xD8163841u ^ seed));
}

// Value noise in [0, 1): random values on the integer lattice, blended with Perlin's quintic
// fade so the surface has continuous first and second derivatives (smooth normals).
float valueNoise(float x, float y, uint32_t seed) {
    float fx = std::floor(x), fy = std::floor(y);
    auto ix = int32_t(fx), iy = int32_t(fy);
    float tx = x - fx, ty = y - fy;
    auto fade = [](float t) { return t * t * t * (t * (t * 6 - 15) + 10); };
    auto at = [&](int32_t i, int32_t j) {
        return float(latticeHash(ix + i, iy + j, seed) >> 8) * 0x1p-24f;
    };
    float ux = fade(tx), uy = fade(ty);
    float a = at(0, 0) + (at(1, 0) - at(0, 0)) * ux;
    float b = at(0, 1) + (at(1, 1) - at(0, 1)) * ux;
    return a + (b - a) * uy;
}

// Value noise that repeats every `period` lattice cells in x and y (the lattice wraps), so
// textures built from it tile seamlessly.
float tileableValueNoise(float x, float y, int32_t period, uint32_t seed) {
    float fx = std::floor(x), fy = std::floor(y);
    auto ix = int32_t(fx), iy = int32_t(fy);
    float tx = x - fx, ty = y - fy;
    auto fade = [](float t) { return t * t * t * (t * (t * 6 - 15) + 10); };
    auto wrap = [&](int32_t v) { return ((v % period) + period) % period; };
    auto at = [&](int32_t i, int32_t j) {
        return float(latticeHash(wrap(ix + i), wrap(iy + j), seed) >> 8) * 0x1p-24f;
    };
    float ux = fade(tx), uy = fade(ty);
    float a = at(0, 0) + (at(1, 0) - at(0, 0)) * ux;
    float b = at(0, 1) + (at(1, 1) - at(0, 1)) * ux;
    return a + (b - a) * uy;
}

// 3D value noise in [0, 1), trilinear with the quintic fade.
float valueNoise3(float x, float y, float z, uint32_t seed) {
    float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
    auto ix = int32_t(fx), iy = int32_t(fy), iz = int32_t(fz);
    auto fade = [](float t) { return t * t * t * (t * (t * 6 - 15) + 10); };
    float ux = fade(x - fx), uy = fade(y - fy), uz = fade(z - fz);
    auto at = [&](int32_t i, int32_t j, int32_t k) {
        uint32_t h = fmix32(uint32_t(iz + k) * 0x9E3779B1u ^ seed);
        return float(latticeHash(ix + i, iy + j, h) >> 8) * 0x1p-24f;
    };
    auto plane = [&](int32_t k) {
        float a = at(0, 0, k) + (at(1, 0, k) - at(0, 0, k)) * ux;
        float b = at(0, 1, k) + (at(1, 1, k) - at(0, 1, k)) * ux;
        return a + (b - a) * uy;
    };
    float p0 = plane(0);
    return p0 + (plane(1) - p0) * uz;
}

uint32_t foldSeed(uint64_t seed) {
    return uint32_t(seed) ^ uint32_t(seed >> 32) ^ 0x5EEDu;
}

// [SECTION] Geometry helpers --------------------------------------------------------------------

Float3 operator+(Float3 a, Float3 b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
Float3 operator-(Float3 a, Float3 b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Float3 operator*(Float3 a, float s) {
    return {a[0] * s, a[1] * s, a[2] * s};
}
Float3 cross(Float3 a, Float3 b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Float3 normalize(Float3 v) {
    return v * (1.0f / std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
}

// Direction the light travels for a sun `elevation` above the horizon whose horizontal travel
// direction is +X turned `azimuth` towards -Z.
Float3 sunDirection(float elevationRadians, float azimuthRadians) {
    float c = std::cos(elevationRadians);
    return {c * std::cos(azimuthRadians), -std::sin(elevationRadians),
            -c * std::sin(azimuthRadians)};
}

// a + (b - a) x, exact at both ends (x = 0 gives a, x = 1 gives b) and constant where a == b,
// so axis-aligned faces stay exactly planar and box corners are bit-identical on every face.
Float3 lerp(Float3 a, Float3 b, float x) {
    return x == 1.0f ? b : a + (b - a) * x;
}

// Appends an nu x nv grid of quads with corners origin, origin + u, origin + v and
// origin + u + v; the face normal is u x v, so triangles are counter-clockwise seen from the
// front.
void addGrid(Primitive& p, Float3 origin, Float3 u, Float3 v, uint32_t nu, uint32_t nv, bool withUv,
             Float2 uvExtent = {1, 1}) {
    const Float3 c00 = origin, c10 = origin + u, c01 = origin + v, c11 = origin + u + v;
    const Float3 normal = normalize(cross(u, v));
    const auto base = uint32_t(p.positions.size());
    for (uint32_t j = 0; j <= nv; ++j)
        for (uint32_t i = 0; i <= nu; ++i) {
            float s = float(i) / float(nu), t = float(j) / float(nv);
            p.positions.push_back(lerp(lerp(c00, c10, s), lerp(c01, c11, s), t));
            p.normals.push_back(normal);
            if (withUv) p.uv0.push_back({s * uvExtent[0], t * uvExtent[1]});
        }
    for (uint32_t j = 0; j < nv; ++j)
        for (uint32_t i = 0; i < nu; ++i) {
            uint32_t a = base + j * (nu + 1) + i, b = a + 1, c = a + nu + 1, d = c + 1;
            p.indices.insert(p.indices.end(), {a, b, d, a, d, c});
        }
}

// Cells per box axis. Side faces are nx (or nz) by ny quads, top and bottom nx by nz, so every
// edge is split the same way on both faces that share it (no T-junctions, no cracks).
struct BoxCells {
    uint32_t nx = 1, ny = 1, nz = 1;
};

uint64_t boxTriangles(BoxCells c) {
    return 4ull * c.ny * (c.nx + c.nz) + 4ull * c.nx * c.nz;
}

// A closed axis-aligned box from lo to hi with outward faces: side faces into `sides`, top and
// bottom into `caps` (which may be the same primitive).
void addBox(Primitive& sides, Primitive& caps, Float3 lo, Float3 hi, BoxCells c, bool withUv) {
    Float3 X{hi[0] - lo[0], 0, 0}, Y{0, hi[1] - lo[1], 0}, Z{0, 0, hi[2] - lo[2]};
    addGrid(sides, lo, Y, X, c.ny, c.nx, withUv);     // -Z
    addGrid(sides, lo + Z, X, Y, c.nx, c.ny, withUv); // +Z
    addGrid(sides, lo, Z, Y, c.nz, c.ny, withUv);     // -X
    addGrid(sides, lo + X, Y, Z, c.ny, c.nz, withUv); // +X
    addGrid(caps, lo, X, Z, c.nx, c.nz, withUv);      // -Y
    addGrid(caps, lo + Y, Z, X, c.nz, c.nx, withUv);  // +Y
}

uint32_t cellsAlong(float extentMeters, float cellMeters) {
    float n = std::round(extentMeters / cellMeters);
    return uint32_t(std::clamp(n, 1.0f, 4096.0f));
}

struct Box {
    Float3 lo, hi;
};

BoxCells cellsFor(const Box& b, float cellMeters) {
    return {cellsAlong(b.hi[0] - b.lo[0], cellMeters), cellsAlong(b.hi[1] - b.lo[1], cellMeters),
            cellsAlong(b.hi[2] - b.lo[2], cellMeters)};
}

uint64_t trianglesFor(const std::vector<Box>& boxes, float cellMeters) {
    uint64_t n = 0;
    for (const Box& b : boxes)
        n += boxTriangles(cellsFor(b, cellMeters));
    return n;
}

// A mesh of closed boxes: walls (side faces) in one primitive, roofs and floors in another.
Mesh boxesMesh(std::string name, const std::vector<Box>& boxes, float cellMeters,
               uint32_t wallMaterial, uint32_t roofMaterial) {
    Mesh m;
    m.name = std::move(name);
    m.primitives.resize(2);
    m.primitives[0].material = wallMaterial;
    m.primitives[1].material = roofMaterial;
    for (const Box& b : boxes)
        addBox(m.primitives[0], m.primitives[1], b.lo, b.hi, cellsFor(b, cellMeters), false);
    return m;
}

// The facade cell size (metres) whose triangle count, as returned by the non-increasing step
// function countFor(cell), is closest to `target`. Bisection in log space between a 5 cm and a
// 10 km cell; the count is cheap to evaluate (arithmetic per box), so 64 rounds cost nothing.
template <class CountFn> float cellSizeForTarget(uint64_t target, CountFn countFor) {
    float fine = 0.05f, coarse = 10000.0f;
    for (int i = 0; i < 64; ++i) {
        float mid = std::sqrt(fine * coarse);
        if (countFor(mid) > target)
            fine = mid;
        else
            coarse = mid;
    }
    auto distance = [&](float cell) {
        uint64_t n = countFor(cell);
        return n > target ? n - target : target - n;
    };
    return distance(fine) < distance(coarse) ? fine : coarse;
}

Material makeMaterial(std::string name, Float3 rgb, float roughness, float metallic = 0.0f) {
    Material m;
    m.name = std::move(name);
    m.baseColorFactor = {rgb[0], rgb[1], rgb[2], 1.0f};
    m.roughnessFactor = roughness;
    m.metallicFactor = metallic;
    return m;
}

uint32_t addMaterial(Document& doc, Material m) {
    doc.materials.push_back(std::move(m));
    return uint32_t(doc.materials.size() - 1);
}

int32_t addMesh(Document& doc, Mesh m) {
    doc.meshes.push_back(std::move(m));
    return int32_t(doc.meshes.size() - 1);
}

uint32_t addNode(Document& doc, Node n) {
    doc.nodes.push_back(std::move(n));
    return uint32_t(doc.nodes.size() - 1);
}

Node meshNode(std::string name, int32_t mesh, Float3 translation = {0, 0, 0},
              Float4 rotation = {0, 0, 0, 1}) {
    Node n;
    n.name = std::move(name);
    n.mesh = mesh;
    n.translation = translation;
    n.rotation = rotation;
    return n;
}

// Adds a camera and its node, looking along `forward` from `position`.
uint32_t addCamera(Document& doc, std::string name, Float3 position, Float3 forward,
                   float yfovRadians, float aspect, float znear, float zfar) {
    doc.cameras.push_back({.name = name,
                           .yfovRadians = yfovRadians,
                           .aspectRatio = aspect,
                           .znear = znear,
                           .zfar = zfar});
    Node n;
    n.name = std::move(name);
    n.translation = position;
    n.rotation = gltf::lookRotation(forward);
    n.camera = int32_t(doc.cameras.size() - 1);
    return addNode(doc, std::move(n));
}

// Adds a directional light shining along `direction`; the node sits `distance` up-sun of
// `target` so it is easy to find in an editor (the position does not affect the lighting).
uint32_t addSun(Document& doc, Float3 direction, Float3 target, float distance, Float3 color,
                float intensity) {
    doc.lights.push_back({.name = "sun",
                          .type = gltf::LightType::Directional,
                          .color = color,
                          .intensity = intensity});
    Node n;
    n.name = "sun";
    n.translation = target - normalize(direction) * distance;
    n.rotation = gltf::lookRotation(direction);
    n.light = int32_t(doc.lights.size() - 1);
    return addNode(doc, std::move(n));
}

// A two-tone checker (RGB, `tile` texels per square) as PNG bytes.
std::vector<uint8_t> checkerPng(uint32_t size, uint32_t tile, Float3 light, Float3 dark) {
    std::vector<uint8_t> pixels(size_t(size) * size * 3);
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            const Float3& c = ((x / tile) + (y / tile)) % 2 == 0 ? light : dark;
            uint8_t* p = &pixels[(size_t(y) * size + x) * 3];
            for (int k = 0; k < 3; ++k)
                p[k] = uint8_t(std::lround(c[k] * 255.0f));
        }
    return encodePng(size, size, 3, pixels);
}

// [SECTION] street-canyon -----------------------------------------------------------------------

} // namespace

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

gltf::Document buildFlatCity(const FlatCityOptions& o) {
    Document doc;
    doc.sceneName = "flat-city";
    const float pitch = o.blockMeters + o.streetMeters;
    const auto blocks =
        uint32_t(std::max(1.0f, std::floor((o.citySizeMeters + o.streetMeters) / pitch)));
    const float span = float(blocks) * pitch - o.streetMeters;
    const float start = -span / 2;
    const float halfGround = std::max(o.groundSizeMeters, span) / 2;
    const float lotSize = o.blockMeters / 3;
    // Footprints up to 0.84 lot: rotated by any multiple of 90 degrees they still fit.
    const float maxFootprint = 0.84f * lotSize;

    const uint32_t asphalt = addMaterial(doc, makeMaterial("asphalt", {0.08f, 0.08f, 0.09f}, 0.9f));
    const uint32_t pavement =
        addMaterial(doc, makeMaterial("pavement", {0.45f, 0.44f, 0.42f}, 0.85f));
    const uint32_t grass = addMaterial(doc, makeMaterial("grass", {0.16f, 0.32f, 0.1f}, 0.95f));
    const uint32_t roof = addMaterial(doc, makeMaterial("roof", {0.2f, 0.2f, 0.22f}, 0.8f));
    const uint32_t facades[5] = {
        addMaterial(doc, makeMaterial("brick", {0.5f, 0.22f, 0.15f}, 0.85f)),
        addMaterial(doc, makeMaterial("sandstone", {0.65f, 0.55f, 0.4f}, 0.8f)),
        addMaterial(doc, makeMaterial("concrete", {0.55f, 0.55f, 0.55f}, 0.9f)),
        addMaterial(doc, makeMaterial("stucco", {0.8f, 0.78f, 0.72f}, 0.75f)),
        addMaterial(doc, makeMaterial("blue-glass", {0.2f, 0.3f, 0.42f}, 0.25f, 0.5f)),
    };

    // Archetypes: a third each low (8-20 m), mid (20-60 m) and high (60-180 m); styles plain box,
    // setback tower (upper third narrower) and box with a rooftop plant room.
    struct Archetype {
        std::vector<Box> boxes;
        uint32_t wall;
        uint64_t instances = 0;
    };
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
        a.wall = facades[arng.below(5)];
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
    auto classRange = [&](uint32_t cls) {
        uint32_t first = (cls * archetypeCount + 2) / 3,
                 last = ((cls + 1) * archetypeCount + 2) / 3;
        return std::pair{first, std::max(first + 1, last)};
    };

    // Lots: 3 x 3 per block; downtown (near the centre) favours the high class.
    struct Placement {
        uint32_t blockI, blockJ, lotA, lotB, archetype, quarterTurns;
    };
    std::vector<Placement> placements;
    Pcg32 rng(o.seed, kStreamCityLayout);
    const float downtownRadius = 0.3f * span;
    for (uint32_t j = 0; j < blocks; ++j)
        for (uint32_t i = 0; i < blocks; ++i)
            for (uint32_t b = 0; b < 3; ++b)
                for (uint32_t a = 0; a < 3; ++a) {
                    const float x = start + float(i) * pitch + (float(a) + 0.5f) * lotSize;
                    const float z = start + float(j) * pitch + (float(b) + 0.5f) * lotSize;
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

    // Ground: block quads (pavement), street quads (asphalt) and a grass ring, none
    // overlapping. Horizontal streets run the full span; vertical ones sit between blocks.
    Mesh ground;
    ground.name = "ground";
    ground.primitives.resize(3);
    ground.primitives[0].material = pavement;
    ground.primitives[1].material = asphalt;
    ground.primitives[2].material = grass;
    auto quad = [&](uint32_t prim, float x0, float z0, float x1, float z1) {
        addGrid(ground.primitives[prim], {x0, 0, z0}, {0, 0, z1 - z0}, {x1 - x0, 0, 0}, 1, 1,
                false);
    };
    for (uint32_t j = 0; j < blocks; ++j) {
        const float z0 = start + float(j) * pitch, z1 = z0 + o.blockMeters;
        for (uint32_t i = 0; i < blocks; ++i) {
            const float x0 = start + float(i) * pitch, x1 = x0 + o.blockMeters;
            quad(0, x0, z0, x1, z1);
            if (i + 1 < blocks) quad(1, x1, z0, x1 + o.streetMeters, z1);
        }
        if (j + 1 < blocks) quad(1, start, z1, start + span, z1 + o.streetMeters);
    }
    quad(2, -halfGround, -halfGround, start, halfGround);       // west
    quad(2, start + span, -halfGround, halfGround, halfGround); // east
    quad(2, start, -halfGround, start + span, start);           // north
    quad(2, start, start + span, start + span, halfGround);     // south
    uint64_t groundTriangles = 0;
    for (const Primitive& p : ground.primitives)
        groundTriangles += p.triangleCount();

    // One cell size for every facade, chosen so the rendered total meets the target.
    const uint64_t budget =
        o.targetTriangles > groundTriangles ? o.targetTriangles - groundTriangles : 0;
    const float cell = cellSizeForTarget(budget, [&](float c) {
        uint64_t n = 0;
        for (const Archetype& a : archetypes)
            n += a.instances * trianglesFor(a.boxes, c);
        return n;
    });

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

    std::vector<int32_t> archetypeMesh(archetypeCount, kNone);
    if (o.instancing)
        for (uint32_t k = 0; k < archetypeCount; ++k)
            if (archetypes[k].instances > 0)
                archetypeMesh[k] =
                    addMesh(doc, boxesMesh("building-archetype-" + std::to_string(k),
                                           archetypes[k].boxes, cell, archetypes[k].wall, roof));
    std::vector<uint32_t> blockNode(size_t(blocks) * blocks, 0);
    for (uint32_t j = 0; j < blocks; ++j)
        for (uint32_t i = 0; i < blocks; ++i) {
            Node block;
            block.name = "block-" + std::to_string(i) + "-" + std::to_string(j);
            block.translation = {start + float(i) * pitch + o.blockMeters / 2, 0,
                                 start + float(j) * pitch + o.blockMeters / 2};
            blockNode[size_t(j) * blocks + i] = addNode(doc, std::move(block));
            doc.nodes[cityNode].children.push_back(blockNode[size_t(j) * blocks + i]);
        }
    for (const Placement& p : placements) {
        const std::string name = "building-" + std::to_string(p.blockI) + "-" +
                                 std::to_string(p.blockJ) + "-" + std::to_string(p.lotA) +
                                 std::to_string(p.lotB);
        int32_t mesh = archetypeMesh[p.archetype];
        if (!o.instancing) {
            const Archetype& a = archetypes[p.archetype];
            mesh = addMesh(doc, boxesMesh(name, a.boxes, cell, a.wall, roof));
        }
        const Float3 local{(float(p.lotA) - 1.0f) * lotSize, 0, (float(p.lotB) - 1.0f) * lotSize};
        const uint32_t node = addNode(
            doc, meshNode(name, mesh, local, gltf::rotationY(float(p.quarterTurns) * kPi / 2)));
        doc.nodes[blockNode[size_t(p.blockJ) * blocks + p.blockI]].children.push_back(node);
    }
    return doc;
}

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

// [SECTION] terrain -----------------------------------------------------------------------------

namespace {

// The terrain's height function: fBm of value noise with a 1024 m base period, remapped so the
// lowlands flatten out and the peaks sharpen.
struct TerrainField {
    uint32_t seed;
    uint32_t octaves;
    float heightMeters;

    float operator()(float x, float z) const {
        float sum = 0, norm = 0, amplitude = 1, frequency = 1.0f / 1024.0f;
        for (uint32_t o = 0; o < octaves; ++o) {
            sum += amplitude * valueNoise(x * frequency, z * frequency, seed + o * 0x9E3779B9u);
            norm += amplitude;
            amplitude *= 0.5f;
            frequency *= 2.0f;
        }
        float n = std::clamp((sum / norm - 0.2f) / 0.6f, 0.0f, 1.0f);
        return heightMeters * std::pow(n, 1.8f);
    }
};

} // namespace

gltf::Document buildTerrain(const TerrainOptions& o) {
    Document doc;
    doc.sceneName = "terrain";
    const uint32_t quads = std::max(1u, o.quadsPerSide);
    const uint32_t tileQuads = std::clamp(o.tileQuads, 1u, quads);
    const float size = o.sizeMeters, half = size / 2, step = size / float(quads);
    const TerrainField field{foldSeed(o.seed), std::max(1u, o.octaves), o.heightMeters};

    const uint32_t ground = addMaterial(doc, makeMaterial("terrain", {0.28f, 0.33f, 0.18f}, 0.95f));
    const uint32_t rock = addMaterial(doc, makeMaterial("rock", {0.42f, 0.38f, 0.33f}, 0.9f));

    // Heights on the grid plus a one-sample border, for central-difference normals that agree
    // across tile seams.
    const uint32_t stride = quads + 3;
    std::vector<float> heights(size_t(stride) * stride);
    auto gridX = [&](int64_t i) { return -half + float(i) * step; };
    for (uint32_t j = 0; j < stride; ++j)
        for (uint32_t i = 0; i < stride; ++i)
            heights[size_t(j) * stride + i] = field(gridX(int64_t(i) - 1), gridX(int64_t(j) - 1));
    // i, j in [-1, quads + 1] (the border included).
    auto heightAt = [&](int64_t i, int64_t j) {
        return heights[size_t(j + 1) * stride + size_t(i + 1)];
    };

    const uint32_t tiles = (quads + tileQuads - 1) / tileQuads;
    std::vector<uint32_t> tileNodes;
    for (uint32_t tj = 0; tj < tiles; ++tj)
        for (uint32_t ti = 0; ti < tiles; ++ti) {
            const uint32_t i0 = ti * tileQuads, i1 = std::min(quads, i0 + tileQuads);
            const uint32_t j0 = tj * tileQuads, j1 = std::min(quads, j0 + tileQuads);
            const Float3 origin{gridX(i0), 0, gridX(j0)};
            Primitive p;
            p.material = ground;
            for (uint32_t j = j0; j <= j1; ++j)
                for (uint32_t i = i0; i <= i1; ++i) {
                    // Tile-local positions (the node carries the tile origin) keep the float
                    // precision of vertices independent of the terrain size.
                    p.positions.push_back(
                        {gridX(i) - origin[0], heightAt(i, j), gridX(j) - origin[2]});
                    const int64_t si = i, sj = j;
                    float dx = (heightAt(si + 1, sj) - heightAt(si - 1, sj)) / (2 * step);
                    float dz = (heightAt(si, sj + 1) - heightAt(si, sj - 1)) / (2 * step);
                    p.normals.push_back(normalize({-dx, 1, -dz}));
                }
            const uint32_t w = i1 - i0 + 1;
            for (uint32_t j = 0; j < j1 - j0; ++j)
                for (uint32_t i = 0; i < i1 - i0; ++i) {
                    uint32_t a = j * w + i, b = a + 1, c = a + w, d = c + 1;
                    // (c - a) x (d - a) = +z x (+x+z) = +Y: counter-clockwise from above.
                    p.indices.insert(p.indices.end(), {a, c, d, a, d, b});
                }
            Mesh m;
            m.name = "terrain-" + std::to_string(ti) + "-" + std::to_string(tj);
            m.primitives.push_back(std::move(p));
            std::string name = m.name;
            tileNodes.push_back(addNode(doc, meshNode(name, addMesh(doc, std::move(m)), origin)));
        }

    // Overhangs, along the camera's diagonal view so they are seen against the terrain: rock
    // slabs floating 12-35 m above the highest ground under them, and arches whose pillars are
    // sunk 40 m (scaled) below the higher foot so they never float on a slope.
    Pcg32 rng(o.seed, kStreamTerrainProps);
    auto alongView = [&](float t, float lateral) {
        // From the camera corner (-0.42, +0.42) towards (+0.42, -0.42), in units of size.
        float d = -0.42f + 0.84f * t;
        return Float2{(d + lateral * 0.7071f) * size, (-d + lateral * 0.7071f) * size};
    };
    for (uint32_t k = 0; k < o.slabs; ++k) {
        const float wx = rng.uniform(25, 50), thickness = rng.uniform(4, 8),
                    wz = rng.uniform(12, 25);
        const Float2 c = alongView(rng.uniform(0.12f, 0.6f), rng.uniform(-0.08f, 0.08f));
        const float yaw = rng.uniform(0, 2 * kPi), lift = rng.uniform(12, 35);
        const float radius = 0.5f * std::sqrt(wx * wx + wz * wz);
        float highest = -1e30f;
        for (int b = -4; b <= 4; ++b)
            for (int a = -4; a <= 4; ++a)
                highest = std::max(
                    highest, field(c[0] + float(a) * radius / 4, c[1] + float(b) * radius / 4));
        Mesh m = boxesMesh("rock-slab-" + std::to_string(k),
                           {{{-wx / 2, -thickness / 2, -wz / 2}, {wx / 2, thickness / 2, wz / 2}}},
                           8.0f, rock, rock);
        std::string name = m.name;
        addNode(doc, meshNode(name, addMesh(doc, std::move(m)),
                              {c[0], highest + lift + thickness / 2, c[1]}, gltf::rotationY(yaw)));
    }
    if (o.arches > 0) {
        // Local frame: pillars 10 x 10 m at x = +-25, from y = -40 (sunk) to 30; lintel 30-38.
        const int32_t arch = addMesh(doc, boxesMesh("rock-arch",
                                                    {{{-30, -40, -5}, {-20, 30, 5}},
                                                     {{20, -40, -5}, {30, 30, 5}},
                                                     {{-30, 30, -5}, {30, 38, 5}}},
                                                    8.0f, rock, rock));
        for (uint32_t k = 0; k < o.arches; ++k) {
            Float2 c{};
            float yaw = 0, scale = 1, base = 0;
            for (int attempt = 0; attempt < 32; ++attempt) {
                c = alongView(rng.uniform(0.2f, 0.7f), rng.uniform(-0.1f, 0.1f));
                yaw = rng.uniform(0, 2 * kPi);
                scale = rng.uniform(0.8f, 1.25f);
                const float px = std::cos(yaw) * 25 * scale, pz = -std::sin(yaw) * 25 * scale;
                const float ha = field(c[0] + px, c[1] + pz), hb = field(c[0] - px, c[1] - pz);
                base = std::max(ha, hb);
                // Both feet well buried, and the opening clear of the ground between them.
                if (base - std::min(ha, hb) < 40 * scale - 8 &&
                    field(c[0], c[1]) < base + 20 * scale)
                    break;
            }
            Node n = meshNode("rock-arch-" + std::to_string(k), arch, {c[0], base, c[1]},
                              gltf::rotationY(yaw));
            n.scale = {scale, scale, scale};
            addNode(doc, std::move(n));
        }
    }

    // Camera 2 m above a grid vertex (where the mesh equals the height function exactly) at the
    // corner, looking across the whole terrain to the far corner, 1 degree below the horizon.
    const auto ci = uint32_t(std::lround(0.08f * float(quads)));
    const auto cj = uint32_t(std::lround(0.92f * float(quads)));
    const Float3 eye{gridX(ci), heightAt(ci, cj) + 2.0f, gridX(cj)};
    const float pitch = radians(-1.0f);
    addCamera(doc, "ground-camera", eye,
              {std::cos(pitch) * 0.7071f, std::sin(pitch), -std::cos(pitch) * 0.7071f}, radians(60),
              16.0f / 9.0f, 0.5f, 2.0f * size);
    addSun(doc, sunDirection(radians(o.sunElevationDegrees), radians(60)), {0, 0, 0}, size,
           {1.0f, 0.95f, 0.88f}, 3.0f);
    return doc;
}

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

// [SECTION] load-test ---------------------------------------------------------------------------

namespace {

// fBm of tileable value noise over a size x size image: `cells` lattice cells across at the
// first octave (doubling each octave, so every octave tiles), normalised to [0, 1].
std::vector<float> tileableFbm(uint32_t size, int32_t cells, uint32_t octaves, uint32_t seed) {
    std::vector<float> out(size_t(size) * size);
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            float sum = 0, norm = 0, amplitude = 1;
            int32_t period = cells;
            for (uint32_t o = 0; o < octaves; ++o) {
                const float scale = float(period) / float(size);
                sum += amplitude * tileableValueNoise(float(x) * scale, float(y) * scale, period,
                                                      seed + o * 0x9E3779B9u);
                norm += amplitude;
                amplitude *= 0.5f;
                period *= 2;
            }
            out[size_t(y) * size + x] = sum / norm;
        }
    return out;
}

uint8_t unorm8(float v) {
    return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

// Base colour: two palette colours mixed by fBm, with darker veins where a second fBm crosses
// its middle value.
std::vector<uint8_t> rockColorPng(uint32_t size, Float3 a, Float3 b, uint32_t seed) {
    const std::vector<float> mix = tileableFbm(size, 8, 5, seed);
    const std::vector<float> veins = tileableFbm(size, 4, 4, seed ^ 0xA511E9B3u);
    std::vector<uint8_t> pixels(size_t(size) * size * 3);
    for (size_t i = 0; i < mix.size(); ++i) {
        const float t = std::clamp((mix[i] - 0.3f) / 0.4f, 0.0f, 1.0f);
        const float vein = std::clamp(std::fabs(veins[i] - 0.5f) * 25.0f, 0.0f, 1.0f);
        const float shade = 0.55f + 0.45f * vein;
        for (int k = 0; k < 3; ++k)
            pixels[i * 3 + size_t(k)] =
                unorm8((a[size_t(k)] + (b[size_t(k)] - a[size_t(k)]) * t) * shade);
    }
    return encodePng(size, size, 3, pixels);
}

// Tangent-space normal map (glTF: +X right, +Y up in texture space, i.e. towards smaller v) of
// a tileable fBm heightfield, by central differences with wrap-around.
std::vector<uint8_t> rockNormalPng(uint32_t size, uint32_t seed) {
    const std::vector<float> h = tileableFbm(size, 16, 5, seed);
    const float strength = float(size) / 16.0f; // slope scale: heights are in [0, 1]
    std::vector<uint8_t> pixels(size_t(size) * size * 3);
    auto at = [&](uint32_t x, uint32_t y) { return h[size_t(y % size) * size + x % size]; };
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            const float dx = (at(x + 1, y) - at(x + size - 1, y)) * 0.5f * strength;
            const float dy = (at(x, y + size - 1) - at(x, y + 1)) * 0.5f * strength; // +Y = up
            const Float3 n = normalize({-dx, -dy, 1.0f});
            uint8_t* p = &pixels[(size_t(y) * size + x) * 3];
            for (int k = 0; k < 3; ++k)
                p[k] = unorm8(n[size_t(k)] * 0.5f + 0.5f);
        }
    return encodePng(size, size, 3, pixels);
}

// The rock surface: radius `radius` times 1 +- 0.25 of 3D fBm over the direction.
struct RockShape {
    float radius;
    Float3 offset; // where this rock samples the noise field
    uint32_t seed;

    float radiusAt(Float3 dir) const {
        float sum = 0, norm = 0, amplitude = 1, frequency = 1.5f;
        for (uint32_t o = 0; o < 4; ++o) {
            const Float3 q = dir * frequency + offset;
            sum += amplitude * valueNoise3(q[0], q[1], q[2], seed + o * 0x9E3779B9u);
            norm += amplitude;
            amplitude *= 0.5f;
            frequency *= 2.0f;
        }
        return radius * (1.0f + 0.5f * (sum / norm - 0.5f));
    }
    // Signed distance-like field |p| - r(p / |p|); the surface is its zero set.
    float field(Float3 p) const {
        const float len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        return len - radiusAt(p * (1.0f / len));
    }
};

// A displaced UV sphere: `rings` latitude bands (poles are single triangles), 2 * rings
// segments, so 4 * rings * (rings - 1) triangles. Normals are the field's gradient (central
// differences in 3D), so they agree across the u seam and at the poles.
Primitive rockPrimitive(const RockShape& shape, uint32_t rings, uint32_t material) {
    const uint32_t segments = 2 * rings;
    Primitive p;
    p.material = material;
    const float eps = shape.radius * 1e-3f;
    for (uint32_t j = 0; j <= rings; ++j) {
        const float theta = kPi * float(j) / float(rings);
        for (uint32_t i = 0; i <= segments; ++i) {
            const float phi = 2 * kPi * float(i == segments ? 0 : i) / float(segments);
            // Exact poles and an exact seam (i == segments repeats i == 0's position).
            const float st = j == 0 || j == rings ? 0.0f : std::sin(theta);
            const float ct = j == 0 ? 1.0f : j == rings ? -1.0f : std::cos(theta);
            const Float3 dir{st * std::cos(phi), ct, st * std::sin(phi)};
            const Float3 pos = dir * shape.radiusAt(dir);
            Float3 g{};
            for (size_t k = 0; k < 3; ++k) {
                Float3 d{0, 0, 0};
                d[k] = eps;
                g[k] = shape.field(pos + d) - shape.field(pos - d);
            }
            p.positions.push_back(pos);
            p.normals.push_back(normalize(g));
            p.uv0.push_back({4.0f * float(i) / float(segments), 2.0f * float(j) / float(rings)});
        }
    }
    const uint32_t row = segments + 1;
    for (uint32_t j = 0; j < rings; ++j)
        for (uint32_t i = 0; i < segments; ++i) {
            const uint32_t a = j * row + i, b = a + 1, c = a + row, d = c + 1;
            // (a, b, c) and (b, d, c) are counter-clockwise seen from outside; at the north pole
            // (j = 0) a == b in position, at the south pole c == d, so one of each is dropped.
            if (j != 0) p.indices.insert(p.indices.end(), {a, b, c});
            if (j != rings - 1) p.indices.insert(p.indices.end(), {b, d, c});
        }
    return p;
}

} // namespace

gltf::Document buildLoadTest(const LoadTestOptions& o) {
    Document doc;
    doc.sceneName = "load-test";
    const uint32_t objects = std::max(1u, o.objects);
    const uint32_t materials = std::max(1u, o.materials);
    const uint32_t texture = std::max(4u, o.textureSize);
    const uint32_t seed = foldSeed(o.seed);

    // Per-material palettes (pairs of sRGB colours): granite, sandstone, slate, basalt, moss.
    static constexpr Float3 kPalettes[][2] = {
        {{0.55f, 0.52f, 0.50f}, {0.80f, 0.78f, 0.74f}},
        {{0.60f, 0.42f, 0.26f}, {0.85f, 0.70f, 0.50f}},
        {{0.22f, 0.26f, 0.30f}, {0.45f, 0.50f, 0.55f}},
        {{0.12f, 0.11f, 0.11f}, {0.35f, 0.32f, 0.30f}},
        {{0.25f, 0.35f, 0.18f}, {0.55f, 0.60f, 0.40f}},
    };
    constexpr size_t kPaletteCount = std::size(kPalettes);
    for (uint32_t k = 0; k < materials; ++k) {
        const Float3* pal = kPalettes[k % kPaletteCount];
        doc.images.push_back({"rock-color-" + std::to_string(k),
                              rockColorPng(texture, pal[0], pal[1], seed + 1000 * (k + 1))});
    }
    for (uint32_t k = 0; k < materials; ++k)
        doc.images.push_back({"rock-normal-" + std::to_string(k),
                              rockNormalPng(texture, seed + 1000 * (k + 1) + 500)});
    for (uint32_t k = 0; k < materials; ++k) {
        Material m = makeMaterial("rock-material-" + std::to_string(k), {1, 1, 1}, 0.85f);
        m.baseColorImage = int32_t(k);
        m.normalImage = int32_t(materials + k);
        addMaterial(doc, std::move(m));
    }

    // Rocks on a grid, 10 per row (fewer if there are fewer rocks), 12 m apart.
    const uint64_t perRock = std::max<uint64_t>(8, o.targetTriangles / objects);
    const auto rings = uint32_t(
        std::clamp(std::round(0.5 + std::sqrt(0.25 + double(perRock) / 4.0)), 2.0, 4096.0));
    const uint32_t columns = std::min(objects, 10u);
    const uint32_t rows = (objects + columns - 1) / columns;
    constexpr float kSpacing = 12.0f;
    Pcg32 rng(o.seed, kStreamLoadTestRocks);
    for (uint32_t n = 0; n < objects; ++n) {
        const RockShape shape{rng.uniform(3.0f, 5.0f),
                              {rng.uniform(0, 100), rng.uniform(0, 100), rng.uniform(0, 100)},
                              seed ^ 0x0C0FFEEu};
        const float yaw = rng.uniform(0, 2 * kPi);
        Mesh m;
        m.name = "rock-" + std::to_string(n);
        m.primitives.push_back(rockPrimitive(shape, rings, n % materials));
        const float x = (float(n % columns) - float(columns - 1) / 2) * kSpacing;
        const float z = (float(n / columns) - float(rows - 1) / 2) * kSpacing;
        std::string name = m.name;
        addNode(doc, meshNode(name, addMesh(doc, std::move(m)), {x, 0.8f * shape.radius, z},
                              gltf::rotationY(yaw)));
    }

    const float halfX = float(columns) * kSpacing / 2, halfZ = float(rows) * kSpacing / 2;
    addCamera(doc, "overview-camera", {0, 0.9f * halfX, halfZ + 1.1f * halfX},
              {0, -0.9f * halfX, -1.1f * halfX}, radians(50), 16.0f / 9.0f, 0.5f,
              8.0f * (halfX + halfZ));
    addSun(doc, sunDirection(radians(45), radians(30)), {0, 0, 0}, 2.0f * (halfX + halfZ),
           {1.0f, 0.96f, 0.9f}, 3.0f);
    return doc;
}

// [SECTION] light-field -------------------------------------------------------------------------

gltf::Document buildLightField(const LightFieldOptions& o) {
    Document doc;
    doc.sceneName = "light-field";
    const float size = o.sizeMeters, half = size / 2;
    const uint32_t boxes = std::max(1u, o.boxesPerSide);
    const float cell = size / float(boxes);

    const uint32_t floorMaterial =
        addMaterial(doc, makeMaterial("floor", {0.6f, 0.6f, 0.6f}, 0.6f));
    constexpr Float3 kBoxColors[] = {
        {0.7f, 0.25f, 0.2f}, {0.25f, 0.55f, 0.3f}, {0.25f, 0.35f, 0.7f}, {0.75f, 0.7f, 0.6f}};
    std::vector<int32_t> boxMeshes;
    for (size_t k = 0; k < std::size(kBoxColors); ++k) {
        const uint32_t mat = addMaterial(
            doc, makeMaterial("box-" + std::to_string(k), kBoxColors[k], 0.4f + 0.1f * float(k)));
        boxMeshes.push_back(
            addMesh(doc, boxesMesh("unit-box-" + std::to_string(k),
                                   {{{-0.5f, 0, -0.5f}, {0.5f, 1, 0.5f}}}, 1.0f, mat, mat)));
    }

    Mesh floorMesh;
    floorMesh.name = "floor";
    floorMesh.primitives.resize(1);
    floorMesh.primitives[0].material = floorMaterial;
    const uint32_t n = std::max(1u, o.floorSubdivisions);
    addGrid(floorMesh.primitives[0], {-half, 0, -half}, {0, 0, size}, {size, 0, 0}, n, n, false);
    addNode(doc, meshNode("floor", addMesh(doc, std::move(floorMesh))));

    Pcg32 boxRng(o.seed, kStreamLightFieldBoxes);
    for (uint32_t j = 0; j < boxes; ++j)
        for (uint32_t i = 0; i < boxes; ++i) {
            const float w = boxRng.uniform(0.3f, 0.6f) * cell,
                        d = boxRng.uniform(0.3f, 0.6f) * cell;
            const float h = boxRng.uniform(1.0f, 4.0f);
            const uint32_t colour = boxRng.below(uint32_t(boxMeshes.size()));
            Node node =
                meshNode("box-" + std::to_string(i) + "-" + std::to_string(j), boxMeshes[colour],
                         {-half + (float(i) + 0.5f) * cell, 0, -half + (float(j) + 0.5f) * cell});
            node.scale = {w, h, d};
            addNode(doc, std::move(node));
        }

    // Point lights on a jittered grid over the floor, above every box.
    constexpr Float3 kLightColors[] = {{1.0f, 0.85f, 0.6f}, {0.6f, 0.75f, 1.0f},
                                       {1.0f, 0.6f, 0.5f},  {0.7f, 1.0f, 0.7f},
                                       {1.0f, 1.0f, 1.0f},  {0.9f, 0.7f, 1.0f}};
    const uint32_t lights = std::min(o.lights, 4096u);
    if (lights > 0) {
        const auto side = uint32_t(std::ceil(std::sqrt(double(lights))));
        const float lightCell = size / float(side);
        const float range = std::max(6.0f, 2.5f * lightCell);
        const float intensity = 120.0f / std::sqrt(float(lights));
        Pcg32 lightRng(o.seed, kStreamLightFieldLights);
        for (uint32_t k = 0; k < lights; ++k) {
            const float x =
                -half + (float(k % side) + 0.5f + lightRng.uniform(-0.35f, 0.35f)) * lightCell;
            const float z =
                -half + (float(k / side) + 0.5f + lightRng.uniform(-0.35f, 0.35f)) * lightCell;
            const float y = lightRng.uniform(4.5f, 6.0f);
            const std::string name = "point-light-" + std::to_string(k);
            doc.lights.push_back({.name = name,
                                  .type = gltf::LightType::Point,
                                  .color = kLightColors[k % std::size(kLightColors)],
                                  .intensity = intensity,
                                  .range = range});
            Node l;
            l.name = name;
            l.translation = {x, y, z};
            l.light = int32_t(doc.lights.size() - 1);
            addNode(doc, std::move(l));
        }
    }

    addCamera(doc, "low-camera", {0, 3.0f, 0.45f * size}, {0, -2.5f, -0.6f * size}, radians(55),
              16.0f / 9.0f, 0.1f, 4.0f * size);
    addSun(doc, sunDirection(radians(40), radians(20)), {0, 0, 0}, size, {0.7f, 0.75f, 1.0f}, 0.3f);
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

    auto boxMesh = [&](std::string name, uint32_t material, const std::vector<Box>& parts) {
        Mesh m;
        m.name = std::move(name);
        m.primitives.resize(1);
        m.primitives[0].material = material;
        for (const Box& b : parts)
            addBox(m.primitives[0], m.primitives[0], b.lo, b.hi, {}, false);
        return m;
    };
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
    return std::nullopt;
}

} // namespace pnb::assets
