// surface_input.glsl — the fragment side of surface.vert's outputs.
#ifndef PNB_SURFACE_INPUT_GLSL
#define PNB_SURFACE_INPUT_GLSL

#include "material.glsl"

layout(location = 0) in vec3 vPosition;
layout(location = 1) in vec3 vNormal;
layout(location = 2) in vec4 vTangent;
layout(location = 3) in vec2 vUv0;
layout(location = 4) in vec2 vUv1;
layout(location = 5) in vec4 vColor;

SurfaceInput surfaceInput() {
    SurfaceInput s;
    s.normal = vNormal;
    s.tangent = vTangent;
    s.uv0 = vUv0;
    s.uv1 = vUv1;
    s.color = vColor;
    s.frontFacing = gl_FrontFacing;
    return s;
}

#endif
