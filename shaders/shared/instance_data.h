// instance_data.h — one copy of an instanced batch (EXT_mesh_gpu_instancing) as surface.vert
// reads it (std430 element of InstanceBlock, binding PNB_BINDING_INSTANCES) and the player packs
// it (pnb::player::InstanceData, frame/draw_lists.cpp): each copy's own object-block matrices
// and params, read when the batch's ObjectBlock says so (params.w). gpu_layout.h says how one
// list serves both languages.
#ifndef PNB_SHARED_INSTANCE_DATA_H
#define PNB_SHARED_INSTANCE_DATA_H

#include "gpu_layout.h"

#define PNB_INSTANCE_DATA_MEMBERS(FIELD, ARRAY)                                                    \
    FIELD(mat4, model, model)               /* object -> camera-relative world (uModel's) */       \
    FIELD(mat4, normalMatrix, normalMatrix) /* uNormalMatrix's */                                  \
    FIELD(vec4, params, params)             /* uObjectParams' (z: -1 if the copy mirrors) */

PNB_NAMESPACE_BEGIN
PNB_STRUCT(InstanceData, InstanceData) {
    PNB_INSTANCE_DATA_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
PNB_CHECK_LAYOUT(Std430, InstanceData, PNB_INSTANCE_DATA_MEMBERS)
PNB_NAMESPACE_END

#endif
