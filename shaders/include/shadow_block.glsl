// shadow_block.glsl — the sun's shadow maps as the player fitted them this frame. Written by the
// CPU (single, LiSPSM, PSSM) or by the SDSM compute passes (player/shaders/sdsm_*.comp, which
// mirror this layout), and read by the shadow pass and by lighting.
#ifndef PNB_SHADOW_BLOCK_GLSL
#define PNB_SHADOW_BLOCK_GLSL

#define PNB_MAX_CASCADES 8

layout(std140, binding = 4) uniform ShadowBlock {
    mat4 uShadowMatrix[PNB_MAX_CASCADES];  // camera-relative world -> shadow clip (divide by w)
    vec4 uShadowCascade[PNB_MAX_CASCADES]; // view depth start, end; texel world size; 1 if perspective
    vec4 uShadowLight;   // xyz: unit vector toward the light; w: index of the shadowing light
    vec4 uShadowParams;  // cascade count (0 = off), filter (0 hardware, 1 Poisson, 2 PCSS), taps, radius (texels)
    vec4 uShadowBias;    // normal offset (texels), slope bias (texels), blend band, selection (0 depth, 1 bounds)
    vec4 uShadowMapInfo; // resolution, 1 / resolution, PCSS tan(light angular radius), output (0 lit, 1 cascade tint, 2 capture)
    vec4 uShadowView;    // tan(vertical fov / 2), viewport height, judged light (-1: the sun),
                         // orthographic half height (then x = 0): a pixel is 2 (depth x + w) / y wide
};

#endif
