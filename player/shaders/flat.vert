#version 450 core
// flat.vert — positions only, for the layer and overdraw debug views. The blocks repeat
// shaders/include/interface.glsl (bindings 0 and 1); keep them in step.
layout(std140, binding = 0) uniform FrameBlock {
    mat4 uViewProjection;
    mat4 uView;
    vec4 uCameraPosition;
    vec4 uViewport;
    vec4 uAmbient;
};
layout(std140, binding = 1) uniform ObjectBlock {
    mat4 uModel;
    mat4 uNormalMatrix;
    vec4 uDequantScale;
    vec4 uDequantOffset;
    vec4 uObjectParams;
};
layout(location = 0) in vec3 inPosition;

void main() {
    vec3 objectPosition = inPosition * uDequantScale.xyz + uDequantOffset.xyz;
    gl_Position = uViewProjection * (uModel * vec4(objectPosition, 1.0));
}
