// Tests of processMesh (converter/src/mesh_*.cpp). Outputs are checked by decoding the streams
// with an independent reader written from the encoding table in mesh_processing.h, as a player
// would, never by peeking at internals.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <set>

#include "pnb_converter/mesh_processing.h"

namespace {

using namespace pnb;
using namespace pnb::converter;

// [SECTION] decoding, as a player would

float halfToFloat(uint16_t h) {
    int sign = h >> 15, exponent = (h >> 10) & 0x1F, mantissa = h & 0x3FF;
    float v;
    if (exponent == 0)
        v = std::ldexp(float(mantissa), -24);
    else if (exponent == 31)
        v = mantissa ? NAN : INFINITY;
    else
        v = std::ldexp(float(mantissa | 0x400), exponent - 25);
    return sign ? -v : v;
}

uint32_t loadLE(const std::byte* p, size_t size) {
    uint32_t v = 0;
    for (size_t k = 0; k < size; ++k)
        v |= uint32_t(p[k]) << (8 * k);
    return v;
}

// One stored component, normalised per FORMAT.md §4.3.
float component(const OwnedStream& s, size_t index) {
    const std::byte* p = &s.bytes[index * componentSizeBytes(s.desc.componentType)];
    switch (s.desc.componentType) {
    case ComponentType::F32: {
        uint32_t bits = loadLE(p, 4);
        float f;
        std::memcpy(&f, &bits, 4);
        return f;
    }
    case ComponentType::F16:
        return halfToFloat(uint16_t(loadLE(p, 2)));
    case ComponentType::U8: {
        float q = float(loadLE(p, 1));
        return s.desc.normalized ? q / 255.0f : q;
    }
    case ComponentType::U16: {
        float q = float(loadLE(p, 2));
        return s.desc.normalized ? q / 65535.0f : q;
    }
    case ComponentType::I16: {
        float q = float(int16_t(uint16_t(loadLE(p, 2))));
        return s.desc.normalized ? std::max(q / 32767.0f, -1.0f) : q;
    }
    default:
        ADD_FAILURE() << "unexpected component type";
        return 0;
    }
}

// Decoded values per vertex: 3 for an octahedral stream, componentCount otherwise.
std::vector<float> decode(const OwnedStream& s, uint32_t vertexCount) {
    const size_t comps = s.desc.componentCount;
    EXPECT_EQ(s.bytes.size(), vertexCount * comps * componentSizeBytes(s.desc.componentType));
    const float scale[3] = {s.desc.dequantScale.x, s.desc.dequantScale.y, s.desc.dequantScale.z};
    const float offset[3] = {s.desc.dequantOffset.x, s.desc.dequantOffset.y,
                             s.desc.dequantOffset.z};
    std::vector<float> out;
    for (size_t v = 0; v < vertexCount; ++v) {
        float c[4] = {};
        for (size_t k = 0; k < comps; ++k) {
            c[k] = component(s, v * comps + k);
            if (k < 3) c[k] = c[k] * scale[k] + offset[k];
        }
        if (s.desc.encoding == VertexEncoding::Octahedral) {
            float x = c[0], y = c[1], z = 1.0f - std::fabs(x) - std::fabs(y);
            if (z < 0) {
                float fx = (1.0f - std::fabs(y)) * (x < 0 ? -1.0f : 1.0f);
                float fy = (1.0f - std::fabs(x)) * (y < 0 ? -1.0f : 1.0f);
                x = fx, y = fy;
            }
            float len = std::sqrt(x * x + y * y + z * z);
            out.insert(out.end(), {x / len, y / len, z / len});
        } else {
            out.insert(out.end(), c, c + comps);
        }
    }
    return out;
}

const OwnedStream* findStream(const ProcessedMesh& m, VertexSemantic semantic) {
    for (const OwnedStream& s : m.streams)
        if (s.desc.semantic == semantic) return &s;
    return nullptr;
}

std::vector<float> decoded(const ProcessedMesh& m, VertexSemantic semantic) {
    const OwnedStream* s = findStream(m, semantic);
    EXPECT_NE(s, nullptr) << "no stream " << int(semantic);
    return s ? decode(*s, m.vertexCount) : std::vector<float>{};
}

std::vector<uint32_t> indicesOf(const ProcessedMesh& m) {
    size_t size = m.indexType == IndexType::U16 ? 2 : 4;
    std::vector<uint32_t> out(m.indices.size() / size);
    for (size_t i = 0; i < out.size(); ++i)
        out[i] = loadLE(&m.indices[i * size], size);
    return out;
}

using Triangle = std::array<float, 9>;

// Level-0 triangles as position triples, each rotated to start at its smallest corner (winding
// kept), sorted: equal sets of triangles give equal vectors whatever the index or vertex order.
std::vector<Triangle> triangleSet(const ProcessedMesh& m) {
    std::vector<float> pos = decoded(m, VertexSemantic::Position);
    std::vector<uint32_t> ix = indicesOf(m);
    std::vector<Triangle> out;
    for (const Submesh& s : m.submeshes) {
        if (s.lod != 0) continue;
        for (uint32_t t = s.firstIndex; t < s.firstIndex + s.indexCount; t += 3) {
            std::array<std::array<float, 3>, 3> c;
            for (int k = 0; k < 3; ++k)
                c[k] = {pos[ix[t + k] * 3], pos[ix[t + k] * 3 + 1], pos[ix[t + k] * 3 + 2]};
            auto first = std::min_element(c.begin(), c.end());
            std::rotate(c.begin(), first, c.end());
            Triangle tri;
            for (int k = 0; k < 9; ++k)
                tri[k] = c[k / 3][k % 3];
            out.push_back(tri);
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

// [SECTION] test meshes

// Axis-aligned unit cube around the origin as 6 separate quads (24 vertices), with face normals
// if `faceNormals`, else without normals.
IrPrimitive cubeFaces(bool faceNormals) {
    IrPrimitive p;
    const float n[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int f = 0; f < 6; ++f) {
        // Two axes spanning the face, ordered so that u × v = n (counter-clockwise outside).
        float u[3] = {n[f][1], n[f][2], n[f][0]};
        float v[3] = {n[f][1] * u[2] - n[f][2] * u[1], n[f][2] * u[0] - n[f][0] * u[2],
                      n[f][0] * u[1] - n[f][1] * u[0]};
        // v = n × u, so u × v = n.
        uint32_t base = uint32_t(p.vertexCount());
        for (auto [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
            for (int k = 0; k < 3; ++k)
                p.positions.push_back(0.5f * (n[f][k] + a * u[k] + b * v[k]));
            // Each face its own strip of the texture: corner copies differ in uv.
            p.uv0.insert(p.uv0.end(), {(float(f) + a * 0.5f + 0.5f) / 6.0f, b * 0.5f + 0.5f});
            if (faceNormals) p.normals.insert(p.normals.end(), n[f], n[f] + 3);
        }
        p.indices.insert(p.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    return p;
}

// Latitude-longitude sphere as a typical exporter writes it: the seam column and the pole rows
// are duplicated vertices (different uv), so smooth normals must be summed per position.
IrPrimitive uvSphere(int slices, int stacks, float radius, const float center[3]) {
    IrPrimitive p;
    for (int j = 0; j <= stacks; ++j) {
        float theta = std::numbers::pi_v<float> * float(j) / float(stacks);
        for (int i = 0; i <= slices; ++i) {
            float phi = 2 * std::numbers::pi_v<float> * float(i % slices) / float(slices);
            float dir[3] = {std::sin(theta) * std::cos(phi), std::cos(theta),
                            std::sin(theta) * std::sin(phi)};
            if (j == 0 || j == stacks) dir[0] = dir[2] = 0; // exact poles
            for (int k = 0; k < 3; ++k)
                p.positions.push_back(center[k] + radius * dir[k]);
            p.uv0.insert(p.uv0.end(), {float(i) / float(slices), float(j) / float(stacks)});
        }
    }
    auto at = [&](int i, int j) { return uint32_t(j * (slices + 1) + i); };
    for (int j = 0; j < stacks; ++j) {
        for (int i = 0; i < slices; ++i) {
            // Outward winding (y up, phi towards +z).
            if (j != 0) p.indices.insert(p.indices.end(), {at(i, j), at(i + 1, j), at(i, j + 1)});
            if (j != stacks - 1)
                p.indices.insert(p.indices.end(), {at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
    return p;
}

// A w × h quad grid in the z = 0 plane, uv = (x, y) / size.
IrPrimitive grid(int w, int h) {
    IrPrimitive p;
    for (int y = 0; y <= h; ++y) {
        for (int x = 0; x <= w; ++x) {
            p.positions.insert(p.positions.end(), {float(x), float(y), 0});
            p.uv0.insert(p.uv0.end(), {float(x) / float(w), float(y) / float(h)});
        }
    }
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            uint32_t a = uint32_t(y * (w + 1) + x), b = a + 1, c = a + uint32_t(w) + 1, d = c + 1;
            p.indices.insert(p.indices.end(), {a, b, d, a, d, c});
        }
    }
    return p;
}

IrMesh meshOf(std::string name, std::vector<IrPrimitive> primitives) {
    IrMesh m;
    m.name = std::move(name);
    m.primitives = std::move(primitives);
    return m;
}

ProcessedMesh process(const IrMesh& mesh, MeshStats& stats, StreamNeeds needs = {},
                      MeshSettings settings = {}) {
    auto r = processMesh(mesh, needs, settings, stats);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(r).value() : ProcessedMesh{};
}

double dot3(const float* a, const float* b) {
    return double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2];
}

// Angle between two unit vectors, accurate near 0 (acos of the dot product is not).
double angleBetween(const float* a, const float* b) {
    double c[3] = {double(a[1]) * b[2] - double(a[2]) * b[1],
                   double(a[2]) * b[0] - double(a[0]) * b[2],
                   double(a[0]) * b[1] - double(a[1]) * b[0]};
    return std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), dot3(a, b));
}

bool inside(const Aabb& box, const float* p) {
    return p[0] >= box.min.x && p[1] >= box.min.y && p[2] >= box.min.z && p[0] <= box.max.x &&
           p[1] <= box.max.y && p[2] <= box.max.z;
}

bool inside(const Aabb& box, const Vec3& p) {
    const float q[3] = {p.x, p.y, p.z};
    return inside(box, q);
}

// [SECTION] welding

TEST(MeshProcessing, CubeWithFaceNormalsKeeps24Vertices) {
    MeshStats stats;
    ProcessedMesh m = process(meshOf("cube", {cubeFaces(true)}), stats);
    EXPECT_EQ(m.vertexCount, 24u) << "same positions, different normals: hard edges stay";
    EXPECT_EQ(stats.inputVertices, 24u);
    EXPECT_EQ(stats.outputVertices, 24u);
    EXPECT_EQ(stats.outputTriangles, 12u);
    EXPECT_FALSE(stats.normalsGenerated);
    std::vector<float> n = decoded(m, VertexSemantic::Normal);
    std::vector<float> p = decoded(m, VertexSemantic::Position);
    for (uint32_t v = 0; v < m.vertexCount; ++v) {
        // The face normal is the axis along which |p| is 0.5 and p·n > 0.
        EXPECT_NEAR(dot3(&n[v * 3], &p[v * 3]), 0.5, 1e-6);
    }
}

TEST(MeshProcessing, CubeWithIdenticalDuplicatesWeldsTo8) {
    MeshStats stats;
    // No normals: generated ones are per position, so the 3 copies of a corner become equal;
    // uv differs but is not output (StreamNeeds::uv0 false), so it does not keep them apart.
    ProcessedMesh m = process(meshOf("cube", {cubeFaces(false)}), stats);
    EXPECT_EQ(m.vertexCount, 8u);
    EXPECT_EQ(stats.inputVertices, 24u);
    EXPECT_EQ(stats.outputVertices, 8u);
    EXPECT_EQ(stats.outputTriangles, 12u);
    EXPECT_TRUE(stats.normalsGenerated);
    EXPECT_EQ(findStream(m, VertexSemantic::TexCoord0), nullptr);

    // With uv needed, the per-face uv keeps the copies apart again.
    ProcessedMesh withUv = process(meshOf("cube", {cubeFaces(false)}), stats, {.uv0 = true});
    EXPECT_EQ(withUv.vertexCount, 24u);
}

// [SECTION] triangle filtering

TEST(MeshProcessing, DegenerateAndNonFiniteTrianglesAreCountedAndDropped) {
    IrPrimitive p = grid(4, 4); // 32 triangles, 25 vertices
    const uint64_t good = p.indices.size() / 3;
    p.indices.insert(p.indices.end(), {0, 0, 1}); // repeated index
    p.indices.insert(p.indices.end(), {0, 1, 2}); // collinear: zero area
    p.positions.insert(p.positions.end(), {NAN, 0, 0});
    uint32_t nanVertex = uint32_t(p.vertexCount() - 1);
    p.uv0.insert(p.uv0.end(), {0, 0});
    p.indices.insert(p.indices.end(), {0, 1, nanVertex}); // non-finite
    MeshStats stats;
    ProcessedMesh m = process(meshOf("g", {p}), stats);
    EXPECT_EQ(stats.inputTriangles, good + 3);
    EXPECT_EQ(stats.degenerateTriangles, 2u);
    EXPECT_EQ(stats.nonFiniteTriangles, 1u);
    EXPECT_EQ(stats.outputTriangles, stats.inputTriangles - 3);
    EXPECT_EQ(m.submeshes[0].indexCount, good * 3);
    EXPECT_EQ(m.vertexCount, 25u) << "the NaN vertex is unreferenced now and dropped";
    for (float f : decoded(m, VertexSemantic::Position))
        EXPECT_TRUE(std::isfinite(f));
}

TEST(MeshProcessing, SliverBelowFloatResolutionIsDegenerateButSmallTriangleIsNot) {
    IrPrimitive p = grid(1, 1); // spans 1 unit: the threshold height is ~1.7e-7
    uint32_t n = uint32_t(p.vertexCount());
    // A needle of height 1e-8 along the diagonal: below float resolution at this scale.
    p.positions.insert(p.positions.end(),
                       {0.5f, 0.5f + 1e-8f, 0, 0.25f, 0.25f, 0, 0.75f, 0.75f, 0});
    // A small but real triangle (edges 1e-3).
    p.positions.insert(p.positions.end(), {0.1f, 0.1f, 0, 0.101f, 0.1f, 0, 0.1f, 0.101f, 0});
    p.uv0.resize(p.positions.size() / 3 * 2);
    p.indices.insert(p.indices.end(), {n + 1, n + 2, n, n + 3, n + 4, n + 5});
    MeshStats stats;
    ProcessedMesh m = process(meshOf("s", {p}), stats);
    EXPECT_EQ(stats.degenerateTriangles, 1u);
    EXPECT_EQ(stats.outputTriangles, 3u);
}

TEST(MeshProcessing, AllTrianglesDroppedGivesEmptyMeshNotError) {
    IrPrimitive p;
    p.positions = {0, 0, 0, 1, 1, 1, 2, 2, 2};
    p.indices = {0, 1, 2, 0, 0, 0};
    MeshStats stats;
    auto r = processMesh(meshOf("line", {p}), {}, {.lodCount = 2}, stats);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->vertexCount, 0u);
    EXPECT_EQ(r->submeshes.size(), 1u);
    EXPECT_EQ(r->submeshes[0].indexCount, 0u);
    EXPECT_TRUE(r->indices.empty());
    EXPECT_EQ(stats.degenerateTriangles, 2u);
    EXPECT_EQ(stats.outputTriangles, 0u);
}

// [SECTION] normals and tangents

TEST(MeshProcessing, GeneratedNormalsPointOutwardOnClosedConvexMesh) {
    const float center[3] = {3, -2, 1};
    MeshStats stats;
    ProcessedMesh m = process(meshOf("sphere", {uvSphere(32, 16, 2.0f, center)}), stats);
    EXPECT_TRUE(stats.normalsGenerated);
    // Seam and pole duplicates weld: one vertex per distinct position.
    EXPECT_EQ(m.vertexCount, 32u * 15u + 2u);
    std::vector<float> n = decoded(m, VertexSemantic::Normal);
    std::vector<float> p = decoded(m, VertexSemantic::Position);
    for (uint32_t v = 0; v < m.vertexCount; ++v) {
        float radial[3] = {p[v * 3] - center[0], p[v * 3 + 1] - center[1],
                           p[v * 3 + 2] - center[2]};
        double len = std::sqrt(dot3(radial, radial));
        EXPECT_NEAR(std::sqrt(dot3(&n[v * 3], &n[v * 3])), 1.0, 1e-6);
        EXPECT_GT(dot3(&n[v * 3], radial) / len, 0.99) << "vertex " << v;
    }
}

TEST(MeshProcessing, ZeroLengthSourceNormalsAreRegeneratedOthersNormalised) {
    IrPrimitive p = grid(2, 2);
    p.normals.assign(p.vertexCount() * 3, 0.0f);
    for (size_t v = 0; v < p.vertexCount(); ++v)
        p.normals[v * 3 + 2] = v == 4 ? 0.0f : 5.0f;
    MeshStats stats;
    ProcessedMesh m = process(meshOf("g", {p}), stats);
    EXPECT_TRUE(stats.normalsGenerated);
    std::vector<float> n = decoded(m, VertexSemantic::Normal);
    for (uint32_t v = 0; v < m.vertexCount; ++v) {
        EXPECT_FLOAT_EQ(n[v * 3 + 2], 1.0f);
        EXPECT_EQ(n[v * 3], 0.0f);
    }
}

void expectOrthonormalTangents(const ProcessedMesh& m, double tolerance) {
    std::vector<float> n = decoded(m, VertexSemantic::Normal);
    std::vector<float> t = decoded(m, VertexSemantic::Tangent);
    ASSERT_EQ(t.size(), size_t(m.vertexCount) * 4);
    for (uint32_t v = 0; v < m.vertexCount; ++v) {
        float* tv = &t[v * 4];
        double len = std::sqrt(dot3(tv, tv));
        EXPECT_NEAR(len, 1.0, tolerance) << "vertex " << v;
        EXPECT_NEAR(dot3(tv, &n[v * 3]) / len, 0.0, tolerance) << "vertex " << v;
        EXPECT_EQ(std::fabs(tv[3]), 1.0f);
    }
}

TEST(MeshProcessing, TangentsAreOrthogonalToNormalsWithUnitHandedness) {
    const float center[3] = {0, 0, 0};
    MeshStats stats;
    ProcessedMesh m =
        process(meshOf("sphere", {uvSphere(24, 12, 1.0f, center)}), stats, {.tangents = true});
    EXPECT_TRUE(stats.tangentsGenerated);
    EXPECT_FALSE(stats.tangentsArbitrary);
    EXPECT_EQ(findStream(m, VertexSemantic::TexCoord0), nullptr) << "uv0 only fed the tangents";
    expectOrthonormalTangents(m, 1e-5);

    // Quantized: I16 ×4, w still exactly ±1, xyz within 16-bit snorm precision.
    ProcessedMesh q = process(meshOf("sphere", {uvSphere(24, 12, 1.0f, center)}), stats,
                              {.tangents = true}, {.quantize = true});
    const OwnedStream* ts = findStream(q, VertexSemantic::Tangent);
    ASSERT_NE(ts, nullptr);
    EXPECT_EQ(ts->desc.componentType, ComponentType::I16);
    EXPECT_EQ(ts->desc.componentCount, 4);
    expectOrthonormalTangents(q, 1e-3);
}

TEST(MeshProcessing, TangentFollowsUAndMirroringFlipsHandedness) {
    for (float uSign : {1.0f, -1.0f}) {
        IrPrimitive p = grid(2, 2);
        for (size_t v = 0; v < p.vertexCount(); ++v)
            p.uv0[v * 2] *= uSign;
        MeshStats stats;
        ProcessedMesh m = process(meshOf("g", {p}), stats, {.uv0 = true, .tangents = true});
        std::vector<float> t = decoded(m, VertexSemantic::Tangent);
        std::vector<float> n = decoded(m, VertexSemantic::Normal);
        for (uint32_t v = 0; v < m.vertexCount; ++v) {
            EXPECT_NEAR(n[v * 3 + 2], 1.0f, 1e-6); // grid winding faces +Z
            EXPECT_NEAR(t[v * 4], uSign, 1e-6) << "tangent points along +u";
            // The grid's +v is +y; glTF's v runs down the image and its normal maps store +Y
            // up the image, so the bitangent cross(n, t) * w must point along -v = -y: with
            // n = +z and t = uSign x, cross(n, t) = uSign y, hence w = -uSign.
            EXPECT_EQ(t[v * 4 + 3], -uSign);
        }
    }
}

TEST(MeshProcessing, SourceTangentsAreKept) {
    IrPrimitive p = grid(1, 1);
    for (size_t v = 0; v < p.vertexCount(); ++v)
        p.tangents.insert(p.tangents.end(), {0, 2, 0, -1});
    MeshStats stats;
    ProcessedMesh m = process(meshOf("g", {p}), stats, {.tangents = true});
    EXPECT_FALSE(stats.tangentsGenerated);
    std::vector<float> t = decoded(m, VertexSemantic::Tangent);
    for (uint32_t v = 0; v < m.vertexCount; ++v) {
        EXPECT_EQ(t[v * 4 + 1], 1.0f) << "normalised";
        EXPECT_EQ(t[v * 4 + 3], -1.0f);
    }
}

TEST(MeshProcessing, TangentsWithoutUvAreArbitraryAndFlagged) {
    IrPrimitive p = cubeFaces(true);
    p.uv0.clear();
    MeshStats stats;
    ProcessedMesh m = process(meshOf("cube", {p}), stats, {.tangents = true});
    EXPECT_TRUE(stats.tangentsGenerated);
    EXPECT_TRUE(stats.tangentsArbitrary);
    expectOrthonormalTangents(m, 1e-5);
}

// [SECTION] streams

TEST(MeshProcessing, OnlyNeededStreamsAreOutput) {
    IrPrimitive p = grid(2, 2);
    p.colors.assign(p.vertexCount() * 4, 0.5f);
    p.uv1 = p.uv0;
    MeshStats stats;
    ProcessedMesh m = process(meshOf("g", {p}), stats);
    ASSERT_EQ(m.streams.size(), 2u);
    EXPECT_EQ(m.streams[0].desc.semantic, VertexSemantic::Position);
    EXPECT_EQ(m.streams[1].desc.semantic, VertexSemantic::Normal);

    ProcessedMesh all = process(meshOf("g", {p}), stats,
                                {.uv0 = true, .uv1 = true, .tangents = true, .colors = true});
    std::vector<VertexSemantic> order;
    for (const OwnedStream& s : all.streams)
        order.push_back(s.desc.semantic);
    EXPECT_EQ(order, (std::vector{VertexSemantic::Position, VertexSemantic::Normal,
                                  VertexSemantic::Tangent, VertexSemantic::TexCoord0,
                                  VertexSemantic::TexCoord1, VertexSemantic::Color0}));
}

TEST(MeshProcessing, PrimitivesMergeIntoSubmeshesWithDefaultsForMissingStreams) {
    IrPrimitive a = grid(1, 1), b = grid(1, 1);
    a.colors.assign(a.vertexCount() * 4, 0.25f);
    a.material = 3;
    b.material = -1;
    for (size_t v = 0; v < b.vertexCount(); ++v)
        b.positions[v * 3 + 2] = 1; // lift b to z = 1
    b.uv0.clear();
    MeshStats stats;
    ProcessedMesh m = process(meshOf("two", {a, b}), stats, {.uv0 = true, .colors = true});
    ASSERT_EQ(m.submeshes.size(), 2u);
    EXPECT_EQ(m.submeshes[0].material, 3u);
    EXPECT_EQ(m.submeshes[1].material, kNone);
    EXPECT_EQ(m.submeshes[0].firstIndex, 0u);
    EXPECT_EQ(m.submeshes[1].firstIndex, m.submeshes[0].indexCount);
    EXPECT_EQ(m.submeshes[1].indexCount, 6u);
    EXPECT_EQ(m.vertexCount, 8u);
    std::vector<float> p = decoded(m, VertexSemantic::Position);
    std::vector<float> c = decoded(m, VertexSemantic::Color0);
    std::vector<float> uv = decoded(m, VertexSemantic::TexCoord0);
    for (uint32_t v = 0; v < m.vertexCount; ++v) {
        bool fromB = p[v * 3 + 2] == 1.0f;
        EXPECT_EQ(c[v * 4], fromB ? 1.0f : 0.25f);
        EXPECT_EQ(c[v * 4 + 3], fromB ? 1.0f : 0.25f);
        if (fromB) {
            EXPECT_EQ(uv[v * 2] + uv[v * 2 + 1], 0.0f);
        }
    }
    EXPECT_EQ(m.submeshes[1].bounds.min.z, 1.0f);
    EXPECT_EQ(m.submeshes[0].bounds.max.z, 0.0f);
}

// [SECTION] quantization

TEST(MeshProcessing, QuantizedPositionsAndNormalsDecodeWithinTheStatedBound) {
    const float center[3] = {100.0f, -3.0f, 7.5f};
    IrMesh mesh = meshOf("sphere", {uvSphere(64, 32, 5.0f, center)});
    MeshStats floatStats, stats;
    ProcessedMesh exact = process(mesh, floatStats, {.uv0 = true, .colors = true});
    ProcessedMesh q = process(mesh, stats, {.uv0 = true, .colors = true}, {.quantize = true});
    ASSERT_EQ(exact.vertexCount, q.vertexCount);
    EXPECT_EQ(floatStats.maxPositionError, 0.0f);

    const OwnedStream* ps = findStream(q, VertexSemantic::Position);
    ASSERT_NE(ps, nullptr);
    EXPECT_EQ(ps->desc.componentType, ComponentType::U16);
    EXPECT_TRUE(ps->desc.normalized);
    const OwnedStream* ns = findStream(q, VertexSemantic::Normal);
    EXPECT_EQ(ns->desc.componentType, ComponentType::I16);
    EXPECT_EQ(ns->desc.componentCount, 2);
    EXPECT_EQ(ns->desc.encoding, VertexEncoding::Octahedral);
    EXPECT_EQ(findStream(q, VertexSemantic::TexCoord0)->desc.componentType, ComponentType::F16);
    EXPECT_EQ(findStream(q, VertexSemantic::Color0)->desc.componentType, ComponentType::U8);

    // Same processing before encoding, so vertex i is the same vertex in both.
    std::vector<float> original = decoded(exact, VertexSemantic::Position);
    std::vector<float> restored = decoded(q, VertexSemantic::Position);
    const float extent[3] = {q.bounds.max.x - q.bounds.min.x, q.bounds.max.y - q.bounds.min.y,
                             q.bounds.max.z - q.bounds.min.z};
    const float magnitude =
        std::max({std::fabs(q.bounds.min.x), std::fabs(q.bounds.max.x), std::fabs(q.bounds.min.y),
                  std::fabs(q.bounds.max.y), std::fabs(q.bounds.min.z), std::fabs(q.bounds.max.z)});
    const double floatSlack = 2.0 * std::numeric_limits<float>::epsilon() * magnitude;
    double measured = 0, bound = 0;
    for (size_t i = 0; i < original.size(); ++i) {
        double axisBound = extent[i % 3] / 65535.0 / 2 + floatSlack;
        double e = std::fabs(double(restored[i]) - original[i]);
        EXPECT_LE(e, axisBound) << "component " << i;
        measured = std::max(measured, e);
        bound = std::max(bound, axisBound);
    }
    EXPECT_LE(stats.maxPositionError, bound);
    EXPECT_NEAR(stats.maxPositionError, measured, 1e-6 * magnitude) << "the stat is the real error";

    std::vector<float> n0 = decoded(exact, VertexSemantic::Normal);
    std::vector<float> n1 = decoded(q, VertexSemantic::Normal);
    double maxAngle = 0;
    for (uint32_t v = 0; v < q.vertexCount; ++v)
        maxAngle = std::max(maxAngle, angleBetween(&n0[v * 3], &n1[v * 3]));
    EXPECT_LE(stats.maxNormalErrorRadians, 1e-4f);
    // The reader normalises in float: allow its rounding on top of the reported error.
    EXPECT_LE(maxAngle, stats.maxNormalErrorRadians + 1e-6);
    std::printf("[ quantize ] %u vertices, extent %.3f x %.3f x %.3f at |x| <= %.1f: max position "
                "error %.3g (bound %.3g), max normal error %.3g rad\n",
                q.vertexCount, extent[0], extent[1], extent[2], magnitude,
                double(stats.maxPositionError), bound, double(stats.maxNormalErrorRadians));

    std::vector<float> uv0 = decoded(exact, VertexSemantic::TexCoord0);
    std::vector<float> uv1 = decoded(q, VertexSemantic::TexCoord0);
    for (size_t i = 0; i < uv0.size(); ++i)
        EXPECT_NEAR(uv1[i], uv0[i], 1.0 / 2048);
}

TEST(MeshProcessing, QuantizedFlatMeshHasZeroScaleAxis) {
    MeshStats stats;
    ProcessedMesh m = process(meshOf("g", {grid(3, 3)}), stats, {}, {.quantize = true});
    const OwnedStream* ps = findStream(m, VertexSemantic::Position);
    EXPECT_EQ(ps->desc.dequantScale.z, 0.0f);
    EXPECT_LE(stats.maxPositionError, 3.0 / 131070 + 4 * std::numeric_limits<float>::epsilon());
    std::vector<float> p = decoded(m, VertexSemantic::Position);
    for (size_t v = 0; v < p.size() / 3; ++v)
        EXPECT_EQ(p[v * 3 + 2], 0.0f) << "flat axis exact";
}

// [SECTION] optimisation, LODs, bounds, determinism

TEST(MeshProcessing, OptimisationNeverChangesTheTriangleSet) {
    const float center[3] = {0, 0, 0};
    IrPrimitive sphere = uvSphere(40, 20, 1.0f, center);
    IrPrimitive plane = grid(20, 20);
    // Shuffle the plane's triangles deterministically so the optimisers have work to do.
    for (size_t t = 0; t + 3 < plane.indices.size() / 3; t += 2) {
        size_t u = (t * 7919) % (plane.indices.size() / 3);
        for (int k = 0; k < 3; ++k)
            std::swap(plane.indices[t * 3 + k], plane.indices[u * 3 + k]);
    }
    IrMesh mesh = meshOf("two", {sphere, plane});
    MeshStats a, b;
    ProcessedMesh plain = process(mesh, a, {.uv0 = true}, {.optimize = false});
    ProcessedMesh optimised = process(mesh, b, {.uv0 = true}, {.optimize = true});
    EXPECT_EQ(plain.vertexCount, optimised.vertexCount);
    EXPECT_NE(plain.indices, optimised.indices) << "the optimisers did reorder";
    EXPECT_EQ(triangleSet(plain), triangleSet(optimised));
    ASSERT_EQ(plain.submeshes.size(), optimised.submeshes.size());
    for (size_t s = 0; s < plain.submeshes.size(); ++s) {
        EXPECT_EQ(plain.submeshes[s].firstIndex, optimised.submeshes[s].firstIndex);
        EXPECT_EQ(plain.submeshes[s].indexCount, optimised.submeshes[s].indexCount);
    }
    // And per submesh: the sphere's triangles stay in the sphere's range.
    ProcessedMesh sphereOnly = process(meshOf("s", {sphere}), a, {.uv0 = true});
    ProcessedMesh firstOnly = optimised;
    firstOnly.submeshes.resize(1);
    EXPECT_EQ(triangleSet(firstOnly), triangleSet(sphereOnly));
}

TEST(MeshProcessing, LodLevelsShrinkWithNonNegativeErrors) {
    const float center[3] = {0, 0, 0};
    IrPrimitive sphere = uvSphere(96, 48, 1.0f, center);
    MeshStats stats;
    ProcessedMesh m =
        process(meshOf("sphere", {sphere}), stats, {}, {.lodCount = 4, .lodRatio = 0.5f});
    ASSERT_GE(stats.lodErrors.size(), 1u);
    EXPECT_LE(stats.lodErrors.size(), 4u);
    ASSERT_EQ(m.submeshes.size(), 1 + stats.lodErrors.size());
    uint32_t previous = m.submeshes[0].indexCount;
    uint32_t end = 0;
    for (size_t s = 0; s < m.submeshes.size(); ++s) {
        const Submesh& sm = m.submeshes[s];
        EXPECT_EQ(sm.lod, s);
        EXPECT_EQ(sm.firstIndex, end) << "levels are appended in order";
        end = sm.firstIndex + sm.indexCount;
        EXPECT_EQ(sm.indexCount % 3, 0u);
        if (s > 0) {
            EXPECT_LT(sm.indexCount, previous);
            EXPECT_GE(sm.lodError, 0.0f);
            EXPECT_EQ(sm.lodError, stats.lodErrors[s - 1]);
            EXPECT_LE(sm.lodError, 0.05f) << "1% target of a 2-unit sphere, in mesh units";
            previous = sm.indexCount;
        }
        std::printf("[ lod ] level %u: %u triangles, error %.4g\n", unsigned(sm.lod),
                    sm.indexCount / 3, double(sm.lodError));
    }
    EXPECT_EQ(end * (m.indexType == IndexType::U16 ? 2u : 4u), m.indices.size());
    for (uint32_t i : indicesOf(m))
        EXPECT_LT(i, m.vertexCount);
}

// Tiles that meet edge to edge (terrain) are simplified each on its own; if a level moved or
// removed a vertex of the tile's open border, the neighbour drawn at another level would no
// longer meet it and the seam would crack. With lodLockBorders (the default) every level keeps
// every border vertex of level 0; without it the simplifier takes some of them away.
TEST(MeshProcessing, LodLevelsKeepOpenBorderVerticesUnlessFreed) {
    constexpr int n = 32;
    IrPrimitive tile = grid(n, n);
    for (size_t i = 0; i < tile.positions.size(); i += 3) // a gentle heightfield
        tile.positions[i + 2] =
            0.4f * std::sin(tile.positions[i] * 0.45f) * std::cos(tile.positions[i + 1] * 0.3f);
    auto borderVerticesPerLevel = [&](bool lock) {
        MeshStats stats;
        ProcessedMesh m = process(meshOf("tile", {tile}), stats, {},
                                  {.lodCount = 3, .lodRatio = 0.5f, .lodLockBorders = lock});
        std::vector<float> pos = decoded(m, VertexSemantic::Position);
        std::vector<uint32_t> ix = indicesOf(m);
        std::vector<std::pair<size_t, uint32_t>> out; // (border vertices used, triangles)
        for (const Submesh& sm : m.submeshes) {
            std::set<uint32_t> border;
            for (uint32_t k = sm.firstIndex; k < sm.firstIndex + sm.indexCount; ++k) {
                const float x = pos[size_t(ix[k]) * 3], y = pos[size_t(ix[k]) * 3 + 1];
                if (x == 0 || y == 0 || x == n || y == n) border.insert(ix[k]);
            }
            out.emplace_back(border.size(), sm.indexCount / 3);
        }
        return out;
    };
    const auto locked = borderVerticesPerLevel(true);
    ASSERT_GE(locked.size(), 2u) << "no LOD level was produced";
    EXPECT_EQ(locked[0].first, size_t(4 * n)) << "level 0 uses every border vertex";
    for (size_t level = 1; level < locked.size(); ++level) {
        EXPECT_EQ(locked[level].first, locked[0].first) << "level " << level;
        EXPECT_LT(locked[level].second, locked[level - 1].second) << "level " << level;
    }
    const auto freed = borderVerticesPerLevel(false);
    ASSERT_GE(freed.size(), 2u);
    EXPECT_LT(freed.back().first, freed[0].first)
        << "with free borders the coarsest level should drop border vertices";
}

TEST(MeshProcessing, LodChainStopsWhenNothingCanBeRemoved) {
    MeshStats stats;
    // One triangle: nothing to remove, so no level is produced.
    IrPrimitive tri;
    tri.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    tri.indices = {0, 1, 2};
    ProcessedMesh m = process(meshOf("t", {tri}), stats, {}, {.lodCount = 3});
    EXPECT_EQ(m.submeshes.size(), 1u);
    EXPECT_TRUE(stats.lodErrors.empty());
}

TEST(MeshProcessing, BoundsContainEveryVertex) {
    const float center[3] = {-40, 12, 3};
    IrPrimitive a = uvSphere(17, 9, 3.0f, center);
    IrPrimitive b = grid(7, 3);
    for (float& f : b.positions)
        f = f * 1.37f - 2.0f;
    MeshStats stats;
    for (bool quantize : {false, true}) {
        ProcessedMesh m =
            process(meshOf("m", {a, b}), stats, {}, {.quantize = quantize, .lodCount = 2});
        std::vector<float> p = decoded(m, VertexSemantic::Position);
        std::vector<uint32_t> ix = indicesOf(m);
        double maxDistance = 0;
        for (uint32_t v = 0; v < m.vertexCount; ++v) {
            const float* pv = &p[v * 3];
            EXPECT_TRUE(inside(m.bounds, pv)) << "vertex " << v;
            double d[3] = {pv[0] - double(m.boundingSphere.center.x),
                           pv[1] - double(m.boundingSphere.center.y),
                           pv[2] - double(m.boundingSphere.center.z)};
            double dist = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            maxDistance = std::max(maxDistance, dist);
            EXPECT_LE(dist, m.boundingSphere.radius) << "vertex " << v;
        }
        // Tight about its centre, and no worse than the sphere around the box.
        EXPECT_LE(m.boundingSphere.radius, maxDistance * (1 + 1e-5));
        double dx = double(m.bounds.max.x) - m.bounds.min.x,
               dy = double(m.bounds.max.y) - m.bounds.min.y,
               dz = double(m.bounds.max.z) - m.bounds.min.z;
        EXPECT_LE(m.boundingSphere.radius,
                  0.5 * std::sqrt(dx * dx + dy * dy + dz * dz) * (1 + 1e-5));
        for (const Submesh& s : m.submeshes) {
            for (uint32_t i = s.firstIndex; i < s.firstIndex + s.indexCount; ++i)
                EXPECT_TRUE(inside(s.bounds, &p[ix[i] * 3]));
            EXPECT_TRUE(inside(m.bounds, s.bounds.min) && inside(m.bounds, s.bounds.max));
        }
    }
}

TEST(MeshProcessing, OutputIsDeterministic) {
    const float center[3] = {1, 2, 3};
    IrMesh mesh = meshOf("d", {uvSphere(30, 15, 1.0f, center), grid(9, 9)});
    MeshSettings settings{.quantize = true, .lodCount = 2};
    StreamNeeds needs{.uv0 = true, .tangents = true};
    MeshStats s1, s2;
    ProcessedMesh a = process(mesh, s1, needs, settings);
    ProcessedMesh b = process(mesh, s2, needs, settings);
    EXPECT_EQ(a.indices, b.indices);
    ASSERT_EQ(a.streams.size(), b.streams.size());
    for (size_t i = 0; i < a.streams.size(); ++i)
        EXPECT_EQ(a.streams[i].bytes, b.streams[i].bytes);
    EXPECT_EQ(s1.lodErrors, s2.lodErrors);
}

// [SECTION] errors and hostile input

std::string errorOf(const IrMesh& mesh, MeshSettings settings = {}) {
    MeshStats stats;
    auto r = processMesh(mesh, {}, settings, stats);
    EXPECT_FALSE(r.ok());
    if (r.ok()) return "";
    EXPECT_EQ(r.error().kind, ConvertErrorKind::Input);
    return r.error().message;
}

TEST(MeshProcessing, OutOfRangeIndexNamesMeshAndPrimitive) {
    IrPrimitive ok = grid(1, 1), bad;
    bad.positions.assign(800 * 3, 0.0f);
    bad.indices = {0, 1, 812};
    EXPECT_EQ(errorOf(meshOf("Wheel", {ok, ok, bad})),
              "mesh 'Wheel' primitive 2: index 812 out of range (800 vertices)");
}

TEST(MeshProcessing, HostileInputIsAnErrorNotACrash) {
    EXPECT_EQ(errorOf(meshOf("e", {})), "mesh 'e': no primitives");
    EXPECT_EQ(errorOf(meshOf("z", {IrPrimitive{}})), "mesh 'z' primitive 0: no positions");

    IrPrimitive p = grid(1, 1);
    p.indices.push_back(0);
    EXPECT_EQ(errorOf(meshOf("m", {p})), "mesh 'm' primitive 0: 7 indices, not a multiple of 3");

    p = grid(1, 1);
    p.indices.insert(p.indices.end(), {0, 1, 0xFFFFFFFFu});
    EXPECT_EQ(errorOf(meshOf("m", {p})),
              "mesh 'm' primitive 0: index 4294967295 out of range (4 vertices)");

    p = grid(1, 1);
    p.positions.pop_back();
    EXPECT_NE(errorOf(meshOf("m", {p})).find("not a multiple of 3"), std::string::npos);

    p = grid(1, 1);
    p.normals = {0, 0, 1};
    EXPECT_EQ(errorOf(meshOf("m", {p})),
              "mesh 'm' primitive 0: 3 normal floats, expected 12 (4 vertices × 3)");

    p = grid(1, 1);
    p.material = -7;
    EXPECT_NE(errorOf(meshOf("m", {p})).find("material index -7"), std::string::npos);

    EXPECT_NE(
        errorOf(meshOf("m", {grid(1, 1)}), {.lodCount = 1, .lodRatio = NAN}).find("LOD ratio"),
        std::string::npos);

    // Valid but unpleasant: huge coordinates, infinities, NaN attributes. No crash, finite output.
    p = grid(2, 2);
    // Coordinates -2e38, 0, 2e38: valid floats, but the extent 4e38 overflows float.
    for (float& f : p.positions)
        f = float(double(f) * 2e38 - 2e38);
    p.positions[7] = INFINITY; // vertex 2 y
    p.uv0[2] = NAN;
    p.normals.assign(p.vertexCount() * 3, NAN);
    MeshStats stats;
    auto r = processMesh(meshOf("h", {p}), {.uv0 = true, .tangents = true},
                         {.quantize = true, .lodCount = 2}, stats);
    ASSERT_TRUE(r.ok());
    EXPECT_GT(stats.nonFiniteTriangles, 0u);
    for (float f : decoded(*r, VertexSemantic::Normal))
        EXPECT_TRUE(std::isfinite(f));
    for (float f : decoded(*r, VertexSemantic::TexCoord0))
        EXPECT_TRUE(std::isfinite(f));
    EXPECT_EQ(findStream(*r, VertexSemantic::Position)->desc.componentType, ComponentType::F32)
        << "an extent past float range cannot be a dequantScale";
    for (uint32_t i : indicesOf(*r))
        EXPECT_LT(i, r->vertexCount);
    EXPECT_GT(r->vertexCount, 0u);
    for (float e : stats.lodErrors)
        EXPECT_TRUE(std::isfinite(e));
    EXPECT_TRUE(std::isfinite(r->boundingSphere.radius));

    // No triangles left: still every stream the materials need, each empty.
    IrPrimitive flat;
    flat.positions = {0, 0, 0, 1, 0, 0, 2, 0, 0};
    flat.indices = {0, 1, 2};
    auto empty = processMesh(meshOf("flat", {flat}), {.uv0 = true, .colors = true},
                             {.quantize = true}, stats);
    ASSERT_TRUE(empty.ok());
    EXPECT_EQ(empty->streams.size(), 4u);
    for (const OwnedStream& s : empty->streams)
        EXPECT_TRUE(s.bytes.empty());
}

// Random triangle soups on a coarse lattice (so duplicates, slivers and degenerates are common),
// with random NaNs, random stream presence and random settings: the invariants must hold.
TEST(MeshProcessing, RandomSoupsKeepInvariants) {
    uint64_t state = 12345;
    auto next = [&](uint32_t bound) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return uint32_t((state >> 33) % bound);
    };
    for (int iteration = 0; iteration < 200; ++iteration) {
        IrMesh mesh;
        mesh.name = "soup" + std::to_string(iteration);
        for (uint32_t prim = 0, count = 1 + next(3); prim < count; ++prim) {
            IrPrimitive p;
            uint32_t vertices = 1 + next(40);
            for (uint32_t v = 0; v < vertices * 3; ++v)
                p.positions.push_back(next(50) == 0 ? NAN : float(next(4)) * 0.5f);
            auto maybe = [&](std::vector<float>& stream, size_t components, float scale) {
                if (next(2))
                    for (size_t k = 0; k < vertices * components; ++k)
                        stream.push_back(float(next(3)) * scale - scale);
            };
            maybe(p.normals, 3, 1.0f);
            maybe(p.tangents, 4, 1.0f);
            maybe(p.uv0, 2, 0.5f);
            maybe(p.uv1, 2, 0.5f);
            maybe(p.colors, 4, 0.5f);
            for (uint32_t t = 0, tris = next(60); t < tris * 3; ++t)
                p.indices.push_back(next(vertices));
            p.material = int(next(3)) - 1;
            mesh.primitives.push_back(std::move(p));
        }
        StreamNeeds needs{.uv0 = next(2) == 1,
                          .uv1 = next(2) == 1,
                          .tangents = next(2) == 1,
                          .colors = next(2) == 1};
        MeshSettings settings{.optimize = next(2) == 1,
                              .quantize = next(2) == 1,
                              .lodCount = next(3),
                              .lodRatio = 0.5f};
        MeshStats stats, again;
        ProcessedMesh m = process(mesh, stats, needs, settings);
        ProcessedMesh m2 = process(mesh, again, needs, settings);
        ASSERT_EQ(m.indices, m2.indices) << "iteration " << iteration;

        EXPECT_EQ(stats.outputTriangles,
                  stats.inputTriangles - stats.degenerateTriangles - stats.nonFiniteTriangles);
        uint64_t level0 = 0;
        for (const Submesh& sm : m.submeshes) {
            if (sm.lod == 0) level0 += sm.indexCount;
            EXPECT_LE(uint64_t(sm.firstIndex) + sm.indexCount, indicesOf(m).size());
        }
        EXPECT_EQ(level0, stats.outputTriangles * 3);
        EXPECT_EQ(
            m.submeshes.size(), mesh.primitives.size() + [&] {
                size_t lods = 0;
                for (const Submesh& sm : m.submeshes)
                    lods += sm.lod != 0;
                return lods;
            }());
        std::vector<uint32_t> ix = indicesOf(m);
        for (uint32_t i : ix)
            ASSERT_LT(i, m.vertexCount);
        for (size_t t = 0; t + 2 < level0; t += 3)
            EXPECT_TRUE(ix[t] != ix[t + 1] && ix[t + 1] != ix[t + 2] && ix[t] != ix[t + 2]);
        EXPECT_EQ(m.streams.size(),
                  2u + needs.tangents + needs.uv0 + needs.uv1 + size_t(needs.colors));
        std::vector<float> pos = decoded(m, VertexSemantic::Position);
        std::vector<float> nrm = decoded(m, VertexSemantic::Normal);
        for (uint32_t v = 0; v < m.vertexCount; ++v) {
            EXPECT_TRUE(inside(m.bounds, &pos[v * 3]));
            EXPECT_NEAR(std::sqrt(dot3(&nrm[v * 3], &nrm[v * 3])), 1.0, 1e-5);
        }
        if (needs.tangents) {
            std::vector<float> tan = decoded(m, VertexSemantic::Tangent);
            for (uint32_t v = 0; v < m.vertexCount; ++v) {
                EXPECT_NEAR(std::sqrt(dot3(&tan[v * 4], &tan[v * 4])), 1.0, 1e-3);
                EXPECT_EQ(std::fabs(tan[v * 4 + 3]), 1.0f);
            }
        }
        for (float e : stats.lodErrors)
            EXPECT_GE(e, 0.0f);
    }
}

// [SECTION] scale

TEST(MeshProcessing, LargeGridProcessesQuickly) {
    IrPrimitive p = grid(317, 317); // 200,978 triangles, 101,124 vertices
    IrMesh mesh = meshOf("big", {p});
    MeshStats stats;
    auto start = std::chrono::steady_clock::now();
    ProcessedMesh m = process(mesh, stats, {.uv0 = true, .tangents = true}, {.quantize = true});
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("[ timing ] %llu triangles, %u vertices: %.3f s (optimize + quantize + tangents)\n",
                (unsigned long long)stats.outputTriangles, m.vertexCount, seconds);
    EXPECT_EQ(stats.outputTriangles, 317u * 317u * 2u);
    EXPECT_EQ(m.vertexCount, 318u * 318u);
    EXPECT_EQ(m.indexType, IndexType::U32) << "more than 65535 vertices";

    MeshStats small;
    ProcessedMesh s = process(meshOf("small", {grid(100, 100)}), small);
    EXPECT_EQ(s.indexType, IndexType::U16);
}

} // namespace
