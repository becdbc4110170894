// light_cluster_masks.h — the light clusters of the frame (std430 LightClusters, binding
// PNB_BINDING_LIGHT_CLUSTERS for its readers): a 32-byte header, then the masks, one 32-bit word
// per 32 lights (tile masks row by row, then depth-slice masks near to far). Written on the GPU
// (player/shaders/light_clusters.comp), read by lighting (shaders/include/lights.glsl) and the
// light-count debug view (player/shaders/debug_view.frag); the player sizes it
// (pnb::player::LightClustersHeader, lights/light_clusters.h). gpu_layout.h says how one list
// serves both languages.
#ifndef PNB_SHARED_LIGHT_CLUSTER_MASKS_H
#define PNB_SHARED_LIGHT_CLUSTER_MASKS_H

#include "gpu_layout.h"

#define PNB_LIGHT_CLUSTERS_HEADER_MEMBERS(FIELD, ARRAY)                                            \
    FIELD(uvec4, grid, uClusterGrid) /* tiles across, tiles down, depth slices, 32-bit words per   \
                                        mask */                                                    \
    FIELD(vec4, depth, uClusterDepth) /* 1 / tile size (px), slice scale, slice bias, 0 (slice =   \
                                         log(view depth) * scale + bias) */

// The shaders declare the header's members straight in their storage block, before
// `uint uClusterMasks[]` (no struct in GLSL); C++ sizes the buffer from the struct.
PNB_NAMESPACE_BEGIN
#ifdef __cplusplus
struct LightClustersHeader {
    PNB_LIGHT_CLUSTERS_HEADER_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
#endif
PNB_CHECK_LAYOUT(Std430, LightClustersHeader, PNB_LIGHT_CLUSTERS_HEADER_MEMBERS)
PNB_NAMESPACE_END

#endif
