// shadow_sampling.glsl — the sun's visibility at a camera-relative point: cascade selection (by
// view depth or by map bounds) with a blend band, receiver offsets scaled by the texel size of the
// cascade read (normal offset plus slope-scaled offset toward the light), and three filters:
// hardware 2x2 PCF, N-tap Poisson-like PCF rotated per pixel, and PCSS.
// Compiled in when the container has a shadow-casting light (the SHADOWS define).
// TRANSLUCENT_SHADOWS (blended casters, issue 43): the visibility is a colour, the opaque
// visibility times the transmittance of the panes between the point and the light, read from
// the maps' colour companions where the receiver lies behind the nearest pane.
#ifndef PNB_SHADOW_SAMPLING_GLSL
#define PNB_SHADOW_SAMPLING_GLSL

#include "interface.glsl"
#include "shadow_block.glsl"

layout(binding = 8) uniform sampler2DArrayShadow uShadowMapCompare;
layout(binding = 9) uniform sampler2DArray uShadowMapDepth; // raw depths: PCSS blocker search

// What the last shadowVisibility() call read, for the cascade tint and the capture output:
// the colour visibility, and its mean (the opaque visibility x the mean transmittance).
float gShadowVisibility = 1.0;
vec3 gShadowColor = vec3(1.0);
int gShadowCascade = -1;
float gShadowTexelRatio = 0.0;
// Set by local_shadows.glsl when the judged light (shadows.judged_light, uShadowView.z >= 0) is a
// point or spot light that reaches this pixel: the capture then describes that light, not the sun.
bool gLocalJudged = false;

vec3 shadowCoord(int c, vec3 p) {
    vec4 s = uShadowMatrix[c] * vec4(p, 1.0);
    return vec3(s.xy / s.w * 0.5 + 0.5, s.z / s.w);
}

// World size of one texel of cascade `c` at `p`: stored for orthographic maps, measured through
// the matrix for LiSPSM's perspective map.
float shadowTexelWorld(int c, vec3 p) {
    float nominal = uShadowCascade[c].z;
    if (uShadowCascade[c].w < 0.5) return nominal;
    vec3 l = uShadowLight.xyz;
    vec3 t1 = normalize(cross(l, abs(l.y) < 0.99 ? vec3(0, 1, 0) : vec3(1, 0, 0)));
    vec3 t2 = cross(l, t1);
    vec2 s0 = shadowCoord(c, p).xy;
    float d1 = length(shadowCoord(c, p + t1 * nominal).xy - s0);
    float d2 = length(shadowCoord(c, p + t2 * nominal).xy - s0);
    return nominal / max(max(d1, d2) * uShadowMapInfo.x, 1e-6);
}

// Vogel disk: any tap count, evenly spread, rotated by `angle`.
vec2 diskTap(int i, int n, float angle) {
    float r = sqrt((float(i) + 0.5) / float(n));
    float theta = float(i) * 2.39996323 + angle;
    return r * vec2(cos(theta), sin(theta));
}

float interleavedGradientNoise(vec2 pixel) {
    return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
}

float pcf(int c, vec3 s, float radiusTexels, int taps) {
    if (radiusTexels <= 0.0 || taps <= 1) return texture(uShadowMapCompare, vec4(s.xy, float(c), s.z));
    float angle = 6.28318531 * interleavedGradientNoise(gl_FragCoord.xy);
    float sum = 0.0;
    for (int i = 0; i < taps; ++i) {
        vec2 uv = s.xy + diskTap(i, taps, angle) * radiusTexels * uShadowMapInfo.y;
        sum += texture(uShadowMapCompare, vec4(uv, float(c), s.z));
    }
    return sum / float(taps);
}

// PCSS for a directional light: penumbra width = blocker-receiver distance x the light's angular
// size; the blocker distance is averaged over a search disk.
float pcss(int c, vec3 s, vec3 p, float texelWorld, int taps) {
    float search = max(uShadowParams.w, 1.0) * 8.0;
    float angle = 6.28318531 * interleavedGradientNoise(gl_FragCoord.xy);
    float blockers = 0.0, blockerDepth = 0.0;
    for (int i = 0; i < taps; ++i) {
        vec2 uv = s.xy + diskTap(i, taps, angle) * search * uShadowMapInfo.y;
        float d = texture(uShadowMapDepth, vec3(uv, float(c))).r;
        if (d < s.z) {
            blockers += 1.0;
            blockerDepth += d;
        }
    }
    if (blockers == 0.0) return 1.0;
    blockerDepth /= blockers;
    // World distance per unit of map depth, measured along the light (any projection).
    float depthPerWorld = abs(shadowCoord(c, p + uShadowLight.xyz * texelWorld).z - s.z) / texelWorld;
    float distanceWorld = (s.z - blockerDepth) / max(depthPerWorld, 1e-12);
    float penumbraTexels = 2.0 * distanceWorld * uShadowMapInfo.z / texelWorld;
    return pcf(c, s, clamp(penumbraTexels, 0.5, 32.0), taps);
}

#ifdef TRANSLUCENT_SHADOWS
// The companions of the cascade array (player/src/shadows/shadow_resources.cpp): transmittance
// (sRGB-encoded RGBA8, read linear: the product of the panes' T) and the nearest pane's depth (R32F), both 1 where none.
layout(binding = 20) uniform sampler2DArray uShadowTransmittance;
layout(binding = 21) uniform sampler2DArray uShadowTranslucentDepth;

// Transmittance toward the light at shadow coordinate `s` of layer `layer`: each of the 2x2
// texels around it counts where the receiver (with the opaque test's offsets, so a pane does
// not tint itself) is farther than that texel's nearest pane, weighted bilinearly. `reversed`:
// depths stored as 1 - z (the local atlas). Outside the map nothing is in the way.
vec3 translucentTransmittance(sampler2DArray transmittance, sampler2DArray nearest, int layer, vec3 s,
                              bool reversed) {
    if (any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0)))) return vec3(1.0);
    ivec3 extent = textureSize(nearest, 0);
    if (extent.x == 0) return vec3(1.0); // nothing bound (a player that predates the companions)
    ivec2 size = extent.xy;
    layer = min(layer, extent.z - 1); // the 1x1x1 stand-ins serve every cascade
    vec2 t = s.xy * vec2(size) - 0.5;
    ivec2 i0 = ivec2(floor(t));
    vec2 f = t - floor(t);
    float z = reversed ? 1.0 - s.z : s.z;
    vec3 sum = vec3(0.0);
    for (int k = 0; k < 4; ++k) {
        ivec2 o = ivec2(k & 1, k >> 1);
        ivec3 texel = ivec3(clamp(i0 + o, ivec2(0), size - 1), layer);
        float w = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y);
        bool behind = z > texelFetch(nearest, texel, 0).r;
        sum += w * (behind ? texelFetch(transmittance, texel, 0).rgb : vec3(1.0));
    }
    return sum;
}
#endif

// The opaque visibility of cascade `c` into gCascadeOpaque; returns the offset shadow coordinate.
float gCascadeOpaque = 1.0;
vec3 cascadeOpaque(int c, vec3 p, vec3 n, float ndotl) {
    float texelWorld = shadowTexelWorld(c, p);
    float tanTheta = min(sqrt(max(1.0 - ndotl * ndotl, 0.0)) / max(ndotl, 1e-3), 10.0);
    vec3 offset = n * (uShadowBias.x * texelWorld) + uShadowLight.xyz * (uShadowBias.y * texelWorld * tanTheta);
    vec3 s = shadowCoord(c, p + offset);
    int filterMode = int(uShadowParams.y);
    int taps = int(uShadowParams.z);
    gCascadeOpaque = filterMode == 0 ? texture(uShadowMapCompare, vec4(s.xy, float(c), s.z))
                   : filterMode == 1 ? pcf(c, s, uShadowParams.w, taps)
                                     : pcss(c, s, p + offset, texelWorld, taps);
    return s;
}

// The colour visibility of cascade `c`: opaque x transmittance.
vec3 cascadeVisibility(int c, vec3 p, vec3 n, float ndotl) {
    vec3 s = cascadeOpaque(c, p, n, ndotl);
    float v = gCascadeOpaque;
#ifdef TRANSLUCENT_SHADOWS
    return v * translucentTransmittance(uShadowTransmittance, uShadowTranslucentDepth, c, s, false);
#else
    return vec3(v);
#endif
}

bool insideMap(vec3 s, float margin) {
    return all(greaterThanEqual(s.xy, vec2(margin))) && all(lessThanEqual(s.xy, vec2(1.0 - margin))) &&
           s.z >= 0.0 && s.z <= 1.0;
}

// The sun's visibility, recording what the capture and the cascade tint show.
vec3 sunShadowVisibility(vec3 p, vec3 n) {
    gShadowVisibility = 1.0;
    gShadowColor = vec3(1.0);
    gShadowCascade = -1;
    gShadowTexelRatio = 0.0;
    int count = int(uShadowParams.x);
    if (count == 0) return vec3(1.0);
    float ndotl = dot(n, uShadowLight.xyz);
    if (ndotl <= 0.0) {
        gShadowVisibility = 0.0; // facing away: the BRDF is zero anyway
        gShadowColor = vec3(0.0);
        gShadowCascade = -2;     // (the capture leaves such pixels out)
        return vec3(0.0);
    }
    float depth = -(uView * vec4(p, 1.0)).z;
    int c = -1;
    float blend = 0.0; // weight of cascade c + 1
    if (uShadowBias.w < 0.5) {
        for (int i = 0; i < count; ++i) {
            if (depth <= uShadowCascade[i].y) {
                c = i;
                break;
            }
        }
        if (c >= 0 && c + 1 < count) {
            float band = uShadowBias.z * (uShadowCascade[c].y - uShadowCascade[c].x);
            if (band > 0.0) blend = clamp((depth - (uShadowCascade[c].y - band)) / band, 0.0, 1.0);
        }
    } else {
        float margin = (uShadowParams.w + 1.0) * uShadowMapInfo.y;
        for (int i = 0; i < count; ++i) {
            vec3 s = shadowCoord(i, p);
            if (insideMap(s, margin)) {
                c = i;
                if (i + 1 < count && uShadowBias.z > 0.0) {
                    float edge = min(min(s.x, 1.0 - s.x), min(s.y, 1.0 - s.y)) - margin;
                    blend = clamp(1.0 - edge / (0.5 * uShadowBias.z), 0.0, 1.0);
                }
                break;
            }
        }
    }
    if (c < 0) return vec3(1.0); // beyond the shadowed range
    vec3 v = cascadeVisibility(c, p, n, ndotl);
    if (blend > 0.0) v = mix(v, cascadeVisibility(c + 1, p, n, ndotl), blend);
    gShadowColor = v;
    gShadowVisibility = (v.r + v.g + v.b) / 3.0;
    gShadowCascade = c;
    float pixelWorld = 2.0 * (depth * uShadowView.x + uShadowView.w) / uShadowView.y;
    gShadowTexelRatio = shadowTexelWorld(c, p) / max(pixelWorld, 1e-30);
    return v;
}

// 1 lit .. 0 shadowed, per colour channel. `p` camera-relative, `n` the unit surface normal. While a local light is
// judged, the sun's record is left as the local light's shadow set it.
vec3 shadowVisibility(vec3 p, vec3 n) {
    if (uShadowView.z < 0.0) return sunShadowVisibility(p, n);
    float v0 = gShadowVisibility, r0 = gShadowTexelRatio;
    vec3 color0 = gShadowColor;
    int c0 = gShadowCascade;
    vec3 v = sunShadowVisibility(p, n);
    gShadowVisibility = v0;
    gShadowColor = color0;
    gShadowTexelRatio = r0;
    gShadowCascade = c0;
    return v;
}

// The lit colour, or what debug.view / the shadow capture asks for instead. The capture describes
// the surface whose depth the frame kept (the truth is traced there): a translucent layer writes
// no depth, so it leaves the value below it (alpha 0), as the GI and sky captures do.
vec4 shadowOutput(vec4 color) {
    int mode = int(uShadowMapInfo.w);
    if (mode == 1) {
        const vec3 tint[8] = vec3[8](vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0, 1, 1),
                                     vec3(1, 0, 1), vec3(1, 0.5, 0), vec3(0.5, 0, 1), vec3(0.5, 0.5, 0.5));
        vec3 t = gShadowCascade == -1 ? vec3(1, 1, 0) : tint[max(gShadowCascade, 0)];
        return vec4(color.rgb * 0.35 + t * (0.15 + 0.5 * gShadowVisibility), color.a);
    }
    float keep = color.a < 1.0 ? 0.0 : 1.0;
    if (mode == 3) { // colour capture (CaptureBuffer::ShadowColor): rgb visibility, -1 unclassified
        bool classified = uShadowView.z >= 0.0 ? gLocalJudged : gShadowCascade != -2;
        return classified ? vec4(gShadowColor, keep) : vec4(-1, -1, -1, keep);
    }
    if (mode == 2 && uShadowView.z >= 0.0) // capture of a point or spot light: visibility, 0
        return gLocalJudged ? vec4(gShadowVisibility, 0.0, 0.0, keep) : vec4(-1, -1, 0, keep);
    if (mode == 2) // capture: visibility (-1: not classified), cascade, texel/pixel ratio
        return gShadowCascade == -2 ? vec4(-1, -1, 0, keep)
                                    : vec4(gShadowVisibility, float(gShadowCascade), gShadowTexelRatio, keep);
    return color;
}

#endif
