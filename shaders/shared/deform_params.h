// deform_params.h — the deform pass's interface (shaders/deform.comp, player/src/anim/
// pass_deform.cpp): its storage buffers' bindings and its uniforms' locations, named once for
// GLSL and C++. The program is packed in containers (PROG "deform"), so changing a number breaks
// existing containers' deform programs, as for bindings.h's surface-shader numbers.
//
// Every buffer is bound whole (glBindBufferBase) and the shader indexes it with the element
// offsets below: no glBindBufferRange, so GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT never
// constrains where a stream starts in its mesh's buffer.
#ifndef PNB_SHARED_DEFORM_PARAMS_H
#define PNB_SHARED_DEFORM_PARAMS_H

// Storage buffers (numbers the surface shaders' storage buffers do not use: the pass runs
// before the frame's passes bind theirs, and binds its own each dispatch).
#define PNB_BINDING_DEFORM_SOURCE 0 /* the source mesh's buffer, as 32-bit words (streams) */
#define PNB_BINDING_DEFORM_POSED 1  /* the posed buffer written: positions, normals, tangents */
#define PNB_BINDING_DEFORM_FRAME 2  /* this frame's joint matrices and morph weights (floats) */
#define PNB_BINDING_DEFORM_MORPH 4  /* the mesh's morph deltas (floats) */

// Uniform locations (uint each). Offsets are in 32-bit words; PNB_DEFORM_ABSENT marks a missing
// stream.
#define PNB_DEFORM_ABSENT 0xFFFFFFFFu
#define PNB_DEFORM_LOC_VERTEX_COUNT 0
#define PNB_DEFORM_LOC_SOURCE_POSITION 1
#define PNB_DEFORM_LOC_SOURCE_NORMAL 2
#define PNB_DEFORM_LOC_SOURCE_TANGENT 3
#define PNB_DEFORM_LOC_SOURCE_JOINTS 4
#define PNB_DEFORM_LOC_JOINTS_U16 5      /* 0: Joints0 is U8 x 4 (one word), 1: U16 x 4 (two) */
#define PNB_DEFORM_LOC_SOURCE_WEIGHTS 6
#define PNB_DEFORM_LOC_JOINT_BASE 7      /* first float of this node's joint matrices (16 each) */
#define PNB_DEFORM_LOC_JOINT_COUNT 8     /* 0: no skin */
#define PNB_DEFORM_LOC_TARGET_COUNT 9    /* 0: no morph targets */
#define PNB_DEFORM_LOC_WEIGHT_BASE 10    /* first float of this node's morph weights */
#define PNB_DEFORM_LOC_MORPH_STRIDE 11   /* floats of one attribute of one target (3 x vertices) */
#define PNB_DEFORM_LOC_MORPH_ATTRIBUTES 12 /* attributes per target: position[, normal][, tangent] */
#define PNB_DEFORM_LOC_POSED_NORMAL 13
#define PNB_DEFORM_LOC_POSED_TANGENT 14

#define PNB_DEFORM_GROUP_SIZE 64

#endif
