// light_list.h — the frame's light list (std430 LightBuffer, binding PNB_BINDING_LIGHT_LIST): a
// 16-byte header, then one GpuLight (gpu_light.h) per light. Lighting reads it (shaders/include/
// lights.glsl; the light-count debug view, player/shaders/debug_view.frag, reads the header); the
// player writes it (pnb::player::LightListHeader, lights/pass_light_clusters.cpp). gpu_layout.h
// says how one list serves both languages.
#ifndef PNB_SHARED_LIGHT_LIST_H
#define PNB_SHARED_LIGHT_LIST_H

#include "gpu_layout.h"
#include "gpu_light.h"

#define PNB_LIGHT_LIST_HEADER_MEMBERS(FIELD, ARRAY)                                                \
    FIELD(uint, count, uLightCount)                                                                \
    FIELD(uint, clustered, uLightsClustered) /* 1: shade the cluster's lights (LightClusters,      \
                                                light_cluster_masks.h); 0: all lights */           \
    FIELD(uint, pad0, uLightListPad0)                                                              \
    FIELD(uint, pad1, uLightListPad1)

// The shaders declare the header's members straight in their storage block, before the lights
// (no struct in GLSL); C++ writes the struct, then the lights at sizeof(LightListHeader).
PNB_NAMESPACE_BEGIN
#ifdef __cplusplus
struct LightListHeader {
    PNB_LIGHT_LIST_HEADER_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
// std430 starts the GpuLight array at its element's alignment (a vec4's, 16): right after the
// header only while the header fills whole vec4s.
static_assert(sizeof(LightListHeader) % 16 == 0, "the lights must follow the header directly");
#endif
PNB_CHECK_LAYOUT(Std430, LightListHeader, PNB_LIGHT_LIST_HEADER_MEMBERS)
PNB_NAMESPACE_END

#endif
