#version 450 core
layout(location = 0) in vec3 vNormal;
layout(location = 1) in vec2 vTexCoord0;
layout(binding = 0) uniform sampler2D uBaseColor;
layout(location = 1) uniform vec4 uBaseColorFactor;
layout(location = 0) out vec4 outColor;
void main() {
    vec4 base = uBaseColorFactor;
#ifdef HAS_BASE_COLOR_TEXTURE
    base *= texture(uBaseColor, vTexCoord0);
#endif
    float ndotl = max(dot(normalize(vNormal), normalize(vec3(0.3, 0.8, 0.5))), 0.0);
    outColor = vec4(base.rgb * (0.2 + 0.8 * ndotl), base.a);
}
