#version 450 core
// gi_transmit.frag — what one translucent caster lets through (issue 43's contract): per channel
// T = baseColor.rgb * (1 - alpha), base colour and alpha being the material's factor times its
// base colour texture at the fragment's coordinate (through the texture transform, exactly as the
// G-buffer program reads them; no vertex colour). Two uses:
//   (default) the reflective shadow map: written with multiplicative blending (dst * src) over the
//             map's base colour after its opaque surfaces, depth-tested without writing depth, so
//             the flux of what lies behind a pane (the VPLs, LPV injection) is tinted and dimmed,
//             several panes multiplying. The colour target is sRGB with GL_FRAMEBUFFER_SRGB on:
//             the blend happens on linear values. Only location 0 is written (the normal target
//             is masked by the pass).
//   VOXELIZE  the probes' transmittance grid (gi.technique = probes) or one LPV cascade's glass
//             cells (gi.technique = lpv, uLayer = the cascade's first z): drawn three times, once
//             along each axis as gi_voxelize.frag; a fragment stores T in its voxel (idempotent:
//             any writer of one pane writes its T; two panes in one voxel keep either's).
#define HAS_BASE_COLOR_MAP
#include "include/material.glsl"

layout(location = 3) in vec2 vUv0;
layout(location = 4) in vec2 vUv1;
// 1 when the material has a base colour texture (unit PNB_TEX_BASE_COLOR), else 0: the pass sets
// it per material, since the unit then holds no texture at all.
layout(location = 2) uniform int uHasBaseColorMap;

#ifdef VOXELIZE
layout(rgba8, binding = 1) writeonly uniform image3D uTransmit;
layout(location = 0) uniform int uAxis;       // 0: viewed along x, 1: along y, 2: along z
layout(location = 1) uniform int uResolution; // voxels along each side
layout(location = 3) uniform int uLayer;      // z of the grid's first layer (LPV: cascades stacked)
#else
layout(location = 0) out vec4 outTransmit;
#endif

vec3 transmittance() {
    SurfaceInput s;
    s.uv0 = vUv0;
    s.uv1 = vUv1;
    vec4 base = uBaseColorFactor;
    if (uHasBaseColorMap != 0) base *= texture(uBaseColorMap, slotUv(PNB_TEX_BASE_COLOR, s));
    return clamp(base.rgb * (1.0 - base.a), 0.0, 1.0);
}

void main() {
    vec3 t = transmittance();
#ifdef VOXELIZE
    vec3 f = vec3(gl_FragCoord.xy / float(uResolution), gl_FragCoord.z); // [0, 1]^3 in view order
    vec3 u = uAxis == 0 ? vec3(f.z, f.y, f.x) : uAxis == 1 ? vec3(f.x, f.z, f.y) : f;
    ivec3 v = clamp(ivec3(floor(u * float(uResolution))), ivec3(0), ivec3(uResolution - 1));
    imageStore(uTransmit, v + ivec3(0, 0, uLayer), vec4(t, 1.0));
#else
    outTransmit = vec4(t, 1.0); // alpha: the blend keeps the map's own (GL_ZERO, GL_ONE)
#endif
}
