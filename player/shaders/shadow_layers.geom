#version 450 core
// shadow_layers.geom — the layered shadow pass where the vertex shader cannot write gl_Layer:
// each caster triangle is emitted once per cascade in its mask, into that layer, with that
// cascade's matrix. Linked between the container's shadow.vert (compiled with
// LAYER_FROM_GEOMETRY) and shadow.frag.

// The ShadowBlock lighting reads (only the matrices are used here).
#include "shared/shadow_block.h"

layout(triangles) in;
layout(triangle_strip, max_vertices = 24) out;

layout(location = 4) flat in uint vCascadeMask[];
#if defined(ALPHA_MASK) || defined(TRANSLUCENT)
layout(location = 3) in vec2 vUv0[];
layout(location = 3) out vec2 gUv0;
#endif

void main() {
    uint mask = vCascadeMask[0];
    while (mask != 0u) {
        int c = findLSB(mask);
        mask &= mask - 1u;
        for (int i = 0; i < 3; ++i) {
            gl_Position = uShadowMatrix[c] * gl_in[i].gl_Position;
            gl_Layer = c;
#if defined(ALPHA_MASK) || defined(TRANSLUCENT)
            gUv0 = vUv0[i];
#endif
            EmitVertex();
        }
        EndPrimitive();
    }
}
