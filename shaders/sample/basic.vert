#version 450 core
layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inTexCoord0;
layout(location = 0) uniform mat4 uModelViewProjection;
layout(location = 0) out vec3 vNormal;
layout(location = 1) out vec2 vTexCoord0;
void main() {
    vNormal = inNormal;
    vTexCoord0 = inTexCoord0;
    gl_Position = uModelViewProjection * vec4(inPosition, 1.0);
}
