// converter/src/mesh_normals.cpp — smooth vertex normals for meshes whose source has none.
//
// Each triangle adds its unnormalised face normal (b - a) × (c - a), whose length is twice its
// area, to the sum of each of its corners' *positions*: vertices that share a position bitwise
// share one sum, so a seam the source split for UVs (or between two primitives) shades smoothly.
// Large triangles dominate small ones, which keeps a finely tessellated strip from pulling the
// normal of a big flat face.
//
// Crease behaviour: none. Generated normals are smooth across every shared position; hard edges
// exist only where the source supplies normals (those are kept, see mesh_processing.cpp). glTF
// asks for flat normals when they are missing; we smooth instead because sources without
// normals are mostly scans and OBJ exports of smooth surfaces, and a flat-shaded result would
// also triple the vertex count. A crease-angle split would be the next step if that changes.
//
// Cancellation: where the faces around a position cancel (a two-sided sheet stored as two
// coincident, opposite-facing surfaces that share positions), the position sum is ~0 and has no
// meaningful direction. Then the vertex's own faces are used (the two sides of such a sheet are
// normally separate vertices), and only if those cancel too, +Z.
//
// Based on: Max, "Weights for Computing Vertex Normals from Facet Normals" (1999) — area
// weighting as the simplest of the compared schemes.

#include <cmath>
#include <cstring>

#include <meshoptimizer.h>

#include "mesh_internal.h"

namespace pnb::converter::mesh_detail {

namespace {

// |sum| below this fraction of the summed face normal lengths means the faces cancel.
constexpr double kCancelFraction = 1e-4;

void addTo(std::vector<double>& acc, size_t i, const double n[3]) {
    acc[i * 3 + 0] += n[0];
    acc[i * 3 + 1] += n[1];
    acc[i * 3 + 2] += n[2];
}

double length3(const double* v) {
    return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

} // namespace

void generateNormals(VertexData& v, std::span<const uint32_t> indices,
                     std::span<const uint8_t> generate) {
    if (indices.empty()) return;
    // Position ids: remap[i] is the first vertex with i's position bits (~0u if unreferenced).
    std::vector<uint32_t> positionId(v.count);
    meshopt_generateVertexRemap(positionId.data(), indices.data(), indices.size(),
                                v.positions.data(), v.count, sizeof(float) * 3);

    std::vector<double> positionSum(v.count * 3, 0.0), vertexSum(v.count * 3, 0.0);
    std::vector<double> positionWeight(v.count, 0.0);
    const float* p = v.positions.data();
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
        double e1[3], e2[3];
        for (int k = 0; k < 3; ++k) {
            e1[k] = double(p[b * 3 + k]) - p[a * 3 + k];
            e2[k] = double(p[c * 3 + k]) - p[a * 3 + k];
        }
        double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
        double len = length3(n);
        for (uint32_t corner : {a, b, c}) {
            addTo(positionSum, positionId[corner], n);
            positionWeight[positionId[corner]] += len;
            addTo(vertexSum, corner, n);
        }
    }

    for (size_t i = 0; i < v.count; ++i) {
        if (!generate[i] || positionId[i] == ~0u) continue;
        const double* s = &positionSum[size_t(positionId[i]) * 3];
        double len = length3(s);
        if (!(len > kCancelFraction * positionWeight[positionId[i]])) {
            s = &vertexSum[i * 3];
            len = length3(s);
        }
        float* out = &v.normals[i * 3];
        if (len > 0 && std::isfinite(len)) {
            for (int k = 0; k < 3; ++k)
                out[k] = float(s[k] / len) + 0.0f; // +0: no -0 bits
        } else {
            out[0] = 0, out[1] = 0, out[2] = 1;
        }
    }
}

} // namespace pnb::converter::mesh_detail
