// lights.glsl — punctual lights (KHR_lights_punctual semantics) from a storage buffer, so the
// light count is not limited by uniform space (UberRender's cap was 1 + 32 + 32).
//
// Two ways through the lights, chosen per frame by the player (docs/PLAYER.md "Many lights"):
// every light at every pixel, or only the lights of the pixel's cluster (a screen tile x an
// exponential depth slice), whose bit masks the player's light_clusters.comp built this frame.
// The branch is uniform over the draw, so the unused way costs nothing but code size.
#ifndef PNB_LIGHTS_GLSL
#define PNB_LIGHTS_GLSL

#include "interface.glsl"
#include "brdf.glsl"
#ifdef SHADOWS
#include "shadow_sampling.glsl"
#include "local_shadows.glsl"
#endif

#define PNB_LIGHT_DIRECTIONAL 0
#define PNB_LIGHT_POINT 1
#define PNB_LIGHT_SPOT 2

#include "../shared/bindings.h"
#include "../shared/light_list.h"
#include "../shared/light_cluster_masks.h"

// The light list: its header (uLightCount, uLightsClustered), then the lights.
layout(std430, binding = PNB_BINDING_LIGHT_LIST) readonly buffer LightBuffer {
    PNB_LIGHT_LIST_HEADER_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
    GpuLight uLights[];
};

// The clusters' light masks (player/shaders/light_clusters.comp writes them; the player binds
// another buffer here while uLightsClustered is 0, which is then never read). A cluster's lights
// are its screen tile's mask AND its depth slice's mask: two lists of (tiles + slices) masks
// instead of one per froxel, at the cost of lights that touch the tile and the slice but not
// their intersection (they are shaded, and their range window makes them add nothing).
layout(std430, binding = PNB_BINDING_LIGHT_CLUSTERS) readonly buffer LightClusters {
    // uClusterGrid (the grid), uClusterDepth (its slicing)
    PNB_LIGHT_CLUSTERS_HEADER_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
    uint uClusterMasks[]; // tile masks (row by row), then slice masks (near to far)
};

// glTF's recommended range window: smooth falloff to zero at `range`, inverse-square inside.
// The clamp is 1 cm² in glTF's unit (metres; KHR_lights_punctual intensities are candela per
// metre²): a light never gets brighter than at 1 cm from its point. Scenes in other units carry
// their scale in the container's meters_per_unit, not here.
float rangeAttenuation(float distanceSquared, float range) {
    float inverseSquare = 1.0 / max(distanceSquared, 1e-4);
    if (range <= 0.0) return inverseSquare;
    float r = distanceSquared / (range * range);
    float window = clamp(1.0 - r * r, 0.0, 1.0);
    return window * window * inverseSquare;
}

// Whether light `i` can light camera-relative `p`: a directional light always, a point or spot
// light within its range (a spot's cone is left to shadeLight).
bool lightReaches(uint i, vec3 p) {
    vec4 positionRange = uLights[i].positionRange;
    vec3 toLight = positionRange.xyz - p;
    float range = positionRange.w; // 0: directional, or a point or spot light without a range
    return range <= 0.0 || dot(toLight, toLight) < range * range;
}

// Whether light `i` is shadowed this frame: the sun's cascades or a local light's tiles.
bool lightShadowed(uint i) {
#ifdef SHADOWS
    return float(i) == uShadowLight.w || uLights[i].cone.z >= 0.0;
#else
    return false;
#endif
}

// Radiance reflected towards the viewer by light `i`, with its shadow if `shadowed` (callers
// pass a constant, so the shadow lookups are compiled out of the unshadowed call).
vec3 shadeLight(uint i, vec3 baseColor, float metallic, float roughness, vec3 n, vec3 p, vec3 v,
                bool shadowed) {
    GpuLight light = uLights[i];
    int type = int(light.directionType.w);
    vec3 l;
    float attenuation = 1.0;
    if (type == PNB_LIGHT_DIRECTIONAL) {
        l = -light.directionType.xyz;
    } else {
        vec3 toLight = light.positionRange.xyz - p;
        float d2 = dot(toLight, toLight);
        l = d2 > 0.0 ? toLight * inversesqrt(d2) : vec3(0.0, 0.0, 1.0); // unit at any scale
        attenuation = rangeAttenuation(d2, light.positionRange.w);
        if (type == PNB_LIGHT_SPOT) {
            float cd = dot(light.directionType.xyz, -l);
            float t = clamp((cd - light.cone.x) * light.cone.y, 0.0, 1.0);
            attenuation *= t * t;
        }
    }
    vec3 radiance = light.colorIntensity.rgb * light.colorIntensity.a * attenuation;
#ifdef SHADOWS
    if (shadowed && float(i) == uShadowLight.w) radiance *= shadowVisibility(p, n);
    if (shadowed && light.cone.z >= 0.0 && attenuation > 0.0) {
        // Six faces for point lights and spots wider than 60 degrees (cos < 0.5), as the player
        // places them (pass_local_shadows.cpp).
        vec3 visibility = localShadowVisibility(int(light.cone.z), type == PNB_LIGHT_POINT || light.cone.x < 0.5,
                                                light.positionRange.xyz, p, n, l);
        radiance *= visibility;
        if (float(i) == uShadowView.z) { // the judged light (shadows.judged_light): the capture
            gLocalJudged = dot(n, l) > 0.0;
            gShadowColor = visibility;
            gShadowVisibility = (visibility.r + visibility.g + visibility.b) / 3.0;
            gShadowCascade = 0;
        }
    }
#endif
    return shadeBrdf(baseColor, metallic, roughness, n, v, l, radiance);
}

// The cluster of the fragment being shaded at camera-relative `p`: its tile's and its slice's
// first mask word. Depths before the first slice fall into it, past the last into the last.
uvec2 clusterMaskStarts(vec3 p) {
    uvec2 tile = uvec2(gl_FragCoord.xy * uClusterDepth.x);
    tile = min(tile, uClusterGrid.xy - 1u);
    float depth = -(uView * vec4(p, 0.0)).z;
    float s = log(max(depth, 1e-30)) * uClusterDepth.y + uClusterDepth.z;
    uint slice = uint(clamp(s, 0.0, float(uClusterGrid.z - 1u)));
    uint words = uClusterGrid.w;
    uint tiles = uClusterGrid.x * uClusterGrid.y;
    return uvec2((tile.y * uClusterGrid.x + tile.x) * words, (tiles + slice) * words);
}

// Radiance reflected towards the viewer by all lights. `p` is camera-relative, `v` points from
// the surface to the camera. `receivesShadows`: the material's flag (forward programs of
// materials that do not receive are built without SHADOWS; deferred ones read a G-buffer bit).
//
// Two phases, so that only the lights in reach pay for a BRDF, and only the shadowed ones for a
// shadow lookup: first the cheap range test of every candidate (the cluster's mask bits, or every
// light), collecting the reached lights' indices in two short lists (unshadowed; shadowed by the
// sun's cascades or a local light's tiles), then one shading loop per list. Shader compilers for
// SIMD CPUs (llvmpipe) run a branch's body for every lane, and a loop's body at least once even
// when no lane enters it; so per-light branches, or shading loops inside the loop over mask
// words, cost a full BRDF (and shadow lookup) per candidate or per word (1024 lights: ~10x).
// The lists hold PNB_LIGHT_BATCH lights; more lights in reach of one pixel are shaded in further
// batches, so none is dropped.
#define PNB_LIGHT_BATCH 32

// Mask word `w` of this pixel's candidates: its cluster's, or every light.
uint candidateWord(uint w, bool clustered, uvec2 start, uint words) {
    if (clustered) return uClusterMasks[start.x + w] & uClusterMasks[start.y + w];
    return w + 1u < words || uLightCount % 32u == 0u ? ~0u : (1u << (uLightCount % 32u)) - 1u;
}

vec3 shadeLights(vec3 baseColor, float metallic, float roughness, vec3 n, vec3 p, vec3 v,
                 bool receivesShadows) {
    vec3 sum = vec3(0.0);
    bool clustered = uLightsClustered != 0u;
    uint words = (uLightCount + 31u) / 32u;
    uvec2 start = clustered ? clusterMaskStarts(p) : uvec2(0u);
    uint w = 0u;
    uint candidates = words > 0u ? candidateWord(0u, clustered, start, words) : 0u;
    bool done = words == 0u;
    uint plainList[PNB_LIGHT_BATCH], shadowedList[PNB_LIGHT_BATCH];
    while (!done) {
        uint plainCount = 0u, shadowedCount = 0u;
        while (!done && plainCount < PNB_LIGHT_BATCH && shadowedCount < PNB_LIGHT_BATCH) {
            if (candidates == 0u) { // the next word
                ++w;
                done = w >= words;
                candidates = done ? 0u : candidateWord(w, clustered, start, words);
                continue;
            }
            int b = findLSB(candidates);
            candidates &= candidates - 1u;
            uint i = w * 32u + uint(b);
            if (lightReaches(i, p)) {
                if (receivesShadows && lightShadowed(i)) shadowedList[shadowedCount++] = i;
                else plainList[plainCount++] = i;
            }
        }
        for (uint k = 0u; k < plainCount; ++k)
            sum += shadeLight(plainList[k], baseColor, metallic, roughness, n, p, v, false);
        for (uint k = 0u; k < shadowedCount; ++k)
            sum += shadeLight(shadowedList[k], baseColor, metallic, roughness, n, p, v, true);
    }
    return sum;
}

#endif
