// local_shadow_tile.h — one tile of the point and spot light shadow atlas as lighting reads it
// (std430 element of shaders/include/local_shadows.glsl's LocalShadows) and the player writes it
// (pnb::player::GpuShadowTile, shadows/pass_local_shadows.cpp). gpu_layout.h says how one list
// serves both languages.
#ifndef PNB_SHARED_LOCAL_SHADOW_TILE_H
#define PNB_SHARED_LOCAL_SHADOW_TILE_H

#include "gpu_layout.h"

#define PNB_LOCAL_SHADOW_TILE_MEMBERS(FIELD, ARRAY)                                                \
    FIELD(mat4, matrix, matrix) /* camera-relative world -> tile clip (reversed-Z: the light's     \
                                   near plane at 1) */                                             \
    FIELD(vec4, rect, rect) /* atlas u0, v0, uv size, world size of one texel per unit of          \
                               distance */

PNB_NAMESPACE_BEGIN
PNB_STRUCT(GpuShadowTile, LocalShadowTile) {
    PNB_LOCAL_SHADOW_TILE_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
PNB_CHECK_LAYOUT(Std430, GpuShadowTile, PNB_LOCAL_SHADOW_TILE_MEMBERS)
PNB_NAMESPACE_END

#endif
