// converter/src/mesh_encode.cpp — float vertex streams into container streams (F32 or quantized)
// and index bytes.
//
// The quantized encodings, and how a reader decodes them, are specified in mesh_processing.h
// (MeshSettings::quantize); this file must match that table. Each quantizer picks, among the
// codes next to the rounded one, the code whose *decoded* value (computed in float exactly as
// documented) is closest to the source, so the reported error is the error a reader sees, and
// rounding inside the decode formula cannot push it past half a step.
//
// Based on: Cigolle et al., "A Survey of Efficient Representations for Independent Unit Vectors"
// (JCGT 2014) — octahedral mapping and its "precise" variant (best of the 4 neighbouring codes).

#include <algorithm>
#include <bit>
#include <cmath>

#include <meshoptimizer.h>

#include "mesh_internal.h"

namespace pnb::converter::mesh_detail {

namespace {

// Little-endian stores; the container is little-endian on every host.
void store16(std::byte* d, uint16_t v) {
    d[0] = std::byte(v & 0xFF);
    d[1] = std::byte(v >> 8);
}
void store32(std::byte* d, uint32_t v) {
    for (int k = 0; k < 4; ++k)
        d[k] = std::byte((v >> (8 * k)) & 0xFF);
}

OwnedStream makeStream(VertexSemantic semantic, ComponentType type, uint8_t components,
                       bool normalized, VertexEncoding encoding, size_t vertexCount) {
    OwnedStream s;
    s.desc.semantic = semantic;
    s.desc.componentType = type;
    s.desc.componentCount = components;
    s.desc.normalized = normalized;
    s.desc.encoding = encoding;
    s.bytes.resize(vertexCount * components * componentSizeBytes(type));
    return s;
}

OwnedStream encodeF32(VertexSemantic semantic, const std::vector<float>& data, uint8_t components,
                      size_t vertexCount) {
    OwnedStream s = makeStream(semantic, ComponentType::F32, components, false,
                               VertexEncoding::Plain, vertexCount);
    for (size_t i = 0; i < data.size(); ++i)
        store32(&s.bytes[i * 4], std::bit_cast<uint32_t>(data[i]));
    return s;
}

// [positions] U16 normalized, per-axis box: value = (q / 65535) * extent + min.
float decodeUnorm16(int q, float extent, float min) {
    return float(q) / 65535.0f * extent + min;
}

uint16_t quantizePosition(float p, float extent, float min, float& decoded, double& error) {
    int rounded = extent > 0
                      ? int(std::lround(std::clamp((double(p) - min) / extent, 0.0, 1.0) * 65535.0))
                      : 0;
    int best = rounded;
    double bestError = std::fabs(double(decodeUnorm16(rounded, extent, min)) - p);
    for (int q : {rounded - 1, rounded + 1}) {
        if (q < 0 || q > 65535) continue;
        double e = std::fabs(double(decodeUnorm16(q, extent, min)) - p);
        if (e < bestError) bestError = e, best = q;
    }
    error = bestError;
    decoded = decodeUnorm16(best, extent, min);
    return uint16_t(best);
}

// [normals] octahedral mapping of a unit vector to [-1,1]^2 and back.
float signNotZero(float v) {
    return v < 0 ? -1.0f : 1.0f;
}

void octEncode(const float n[3], float& u, float& v) {
    float l1 = std::fabs(n[0]) + std::fabs(n[1]) + std::fabs(n[2]);
    u = n[0] / l1;
    v = n[1] / l1;
    if (n[2] < 0) {
        float fu = (1.0f - std::fabs(v)) * signNotZero(u);
        float fv = (1.0f - std::fabs(u)) * signNotZero(v);
        u = fu, v = fv;
    }
}

float decodeSnorm16(int q) {
    return std::max(float(q) / 32767.0f, -1.0f);
}

void octDecode(int qu, int qv, double out[3]) {
    float u = decodeSnorm16(qu), v = decodeSnorm16(qv);
    float z = 1.0f - std::fabs(u) - std::fabs(v);
    if (z < 0) {
        float fu = (1.0f - std::fabs(v)) * signNotZero(u);
        float fv = (1.0f - std::fabs(u)) * signNotZero(v);
        u = fu, v = fv;
    }
    double len = std::sqrt(double(u) * u + double(v) * v + double(z) * z);
    out[0] = u / len, out[1] = v / len, out[2] = z / len;
}

// Angle between unit vectors, accurate near 0 (acos of a dot product is not).
double angleBetween(const float a[3], const double b[3]) {
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    return std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), d);
}

void quantizeOctahedral(const float n[3], int16_t& outU, int16_t& outV, double& error) {
    float u, v;
    octEncode(n, u, v);
    int fu = int(std::floor(u * 32767.0f)), fv = int(std::floor(v * 32767.0f));
    error = 10; // > pi
    for (int du = 0; du < 2; ++du) {
        for (int dv = 0; dv < 2; ++dv) {
            int qu = std::clamp(fu + du, -32767, 32767), qv = std::clamp(fv + dv, -32767, 32767);
            double decoded[3];
            octDecode(qu, qv, decoded);
            double e = angleBetween(n, decoded);
            if (e < error) error = e, outU = int16_t(qu), outV = int16_t(qv);
        }
    }
}

} // namespace

std::vector<OwnedStream> encodeStreams(const VertexData& v, const StreamNeeds& needs,
                                       const Aabb& box, bool quantizeAll,
                                       std::vector<float>& storedPositions, MeshStats& stats) {
    // A deformed mesh's positions, normals and tangents are what the deforming pass reads and
    // rewrites: F32 Plain whatever --quantize says (FORMAT.md "MRPH"); its other streams follow
    // the setting.
    const bool quantize = quantizeAll && !v.deformed;
    stats.maxPositionError = 0;
    stats.maxNormalErrorRadians = 0;
    const size_t n = v.count;
    std::vector<OwnedStream> out;

    const float lo[3] = {box.min.x, box.min.y, box.min.z};
    float extent[3] = {box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z};
    // An extent past float range (coordinates near ±3.4e38) cannot be a dequantScale.
    bool extentOk = n == 0 || (std::isfinite(extent[0]) && std::isfinite(extent[1]) &&
                               std::isfinite(extent[2]));
    if (quantize && extentOk) {
        OwnedStream s = makeStream(VertexSemantic::Position, ComponentType::U16, 3, true,
                                   VertexEncoding::Plain, n);
        if (n == 0) extent[0] = extent[1] = extent[2] = 0;
        s.desc.dequantScale = {extent[0], extent[1], extent[2]};
        s.desc.dequantOffset = {n ? lo[0] : 0, n ? lo[1] : 0, n ? lo[2] : 0};
        storedPositions.resize(n * 3);
        double maxError = 0;
        for (size_t i = 0; i < n * 3; ++i) {
            double e;
            store16(&s.bytes[i * 2], quantizePosition(v.positions[i], extent[i % 3], lo[i % 3],
                                                      storedPositions[i], e));
            maxError = std::max(maxError, e);
        }
        stats.maxPositionError = float(maxError);
        out.push_back(std::move(s));
    } else {
        storedPositions = v.positions;
        out.push_back(encodeF32(VertexSemantic::Position, v.positions, 3, n));
    }

    if (quantize) {
        OwnedStream s = makeStream(VertexSemantic::Normal, ComponentType::I16, 2, true,
                                   VertexEncoding::Octahedral, n);
        double maxError = 0;
        for (size_t i = 0; i < n; ++i) {
            int16_t qu = 0, qv = 0;
            double e;
            quantizeOctahedral(&v.normals[i * 3], qu, qv, e);
            store16(&s.bytes[i * 4], uint16_t(qu));
            store16(&s.bytes[i * 4 + 2], uint16_t(qv));
            maxError = std::max(maxError, e);
        }
        stats.maxNormalErrorRadians = float(maxError);
        out.push_back(std::move(s));
    } else {
        out.push_back(encodeF32(VertexSemantic::Normal, v.normals, 3, n));
    }

    if (needs.tangents) {
        if (quantize) {
            OwnedStream s = makeStream(VertexSemantic::Tangent, ComponentType::I16, 4, true,
                                       VertexEncoding::Plain, n);
            for (size_t i = 0; i < n * 4; ++i) {
                // xyz: unit vector components; w: exactly ±1 (±32767).
                int q = i % 4 == 3 ? (v.tangents[i] < 0 ? -32767 : 32767)
                                   : meshopt_quantizeSnorm(v.tangents[i], 16);
                store16(&s.bytes[i * 2], uint16_t(int16_t(q)));
            }
            out.push_back(std::move(s));
        } else {
            out.push_back(encodeF32(VertexSemantic::Tangent, v.tangents, 4, n));
        }
    }

    auto encodeUv = [&](VertexSemantic semantic, const std::vector<float>& uv, bool needed) {
        if (!needed) return;
        if (!quantizeAll) {
            out.push_back(encodeF32(semantic, uv, 2, n));
            return;
        }
        OwnedStream s =
            makeStream(semantic, ComponentType::F16, 2, false, VertexEncoding::Plain, n);
        for (size_t i = 0; i < n * 2; ++i) {
            // Clamp to the largest finite half: a huge tiling factor must not become infinity.
            store16(&s.bytes[i * 2], meshopt_quantizeHalf(std::clamp(uv[i], -65504.0f, 65504.0f)));
        }
        out.push_back(std::move(s));
    };
    encodeUv(VertexSemantic::TexCoord0, v.uv0, needs.uv0);
    encodeUv(VertexSemantic::TexCoord1, v.uv1, needs.uv1);

    if (needs.colors) {
        if (quantizeAll) {
            OwnedStream s = makeStream(VertexSemantic::Color0, ComponentType::U8, 4, true,
                                       VertexEncoding::Plain, n);
            for (size_t i = 0; i < n * 4; ++i)
                s.bytes[i] = std::byte(meshopt_quantizeUnorm(v.colors[i], 8)); // clamps to [0,1]
            out.push_back(std::move(s));
        } else {
            out.push_back(encodeF32(VertexSemantic::Color0, v.colors, 4, n));
        }
    }
    if (!v.joints.empty()) {
        // U8 when every index fits, else U16 (a skin has at most kMaxJoints joints).
        const bool small = std::all_of(v.joints.begin(), v.joints.end(), [](uint32_t j) { return j < 256; });
        OwnedStream s = makeStream(VertexSemantic::Joints0, small ? ComponentType::U8 : ComponentType::U16, 4,
                                   false, VertexEncoding::Plain, n);
        for (size_t i = 0; i < n * 4; ++i) {
            if (small) s.bytes[i] = std::byte(v.joints[i]);
            else store16(&s.bytes[i * 2], uint16_t(v.joints[i]));
        }
        out.push_back(std::move(s));
        out.push_back(encodeF32(VertexSemantic::Weights0, v.weights, 4, n));
    }
    return out;
}

std::vector<ProcessedMorphTarget> encodeMorphTargets(const VertexData& v,
                                                     const std::vector<MorphSlots>& targets) {
    std::vector<ProcessedMorphTarget> out(targets.size());
    const size_t n = v.count;
    std::vector<float> delta(n * 3);
    for (size_t t = 0; t < targets.size(); ++t) {
        const MorphSlots& slots = targets[t];
        const std::pair<VertexSemantic, int> kept[] = {{VertexSemantic::Position, slots.position},
                                                       {VertexSemantic::Normal, slots.normal},
                                                       {VertexSemantic::Tangent, slots.tangent}};
        for (const auto& [semantic, slot] : kept) {
            if (slot < 0) continue;
            for (size_t i = 0; i < n; ++i)
                std::copy_n(&v.morph[i * v.morphStride + size_t(slot)], 3, &delta[i * 3]);
            out[t].deltas.push_back(encodeF32(semantic, delta, 3, n));
        }
    }
    return out;
}

std::vector<std::byte> encodeIndices(std::span<const uint32_t> indices, IndexType type) {
    std::vector<std::byte> bytes(indices.size() * (type == IndexType::U16 ? 2 : 4));
    for (size_t i = 0; i < indices.size(); ++i) {
        if (type == IndexType::U16)
            store16(&bytes[i * 2], uint16_t(indices[i]));
        else
            store32(&bytes[i * 4], indices[i]);
    }
    return bytes;
}

} // namespace pnb::converter::mesh_detail
