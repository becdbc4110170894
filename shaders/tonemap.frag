#version 450 core
// tonemap.frag — HDR -> display: exposure, ACES filmic fit (Narkowicz 2015). The player renders
// into an sRGB framebuffer, so the hardware applies the sRGB transfer function on write.
// Mirrored on the CPU by lighting/include/pnb_lighting/tonemap.h: change both together.
layout(binding = 0) uniform sampler2D uHdr;
layout(location = 0) uniform float uExposure;

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

vec3 acesFitted(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

void main() {
    // An infinity (RGBA16F overflows above 65504) is white, not the NaN that ACES makes of
    // Inf/Inf; the headless frame check still counts it (benchmark.cpp, "frame_check").
    vec3 hdr = min(texture(uHdr, vUv).rgb * uExposure, vec3(65504.0));
    outColor = vec4(acesFitted(hdr), 1.0);
}
