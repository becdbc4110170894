// gi_block.h — where the cascaded light propagation volumes are this frame (binding
// PNB_BINDING_GI_BLOCK, bindings.h), for GLSL (shaders/include/gi_lookup.glsl) and C++
// (pnb::player::GiBlock, gi/gi.h). gpu_layout.h says how one list serves both.
#ifndef PNB_SHARED_GI_BLOCK_H
#define PNB_SHARED_GI_BLOCK_H

#include "bindings.h"
#include "gpu_layout.h"

#define PNB_MAX_GI_CASCADES 4

#define PNB_GI_BLOCK_MEMBERS(FIELD, ARRAY)                                                         \
    ARRAY(vec4, cascade, uGiCascade, PNB_MAX_GI_CASCADES) /* camera-relative minimum corner, cell  \
                                                             size */                               \
    FIELD(vec4, grid, uGiGrid) /* cells, cascades, 1 if the outer cascade fades out at its border, \
                                  1 if lighting writes the indirect irradiance instead of          \
                                  radiance */                                                      \
    FIELD(vec4, irradiance, uGiIrradiance) /* sun irradiance (rgb, lux or W/m^2) times             \
                                              gi.intensity */

PNB_NAMESPACE_BEGIN
#ifdef __cplusplus
inline constexpr std::uint32_t kMaxGiCascades = PNB_MAX_GI_CASCADES;
#endif

PNB_UNIFORM_BLOCK(GiBlock, GiBlock, PNB_BINDING_GI_BLOCK) {
    PNB_GI_BLOCK_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
PNB_CHECK_LAYOUT(Std140, GiBlock, PNB_GI_BLOCK_MEMBERS)
PNB_NAMESPACE_END

#endif
