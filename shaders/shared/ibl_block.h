// ibl_block.h — the environment light this frame (binding PNB_BINDING_IBL_BLOCK, bindings.h), for
// GLSL (shaders/include/ibl.glsl) and C++ (pnb::player::IblBlock, sky/ibl.h). gpu_layout.h says
// how one list serves both.
#ifndef PNB_SHARED_IBL_BLOCK_H
#define PNB_SHARED_IBL_BLOCK_H

#include "bindings.h"
#include "gpu_layout.h"

#define PNB_IBL_BLOCK_MEMBERS(FIELD, ARRAY)                                                        \
    ARRAY(vec4, sh, uIblSh, 9) /* irradiance SH (rgb, lux): the ENVM's, rotated, times             \
                                  ibl.intensity */                                                 \
    FIELD(vec4, rotation, uIblRotation) /* cos, sin of ibl.rotation_deg; specular cube's roughest  \
                                           level; 1 = specular on */                               \
    FIELD(vec4, params, uIblParams) /* 1 = IBL on; 1 = lighting writes the sky irradiance          \
                                       (capture); sky-visibility radius (0 = none); specular       \
                                       radiance scale */                                           \
    FIELD(vec4, heightRect, uIblHeightRect) /* height map: camera-relative minimum x, z; 1 / size  \
                                               x, z */                                             \
    FIELD(vec4, heightRange, uIblHeightRange) /* camera-relative bottom y; top - bottom;           \
                                                 visibility (0 none, 1 screen, 2 height, 3 volume, \
                                                 4 probes); the height map's texel size */

PNB_NAMESPACE_BEGIN
PNB_UNIFORM_BLOCK(IblBlock, IblBlock, PNB_BINDING_IBL_BLOCK) {
    PNB_IBL_BLOCK_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
PNB_CHECK_LAYOUT(Std140, IblBlock, PNB_IBL_BLOCK_MEMBERS)
PNB_NAMESPACE_END

#endif
