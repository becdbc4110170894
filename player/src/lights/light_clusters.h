// light_clusters.h — the frame's light list and, where many lights make it pay, its clusters
// (docs/PLAYER.md "Many lights"): which lights may reach each screen tile x depth slice, built
// on the GPU by player/shaders/light_clusters.comp and read by shaders/include/lights.glsl in
// the deferred lighting pass and in forward materials alike.
//
// The CPU part is plain math (tested in tests/player/light_cluster_math_test.cpp): each light's
// bounding sphere in view space, the grid for a viewport and depth range, and whether this
// frame clusters at all. Below lights.cluster_min local lights every light is shaded at every
// pixel and neither the pass nor its buffer exists.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "pnb/chunks.h"
#include "pnb_player/gl_handles.h"
#include "pnb_player/settings.h"
#include "shared/light_cluster_masks.h" // LightClustersHeader (GLSL and C++)
#include "shared/light_list.h" // LightListHeader, GpuLight (GLSL and C++)

namespace pnb::player {

struct FrameContext;
struct FrameView;
struct SceneLight;

// A light as the cluster pass sees it: a view-space bounding sphere (xyz centre, w radius);
// w < 0 for a directional light (it reaches every cluster).
// Point light: its range. Spot light: the smallest of two spheres around the spherical sector
// of half-angle `outer` and radius `range` — the one through the apex and the sector's rim
// (radius range / (2 cos outer), centre on the axis; smaller while outer < 60 degrees) or the
// light's range sphere.
glm::vec4 lightBoundingSphere(const GpuLight& light, const glm::mat4& view);

struct LightClusterGrid {
    uint32_t tilesX = 0, tilesY = 0, slices = 0;
    uint32_t words = 0;      // 32-bit words per mask: ceil(lights / 32)
    float invTilePx = 0;     // 1 / tile side in pixels
    float sliceScale = 0;    // slice = log(view depth) * scale + bias
    float sliceBias = 0;
    uint64_t maskBytes() const {
        return sizeof(LightClustersHeader) + uint64_t(tilesX * tilesY + slices) * words * sizeof(uint32_t);
    }
};

// Tiles of `tilePx` over width x height, `slices` exponential slices from zNear to zFar (zFar is
// raised to 2 zNear if it is not beyond it; zNear must be > 0), masks for `lights` lights.
LightClusterGrid lightClusterGrid(uint32_t width, uint32_t height, uint32_t tilePx,
                                  uint32_t slices, uint32_t lights, float zNear, float zFar);

// Whether this frame clusters: lights.culling = clusters (any count of local lights > 0),
// off (never), or auto: from lights.cluster_min local (point and spot) lights on.
bool clustersWanted(const RenderSettings& settings, uint32_t localLights);

// The renderer's light state across frames.
struct LightContext {
    GlHandle clusterProgram; // light_clusters.comp, while clustering
    GlHandle masks;          // LightClusters (PNB_BINDING_LIGHT_CLUSTERS), grown as needed
    uint64_t maskCapacity = 0;
    bool clustered = false;  // this frame
    LightClusterGrid grid;   // this frame's, if clustered
    uint32_t localLights = 0;
    std::vector<GpuLight> list;      // this frame's lights, camera-relative (planLights)
    std::vector<glm::vec4> spheres;  // their view-space bounding spheres, if clustered
    std::byte* listData = nullptr; // this frame's light list in the mapped ring (LightListHeader, then
                                   // GpuLight i at sizeof(LightListHeader) + sizeof(GpuLight) i)
    size_t listOffset = 0, listBytes = 0; // its place in the ring
    size_t sphereOffset = 0;              // the spheres' place in the ring (clustered)
};

// Writes this frame's light list into the ring (PNB_BINDING_LIGHT_LIST) and, if clustering, runs
// the cluster pass (PNB_BINDING_LIGHT_CLUSTERS). After the view and the viewport are known, before any lighting.
// The CPU step, without GL: the light list, and where the frame clusters, the lights' spheres
// and the cluster grid.
void planLights(const FrameView& in, LightContext& lights);

// planLights, then the list (and spheres) into the ring, bound for lighting (PNB_BINDING_LIGHT_LIST).
void prepareLights(FrameContext& ctx, LightContext& lights);

// The lights.clusters pass: one light mask per screen tile and per depth slice
// (PNB_BINDING_LIGHT_CLUSTERS).
void runLightClusters(FrameContext& ctx, const LightContext& lights);

} // namespace pnb::player
