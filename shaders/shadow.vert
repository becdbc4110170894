#version 450 core
// shadow.vert — depth-only draw into a shadow map (cascades select their matrix per draw).
#include "include/interface.glsl"

layout(location = PNB_ATTR_POSITION) in vec3 inPosition;
#ifdef ALPHA_MASK
layout(location = PNB_ATTR_UV0) in vec2 inUv0;
layout(location = 3) out vec2 vUv0;
#endif

void main() {
    vec3 objectPosition = inPosition * uDequantScale.xyz + uDequantOffset.xyz;
#ifdef ALPHA_MASK
    vUv0 = inUv0;
#endif
    gl_Position = uViewProjection * (uModel * vec4(objectPosition, 1.0));
}
