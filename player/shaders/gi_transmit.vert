#version 450 core
// gi_transmit.vert — the translucent casters (BLEND materials that cast shadows) for GI: into the
// reflective shadow map, multiplying its flux (gi_transmit.frag), or into the probes'
// transmittance grid (VOXELIZE). Position and both texture coordinates: the base colour's
// transform picks its set (material.glsl's slotUv). The blocks are interface.glsl's (bindings 0
// and 1), drawn per item (drawItems with a program of its own never batches instances).
#include "shared/frame_block.h"
#include "shared/object_block.h"
layout(location = 0) in vec3 inPosition;
layout(location = 3) in vec2 inUv0; // PNB_ATTR_UV0; a mesh without the stream reads (0, 0)
layout(location = 4) in vec2 inUv1; // PNB_ATTR_UV1

layout(location = 3) out vec2 vUv0;
layout(location = 4) out vec2 vUv1;

void main() {
    vec3 objectPosition = inPosition * uDequantScale.xyz + uDequantOffset.xyz;
    vUv0 = inUv0;
    vUv1 = inUv1;
    gl_Position = uViewProjection * (uModel * vec4(objectPosition, 1.0));
}
