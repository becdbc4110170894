// local_shadows.glsl — point and spot light shadows from the player's atlas (player/src/
// local_shadows.h): a spot light's tile, or the cube face of a point light's six that holds the
// direction to the point, read with the sun's PCF (a rotated Vogel disk of 2x2 hardware-compared
// taps, shadows.radius texels) at shadows.local_taps taps (a pixel may read a dozen lights'
// tiles: 1 tap = one 2x2 PCF lookup), and the sun's receiver offsets, which are in texels: in
// world units a texel at distance d from the light is d x rect.w, so the offsets follow each
// tile's resolution as the sun's follow each cascade's.
// TRANSLUCENT_SHADOWS: times the transmittance of the blended casters in the tile's colour
// companions (as the sun's, shadow_sampling.glsl), so the visibility is a colour.
// Compiled in with SHADOWS, after shadow_sampling.glsl.
#ifndef PNB_LOCAL_SHADOWS_GLSL
#define PNB_LOCAL_SHADOWS_GLSL

#include "../shared/bindings.h"
#include "../shared/local_shadow_tile.h"

layout(std430, binding = PNB_BINDING_LOCAL_SHADOWS) readonly buffer LocalShadows {
    PNB_LOCAL_SHADOWS_HEADER_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY) // uLocalShadowAtlas
    LocalShadowTile uLocalShadowTiles[];
};

layout(binding = 19) uniform sampler2DShadow uLocalShadowMap; // units 10-18: GI and the sky
#ifdef TRANSLUCENT_SHADOWS
// One layer each; the nearest pane's depth stored as 1 - z (the atlas is reversed-Z).
layout(binding = 22) uniform sampler2DArray uLocalTransmittance;
layout(binding = 23) uniform sampler2DArray uLocalTranslucentDepth;
#endif

// The opaque visibility times, with TRANSLUCENT_SHADOWS, the panes' transmittance at atlas
// coordinate `uv` (kept inside the tile) and depth `z`.
vec3 localColorVisibility(float opaque, vec2 uv, float z) {
#ifdef TRANSLUCENT_SHADOWS
    return opaque * translucentTransmittance(uLocalTransmittance, uLocalTranslucentDepth, 0, vec3(uv, z), true);
#else
    return vec3(opaque);
#endif
}

// 1 lit .. 0 shadowed (per colour channel), for the light whose tiles start at `firstTile`. `lightPosition` and `p`
// camera-relative, `n` the unit normal, `l` the unit vector to the light, `cube`: six faces.
vec3 localShadowVisibility(int firstTile, bool cube, vec3 lightPosition, vec3 p, vec3 n, vec3 l) {
    float ndotl = dot(n, l);
    if (ndotl <= 0.0) return vec3(0.0); // facing away: the BRDF is zero anyway
    vec3 fromLight = p - lightPosition;
    int tile = firstTile;
    if (cube) { // the face whose axis is the largest component: +x, -x, +y, -y, +z, -z
        vec3 a = abs(fromLight);
        int face = a.x >= a.y && a.x >= a.z ? (fromLight.x > 0.0 ? 0 : 1)
                 : a.y >= a.z               ? (fromLight.y > 0.0 ? 2 : 3)
                                            : (fromLight.z > 0.0 ? 4 : 5);
        tile += face;
    }
    LocalShadowTile t = uLocalShadowTiles[tile];
    float texelWorld = length(fromLight) * t.rect.w;
    float tanTheta = min(sqrt(max(1.0 - ndotl * ndotl, 0.0)) / max(ndotl, 1e-3), 10.0);
    vec3 q = p + n * (uShadowBias.x * texelWorld) + l * (uShadowBias.y * texelWorld * tanTheta);
    vec4 c = t.matrix * vec4(q, 1.0);
    if (c.w <= 0.0) return vec3(1.0); // behind the light's plane (cannot be: the faces cover all)
    vec3 s = c.xyz / c.w;
    vec2 texel = vec2(uLocalShadowAtlas.x);
    vec2 lo = t.rect.xy + texel, hi = t.rect.xy + t.rect.z - texel; // taps stay in the tile
    vec2 uv = t.rect.xy + (s.xy * 0.5 + 0.5) * t.rect.z;
    int taps = int(uLocalShadowAtlas.y);
    float radius = uLocalShadowAtlas.z;
    vec2 centre = clamp(uv, lo, hi);
    if (taps <= 1 || radius <= 0.0) return localColorVisibility(texture(uLocalShadowMap, vec3(centre, s.z)), centre, s.z);
    float angle = 6.28318531 * interleavedGradientNoise(gl_FragCoord.xy);
    float sum = 0.0;
    for (int i = 0; i < taps; ++i) {
        vec2 tap = uv + diskTap(i, taps, angle) * radius * texel;
        sum += texture(uLocalShadowMap, vec3(clamp(tap, lo, hi), s.z));
    }
    return localColorVisibility(sum / float(taps), centre, s.z);
}

#endif
