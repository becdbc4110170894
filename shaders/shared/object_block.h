// object_block.h — the per-draw uniform block (binding PNB_BINDING_OBJECT_BLOCK, bindings.h), for
// GLSL (interface.glsl, player/shaders/flat.vert) and C++ (pnb::player::ObjectBlock,
// draw_lists.cpp). gpu_layout.h says how one list serves both.
#ifndef PNB_SHARED_OBJECT_BLOCK_H
#define PNB_SHARED_OBJECT_BLOCK_H

#include "bindings.h"
#include "gpu_layout.h"

#define PNB_OBJECT_BLOCK_MEMBERS(FIELD, ARRAY)                                                     \
    FIELD(mat4, model, uModel)               /* object -> camera-relative world */                 \
    FIELD(mat4, normalMatrix, uNormalMatrix) /* inverse-transpose of uModel's upper 3x3 (in a mat4 \
                                                for std140) */                                     \
    FIELD(vec4, dequantScale, uDequantScale) /* position = stored * scale + offset (identity for   \
                                                float streams) */                                  \
    FIELD(vec4, dequantOffset, uDequantOffset)                                                     \
    FIELD(vec4, params, uObjectParams) /* x: 1 if normals are octahedral-encoded (2 components),   \
                                          y: caster index (shadow passes), z: -1 if the model      \
                                          matrix mirrors, else 1, w: 1 for an instanced batch      \
                                          (surface.vert reads InstanceBlock) */

PNB_NAMESPACE_BEGIN
PNB_UNIFORM_BLOCK(ObjectBlock, ObjectBlock, PNB_BINDING_OBJECT_BLOCK) {
    PNB_OBJECT_BLOCK_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
PNB_CHECK_LAYOUT(Std140, ObjectBlock, PNB_OBJECT_BLOCK_MEMBERS)
PNB_NAMESPACE_END

#endif
