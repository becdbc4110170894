// embree_geometry.h — one mesh instance's triangles as an Embree geometry, placed the way every
// tracer of pnb_reference places them (shadow_tracer.h "Self-intersection", docs/REFERENCE.md
// "Tolerances"): world space in double, then relative to the tracer's origin, then float, so a
// scene far from the world origin keeps its precision near the camera; with each triangle's own
// error band (kVertexRelativeError x its largest origin-relative vertex magnitude) as the
// filter's user data.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace pnb::reference::detail {

struct TriangleGeometry {
    std::span<const glm::dvec4> local; // the mesh's decoded positions (decodeStream; w unused)
    glm::dmat4 world{1.0};             // the instance's placement
    glm::dvec3 origin{0.0};            // the tracer's origin
    std::span<const uint32_t> indices; // 3 per triangle, each below local.size()
    RTCFilterFunctionN filter = nullptr;
    bool intersectToo = false;         // the filter on intersection queries as well as occlusion ones
};

// Attaches `g` to `scene`, its error bands appended to `tolerances` (which must outlive the
// scene); raises `worldBand` to kWorldRelativeError x its largest world-space magnitude. Returns
// the geometry id, or nothing when Embree fails.
std::optional<unsigned> attachTriangles(RTCDevice device, RTCScene scene, const TriangleGeometry& g,
                                        std::vector<std::unique_ptr<std::vector<float>>>& tolerances,
                                        double& worldBand);

} // namespace pnb::reference::detail
