#version 450 core
// flat.vert — positions only, for the layer and overdraw debug views. The blocks are
// shaders/include/interface.glsl's (bindings 0 and 1), from the same headers.
#include "shared/frame_block.h"
#include "shared/object_block.h"
layout(location = 0) in vec3 inPosition;

void main() {
    vec3 objectPosition = inPosition * uDequantScale.xyz + uDequantOffset.xyz;
    gl_Position = uViewProjection * (uModel * vec4(objectPosition, 1.0));
}
