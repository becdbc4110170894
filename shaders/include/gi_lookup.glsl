// gi_lookup.glsl — indirect irradiance from GI's summed volumes (GI permutation), whichever
// technique filled them (gi.technique): the cascaded light propagation volumes (the player's
// lpv_*.comp passes) or the probes' one grid (gi_vpls.comp + gi_probe_gather.comp gather into the
// same volume, one cascade). The volumes hold radiance over the
// sun's irradiance as L1 SH per colour; irradiance at a surface with normal n is the radiance
// integrated against max(0, -n.w) (light travelling towards the surface), i.e. the dot product
// with the clamped-cosine lobe along -n, times the sun's irradiance.
// GI can be switched off at run time: the frame block's uAmbient.a is then 0 and nothing here
// (block or textures) is touched.
#ifndef PNB_GI_LOOKUP_GLSL
#define PNB_GI_LOOKUP_GLSL

#include "../shared/gi_block.h"
layout(binding = 10) uniform sampler3D uGiR;
layout(binding = 11) uniform sampler3D uGiG;
layout(binding = 12) uniform sampler3D uGiB;

vec3 giSample(int c, vec3 q, vec4 lobe) {
    float cells = uGiGrid.x;
    // Texel coordinates clamped to this cascade's slab so that filtering never reads the next.
    vec3 t = clamp(q, vec3(0.5), vec3(cells - 0.5));
    vec3 uvw = (t + vec3(0.0, 0.0, float(c) * cells)) / vec3(cells, cells, cells * uGiGrid.y);
    return vec3(dot(textureLod(uGiR, uvw, 0.0), lobe), dot(textureLod(uGiG, uvw, 0.0), lobe),
                dot(textureLod(uGiB, uvw, 0.0), lobe));
}

bool giCaptureIrradiance() { return uAmbient.a > 0.0 && uGiGrid.w > 0.5; }

// Irradiance at camera-relative p with unit normal n. Read half a cell in front of the surface
// (where injection put its light), from the finest cascade that holds the point, blended over
// two cells into the next coarser one near its border.
vec3 giIrradiance(vec3 p, vec3 n) {
    if (uAmbient.a <= 0.0) return vec3(0.0);
    vec4 lobe = vec4(0.886226925, 1.023326708 * n.y, -1.023326708 * n.z, 1.023326708 * n.x); // along -n
    int cascades = int(uGiGrid.y);
    float cells = uGiGrid.x;
    vec3 result = vec3(0.0);
    float remaining = 1.0; // weight not yet taken by a finer cascade
    for (int c = 0; c < cascades; ++c) {
        vec4 cascade = uGiCascade[c];
        vec3 q = (p - cascade.xyz) / cascade.w + 0.5 * n;
        float inside = min(min(min(q.x, q.y), q.z), min(min(cells - q.x, cells - q.y), cells - q.z));
        bool outer = c == cascades - 1;
        float w = (outer && uGiGrid.z < 0.5) ? 1.0 : clamp((inside - 0.5) * 0.5, 0.0, 1.0);
        if (inside > 0.5 && remaining > 0.0) {
            result += remaining * w * giSample(c, q, lobe);
            remaining *= 1.0 - w;
        }
    }
    return max(result, vec3(0.0)) * uGiIrradiance.rgb;
}

#endif
