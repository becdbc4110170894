#version 450 core
// shadow.frag — alpha-tested casters discard below their cutoff; opaque casters need no
// fragment work at all (the ALPHA_MASK-free permutation is an empty shader).
// TRANSLUCENT: a blended caster (issue 43) drawn after the opaque ones writes what light it lets
// through into the map's colour companions: its transmittance T = baseColor.rgb x (1 - alpha)
// (factor x texture), multiplied into attachment 0 (blending dst x src), and its depth, kept
// nearest by GL_MIN in attachment 1, so lighting tints only receivers behind the nearest pane
// (docs/PLAYER.md "Light through glass"). The companions are 1/uDivisor of the map's side, so
// they have no depth buffer of their own: a fragment is tested here against the opaque depths
// of the divisor x divisor texels it covers, and counts if it lies before the farthest of them
// (a pane wholly behind an opaque caster adds nothing).
#include "include/interface.glsl"

#if defined(ALPHA_MASK) || defined(TRANSLUCENT)
layout(binding = PNB_TEX_BASE_COLOR) uniform sampler2D uBaseColorMap;
layout(location = 3) in vec2 vUv0;
#endif

#ifdef TRANSLUCENT
// 1: the material has a base colour texture at unit 0 (else the factor alone).
layout(location = 1) uniform int uHasBaseColorMap;
// 1: reversed-Z (the local-light atlas: nearer is larger), the depth is stored as 1 - z so that
// GL_MIN keeps the nearest in both maps.
layout(location = 2) uniform int uReversedDepth;
layout(location = 3) uniform int uDepthLayer; // the layer of uOpaqueDepth (-1: gl_Layer)
layout(location = 4) uniform int uDivisor;    // depth texels per companion texel, each way
layout(binding = 9) uniform sampler2DArray uOpaqueDepth; // the map's depths (not attached now)
layout(location = 0) out vec4 outTransmittance;
layout(location = 1) out float outNearestDepth;

// KHR_texture_transform of the base colour slot (as material.glsl's slotUv, TEXCOORD_0).
vec2 baseColorUv(vec2 uv) {
    vec4 a = uTexTransform[PNB_TEX_BASE_COLOR * 2];
    vec4 b = uTexTransform[PNB_TEX_BASE_COLOR * 2 + 1];
    float c = cos(b.x), sn = sin(b.x);
    return mat2(c, -sn, sn, c) * (uv * a.zw) + a.xy;
}
#endif

void main() {
#ifdef ALPHA_MASK
    if ((uBaseColorFactor.a * texture(uBaseColorMap, vUv0).a) < uAlphaParams.x) discard;
#endif
#ifdef TRANSLUCENT
    vec4 base = uBaseColorFactor;
    if (uHasBaseColorMap != 0) base *= texture(uBaseColorMap, baseColorUv(vUv0));
    outTransmittance = vec4(clamp(base.rgb * (1.0 - base.a), 0.0, 1.0), 1.0);
    float z = clamp(gl_FragCoord.z, 0.0, 1.0); // depth clamp may leave it outside
    int layer = uDepthLayer >= 0 ? uDepthLayer : gl_Layer;
    ivec2 first = ivec2(gl_FragCoord.xy) * uDivisor;
    bool seen = false; // before some opaque depth of the block
    for (int y = 0; y < uDivisor; ++y)
        for (int x = 0; x < uDivisor; ++x) {
            float opaque = texelFetch(uOpaqueDepth, ivec3(first + ivec2(x, y), layer), 0).r;
            seen = seen || (uReversedDepth != 0 ? z > opaque : z < opaque);
        }
    if (!seen) discard;
    outNearestDepth = uReversedDepth != 0 ? 1.0 - z : z;
#endif
}
