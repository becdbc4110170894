// converter/src/mesh_processing.cpp — processMesh: the per-mesh pipeline, in this order.
//
//  1. Validate every primitive (sizes, index range) before touching data: hostile input fails
//     with a message naming mesh and primitive, and no later step needs bounds checks.
//  2. Drop triangles with a non-finite position, then degenerate ones (repeated index, or a
//     height below float resolution at the mesh's scale; see isDegenerate). Done first so that
//     NaNs never reach normals, tangents, bounds or meshoptimizer, and a zero-area triangle
//     cannot poison a normal sum or a UV gradient.
//  3. Merge the primitives into one vertex/index buffer, one submesh (index range) per
//     primitive. Only streams the materials need (StreamNeeds) plus positions and normals are
//     carried; a primitive lacking a needed stream gets defaults (uv 0, colour 1). Non-finite
//     uv/colour components become those defaults too; -0 becomes +0 so equal values weld.
//  4. Normals: kept (normalised) where the source has usable ones, generated elsewhere
//     (mesh_normals.cpp). Before the weld, so generated normals take part in it.
//  5. Tangents, only when a normal map needs them: kept from the source, else derived from uv0
//     (mesh_tangents.cpp). After normals (they are orthogonalised against them), before the weld.
//  6. Weld: vertices equal in every *output* stream merge (meshopt_generateVertexRemapMulti,
//     bitwise). Streams that are not output do not keep vertices apart. Unreferenced vertices
//     (e.g. only used by dropped triangles) disappear here.
//  7. Optimise (settings.optimize): vertex cache then overdraw per submesh — each submesh is a
//     draw call, and the optimisers reorder triangles only within the range they are given —
//     then one global vertex-fetch reorder (the vertex buffer is shared by all submeshes).
//     meshoptimizer's recommended order: remap → cache → overdraw → fetch.
//  8. LODs: each level simplifies the *level-0* submesh to previous level × lodRatio indices, so
//     lodError is the error against full detail rather than an accumulation; simplified indices
//     reference the same vertices. Appended after all level-0 submeshes, ordered by level then
//     submesh. A submesh stops when simplification no longer reduces it. Open borders are
//     locked (settings.lodLockBorders): a submesh simplified on its own would move its border
//     vertices independently of the neighbour that shares them, and tiles would crack apart
//     where they meet at different levels.
//  9. Encode streams and indices (mesh_encode.cpp). Quantization is last: every geometric step
//     above works on the source floats.
// 10. Bounds: AABB of the mesh and of each submesh range, bounding sphere (mesh_bounds.cpp), of
//     the positions *as stored*, so they contain what a reader decodes even when quantization
//     rounds a coordinate an ulp past the float box.
//
// Determinism: single-threaded, no hashing of pointers, no unordered iteration; meshoptimizer's
// functions are deterministic. Equal input gives equal output bytes.

#include "pnb_converter/mesh_processing.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <cstring>
#include <unordered_map>

#include <meshoptimizer.h>

#include "mesh_internal.h"

namespace pnb::converter {

namespace {

using namespace mesh_detail;

// A triangle whose height over its longest edge is at most this fraction of the mesh's box
// diagonal is degenerate: float positions at that scale resolve about FLT_EPSILON × size, so
// the triangle is a line or a point as far as the data can tell. It rasterises to nothing and
// only breaks normal and tangent sums. Exactly-zero area is the special case.
constexpr double kDegenerateHeight = std::numeric_limits<float>::epsilon();

// meshopt_simplify's target error, relative to the mesh extent: 1% deformation at most.
constexpr float kLodTargetError = 1e-2f;
// meshopt_optimizeOverdraw: accept up to 5% worse vertex-cache efficiency for less overdraw.
constexpr float kOverdrawThreshold = 1.05f;
// Submesh::lod is a u8.
constexpr uint32_t kMaxLodLevels = 255;

struct Range {
    uint32_t first = 0, count = 0;
};

ConvertError inputError(const IrMesh& mesh, size_t primitive, const std::string& what) {
    return {ConvertErrorKind::Input,
            "mesh '" + mesh.name + "' primitive " + std::to_string(primitive) + ": " + what};
}

ConvertError inputError(const IrMesh& mesh, const std::string& what) {
    return {ConvertErrorKind::Input, "mesh '" + mesh.name + "': " + what};
}

std::optional<ConvertError> validate(const IrMesh& mesh, size_t index) {
    const IrPrimitive& p = mesh.primitives[index];
    if (p.positions.empty()) return inputError(mesh, index, "no positions");
    if (p.positions.size() % 3 != 0)
        return inputError(mesh, index,
                          std::to_string(p.positions.size()) +
                              " position floats, not a multiple of 3");
    const size_t n = p.vertexCount();
    struct Named {
        const char* name;
        const std::vector<float>* data;
        size_t components;
    };
    for (const Named& s :
         {Named{"normal", &p.normals, kNormalComponents},
          Named{"tangent", &p.tangents, kTangentComponents}, Named{"uv0", &p.uv0, kUvComponents},
          Named{"uv1", &p.uv1, kUvComponents}, Named{"colour", &p.colors, kColorComponents}}) {
        if (!s.data->empty() && s.data->size() != n * s.components)
            return inputError(mesh, index,
                              std::to_string(s.data->size()) + " " + s.name + " floats, expected " +
                                  std::to_string(n * s.components) + " (" + std::to_string(n) +
                                  " vertices × " + std::to_string(s.components) + ")");
    }
    if (p.joints.size() != p.weights.size() || (!p.joints.empty() && p.joints.size() != n * 4))
        return inputError(mesh, index,
                          std::to_string(p.joints.size()) + " joint indices and " +
                              std::to_string(p.weights.size()) + " weights, expected " +
                              std::to_string(n * 4) + " of each or none");
    if (!p.targets.empty() && p.targets.size() != mesh.morphWeights.size())
        return inputError(mesh, index,
                          std::to_string(p.targets.size()) + " morph targets, the mesh has " +
                              std::to_string(mesh.morphWeights.size()) + " weights");
    for (size_t t = 0; t < p.targets.size(); ++t)
        for (const std::vector<float>* d : {&p.targets[t].positions, &p.targets[t].normals, &p.targets[t].tangents})
            if (!d->empty() && d->size() != n * 3)
                return inputError(mesh, index,
                                  "morph target " + std::to_string(t) + ": " + std::to_string(d->size()) +
                                      " delta floats, expected " + std::to_string(n * 3));
    if (p.indices.size() % 3 != 0)
        return inputError(mesh, index,
                          std::to_string(p.indices.size()) + " indices, not a multiple of 3");
    for (uint32_t i : p.indices) {
        if (i >= n)
            return inputError(mesh, index,
                              "index " + std::to_string(i) + " out of range (" + std::to_string(n) +
                                  " vertices)");
    }
    if (p.material < -1)
        return inputError(mesh, index,
                          "material index " + std::to_string(p.material) +
                              " (-1 is the default material, others index the scene's)");
    return std::nullopt;
}

bool finiteVertex(const float* p) {
    return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

bool finiteTriangle(const IrPrimitive& p, size_t t) {
    return finiteVertex(&p.positions[size_t(p.indices[t]) * 3]) &&
           finiteVertex(&p.positions[size_t(p.indices[t + 1]) * 3]) &&
           finiteVertex(&p.positions[size_t(p.indices[t + 2]) * 3]);
}

// Diagonal of the box of all vertices used by finite triangles, in double (float could
// overflow for coordinates near its range).
double finiteDiagonal(const IrMesh& mesh) {
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    bool any = false;
    for (const IrPrimitive& p : mesh.primitives) {
        for (size_t t = 0; t + 2 < p.indices.size(); t += 3) {
            if (!finiteTriangle(p, t)) continue;
            any = true;
            for (size_t c = 0; c < 3; ++c) {
                const float* v = &p.positions[size_t(p.indices[t + c]) * 3];
                for (int k = 0; k < 3; ++k)
                    lo[k] = std::min(lo[k], double(v[k])), hi[k] = std::max(hi[k], double(v[k]));
            }
        }
    }
    if (!any) return 0;
    double d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

bool isDegenerate(const float* a, const float* b, const float* c, double diagonal) {
    double e0[3], e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
        e0[k] = double(b[k]) - a[k];
        e1[k] = double(c[k]) - a[k];
        e2[k] = double(c[k]) - b[k];
    }
    double x = e0[1] * e1[2] - e0[2] * e1[1], y = e0[2] * e1[0] - e0[0] * e1[2],
           z = e0[0] * e1[1] - e0[1] * e1[0];
    double twiceArea = std::sqrt(x * x + y * y + z * z);
    auto len = [](const double* e) { return std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]); };
    double longest = std::max({len(e0), len(e1), len(e2)});
    // height = twiceArea / longest <= kDegenerateHeight * diagonal, without dividing by zero.
    return twiceArea <= kDegenerateHeight * diagonal * longest;
}

// Copies n×components floats, replacing non-finite components by `fallback`, -0 by +0.
void appendSanitised(std::vector<float>& dst, const std::vector<float>& src, size_t count,
                     float fallback) {
    if (src.empty()) {
        dst.insert(dst.end(), count, fallback);
        return;
    }
    for (float f : src)
        dst.push_back(std::isfinite(f) ? f + 0.0f : fallback);
}

// Normalises xyz in double (tiny vectors would underflow in float). False when unusable.
bool normalise3(const float* in, float* out) {
    double x = in[0], y = in[1], z = in[2];
    double len = std::sqrt(x * x + y * y + z * z);
    if (!(len > 0) || !std::isfinite(len)) return false;
    out[0] = float(x / len) + 0.0f;
    out[1] = float(y / len) + 0.0f;
    out[2] = float(z / len) + 0.0f;
    return true;
}

// Reorders `indices` in place with a meshoptimizer pass that wants the range's own compact
// vertex numbering: passing the whole mesh's vertex count instead would cost O(vertexCount) per
// submesh (the optimisers allocate per-vertex tables), quadratic with many primitives.
class LocalRange {
public:
    explicit LocalRange(size_t vertexCount) : mLocal(vertexCount, ~0u) {}

    template <class Optimise>
    void run(std::span<uint32_t> indices, std::span<const float> positions, Optimise&& optimise) {
        mGlobal.clear();
        mIndices.resize(indices.size());
        for (size_t i = 0; i < indices.size(); ++i) {
            uint32_t& local = mLocal[indices[i]];
            if (local == ~0u) {
                local = uint32_t(mGlobal.size());
                mGlobal.push_back(indices[i]);
            }
            mIndices[i] = local;
        }
        mPositions.resize(mGlobal.size() * 3);
        for (size_t i = 0; i < mGlobal.size(); ++i)
            std::copy_n(&positions[size_t(mGlobal[i]) * 3], 3, &mPositions[i * 3]);
        optimise(mIndices, mPositions, mGlobal.size());
        for (size_t i = 0; i < indices.size(); ++i)
            indices[i] = mGlobal[mIndices[i]];
        for (uint32_t g : mGlobal)
            mLocal[g] = ~0u;
    }

private:
    std::vector<uint32_t> mLocal, mGlobal, mIndices;
    std::vector<float> mPositions;
};

void optimiseCacheAndOverdraw(std::vector<uint32_t>& indices, const std::vector<float>& positions,
                              size_t vertexCount) {
    std::vector<uint32_t> scratch(indices.size());
    meshopt_optimizeVertexCache(scratch.data(), indices.data(), indices.size(), vertexCount);
    meshopt_optimizeOverdraw(indices.data(), scratch.data(), indices.size(), positions.data(),
                             vertexCount, sizeof(float) * 3, kOverdrawThreshold);
}

void optimiseCache(std::vector<uint32_t>& indices, const std::vector<float>&, size_t vertexCount) {
    std::vector<uint32_t> scratch(indices.size());
    meshopt_optimizeVertexCache(scratch.data(), indices.data(), indices.size(), vertexCount);
    indices.swap(scratch);
}

void remapStream(std::vector<float>& stream, size_t components, size_t oldCount, size_t newCount,
                 const std::vector<uint32_t>& remap) {
    if (stream.empty()) return;
    std::vector<float> out(newCount * components);
    if (newCount)
        meshopt_remapVertexBuffer(out.data(), stream.data(), oldCount, sizeof(float) * components,
                                  remap.data());
    stream.swap(out);
}

// Any element type and width (morph deltas may be wider than meshopt_remapVertexBuffer takes).
template <class T>
void remapWide(std::vector<T>& stream, size_t components, size_t oldCount, size_t newCount,
               const std::vector<uint32_t>& remap) {
    if (stream.empty()) return;
    std::vector<T> out(newCount * components);
    for (size_t i = 0; i < oldCount; ++i)
        if (remap[i] != ~0u)
            std::copy_n(&stream[i * components], components, &out[size_t(remap[i]) * components]);
    stream.swap(out);
}

void remapAll(VertexData& v, size_t newCount, const std::vector<uint32_t>& remap) {
    remapWide(v.joints, 4, v.count, newCount, remap);
    remapStream(v.weights, 4, v.count, newCount, remap);
    remapWide(v.morph, v.morphStride, v.count, newCount, remap);
    remapStream(v.positions, kPositionComponents, v.count, newCount, remap);
    remapStream(v.normals, kNormalComponents, v.count, newCount, remap);
    remapStream(v.tangents, kTangentComponents, v.count, newCount, remap);
    remapStream(v.uv0, kUvComponents, v.count, newCount, remap);
    remapStream(v.uv1, kUvComponents, v.count, newCount, remap);
    remapStream(v.colors, kColorComponents, v.count, newCount, remap);
    v.count = newCount;
}


// [SECTION] the stages of processMesh, in its order

// 1. Validate: the mesh, the settings and every primitive, before any data is touched. Counts
// the input into `stats`.
std::optional<ConvertError> validateMesh(const IrMesh& mesh, const MeshSettings& settings,
                                         MeshStats& stats) {
    if (mesh.primitives.empty()) return inputError(mesh, "no primitives");
    if (settings.lodCount > 0 && !(settings.lodRatio > 0 && settings.lodRatio < 1))
        return inputError(mesh, "LOD ratio " + std::to_string(settings.lodRatio) +
                                    " is not between 0 and 1");
    uint64_t totalVertices = 0;
    for (size_t i = 0; i < mesh.primitives.size(); ++i) {
        if (auto error = validate(mesh, i)) return *error;
        totalVertices += mesh.primitives[i].vertexCount();
        stats.inputTriangles += mesh.primitives[i].indices.size() / 3;
    }
    stats.inputVertices = totalVertices;
    // Merged indices are u32 and ~0u is meshoptimizer's "unused" marker.
    if (totalVertices >= 0xFFFFFFFFull)
        return inputError(mesh, std::to_string(totalVertices) + " vertices, the limit is 2^32 - 2");
    return std::nullopt;
}

// The primitives merged into one vertex/index buffer (steps 2 and 3), and per vertex where its
// normal and tangent are to come from (steps 4 and 5).
struct MergedMesh {
    VertexData v;
    std::vector<uint32_t> indices;
    std::vector<Range> ranges; // one per primitive
    std::vector<uint8_t> generateNormal;
    std::vector<TangentSource> tangentSource; // empty unless tangents are needed
    std::vector<uint8_t> noUv0;               // tangents arbitrary because the primitive has no uv0
    std::vector<MorphSlots> morphSlots;       // per morph target
};

// 2. A primitive's triangles, less the non-finite and degenerate ones, appended to the merged
// indices (its vertices start at `base`).
// A deformed mesh (`keepZeroArea`) keeps its zero-area triangles: a morph or a skin may give
// them area.
void appendKeptTriangles(const IrPrimitive& p, uint32_t base, double diagonal, bool keepZeroArea,
                         std::vector<uint32_t>& indices, MeshStats& stats) {
    for (size_t t = 0; t < p.indices.size(); t += 3) {
        uint32_t a = p.indices[t], b = p.indices[t + 1], c = p.indices[t + 2];
        if (!finiteTriangle(p, t)) {
            ++stats.nonFiniteTriangles;
            continue;
        }
        if (a == b || b == c || a == c ||
            (!keepZeroArea && isDegenerate(&p.positions[size_t(a) * 3], &p.positions[size_t(b) * 3],
                                           &p.positions[size_t(c) * 3], diagonal))) {
            ++stats.degenerateTriangles;
            continue;
        }
        indices.insert(indices.end(), {base + a, base + b, base + c});
    }
}

// 3. A primitive's vertices appended to the merged streams (they start at `base`): the source's
// usable normals and tangents kept, the rest marked for generation.
void appendPrimitiveVertices(const IrPrimitive& p, const StreamNeeds& needs, uint32_t base,
                             MergedMesh& m) {
    VertexData& v = m.v;
    const size_t n = p.vertexCount();
    // Non-finite positions are only in unreferenced vertices now; keep them out of the
    // weld's equality anyway (0 is as good as anything for a vertex that will vanish).
    for (float f : p.positions)
        v.positions.push_back(std::isfinite(f) ? f + 0.0f : 0.0f);
    for (size_t i = 0; i < n; ++i) {
        bool ok = !p.normals.empty() && normalise3(&p.normals[i * 3], &v.normals[(base + i) * 3]);
        m.generateNormal[base + i] = !ok;
    }
    if (needs.tangents) {
        for (size_t i = 0; i < n; ++i) {
            float* t = &v.tangents[(base + i) * 4];
            if (!p.tangents.empty() && normalise3(&p.tangents[i * 4], t)) {
                t[3] = p.tangents[i * 4 + 3] < 0 ? -1.0f : 1.0f; // NaN w: +1
                m.tangentSource[base + i] = TangentSource::Keep;
            } else if (!p.uv0.empty()) {
                m.tangentSource[base + i] = TangentSource::FromUv;
            } else {
                m.tangentSource[base + i] = TangentSource::Arbitrary;
                m.noUv0[base + i] = 1;
            }
        }
    }
    const bool carryUv0 = needs.uv0 || needs.tangents; // tangents are derived from uv0
    if (carryUv0) appendSanitised(v.uv0, p.uv0, n * kUvComponents, 0.0f);
    if (needs.uv1) appendSanitised(v.uv1, p.uv1, n * kUvComponents, 0.0f);
    if (needs.colors) appendSanitised(v.colors, p.colors, n * kColorComponents, 1.0f);
}

// 3, skinned meshes: a primitive's joints and weights appended, the weights normalised to sum 1
// (negative and non-finite ones count as 0; a vertex whose weights sum to 0 gets weight 1 on its
// first joint). A primitive without them (the importer had none) is all joint 0.
void appendSkinAttributes(const IrPrimitive& p, VertexData& v, MeshStats& stats) {
    const size_t n = p.vertexCount();
    for (size_t i = 0; i < n; ++i) {
        double w[4] = {0, 0, 0, 0}, sum = 0;
        bool clean = !p.weights.empty();
        for (int k = 0; k < 4; ++k) {
            const float x = p.weights.empty() ? 0.0f : p.weights[i * 4 + k];
            clean &= std::isfinite(x) && x >= 0;
            w[k] = std::isfinite(x) && x > 0 ? double(x) : 0.0;
            sum += w[k];
            v.joints.push_back(p.joints.empty() ? 0 : p.joints[i * 4 + k]);
        }
        if (!(sum > 0) || !std::isfinite(sum)) {
            ++stats.weightsZero;
            v.weights.insert(v.weights.end(), {1.0f, 0.0f, 0.0f, 0.0f});
            continue;
        }
        // glTF allows a sum within about 2e-7 per weight of 1 (its normalisation tolerance);
        // anything further off is reported.
        if (!clean || std::abs(sum - 1.0) > 2e-6) ++stats.weightsRenormalised;
        for (int k = 0; k < 4; ++k) v.weights.push_back(float(w[k] / sum) + 0.0f);
    }
}

// 3, morphed meshes: a primitive's deltas appended at the mesh's slots (zero where the
// primitive's target does not move the attribute, or the primitive has no such target).
void appendMorphDeltas(const IrPrimitive& p, const std::vector<MorphSlots>& slots, VertexData& v) {
    const size_t n = p.vertexCount(), first = v.morph.size();
    v.morph.resize(first + n * v.morphStride, 0.0f);
    for (size_t t = 0; t < p.targets.size(); ++t) {
        const IrMorphTarget& target = p.targets[t];
        const std::pair<const std::vector<float>*, int> kept[] = {
            {&target.positions, slots[t].position}, {&target.normals, slots[t].normal},
            {&target.tangents, slots[t].tangent}};
        for (const auto& [delta, slot] : kept) {
            if (slot < 0 || delta->empty()) continue;
            for (size_t i = 0; i < n; ++i)
                for (size_t k = 0; k < 3; ++k) {
                    const float d = (*delta)[i * 3 + k];
                    v.morph[first + i * v.morphStride + size_t(slot) + k] = std::isfinite(d) ? d + 0.0f : 0.0f;
                }
        }
    }
}

// Which attributes each morph target keeps: Position always, Normal where a primitive moves
// normals (the mesh always has them), Tangent where one moves tangents and the mesh keeps them.
std::vector<MorphSlots> morphSlotsOf(const IrMesh& mesh, const StreamNeeds& needs, size_t& stride) {
    std::vector<MorphSlots> slots(mesh.morphWeights.size());
    stride = 0;
    for (size_t t = 0; t < slots.size(); ++t) {
        bool normals = false, tangents = false;
        for (const IrPrimitive& p : mesh.primitives)
            if (t < p.targets.size()) {
                normals |= !p.targets[t].normals.empty();
                tangents |= !p.targets[t].tangents.empty();
            }
        slots[t].position = int(stride);
        stride += 3;
        if (normals) slots[t].normal = int(stride), stride += 3;
        if (tangents && needs.tangents) slots[t].tangent = int(stride), stride += 3;
    }
    return slots;
}

// 2 + 3. Filter triangles while merging indices; merge the vertex streams.
MergedMesh mergePrimitives(const IrMesh& mesh, const StreamNeeds& needs, size_t vertexCount,
                           MeshStats& stats) {
    const double diagonal = finiteDiagonal(mesh);
    MergedMesh m;
    m.v.count = vertexCount;
    m.v.deformed = mesh.deformed();
    m.morphSlots = morphSlotsOf(mesh, needs, m.v.morphStride);
    m.generateNormal.assign(vertexCount, 0);
    m.tangentSource.assign(needs.tangents ? vertexCount : 0, TangentSource::Keep);
    m.noUv0.assign(vertexCount, 0);
    m.v.positions.reserve(vertexCount * 3);
    m.v.normals.resize(vertexCount * 3);
    if (needs.tangents) m.v.tangents.resize(vertexCount * 4);
    uint32_t base = 0;
    for (const IrPrimitive& p : mesh.primitives) {
        Range range{uint32_t(m.indices.size()), 0};
        appendKeptTriangles(p, base, diagonal, m.v.deformed, m.indices, stats);
        range.count = uint32_t(m.indices.size() - range.first);
        m.ranges.push_back(range);
        appendPrimitiveVertices(p, needs, base, m);
        if (mesh.skinned) appendSkinAttributes(p, m.v, stats);
        if (m.v.morphStride) appendMorphDeltas(p, m.morphSlots, m.v);
        base += uint32_t(p.vertexCount());
    }
    stats.outputTriangles = m.indices.size() / 3;
    return m;
}

// 4 + 5. Normals and tangents where the source had none usable, for the vertices a kept
// triangle references; uv0 is dropped afterwards when only the tangents needed it.
void completeNormalsAndTangents(MergedMesh& m, const StreamNeeds& needs, MeshStats& stats) {
    std::vector<uint8_t> referenced(m.v.count, 0);
    for (uint32_t i : m.indices)
        referenced[i] = 1;
    for (size_t i = 0; i < m.v.count; ++i) {
        if (!referenced[i]) continue;
        stats.normalsGenerated |= m.generateNormal[i] != 0;
        if (needs.tangents) stats.tangentsGenerated |= m.tangentSource[i] != TangentSource::Keep;
        stats.tangentsArbitrary |= m.noUv0[i] != 0;
    }
    if (stats.normalsGenerated) generateNormals(m.v, m.indices, m.generateNormal);
    if (stats.tangentsGenerated) generateTangents(m.v, m.indices, m.tangentSource);
    if (!needs.uv0) m.v.uv0.clear();
}

// Per vertex, a number equal for two vertices exactly when their morph deltas are bitwise equal:
// the deltas may be wider than a meshopt_Stream key (256 bytes), so the weld keys on this.
std::vector<uint32_t> morphClasses(const VertexData& v) {
    std::vector<uint32_t> out(v.count, 0);
    if (!v.morphStride) return out;
    const size_t bytes = v.morphStride * sizeof(float);
    auto at = [&](uint32_t i) { return reinterpret_cast<const unsigned char*>(&v.morph[size_t(i) * v.morphStride]); };
    struct Hash {
        decltype(at)& a; size_t n;
        size_t operator()(uint32_t i) const {
            uint64_t h = 1469598103934665603ull; // FNV-1a
            const unsigned char* p = a(i);
            for (size_t k = 0; k < n; ++k) h = (h ^ p[k]) * 1099511628211ull;
            return size_t(h);
        }
    };
    struct Equal {
        decltype(at)& a; size_t n;
        bool operator()(uint32_t x, uint32_t y) const { return std::memcmp(a(x), a(y), n) == 0; }
    };
    std::unordered_map<uint32_t, uint32_t, Hash, Equal> classes(v.count, Hash{at, bytes}, Equal{at, bytes});
    for (uint32_t i = 0; i < uint32_t(v.count); ++i)
        out[i] = classes.emplace(i, uint32_t(classes.size())).first->second;
    return out;
}

// 6. Weld over the output streams.
void weldOutputStreams(VertexData& v, std::vector<uint32_t>& indices) {
    std::vector<meshopt_Stream> keys;
    if (!v.joints.empty()) {
        keys.push_back({v.joints.data(), sizeof(uint32_t) * 4, sizeof(uint32_t) * 4});
        keys.push_back({v.weights.data(), sizeof(float) * 4, sizeof(float) * 4});
    }
    const std::vector<uint32_t> morphClass = morphClasses(v);
    if (v.morphStride) keys.push_back({morphClass.data(), sizeof(uint32_t), sizeof(uint32_t)});
    auto key = [&](const std::vector<float>& s, size_t components) {
        if (!s.empty())
            keys.push_back({s.data(), sizeof(float) * components, sizeof(float) * components});
    };
    key(v.positions, kPositionComponents);
    key(v.normals, kNormalComponents);
    key(v.tangents, kTangentComponents);
    key(v.uv0, kUvComponents);
    key(v.uv1, kUvComponents);
    key(v.colors, kColorComponents);
    // meshoptimizer asserts on a null index pointer: no triangles means no vertices.
    std::vector<uint32_t> remap(v.count, ~0u);
    size_t unique = 0;
    if (!indices.empty()) {
        unique = meshopt_generateVertexRemapMulti(remap.data(), indices.data(), indices.size(),
                                                  v.count, keys.data(), keys.size());
        meshopt_remapIndexBuffer(indices.data(), indices.data(), indices.size(), remap.data());
    }
    remapAll(v, unique, remap);
}

// 7. Optimise: vertex cache and overdraw per submesh, then one vertex-fetch order for all.
void optimiseForGpu(VertexData& v, std::vector<uint32_t>& indices,
                    const std::vector<Range>& ranges) {
    LocalRange local(v.count);
    for (const Range& r : ranges) {
        if (r.count == 0) continue;
        local.run(std::span(indices).subspan(r.first, r.count), v.positions,
                  [](std::vector<uint32_t>& ix, const std::vector<float>& pos, size_t count) {
                      optimiseCacheAndOverdraw(ix, pos, count);
                  });
    }
    std::vector<uint32_t> remap(v.count);
    size_t unique =
        meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), indices.size(), v.count);
    meshopt_remapIndexBuffer(indices.data(), indices.data(), indices.size(), remap.data());
    remapAll(v, unique, remap);
}

// The level-0 submeshes: one per primitive, its index range and material.
std::vector<Submesh> level0Submeshes(const IrMesh& mesh, const std::vector<Range>& ranges) {
    std::vector<Submesh> out;
    for (size_t i = 0; i < mesh.primitives.size(); ++i) {
        Submesh s;
        int material = mesh.primitives[i].material;
        s.material = material < 0 ? kNone : uint32_t(material);
        s.firstIndex = ranges[i].first;
        s.indexCount = ranges[i].count;
        out.push_back(s);
    }
    return out;
}

// 8. LODs: per level, every level-0 submesh simplified to the previous level × lodRatio; the
// simplified indices and their submeshes appended. Returns the level's worst error, or nothing
// when no submesh could be reduced further (the chain ends).
std::optional<float> appendLodLevel(uint32_t level, const VertexData& v, float scale,
                                    const std::vector<Range>& ranges, const MeshSettings& settings,
                                    std::vector<size_t>& previous, LocalRange& local,
                                    std::vector<uint32_t>& indices,
                                    std::vector<Submesh>& submeshes) {
    bool produced = false;
    float levelError = 0;
    std::vector<uint32_t> simplified;
    for (size_t s = 0; s < ranges.size(); ++s) {
        if (previous[s] < 6) continue; // one triangle cannot be reduced
        const Range& r = ranges[s];
        size_t target = size_t(double(previous[s] / 3) * settings.lodRatio) * 3;
        simplified.resize(r.count);
        float error = 0;
        size_t count =
            meshopt_simplify(simplified.data(), &indices[r.first], r.count, v.positions.data(),
                             v.count, sizeof(float) * 3, target, kLodTargetError,
                             settings.lodLockBorders ? meshopt_SimplifyLockBorder : 0, &error);
        if (count == 0 || count >= previous[s]) {
            previous[s] = 0; // no further reduction: this submesh's chain ends
            continue;
        }
        simplified.resize(count);
        if (settings.optimize) {
            local.run(simplified, v.positions,
                      [](std::vector<uint32_t>& ix, const std::vector<float>& pos, size_t n) {
                          optimiseCache(ix, pos, n);
                      });
        }
        Submesh lod = submeshes[s];
        lod.firstIndex = uint32_t(indices.size());
        lod.indexCount = uint32_t(count);
        lod.lod = uint8_t(level);
        // Coordinates near float's limit make the scale infinite: keep the error a
        // finite float (0 × inf would be NaN).
        lod.lodError = error > 0 ? std::min(error * scale, FLT_MAX) : 0.0f;
        submeshes.push_back(lod);
        indices.insert(indices.end(), simplified.begin(), simplified.end());
        previous[s] = count;
        levelError = std::max(levelError, lod.lodError);
        produced = true;
    }
    if (!produced) return std::nullopt;
    return levelError;
}

// 8. LODs: up to settings.lodCount levels after the level-0 submeshes (`ranges`), each with its
// worst error in stats.lodErrors.
void appendLods(const VertexData& v, const std::vector<Range>& ranges, const MeshSettings& settings,
                std::vector<uint32_t>& indices, std::vector<Submesh>& submeshes, MeshStats& stats) {
    const uint32_t levels = std::min(settings.lodCount, kMaxLodLevels);
    if (levels == 0 || indices.empty()) return;
    const float scale = meshopt_simplifyScale(v.positions.data(), v.count, sizeof(float) * 3);
    std::vector<size_t> previous(ranges.size());
    for (size_t s = 0; s < ranges.size(); ++s)
        previous[s] = ranges[s].count;
    LocalRange local(v.count);
    for (uint32_t level = 1; level <= levels; ++level) {
        const std::optional<float> levelError =
            appendLodLevel(level, v, scale, ranges, settings, previous, local, indices, submeshes);
        if (!levelError) break;
        stats.lodErrors.push_back(*levelError);
    }
}

// 9 + 10. Streams and indices encoded into `out`, with the bounds of the positions as stored.
// U16 indices stop at 65535 vertices so that no index is 0xFFFF, the primitive restart value a
// player may enable.
void encodeWithBounds(const VertexData& v, const std::vector<uint32_t>& indices,
                      const StreamNeeds& needs, const MeshSettings& settings, ProcessedMesh& out,
                      MeshStats& stats) {
    out.vertexCount = uint32_t(v.count);
    std::vector<float> stored;
    out.streams =
        encodeStreams(v, needs, boundsOfAll(v.positions), settings.quantize, stored, stats);
    out.bounds = boundsOfAll(stored);
    out.boundingSphere = boundingSphere(stored, out.bounds);
    for (Submesh& s : out.submeshes)
        s.bounds = boundsOfIndexed(stored, std::span(indices).subspan(s.firstIndex, s.indexCount));
    out.indexType = v.count <= 65535 ? IndexType::U16 : IndexType::U32;
    out.indices = encodeIndices(indices, out.indexType);
    stats.outputVertices = v.count;
}

} // namespace

Result<ProcessedMesh, ConvertError> processMesh(const IrMesh& mesh, const StreamNeeds& needs,
                                                const MeshSettings& settings, MeshStats& stats) {
    stats = MeshStats{};
    if (auto error = validateMesh(mesh, settings, stats)) return *error;
    MergedMesh merged = mergePrimitives(mesh, needs, size_t(stats.inputVertices), stats);
    completeNormalsAndTangents(merged, needs, stats);
    VertexData& v = merged.v;
    std::vector<uint32_t>& indices = merged.indices;
    weldOutputStreams(v, indices);
    if (settings.optimize && !indices.empty()) optimiseForGpu(v, indices, merged.ranges);

    ProcessedMesh out;
    out.name = mesh.name;
    out.deformed = v.deformed;
    out.submeshes = level0Submeshes(mesh, merged.ranges);
    appendLods(v, merged.ranges, settings, indices, out.submeshes, stats);
    encodeWithBounds(v, indices, needs, settings, out, stats);
    if (v.morphStride) {
        out.morphWeights = mesh.morphWeights;
        out.morphTargets = encodeMorphTargets(v, merged.morphSlots);
        for (size_t t = 0; t < out.morphTargets.size() && t < mesh.targetNames.size(); ++t)
            out.morphTargets[t].name = mesh.targetNames[t];
    }
    return out;
}

Mesh toContainerMesh(const ProcessedMesh& pm, StringRef name) {
    Mesh m;
    m.name = name;
    m.indexType = pm.indexType;
    m.vertexCount = pm.vertexCount;
    for (const OwnedStream& st : pm.streams) {
        VertexStream vs = st.desc;
        vs.data = st.bytes;
        m.streams.push_back(vs);
    }
    m.indices = pm.indices;
    m.submeshes = pm.submeshes;
    m.bounds = pm.bounds;
    m.boundingSphere = pm.boundingSphere;
    return m;
}

} // namespace pnb::converter
