// local_shadow_tile.h — the tiles of the point and spot light shadow atlas as lighting reads them
// (std430 LocalShadows, binding PNB_BINDING_LOCAL_SHADOWS, shaders/include/local_shadows.glsl: a
// header, then one tile per element) and the player writes them (pnb::player::LocalShadowsHeader
// and GpuShadowTile, shadows/pass_local_shadows.cpp). gpu_layout.h says how one list serves both
// languages.
#ifndef PNB_SHARED_LOCAL_SHADOW_TILE_H
#define PNB_SHARED_LOCAL_SHADOW_TILE_H

#include "gpu_layout.h"

#define PNB_LOCAL_SHADOW_TILE_MEMBERS(FIELD, ARRAY)                                                \
    FIELD(mat4, matrix, matrix) /* camera-relative world -> tile clip (reversed-Z: the light's     \
                                   near plane at 1) */                                             \
    FIELD(vec4, rect, rect) /* atlas u0, v0, uv size, world size of one texel per unit of          \
                               distance */

// The buffer's header, before the tiles.
#define PNB_LOCAL_SHADOWS_HEADER_MEMBERS(FIELD, ARRAY)                                             \
    FIELD(vec4, atlas, uLocalShadowAtlas) /* 1 / atlas side, taps, radius (texels), 0 */

PNB_NAMESPACE_BEGIN
// The shaders declare the header's members straight in their storage block, before the tiles
// (no struct in GLSL); C++ writes the struct, then the tiles at sizeof(LocalShadowsHeader).
#ifdef __cplusplus
struct LocalShadowsHeader {
    PNB_LOCAL_SHADOWS_HEADER_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
// std430 starts the tile array at its element's alignment (a vec4's, 16): right after the header
// only while the header fills whole vec4s.
static_assert(sizeof(LocalShadowsHeader) % 16 == 0, "the tiles must follow the header directly");
#endif
PNB_CHECK_LAYOUT(Std430, LocalShadowsHeader, PNB_LOCAL_SHADOWS_HEADER_MEMBERS)

PNB_STRUCT(GpuShadowTile, LocalShadowTile) {
    PNB_LOCAL_SHADOW_TILE_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
PNB_CHECK_LAYOUT(Std430, GpuShadowTile, PNB_LOCAL_SHADOW_TILE_MEMBERS)
PNB_NAMESPACE_END

#endif
