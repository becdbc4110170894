#include "mip_need.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>

namespace pnb::player {

namespace {

const VertexStream* findStream(const Mesh& mesh, VertexSemantic semantic) {
    for (const VertexStream& s : mesh.streams)
        if (s.semantic == semantic) return &s;
    return nullptr;
}

// Reads vertex `v` of a position (F32x3, or U16x3 normalized with dequantisation) or texture
// coordinate (F32x2, F16x2) stream; false for other encodings.
bool readVertex(const VertexStream& s, uint32_t v, glm::dvec3& out) {
    const uint32_t n = s.componentCount;
    if (s.componentType == ComponentType::F32) {
        float f[4] = {};
        std::memcpy(f, s.data.data() + size_t(v) * n * 4, n * 4);
        out = {f[0], n > 1 ? f[1] : 0, n > 2 ? f[2] : 0};
        return true;
    }
    if (s.componentType == ComponentType::F16) {
        uint16_t h[4] = {};
        std::memcpy(h, s.data.data() + size_t(v) * n * 2, n * 2);
        out = {glm::unpackHalf1x16(h[0]), n > 1 ? glm::unpackHalf1x16(h[1]) : 0.0f,
               n > 2 ? glm::unpackHalf1x16(h[2]) : 0.0f};
        return true;
    }
    if (s.componentType == ComponentType::U16 && s.normalized && n == 3) {
        uint16_t u[3] = {};
        std::memcpy(u, s.data.data() + size_t(v) * 6, 6);
        out = glm::dvec3(u[0], u[1], u[2]) / 65535.0 *
                  glm::dvec3(s.dequantScale.x, s.dequantScale.y, s.dequantScale.z) +
              glm::dvec3(s.dequantOffset.x, s.dequantOffset.y, s.dequantOffset.z);
        return true;
    }
    return false;
}

} // namespace

double uvDensity(const Mesh& mesh, const Submesh& submesh) {
    const VertexStream* pos = findStream(mesh, VertexSemantic::Position);
    const VertexStream* uv = findStream(mesh, VertexSemantic::TexCoord0);
    if (!pos || !uv || mesh.primitive != Primitive::Triangles) return 0;
    const size_t indexCount = meshIndexCount(mesh);
    double area = 0, uvArea = 0;
    const size_t end = std::min<size_t>(size_t(submesh.firstIndex) + submesh.indexCount, indexCount);
    for (size_t k = submesh.firstIndex; k + 3 <= end; k += 3) {
        glm::dvec3 p[3], t[3];
        for (int c = 0; c < 3; ++c) {
            uint32_t v = meshIndex(mesh, k + size_t(c));
            if (v >= mesh.vertexCount || !readVertex(*pos, v, p[c]) || !readVertex(*uv, v, t[c])) return 0;
        }
        area += glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
        uvArea += std::abs((t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y));
    }
    if (!(area > 0) || !std::isfinite(area) || !std::isfinite(uvArea)) return 0;
    return std::sqrt(uvArea / area);
}

double uvDensityFromBounds(const Submesh& submesh) {
    const double edge = std::max({double(submesh.bounds.max.x) - submesh.bounds.min.x,
                                  double(submesh.bounds.max.y) - submesh.bounds.min.y,
                                  double(submesh.bounds.max.z) - submesh.bounds.min.z});
    return edge > 0 && std::isfinite(edge) ? 1.0 / edge : 0.0;
}

uint32_t neededMipLevel(double texelsPerUnit, double distance, double pixelScale, uint32_t mipCount) {
    if (mipCount <= 1) return 0;
    // texels per pixel at level 0; every halving of it is one level coarser.
    const double texelsPerPixel = texelsPerUnit * distance / pixelScale;
    if (std::isinf(texelsPerPixel) && texelsPerPixel > 0) return mipCount - 1; // below a pixel
    if (!(texelsPerPixel > 1)) return 0;                                        // also NaN
    return std::min<uint32_t>(uint32_t(std::floor(std::log2(texelsPerPixel))), mipCount - 1);
}

} // namespace pnb::player
