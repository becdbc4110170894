// converter/src/mesh_internal.h — private interfaces between the mesh processing files
// (mesh_processing.cpp drives; mesh_normals.cpp, mesh_tangents.cpp, mesh_bounds.cpp and
// mesh_encode.cpp each do one step). Not installed, not used outside converter/src.
//
// All vertex data here is "structure of arrays" of float, one std::vector per attribute, tightly
// packed (3 floats per position, ...), indexed by the merged vertex index. Index buffers are
// triangle lists whose every index is below the vertex count (the caller guarantees it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "pnb/chunks.h"
#include "pnb_converter/mesh_processing.h"

namespace pnb::converter::mesh_detail {

// Components per vertex of each attribute, as the IR stores them.
inline constexpr size_t kPositionComponents = 3, kNormalComponents = 3, kTangentComponents = 4,
                        kUvComponents = 2, kColorComponents = 4;

// The merged vertices of one mesh. Streams a material does not need are left empty.
struct VertexData {
    size_t count = 0;
    std::vector<float> positions; // xyz, always
    std::vector<float> normals;   // xyz, always (unit length once normals are resolved)
    std::vector<float> tangents;  // xyzw, only if StreamNeeds::tangents
    std::vector<float> uv0, uv1;  // uv, only if needed
    std::vector<float> colors;    // rgba, only if needed
    // A deformed mesh (skinned or morphed): F32 positions, normals and tangents (encodeStreams).
    bool deformed = false;
    std::vector<uint32_t> joints; // 4 per vertex, only for a skinned mesh
    std::vector<float> weights;   // 4 per vertex (normalised to sum 1), with joints
    // Morph deltas interleaved per vertex, morphStride floats each: every target's kept
    // attributes at the offsets its MorphSlots give, xyz each. Empty without morph targets.
    std::vector<float> morph;
    size_t morphStride = 0;
};

// Where a morph target's deltas sit in VertexData::morph (float offset within a vertex), -1
// for an attribute the target does not keep (the source has no delta for it, or the mesh has no
// such stream).
struct MorphSlots {
    int position = -1, normal = -1, tangent = -1;
};

// [normals] mesh_normals.cpp
// Replaces normals[v] of every vertex with `generate[v] != 0` by the normalised sum of the
// area-weighted face normals of all triangles touching v's position (bitwise-equal positions
// share one sum, so a seam split for UVs is shaded smoothly). Vertices that are not referenced
// by `indices` are left alone.
void generateNormals(VertexData& v, std::span<const uint32_t> indices,
                     std::span<const uint8_t> generate);

// [tangents] mesh_tangents.cpp
enum class TangentSource : uint8_t {
    Keep,      // the source's tangent, already normalised, w = ±1
    FromUv,    // derive from the uv0 gradients (Lengyel)
    Arbitrary, // no uv0: any unit vector orthogonal to the normal, w = +1
};
// Fills tangents[v] for every vertex whose source is not Keep. Requires resolved unit normals
// and v.uv0 when any vertex is FromUv. A FromUv vertex whose UV mapping is degenerate (all its
// triangles have collinear UVs) falls back to Arbitrary.
void generateTangents(VertexData& v, std::span<const uint32_t> indices,
                      std::span<const TangentSource> source);

// A unit vector orthogonal to the unit vector n, deterministic and branch-free; continuous in n
// except where n.z changes sign (Duff et al., "Building an Orthonormal Basis, Revisited", 2017).
void orthonormalTangent(const float n[3], float t[3]);

// [bounds] mesh_bounds.cpp
// Box of the vertices `indices` refer to; empty (min > max) when there are none.
Aabb boundsOfIndexed(std::span<const float> positions, std::span<const uint32_t> indices);
// Box of all vertices.
Aabb boundsOfAll(std::span<const float> positions);
// A sphere containing every vertex: the smaller of Ritter's sphere and the box-centred one,
// its radius rounded up so that |p - center| <= radius holds for each vertex in float and in
// double arithmetic. Zero radius at the origin when there are no vertices.
Sphere boundingSphere(std::span<const float> positions, const Aabb& box);

// [encode] mesh_encode.cpp
// Turns the welded float streams into container streams: F32 or, with `quantize`, the
// encodings documented in mesh_processing.h, quantizing positions within `box` (the box of
// v.positions; a deformed mesh keeps positions, normals and tangents F32), then Joints0 (U8 or
// U16 x 4) and Weights0 (F32 x 4) for a skinned one. `storedPositions` receives the positions a reader decodes (xyz per vertex), so
// bounds can be computed from what is stored. Fills stats.maxPositionError and
// stats.maxNormalErrorRadians (0 when not quantized). Stream order: Position, Normal,
// Tangent, TexCoord0, TexCoord1, Color0: position and normal always, the others as `needs` says
// (present even with no vertices, so a mesh's stream list depends on its materials only).
std::vector<OwnedStream> encodeStreams(const VertexData& v, const StreamNeeds& needs,
                                       const Aabb& box, bool quantize,
                                       std::vector<float>& storedPositions, MeshStats& stats);
// Each morph target's delta streams (F32 x 3 Plain, semantics Position, Normal, Tangent in that
// order, each only where its slot is kept).
std::vector<ProcessedMorphTarget> encodeMorphTargets(const VertexData& v,
                                                     const std::vector<MorphSlots>& targets);
// Index bytes, little-endian, of `type`. Precondition: every index fits `type`.
std::vector<std::byte> encodeIndices(std::span<const uint32_t> indices, IndexType type);

} // namespace pnb::converter::mesh_detail
