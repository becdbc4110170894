// glb_check.h — an independent reader and validator for the .glb files pnb_assets writes.
//
// Tests must not trust the writer to check itself, so this parses the bytes back from scratch
// (GLB container, JSON via nlohmann::json, raw accessor data) and checks the glTF 2.0 rules the
// writer promises (gltf_writer.h). It also offers the small amount of geometry (node world
// matrices, frustum and ray tests) the scene tests need.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace pnb::test {

struct ParsedGlb {
    nlohmann::json json;
    std::vector<uint8_t> bin; // the BIN chunk (empty if there is none)
};

// Parses the GLB container: header magic/version/length, a JSON chunk and an optional BIN chunk,
// both 4-byte aligned, nothing after them. Returns "" on success, else what is wrong.
std::string parseGlb(std::span<const uint8_t> bytes, ParsedGlb& out);

// Checks the glTF document: asset, buffers/bufferViews/accessors bounds and alignment, view
// targets, POSITION min/max against the data, unit normals, index ranges, material/texture/
// image/camera/light references, node hierarchy (one parent, no cycles, scene roots), non-empty
// top-level arrays, KHR_lights_punctual declared; JOINTS_0/WEIGHTS_0 types, morph targets, skins
// (joints, inverse bind matrices) and animations (channel targets, sampler inputs and outputs).
// Returns "" if valid, else the first problem.
std::string validateGltf(const ParsedGlb& g);

// Accessor contents as doubles (count * components values). Precondition: validateGltf passed.
std::vector<double> readAccessor(const ParsedGlb& g, size_t accessor);

// Rendered triangles: each mesh counted once per node of the scene that references it.
uint64_t renderedTriangles(const ParsedGlb& g);

using Vec3 = std::array<double, 3>;
// Column-major 4x4 matrix, as glTF stores them.
using Mat4 = std::array<double, 16>;

// World matrix of every node (parent * T * R * S). Precondition: validateGltf passed.
std::vector<Mat4> worldMatrices(const ParsedGlb& g);
Vec3 transformPoint(const Mat4& m, Vec3 p);
Vec3 transformDirection(const Mat4& m, Vec3 d);

// Index of the node with this name, or -1.
int findNode(const ParsedGlb& g, const std::string& name);

struct Aabb {
    Vec3 min{1e300, 1e300, 1e300}, max{-1e300, -1e300, -1e300};
    void grow(Vec3 p);
};
// World-space bounds of node `node`'s mesh (its POSITION min/max corners transformed).
Aabb worldBounds(const ParsedGlb& g, const std::vector<Mat4>& world, size_t node);

// A perspective camera placed by a rigid world matrix (no scale).
struct Frustum {
    Mat4 world;
    double yfov, aspect, znear, zfar;
    // Signed distances-like values for the 6 planes (near, far, left, right, bottom, top);
    // a point is inside iff all are >= 0.
    std::array<double, 6> planes(Vec3 wsPoint) const;
    bool contains(Vec3 wsPoint) const;
    // True if all 8 corners are outside one and the same plane, i.e. the box is provably
    // disjoint from the frustum.
    bool boxOutside(const Aabb& box) const;
};

// Ray (origin + t * dir, t in (tMin, tMax)) against a box; true on a hit.
bool rayHitsBox(Vec3 origin, Vec3 dir, const Aabb& box, double tMin, double tMax);

} // namespace pnb::test
