// converter/src/mesh_tangents.cpp — per-vertex tangent frames for normal mapping.
//
// Per triangle, the directions in which u and v increase across it (the UV gradients of
// position, "sdir" and "tdir") are solved from its two edges and their UV deltas. They are summed
// per group of vertices with bitwise-equal (position, normal, uv0): vertices that the weld will
// merge later must get the same tangent, or they would not merge. Each vertex's tangent is the
// sum of sdir Gram-Schmidt orthogonalised against its normal; w is the handedness, chosen so
// that glTF's bitangent = cross(normal, tangent.xyz) × w points *up the image*, i.e. along
// -tdir: glTF's UVs run v down the image while its normal maps store +Y up the image (the
// OpenGL convention, what MikkTSpace gives an exporter that flips V, and what the Khronos sample
// viewer derives from screen-space UV derivatives). An unmirrored UV layout gets w = +1.
//
// Deviation from Lengyel: his sums add raw gradients, whose length is |edge| / |uv edge|, so a
// triangle with a nearly collinear UV mapping (huge gradient) dominates its neighbours. We add
// the *unit* gradients weighted by the triangle's area, as the normals are.
//
// Fallbacks: a triangle whose UVs are collinear contributes nothing; a vertex left with no usable
// gradient (or one parallel to its normal) gets an arbitrary orthonormal tangent, w = +1, as do
// vertices of primitives without uv0 (the caller flags that in MeshStats).
//
// Based on: Lengyel, "Computing Tangent Space Basis Vectors for an Arbitrary Mesh" (2001);
// Duff et al., "Building an Orthonormal Basis, Revisited" (JCGT 2017) for the arbitrary basis.

#include <cmath>

#include <meshoptimizer.h>

#include "mesh_internal.h"

namespace pnb::converter::mesh_detail {

namespace {

double length3(const double* v) {
    return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

// Adds `scale` × unit(d) to acc[group]; does nothing for a zero or non-finite d.
void addUnit(std::vector<double>& acc, uint32_t group, const double d[3], double scale) {
    double len = length3(d);
    if (!(len > 0) || !std::isfinite(len)) return;
    for (int k = 0; k < 3; ++k)
        acc[size_t(group) * 3 + k] += d[k] / len * scale;
}

void storeArbitrary(const float* n, float* t) {
    orthonormalTangent(n, t);
    t[3] = 1.0f;
}

} // namespace

void orthonormalTangent(const float n[3], float t[3]) {
    float sign = std::copysign(1.0f, n[2]);
    float a = -1.0f / (sign + n[2]);
    float b = n[0] * n[1] * a;
    t[0] = 1.0f + sign * n[0] * n[0] * a + 0.0f;
    t[1] = sign * b + 0.0f;
    t[2] = -sign * n[0] + 0.0f;
}

void generateTangents(VertexData& v, std::span<const uint32_t> indices,
                      std::span<const TangentSource> source) {
    bool anyFromUv = false;
    for (size_t i = 0; i < v.count; ++i)
        anyFromUv |= source[i] == TangentSource::FromUv;

    std::vector<uint32_t> group;
    std::vector<double> sSum, tSum;
    if (anyFromUv && !indices.empty()) {
        group.resize(v.count);
        const meshopt_Stream keys[] = {
            {v.positions.data(), sizeof(float) * 3, sizeof(float) * 3},
            {v.normals.data(), sizeof(float) * 3, sizeof(float) * 3},
            {v.uv0.data(), sizeof(float) * 2, sizeof(float) * 2},
        };
        meshopt_generateVertexRemapMulti(group.data(), indices.data(), indices.size(), v.count,
                                         keys, 3);
        sSum.assign(v.count * 3, 0.0);
        tSum.assign(v.count * 3, 0.0);
        const float* p = v.positions.data();
        const float* uv = v.uv0.data();
        for (size_t t = 0; t + 2 < indices.size(); t += 3) {
            uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
            if (source[a] != TangentSource::FromUv && source[b] != TangentSource::FromUv &&
                source[c] != TangentSource::FromUv)
                continue;
            double x1[3], x2[3];
            for (int k = 0; k < 3; ++k) {
                x1[k] = double(p[b * 3 + k]) - p[a * 3 + k];
                x2[k] = double(p[c * 3 + k]) - p[a * 3 + k];
            }
            double s1 = double(uv[b * 2]) - uv[a * 2], s2 = double(uv[c * 2]) - uv[a * 2];
            double t1 = double(uv[b * 2 + 1]) - uv[a * 2 + 1];
            double t2 = double(uv[c * 2 + 1]) - uv[a * 2 + 1];
            double det = s1 * t2 - s2 * t1;
            if (det == 0 || !std::isfinite(det)) continue;
            // Gradients up to the common factor 1/det; its sign matters (mirroring), its size
            // does not (unit vectors are added).
            double sign = det < 0 ? -1.0 : 1.0;
            double sdir[3], tdir[3];
            for (int k = 0; k < 3; ++k) {
                sdir[k] = (t2 * x1[k] - t1 * x2[k]) * sign;
                tdir[k] = (s1 * x2[k] - s2 * x1[k]) * sign;
            }
            double cross[3] = {x1[1] * x2[2] - x1[2] * x2[1], x1[2] * x2[0] - x1[0] * x2[2],
                               x1[0] * x2[1] - x1[1] * x2[0]};
            double twiceArea = length3(cross);
            for (uint32_t corner : {a, b, c}) {
                if (group[corner] == ~0u) continue;
                addUnit(sSum, group[corner], sdir, twiceArea);
                addUnit(tSum, group[corner], tdir, twiceArea);
            }
        }
    }

    for (size_t i = 0; i < v.count; ++i) {
        const float* n = &v.normals[i * 3];
        float* out = &v.tangents[i * 4];
        if (source[i] == TangentSource::Keep) continue;
        if (source[i] == TangentSource::Arbitrary || group.empty() || group[i] == ~0u) {
            storeArbitrary(n, out);
            continue;
        }
        const double* s = &sSum[size_t(group[i]) * 3];
        const double* tb = &tSum[size_t(group[i]) * 3];
        double nd = s[0] * n[0] + s[1] * n[1] + s[2] * n[2];
        double t[3] = {s[0] - n[0] * nd, s[1] - n[1] * nd, s[2] - n[2] * nd};
        double len = length3(t);
        // Orthogonalising a sum (nearly) parallel to the normal leaves rounding noise only.
        if (!(len > 1e-6 * length3(s)) || !std::isfinite(len)) {
            storeArbitrary(n, out);
            continue;
        }
        for (int k = 0; k < 3; ++k)
            out[k] = float(t[k] / len) + 0.0f;
        double nxt[3] = {n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2],
                         n[0] * t[1] - n[1] * t[0]};
        out[3] = nxt[0] * tb[0] + nxt[1] * tb[1] + nxt[2] * tb[2] > 0 ? -1.0f : 1.0f;
    }
}

} // namespace pnb::converter::mesh_detail
