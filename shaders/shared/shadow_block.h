// shadow_block.h — the sun's shadow maps as the player fitted them this frame (binding
// PNB_BINDING_SHADOW_BLOCK, bindings.h).
// Written by the CPU (single, LiSPSM, PSSM: pnb::player::ShadowBlock, shadow_maps.h) or by the
// SDSM compute passes (player/shaders/sdsm.comp, which declares a std430 struct from the same
// list: with only vec4 and mat4 members both rules place them alike), and read by the shadow pass
// (player/shaders/shadow_layers.geom) and by lighting (shaders/include/shadow_sampling.glsl).
// gpu_layout.h says how one list serves both languages.
#ifndef PNB_SHARED_SHADOW_BLOCK_H
#define PNB_SHARED_SHADOW_BLOCK_H

#include "bindings.h"
#include "gpu_layout.h"

#define PNB_MAX_CASCADES 8

#define PNB_SHADOW_BLOCK_MEMBERS(FIELD, ARRAY)                                                     \
    ARRAY(mat4, matrix, uShadowMatrix, PNB_MAX_CASCADES) /* camera-relative world -> shadow clip   \
                                                            (divide by w) */                       \
    ARRAY(vec4, cascade, uShadowCascade, PNB_MAX_CASCADES) /* view depth start, end; texel world   \
                                                              size; 1 if perspective */            \
    FIELD(vec4, light, uShadowLight) /* xyz: unit vector toward the light; w: index of the         \
                                        shadowing light */                                         \
    FIELD(vec4, params, uShadowParams) /* cascade count (0 = off), filter (0 hardware, 1 Poisson,  \
                                          2 PCSS), taps, radius (texels) */                        \
    FIELD(vec4, bias, uShadowBias) /* normal offset (texels), slope bias (texels), blend band,     \
                                      selection (0 depth, 1 bounds) */                             \
    FIELD(vec4, mapInfo, uShadowMapInfo) /* resolution, 1 / resolution, PCSS tan(light angular     \
                                            radius), output (0 lit, 1 cascade tint, 2 capture, \
                                            3 colour capture) */                                \
    FIELD(vec4, view, uShadowView) /* tan(vertical fov / 2), viewport height, judged light (-1:    \
                                      the sun), orthographic half height (then x = 0): a pixel is  \
                                      2 (depth x + w) / y wide */

PNB_NAMESPACE_BEGIN
#ifdef __cplusplus
inline constexpr std::uint32_t kMaxCascades = PNB_MAX_CASCADES;
#endif

PNB_UNIFORM_BLOCK(ShadowBlock, ShadowBlock, PNB_BINDING_SHADOW_BLOCK) {
    PNB_SHADOW_BLOCK_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
PNB_CHECK_LAYOUT(Std140, ShadowBlock, PNB_SHADOW_BLOCK_MEMBERS)
PNB_CHECK_LAYOUT(Std430, ShadowBlock, PNB_SHADOW_BLOCK_MEMBERS) // sdsm.comp's storage copy

PNB_NAMESPACE_END

#endif
