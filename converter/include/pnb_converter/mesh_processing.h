// pnb_converter/mesh_processing.h — IR meshes into container-ready meshes.
//
// Per mesh: merge its primitives into one vertex/index buffer with one submesh per primitive;
// drop non-finite positions' triangles (warning) and degenerate triangles (counted); weld equal
// vertices; generate normals when missing (area-weighted); generate tangents only when asked
// (a normal map uses them); meshoptimizer vertex-cache, overdraw and vertex-fetch optimisation;
// bounds (AABB + sphere) per mesh and per submesh; optional quantisation and LOD chain.
//
// Does NOT do: deciding which streams are needed (the caller passes StreamNeeds, derived from
// the materials), writing the container.
//
// Based on: meshoptimizer's README pipeline order (remap → cache → overdraw → fetch);
// Lengyel, "Computing Tangent Space Basis Vectors for an Arbitrary Mesh" (2001).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/error.h"
#include "pnb_converter/scene_ir.h"

namespace pnb::converter {

// Which vertex streams the materials of a mesh use. Positions and normals are always kept.
struct StreamNeeds {
    bool uv0 = false, uv1 = false;
    bool tangents = false; // a normal map samples this mesh
    bool colors = false;   // COLOR_0 present and multiplying base colour
};

struct MeshSettings {
    bool optimize = true;    // meshoptimizer cache/overdraw/fetch passes. Default: true.
    bool quantize = false;   // 16-bit normalized positions (per-mesh box), octahedral 16-bit
                             // normals/tangents, half-float UVs. Default: false.
    uint32_t lodCount = 0;   // extra simplified levels (meshopt_simplify). Default: 0.
    float lodRatio = 0.5f;   // index count of each level relative to the previous. Default: 0.5.
};

struct MeshStats {
    uint64_t inputTriangles = 0;
    uint64_t degenerateTriangles = 0;   // removed: repeated index or zero area
    uint64_t nonFiniteTriangles = 0;    // removed: a NaN/Inf position
    uint64_t outputTriangles = 0;       // level 0 only
    uint64_t inputVertices = 0, outputVertices = 0;
    bool normalsGenerated = false, tangentsGenerated = false;
    float maxPositionError = 0;         // quantisation error, mesh units (0 if not quantized)
    float maxNormalErrorRadians = 0;    // quantisation error of normals
    std::vector<float> lodErrors;       // per extra level, mesh units
};

// A vertex stream with the bytes it owns (a pnb::VertexStream's `data` is filled from `bytes`
// when the container is written).
struct OwnedStream {
    VertexStream desc;
    std::vector<std::byte> bytes;
};

struct ProcessedMesh {
    std::string name;
    uint32_t vertexCount = 0;
    std::vector<OwnedStream> streams;
    IndexType indexType = IndexType::U32; // U16 when vertexCount <= 65535
    std::vector<std::byte> indices;       // little-endian, of indexType
    std::vector<Submesh> submeshes;       // material = IrScene material index (-1 → kNone)
    Aabb bounds;
    Sphere boundingSphere;
};

// Processes one mesh. Errors (Input): no positions, index out of range, array sizes that do not
// match the vertex count — each naming the mesh and primitive. Deterministic.
Result<ProcessedMesh, ConvertError> processMesh(const IrMesh& mesh, const StreamNeeds& needs,
                                                const MeshSettings& settings, MeshStats& stats);

} // namespace pnb::converter
