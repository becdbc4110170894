#version 450 core
// debug_view.frag — shows one buffer. Modes match pnb::player::DebugView.
layout(binding = 0) uniform sampler2D uGBaseColor;
layout(binding = 1) uniform sampler2D uGNormalMaterial;
layout(binding = 2) uniform sampler2D uGEmissive;
layout(binding = 3) uniform sampler2D uDepth;
layout(binding = 4) uniform sampler2D uDebug; // layer or LOD colours, overdraw counts, the RSM
layout(binding = 5) uniform sampler3D uGiR;   // GI's summed volume (gi_volume)
layout(binding = 6) uniform sampler3D uGiG;
layout(binding = 7) uniform sampler3D uGiB;
layout(location = 0) uniform int uMode;
layout(location = 1) uniform vec3 uNearFar; // near, far (0 = infinite), 1 if orthographic
layout(location = 2) uniform vec2 uGiSlice; // normalised z of the slice, 1 if GI is on

// The frame's light list header and light clusters, as shaders/include/lights.glsl reads them
// (shared/light_list.h, shared/light_cluster_masks.h); the lights themselves are not read here.
#include "shared/bindings.h"
#include "shared/light_list.h"
#include "shared/light_cluster_masks.h"
layout(std430, binding = PNB_BINDING_LIGHT_LIST) readonly buffer LightBuffer {
    PNB_LIGHT_LIST_HEADER_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
layout(std430, binding = PNB_BINDING_LIGHT_CLUSTERS) readonly buffer LightClusters {
    PNB_LIGHT_CLUSTERS_HEADER_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
    uint uClusterMasks[];
};

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

// Same mapping as shaders/include/octahedral.glsl.
vec3 octDecode(vec2 e) {
    vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (v.z < 0.0) v.xy = (1.0 - abs(v.yx)) * vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
    return normalize(v);
}

// View depth (distance along the view axis) from a reversed-Z depth value; 1e30 where nothing is.
float viewDepth(float d) {
    float n = uNearFar.x, f = uNearFar.y;
    // Reversed-Z: d = n / z (infinite) or n (f - z) / (z (f - n)); invert to view distance.
    // Orthographic: d = (f - z) / (f - n), linear (pnb_player/camera.h viewDepthFromBuffer).
    if (d <= 0.0) return 1e30;
    if (uNearFar.z > 0.5) return n + (1.0 - d) * (f - n);
    return f > 0.0 ? n * f / (d * (f - n) + n) : n / d;
}

// How many lights the pixel's cluster holds (lights.glsl's clusterMaskStarts, from the depth).
uint clusterLights(float z) {
    if (uLightsClustered == 0u) return uLightCount;
    uvec2 tile = min(uvec2(gl_FragCoord.xy * uClusterDepth.x), uClusterGrid.xy - 1u);
    float s = log(max(z, 1e-30)) * uClusterDepth.y + uClusterDepth.z;
    uint slice = uint(clamp(s, 0.0, float(uClusterGrid.z - 1u)));
    uint words = uClusterGrid.w, tiles = uClusterGrid.x * uClusterGrid.y;
    uint t = (tile.y * uClusterGrid.x + tile.x) * words, sl = (tiles + slice) * words, n = 0u;
    for (uint w = 0u; w < words; ++w) n += uint(bitCount(uClusterMasks[t + w] & uClusterMasks[sl + w]));
    return n;
}

vec3 heat(float t) { // 0 black .. 1 red .. 2 yellow .. 4 white
    return clamp(vec3(t, t - 1.0, (t - 2.0) * 0.5), 0.0, 1.0);
}

void main() {
    vec4 base = texture(uGBaseColor, vUv);
    vec4 nm = texture(uGNormalMaterial, vUv);
    float packedBits = floor(nm.w * 65535.0 + 0.5);
    vec3 c = vec3(0.0);
    if (uMode == 1) c = base.rgb;
    else if (uMode == 2) c = vec3(base.a);
    else if (uMode == 3) c = base.a > 0.0 ? octDecode(nm.xy * 2.0 - 1.0) * 0.5 + 0.5 : vec3(0.0);
    else if (uMode == 4) c = vec3(nm.z);
    else if (uMode == 5) c = vec3(floor(packedBits / 256.0) / 255.0);
    else if (uMode == 6) c = vec3(mod(packedBits, 256.0) / 255.0);
    else if (uMode == 7) c = texture(uGEmissive, vUv).rgb;
    else if (uMode == 8) {
        float d = texture(uDepth, vUv).r;
        // Orthographic: the stored value is already linear in depth (near 1, far 0).
        c = vec3(d <= 0.0 ? 0.0 : uNearFar.z > 0.5 ? d : 1.0 - clamp(log2(viewDepth(d) / uNearFar.x) / 20.0, 0.0, 1.0));
    } else if (uMode == 9) c = texture(uDebug, vUv).rgb;
    else if (uMode == 10) c = heat(texture(uDebug, vUv).r);
    else if (uMode == 15) c = texture(uDebug, vUv).rgb; // RSM (black without GI)
    else if (uMode == 17) c = texture(uDebug, vUv).rgb; // level-of-detail colours
    else if (uMode == 18) { // lights per cluster: red 8, yellow 16, white 32 and more
        float d = texture(uDepth, vUv).r;
        c = d <= 0.0 ? vec3(0.0) : heat(float(clusterLights(viewDepth(d))) / 8.0);
    }
    else if (uMode == 16 && uGiSlice.y > 0.5) { // band 0 = radiance / sun irradiance x 2 sqrt(pi)
        vec3 uvw = vec3(vUv, uGiSlice.x);
        c = 4.0 * vec3(texture(uGiR, uvw).x, texture(uGiG, uvw).x, texture(uGiB, uvw).x); // x4: visible
    }
    outColor = vec4(c, 1.0);
}
