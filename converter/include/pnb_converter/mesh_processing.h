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

// Stream encodings. Without `quantize` every stream is F32, Plain, not normalized, dequantScale
// (1,1,1), dequantOffset (0,0,0): Position ×3, Normal ×3, Tangent ×4 (w = ±1), TexCoord ×2,
// Color0 ×4. With `quantize` (decode per FORMAT.md §4.3: normalise, then × scale + offset):
//   Position  U16 ×3 normalized, Plain: value = (q / 65535) × extent + min, dequantScale = the
//             mesh box's extent, dequantOffset = its min (an axis of zero extent: scale 0).
//             Error <= extent / 131070 per axis, plus float rounding of the decode. (An
//             extent beyond float range cannot be a scale: such positions stay F32.)
//   Normal    I16 ×2 normalized, Octahedral: (u, v) = max(q / 32767, -1); z = 1 - |u| - |v|;
//             if z < 0: (u, v) = ((1 - |v|) × sign(u), (1 - |u|) × sign(v)), sign(0) = +1;
//             normalise (u, v, z). Scale (1,1,1), offset (0,0,0).
//   Tangent   I16 ×4 normalized, Plain: xyz = max(q / 32767, -1) (normalise after decoding),
//             w = exactly ±1. (Octahedral would need a third component for w; not worth it.)
//   TexCoord  F16 ×2, Plain, not normalized (IEEE half; magnitudes clamped to 65504).
//   Color0    U8 ×4 normalized, Plain (linear RGBA clamped to [0, 1]).
// A deformed mesh keeps Position, Normal and Tangent F32 Plain with `quantize` (the deforming
// pass reads and writes them); its Joints0 is U8 ×4 when every index is below 256, else U16 ×4,
// and Weights0 F32 ×4, quantized or not.
// Indices: U16 when vertexCount <= 65535, else U32, quantized or not.
struct MeshSettings {
    bool optimize = true;    // meshoptimizer cache/overdraw/fetch passes. Default: true.
    bool quantize = false;   // the encodings above. Default: false.
    uint32_t lodCount = 0;   // extra simplified levels (meshopt_simplify); fewer when it
                             // stops reducing, at most 255 (Submesh::lod). Default: 0.
    float lodRatio = 0.5f;   // index count of each level relative to the previous, in (0, 1).
                             // Default: 0.5.
    bool lodLockBorders = true; // keep open-boundary vertices of each submesh in every level, so
                                // meshes that meet edge to edge (terrain tiles) stay crack-free
                                // at different levels. Default: true.
    bool proxies = true; // a mesh with levels is written as its coarse proxy (MESH) and its full
                         // detail (MDET, after the first frame's data), so a streaming player
                         // draws coarse geometry first (docs/FORMAT.md "MDET"). Default: true.
};

struct MeshStats {
    uint64_t inputTriangles = 0;
    uint64_t degenerateTriangles = 0;   // removed: repeated index or zero area (height at most
                                        // FLT_EPSILON × the mesh's box diagonal)
    uint64_t nonFiniteTriangles = 0;    // removed: a NaN/Inf position
    uint64_t outputTriangles = 0;       // level 0 only
    uint64_t inputVertices = 0, outputVertices = 0;
    bool normalsGenerated = false, tangentsGenerated = false;
    bool tangentsArbitrary = false;     // tangents were needed but a primitive has no uv0: its
                                        // tangents are an arbitrary orthonormal basis (warn)
    float maxPositionError = 0;         // quantisation error, mesh units (0 if not quantized)
    float maxNormalErrorRadians = 0;    // quantisation error of normals
    std::vector<float> lodErrors;       // per extra level produced, mesh units: the largest
                                        // Submesh::lodError of that level (against level 0)
    uint64_t weightsRenormalised = 0;   // skinned vertices whose weights did not sum to 1
                                        // (or held a negative or non-finite weight)
    uint64_t weightsZero = 0;           // ... whose weights summed to 0: weight 1 on joint 0
};

// A vertex stream with the bytes it owns (a pnb::VertexStream's `data` is filled from `bytes`
// when the container is written).
struct OwnedStream {
    VertexStream desc;
    std::vector<std::byte> bytes;
};

// One morph target of a processed mesh: its delta streams, vertexCount long, in the mesh's
// final vertex order (F32 x 3 Plain: Position always, Normal where the source moves normals,
// Tangent where it moves tangents and the mesh keeps them).
struct ProcessedMorphTarget {
    std::string name;
    std::vector<OwnedStream> deltas;
};

struct ProcessedMesh {
    std::string name;
    // A deformed mesh (IrMesh::deformed): Position/Normal/Tangent F32 Plain even with
    // `quantize`, Joints0/Weights0 streams when skinned, no coarse proxy (MDET).
    bool deformed = false;
    std::vector<ProcessedMorphTarget> morphTargets; // empty or one per IrMesh::morphWeights
    std::vector<float> morphWeights;                // the default weights
    uint32_t vertexCount = 0;
    std::vector<OwnedStream> streams;
    IndexType indexType = IndexType::U32; // U16 when vertexCount <= 65535
    std::vector<std::byte> indices;       // little-endian, of indexType
    std::vector<Submesh> submeshes;       // material = IrScene material index (-1 → kNone)
    Aabb bounds;
    Sphere boundingSphere;
};

// A deformed mesh (skinned or morphed, IrMesh::deformed) goes through the same steps, its
// Joints0/Weights0 and morph deltas carried through every weld and reorder with the other
// streams (vertices that differ in them are not welded), its weights normalised to sum 1 (a
// vertex whose weights sum to 0 gets weight 1 on its first joint; both counted in `stats`),
// and zero-area triangles kept (a morph or a skin may give them area; triangles repeating an
// index are still dropped). See MeshSettings for what `quantize` leaves F32.
//
// Processes one mesh; `stats` is overwritten. Errors (Input): no primitives, no positions, index
// out of range, index count not a multiple of 3, array sizes that do not match the vertex count,
// material below -1 — each naming the mesh and primitive — and lodRatio outside (0, 1) when
// lodCount > 0. A mesh whose triangles are all dropped is not an error: it comes back with no
// vertices and empty submeshes (the caller decides whether to keep it). Deterministic.
// Thread-safe: no shared state, so different meshes may be processed concurrently.
Result<ProcessedMesh, ConvertError> processMesh(const IrMesh& mesh, const StreamNeeds& needs,
                                                const MeshSettings& settings, MeshStats& stats);

// The container record of a processed mesh, named `name` (a StringRef of the caller's string
// table). Its streams and indices are views of `mesh`'s bytes, so `mesh` must stay alive and
// unchanged until the record is written. Submesh materials are copied as they are (kNone stays
// kNone: which material such a submesh draws with is the caller's choice). A mesh with levels
// (pnb::hasLevelChains) is written by a streaming writer as pnb::buildCoarseProxy of this
// record in its MESH chunk and this record in an MDET chunk (MeshSettings::proxies).
Mesh toContainerMesh(const ProcessedMesh& mesh, StringRef name);

} // namespace pnb::converter
