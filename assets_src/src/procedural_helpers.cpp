// assets_src/src/procedural_helpers.cpp — the building helpers every procedural scene uses
// (procedural_scenes_internal.h): noise, grids and boxes, facade cell sizes, materials, cameras,
// suns, checker textures. Kept apart from the scenes so each scene file reads as its layout.
//
// Based on: M. E. O'Neill, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
// Algorithms for Random Number Generation" (2014) for Pcg32; D. Lemire, "Fast Random Integer
// Generation in an Interval" (2019) for bounded integers; K. Perlin, "Improving Noise" (2002) for
// the quintic fade; the murmur3 fmix32 finaliser for the lattice hash.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "pnb_assets/png_writer.h"
#include "procedural_scenes_internal.h"

namespace pnb::assets::procedural_detail {

// [SECTION] Random numbers and noise ------------------------------------------------------------

namespace {

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

} // namespace

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

// Direction the light travels for a sun `elevation` above the horizon whose horizontal travel
// direction is +X turned `azimuth` towards -Z.
Float3 sunDirection(float elevationRadians, float azimuthRadians) {
    float c = std::cos(elevationRadians);
    return {c * std::cos(azimuthRadians), -std::sin(elevationRadians),
            -c * std::sin(azimuthRadians)};
}

// Appends an nu x nv grid of quads with corners origin, origin + u, origin + v and
// origin + u + v; the face normal is u x v, so triangles are counter-clockwise seen from the
// front.
void addGrid(Primitive& p, Float3 origin, Float3 u, Float3 v, uint32_t nu, uint32_t nv, bool withUv,
             Float2 uvExtent) {
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

namespace {

uint32_t cellsAlong(float extentMeters, float cellMeters) {
    float n = std::round(extentMeters / cellMeters);
    return uint32_t(std::clamp(n, 1.0f, 4096.0f));
}

} // namespace

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
Mesh solidBoxesMesh(std::string name, uint32_t material, const std::vector<Box>& boxes) {
    Mesh m;
    m.name = std::move(name);
    m.primitives.resize(1);
    m.primitives[0].material = material;
    for (const Box& b : boxes) addBox(m.primitives[0], m.primitives[0], b.lo, b.hi, {}, false);
    return m;
}

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

Material makeMaterial(std::string name, Float3 rgb, float roughness, float metallic) {
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

Node meshNode(std::string name, int32_t mesh, Float3 translation, Float4 rotation) {
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

} // namespace pnb::assets::procedural_detail
