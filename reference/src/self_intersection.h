// self_intersection.h — the Embree filters every tracer uses to tell a query point's own surface
// from an occluder (docs/REFERENCE.md "Tolerances"), and to let a ray through translucent
// surfaces while recording them ("Light through glass"). Internal to pnb_reference.
#pragma once

#include <cmath>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "pnb_reference/shadow_tracer.h"

namespace pnb::reference::detail {

// A hit on a translucent surface (translucency.h) that a ray went through: which triangle, its
// barycentrics (for the texture coordinate) and its distance along the ray.
struct TranslucentHit {
    unsigned geometry = 0, primitive = 0;
    float u = 0, v = 0, t = 0;
};

// The intersect context of one visibility() call: Embree hands it to the filter below.
struct TraceContext {
    RTCIntersectContext embree; // first: Embree sees a pointer to this member
    glm::dvec3 eye{0.0};        // origin-relative camera the query points were reconstructed for
    double fixedBand = 0;       // the bands common to every hit of the call: kVertexRelativeError
                                // x |eye| + kWorldRelativeError x the largest world magnitude
    // Segments to a point light (ShadowTracer::visibilityToPoint): the ray's direction ends at
    // the light (t = 1), whose own error band is lightBand (kPointRelativeError x its distance
    // from the eye). Negative: rays to infinity, no far end.
    double lightBand = -1;
    // Where passTranslucent records the translucent surfaces a ray crosses: one list per ray of
    // the query, indexed by the ray's id (0 for a single ray). Null: they are passed unrecorded
    // (ShadowTracer::visibility, the opaque part alone).
    std::vector<TranslucentHit>* translucentHits = nullptr;
};

// Whether candidate hit i of a filter call is on the query point's own surface. The point lies on the hit
// triangle (up to the errors of both) when its distance to the triangle's plane, t |dir . Ng| /
// |Ng|, is within the point's error band plus the triangle's; then the hit is the surface the
// point was taken from (or one meeting it there, as a wall meets the ground), not an occluder.
// For a segment to a point light the same test at the light's end rejects a surface the light
// sits on. Everything is relative to magnitudes of the scene, so the test is invariant to the
// unit.
inline bool isOwnSurface(const RTCFilterFunctionNArguments* args, unsigned i) {
    const auto& context = *reinterpret_cast<const TraceContext*>(args->context);
    const auto& tolerance = *static_cast<const std::vector<float>*>(args->geometryUserPtr);
    RTCRayN* ray = args->ray;
    RTCHitN* hit = args->hit;
    const glm::dvec3 org(RTCRayN_org_x(ray, args->N, i), RTCRayN_org_y(ray, args->N, i),
                         RTCRayN_org_z(ray, args->N, i));
    const glm::dvec3 dir(RTCRayN_dir_x(ray, args->N, i), RTCRayN_dir_y(ray, args->N, i),
                         RTCRayN_dir_z(ray, args->N, i));
    const glm::dvec3 ng(RTCHitN_Ng_x(hit, args->N, i), RTCHitN_Ng_y(hit, args->N, i),
                        RTCHitN_Ng_z(hit, args->N, i));
    const double t = RTCRayN_tfar(ray, args->N, i); // the candidate hit's distance
    const double ngLength = glm::length(ng);
    const double distanceToPlane =
        ngLength > 0 ? t * std::fabs(glm::dot(dir, ng)) / ngLength : 0.0; // dir need not be unit
    const double triangleBand = double(tolerance[RTCHitN_primID(hit, args->N, i)]) + context.fixedBand;
    const double band = kPointRelativeError * glm::length(org - context.eye) + triangleBand;
    if (distanceToPlane <= band) return true;
    // The same at the segment's far end: a surface through the light (a lamp set into a
    // ceiling, a light on a wall) is where the light is, not between it and the point. The
    // light's distance to the plane is (1 - t) |dir . Ng| / |Ng| (dir runs from the point
    // to the light), whatever the angle the segment meets the plane at.
    return context.lightBand >= 0 && ngLength > 0 &&
           (1.0 - t) * std::fabs(glm::dot(dir, ng)) / ngLength <= context.lightBand + triangleBand;
}

// Filter of opaque geometry (both queries): rejects a hit on the query point's own surface.
inline void rejectOwnSurface(const RTCFilterFunctionNArguments* args) {
    for (unsigned i = 0; i < args->N; ++i)
        if (args->valid[i] == -1 && isOwnSurface(args, i)) args->valid[i] = 0;
}

// Filter of translucent geometry (translucency.h), both queries: the own-surface test above
// (a point on a pane is not behind it), then every other hit is recorded in the context's list
// for its ray and rejected too, so that the ray goes on to the next surface: an occlusion ray
// ends at an opaque surface only, an intersection ray finds the nearest opaque one. Traversal
// may offer a triangle more than once, and (rtcIntersect) hits beyond the nearest opaque one:
// TranslucentSurfaces::product deduplicates and cuts at a distance.
inline void passTranslucent(const RTCFilterFunctionNArguments* args) {
    const auto& context = *reinterpret_cast<const TraceContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        if (!isOwnSurface(args, i) && context.translucentHits) {
            RTCHitN* hit = args->hit;
            context.translucentHits[RTCRayN_id(args->ray, args->N, i)].push_back(
                {RTCHitN_geomID(hit, args->N, i), RTCHitN_primID(hit, args->N, i), RTCHitN_u(hit, args->N, i),
                 RTCHitN_v(hit, args->N, i), RTCRayN_tfar(args->ray, args->N, i)});
        }
        args->valid[i] = 0;
    }
}

} // namespace pnb::reference::detail
