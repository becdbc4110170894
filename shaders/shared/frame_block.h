// frame_block.h — the per-frame uniform block (binding PNB_BINDING_FRAME_BLOCK, bindings.h), for
// GLSL (interface.glsl, player/shaders/flat.vert) and C++ (pnb::player::FrameBlock,
// frame_context.h). gpu_layout.h says how one list serves both.
//
// Camera-relative rendering: positions reach the shader relative to the camera (the player
// subtracts the camera position in double precision on the CPU), so a scene 10^6 units from the
// origin keeps full float precision near the viewer.
#ifndef PNB_SHARED_FRAME_BLOCK_H
#define PNB_SHARED_FRAME_BLOCK_H

#include "bindings.h"
#include "gpu_layout.h"

#define PNB_FRAME_BLOCK_MEMBERS(FIELD, ARRAY)                                                      \
    FIELD(mat4, viewProjection, uViewProjection) /* camera-relative world -> clip (reversed-Z;     \
                                                    perspective or orthographic) */                \
    FIELD(mat4, view, uView)                     /* camera-relative world -> view */               \
    FIELD(vec4, cameraPosition, uCameraPosition) /* xyz world (for reference only; shading uses    \
                                                    camera-relative) */                            \
    FIELD(vec4, viewport, uViewport)             /* width, height, 1/width, 1/height */            \
    FIELD(vec4, ambient, uAmbient) /* rgb: uniform ambient radiance; a: GI cascades this frame     \
                                      (0 = GI off) */

PNB_NAMESPACE_BEGIN
PNB_UNIFORM_BLOCK(FrameBlock, FrameBlock, PNB_BINDING_FRAME_BLOCK) {
    PNB_FRAME_BLOCK_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
PNB_CHECK_LAYOUT(Std140, FrameBlock, PNB_FRAME_BLOCK_MEMBERS)
PNB_NAMESPACE_END

#endif
