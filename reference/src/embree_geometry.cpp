#include "embree_geometry.h"

#include <algorithm>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "pnb_reference/shadow_tracer.h" // kVertexRelativeError, kWorldRelativeError

namespace pnb::reference::detail {

std::optional<unsigned> attachTriangles(RTCDevice device, RTCScene scene, const TriangleGeometry& g,
                                        std::vector<std::unique_ptr<std::vector<float>>>& tolerances,
                                        double& worldBand) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!geometry) return std::nullopt;
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
    // Embree pads vertex buffers it allocates itself so the last vertex can be read with a
    // 16-byte load.
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                                 RTC_FORMAT_FLOAT3, 3 * sizeof(float), g.local.size()));
    auto* triangles = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), g.indices.size() / 3));
    if (!vertices || !triangles) {
        rtcReleaseGeometry(geometry);
        return std::nullopt;
    }
    std::vector<double> magnitude(g.local.size());
    for (size_t v = 0; v < g.local.size(); ++v) {
        const glm::dvec3 ws = glm::dvec3(g.world * glm::dvec4(glm::dvec3(g.local[v]), 1.0));
        const glm::dvec3 rel = ws - g.origin;
        vertices[v * 3 + 0] = float(rel.x);
        vertices[v * 3 + 1] = float(rel.y);
        vertices[v * 3 + 2] = float(rel.z);
        magnitude[v] = glm::length(rel);
        worldBand = std::max(worldBand, kWorldRelativeError * glm::length(ws));
    }
    std::memcpy(triangles, g.indices.data(), g.indices.size() / 3 * 3 * sizeof(uint32_t));
    auto tolerance = std::make_unique<std::vector<float>>(g.indices.size() / 3);
    for (size_t t = 0; t < tolerance->size(); ++t)
        (*tolerance)[t] = float(kVertexRelativeError * std::max({magnitude[g.indices[t * 3]],
                                                                 magnitude[g.indices[t * 3 + 1]],
                                                                 magnitude[g.indices[t * 3 + 2]]}));
    rtcSetGeometryUserData(geometry, tolerance.get());
    if (g.intersectToo) rtcSetGeometryIntersectFilterFunction(geometry, g.filter);
    rtcSetGeometryOccludedFilterFunction(geometry, g.filter);
    tolerances.push_back(std::move(tolerance));
    rtcCommitGeometry(geometry);
    const unsigned id = rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry); // the scene holds its reference
    return id;
}

} // namespace pnb::reference::detail
