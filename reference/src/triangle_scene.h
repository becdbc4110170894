// triangle_scene.h — the Embree scene of everything a ray meets in the Monte-Carlo tracers
// (IndirectTracer: what light bounces off; SkyTracer: what hides the sky): every level-0 submesh
// instance whose material is not Blend, whatever it casts into the player's shadow maps, and the
// translucent ones (Blend that casts shadows, translucency.h), which attenuate the rays that
// cross them and stop none. Internal to pnb_reference.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "pnb/scene.h"
#include "pnb_reference/shadow_tracer.h"
#include "posed_scene.h"
#include "translucency.h"

namespace pnb::reference::detail {

// An Embree device and a committed scene (robust, high build quality) whose triangles carry the
// self-intersection filter (self_intersection.h) for both rtcIntersect and rtcOccluded: the
// opaque ones rejectOwnSurface, the translucent ones passTranslucent (which records them in the
// query's TraceContext::translucentHits).
struct TriangleScene {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<std::unique_ptr<std::vector<float>>> tolerances; // the filter's per-triangle bands
    double worldBand = 0;   // kWorldRelativeError x the largest world-space vertex magnitude
    uint64_t triangles = 0;
    uint32_t instances = 0; // node x submesh instances attached, translucent ones included
    uint32_t translucentInstances = 0;
    TranslucentSurfaces translucent; // the translucent instances, by geometry id
    std::vector<glm::dmat4> worldOfGeometry; // each attached geometry's placement, by geometry id

    TriangleScene() = default;
    TriangleScene(const TriangleScene&) = delete;
    TriangleScene& operator=(const TriangleScene&) = delete;
    ~TriangleScene();
};

// Called once per attached opaque instance, in node order then submesh order (translucent ones
// are registered in TriangleScene::translucent instead): its Embree geometry id,
// node, mesh index and submesh, and its triangle list (3 indices per triangle, each checked to
// be below the mesh's vertexCount). A returned error stops the build with it.
using TriangleInstanceCallback = std::function<std::optional<TracerError>(
    unsigned geometryId, uint32_t node, uint32_t mesh, const Submesh& submesh, std::vector<uint32_t>&& indices)>;

// How Blend surfaces enter the scene.
enum class BlendSurfaces : uint8_t {
    Translucent, // the default above: casting ones attenuate (passTranslucent), others are absent
    Opaque,      // every Blend instance is an ordinary surface (rejectOwnSurface, onInstance called):
                 // the whole-frame tracer decides per hit whether a ray passes (frame_scene.h)
};

// The copies and positions of `posed` (posed_scene.h: the scene at the instant traced; world
// transforms composed in double), vertices made relative to `origin` before they are rounded to
// float, as ShadowTracer does. The callback's node tells a deformed copy (posed.deformed). Errors: Input (a node, material or
// index out of range, a submesh past the index buffer, no position stream), Unsupported
// (octahedral positions), Embree.
TracerResult<std::unique_ptr<TriangleScene>> buildTriangleScene(const Scene& scene, PosedScene& posed, glm::dvec3 origin,
                                                                const TriangleInstanceCallback& onInstance = {},
                                                                BlendSurfaces blend = BlendSurfaces::Translucent);

} // namespace pnb::reference::detail
