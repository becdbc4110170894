// assets_src/src/procedural_scenes_internal.h — the building helpers the procedural scene files
// share (random numbers and noise, grids, boxes, materials, cameras, suns), defined in
// procedural_helpers.cpp; each scene (or small family of scenes) has its own file, and
// procedural_scenes.cpp holds the registry. Internal to pnb_assets.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "pnb_assets/gltf_writer.h"
#include "pnb_assets/procedural_scenes.h"

namespace pnb::assets::procedural_detail {

using gltf::Document;
using gltf::Float2;
using gltf::Float3;
using gltf::Float4;
using gltf::kNone;
using gltf::Material;
using gltf::Mesh;
using gltf::Node;
using gltf::Primitive;

inline constexpr float kPi = std::numbers::pi_v<float>;
inline float radians(float degrees) {
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
inline constexpr uint64_t kStreamCanyonRows = 11, kStreamCityLayout = 21,
                          kStreamCityArchetypes = 22, kStreamTerrainProps = 31,
                          kStreamGrazingProps = 41, kStreamLoadTestRocks = 51,
                          kStreamLightFieldBoxes = 61, kStreamLightFieldLights = 62,
                          kStreamCrowdWalkers = 71;

// Value noise in [0, 1): random values on the integer lattice, blended with Perlin's quintic
// fade so the surface has continuous first and second derivatives (smooth normals).
float valueNoise(float x, float y, uint32_t seed);

// Value noise that repeats every `period` lattice cells in x and y (the lattice wraps), so
// textures built from it tile seamlessly.
float tileableValueNoise(float x, float y, int32_t period, uint32_t seed);

// 3D value noise in [0, 1), trilinear with the quintic fade.
float valueNoise3(float x, float y, float z, uint32_t seed);

// A 64-bit option seed folded into the 32-bit seed of the noise functions.
uint32_t foldSeed(uint64_t seed);

// [SECTION] Geometry helpers --------------------------------------------------------------------

inline Float3 operator+(Float3 a, Float3 b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline Float3 operator-(Float3 a, Float3 b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline Float3 operator*(Float3 a, float s) {
    return {a[0] * s, a[1] * s, a[2] * s};
}
inline Float3 cross(Float3 a, Float3 b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline Float3 normalize(Float3 v) {
    return v * (1.0f / std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
}

// Direction the light travels for a sun `elevation` above the horizon whose horizontal travel
// direction is +X turned `azimuth` towards -Z.
Float3 sunDirection(float elevationRadians, float azimuthRadians);

// a + (b - a) x, exact at both ends (x = 0 gives a, x = 1 gives b) and constant where a == b,
// so axis-aligned faces stay exactly planar and box corners are bit-identical on every face.
inline Float3 lerp(Float3 a, Float3 b, float x) {
    return x == 1.0f ? b : a + (b - a) * x;
}

// Appends an nu x nv grid of quads with corners origin, origin + u, origin + v and
// origin + u + v; the face normal is u x v, so triangles are counter-clockwise seen from the
// front.
void addGrid(Primitive& p, Float3 origin, Float3 u, Float3 v, uint32_t nu, uint32_t nv, bool withUv,
             Float2 uvExtent = {1, 1});

// Cells per box axis. Side faces are nx (or nz) by ny quads, top and bottom nx by nz, so every
// edge is split the same way on both faces that share it (no T-junctions, no cracks).
struct BoxCells {
    uint32_t nx = 1, ny = 1, nz = 1;
};

uint64_t boxTriangles(BoxCells c);

// A closed axis-aligned box from lo to hi with outward faces: side faces into `sides`, top and
// bottom into `caps` (which may be the same primitive).
void addBox(Primitive& sides, Primitive& caps, Float3 lo, Float3 hi, BoxCells c, bool withUv);

struct Box {
    Float3 lo, hi;
};

// Cells of about `cellMeters` a side on each axis of box `b` (at least 1, at most 4096).
BoxCells cellsFor(const Box& b, float cellMeters);

// Triangles of `boxes` subdivided into cells of about `cellMeters`.
uint64_t trianglesFor(const std::vector<Box>& boxes, float cellMeters);

// A mesh of closed, undivided boxes in one primitive of one material (furniture, slabs).
Mesh solidBoxesMesh(std::string name, uint32_t material, const std::vector<Box>& boxes);

// A mesh of closed boxes: walls (side faces) in one primitive, roofs and floors in another.
Mesh boxesMesh(std::string name, const std::vector<Box>& boxes, float cellMeters,
               uint32_t wallMaterial, uint32_t roofMaterial);

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

// A material of colour `rgb` (opaque), roughness and metallic factors, no textures.
Material makeMaterial(std::string name, Float3 rgb, float roughness, float metallic = 0.0f);

// Appends to the document; each returns the new item's index.
uint32_t addMaterial(Document& doc, Material m);
int32_t addMesh(Document& doc, Mesh m);
uint32_t addNode(Document& doc, Node n);

// A node showing `mesh`, placed by translation and rotation (xyzw).
Node meshNode(std::string name, int32_t mesh, Float3 translation = {0, 0, 0},
              Float4 rotation = {0, 0, 0, 1});

// Adds a camera and its node, looking along `forward` from `position`.
uint32_t addCamera(Document& doc, std::string name, Float3 position, Float3 forward,
                   float yfovRadians, float aspect, float znear, float zfar);

// Adds a directional light shining along `direction`; the node sits `distance` up-sun of
// `target` so it is easy to find in an editor (the position does not affect the lighting).
uint32_t addSun(Document& doc, Float3 direction, Float3 target, float distance, Float3 color,
                float intensity);

// A two-tone checker (RGB, `tile` texels per square) as PNG bytes.
std::vector<uint8_t> checkerPng(uint32_t size, uint32_t tile, Float3 light, Float3 dark);

} // namespace pnb::assets::procedural_detail
