#version 450 core
// gi_voxelize.vert — the probes' occupancy grid with albedo (gi_voxelize.frag, ALBEDO; gi.bounces
// > 1): position, both texture coordinates (the base colour's transform picks its set: material.glsl's
// slotUv) and the vertex colour. A mesh without a colour stream reads the attribute's current
// value, which the pass sets to white (glVertexAttrib4f), as surface.vert's vColor without
// HAS_VERTEX_COLOR. The blocks are interface.glsl's (bindings 0 and 1).
#include "shared/frame_block.h"
#include "shared/object_block.h"
layout(location = 0) in vec3 inPosition;
layout(location = 3) in vec2 inUv0; // PNB_ATTR_UV0; a mesh without the stream reads (0, 0)
layout(location = 4) in vec2 inUv1; // PNB_ATTR_UV1
layout(location = 5) in vec4 inColor; // PNB_ATTR_COLOR

layout(location = 3) out vec2 vUv0;
layout(location = 4) out vec2 vUv1;
layout(location = 5) out vec4 vColor;

void main() {
    vec3 objectPosition = inPosition * uDequantScale.xyz + uDequantOffset.xyz;
    vUv0 = inUv0;
    vUv1 = inUv1;
    vColor = inColor;
    gl_Position = uViewProjection * (uModel * vec4(objectPosition, 1.0));
}
