#version 450 core
// gi_voxelize.frag — the scene into the probes' occupancy grid (gi.technique = probes): drawn
// three times, once along each axis, with an orthographic view whose clip x, y and depth are the
// grid's other two axes and this one, so every surface is rasterised along the axis it faces most
// (a wall edge-on to one view is face-on to another). A fragment marks its voxel; writes are
// idempotent (no atomics, any order gives the same grid; ALBEDO's sums are atomic).
//
// ALBEDO (gi.bounces > 1; with gi_voxelize.vert): also the surface's diffuse albedo, for the
// probes' further bounces (gi_probe_gather.comp, BOUNCE): base colour (the material's factor times
// its base colour texture at the fragment, through the texture transform, times the vertex
// colour: what the G-buffer reads) x (1 - the metallic factor; a metallic-roughness texture is not
// read). Every fragment adds it into its voxel (fixed point, kAlbedoScale per 1.0) and counts
// itself, with atomics into an R32UI volume four texels wide per voxel (r, g, b, count): the
// bounce reads the mean of the surfaces in the voxel, a checker floor its mean, two surfaces
// sharing a voxel their area-weighted mean, whatever the draw order.
layout(r8ui, binding = 0) writeonly uniform uimage3D uVoxels;
layout(location = 0) uniform int uAxis;      // 0: viewed along x, 1: along y, 2: along z
layout(location = 1) uniform int uResolution; // voxels along each side
#ifdef ALBEDO
#define HAS_BASE_COLOR_MAP
#include "include/material.glsl"
layout(location = 3) in vec2 vUv0;
layout(location = 4) in vec2 vUv1;
layout(location = 5) in vec4 vColor;
// 1 when the material has a base colour texture (unit PNB_TEX_BASE_COLOR), else 0: the pass sets
// it per material (drawTranslucentCasters' uniform), since the unit then holds no texture at all.
layout(location = 2) uniform int uHasBaseColorMap;
layout(r32ui, binding = 2) uniform uimage3D uAlbedoSums;
const float kAlbedoScale = 1024.0; // 2^32 / (1024 x 1.0) = 4 M fragments a voxel before overflow
#endif

// A surface lying on a boundary between two voxel layers (a floor at a whole number of voxels: the
// grid's origin is snapped to whole cells, and modelled rooms have whole-metre walls) marks both
// layers. Left to floor(), the rounding of each triangle's interpolated depth put its fragments
// on one side or the other, quad by quad: a floor of several quads came out as a patchwork of two
// layers, and the probes and bounce rays saw it that way (box room: blotches of a probe's size on
// the floor and a bright seam along the ceiling). kBoundary: in voxels along the view axis.
const float kBoundary = 1.0 / 256.0;

#ifdef ALBEDO
// The fragment's diffuse albedo in fixed point (computed once, outside the loop below: the
// texture's implicit derivatives need uniform control flow).
uvec3 fragmentAlbedo() {
    SurfaceInput s;
    s.uv0 = vUv0;
    s.uv1 = vUv1;
    vec4 base = uBaseColorFactor * vColor;
    if (uHasBaseColorMap != 0) base *= texture(uBaseColorMap, slotUv(PNB_TEX_BASE_COLOR, s));
    float metallic = clamp(uMaterialParams.x, 0.0, 1.0);
    return uvec3(round(clamp(base.rgb * (1.0 - metallic), 0.0, 1.0) * kAlbedoScale));
}
#endif

void markVoxel(ivec3 v, uvec3 albedo) {
    imageStore(uVoxels, v, uvec4(1u));
#ifdef ALBEDO
    ivec3 at = ivec3(4 * v.x, v.y, v.z);
    imageAtomicAdd(uAlbedoSums, at, albedo.r);
    imageAtomicAdd(uAlbedoSums, at + ivec3(1, 0, 0), albedo.g);
    imageAtomicAdd(uAlbedoSums, at + ivec3(2, 0, 0), albedo.b);
    imageAtomicAdd(uAlbedoSums, at + ivec3(3, 0, 0), 1u);
#endif
}

void main() {
#ifdef ALBEDO
    uvec3 albedo = fragmentAlbedo();
#else
    uvec3 albedo = uvec3(0u);
#endif
    vec3 f = vec3(gl_FragCoord.xy / float(uResolution), gl_FragCoord.z); // [0, 1]^3 in view order
    float depth = f.z * float(uResolution);
    float nearest = round(depth);
    bool onBoundary = abs(depth - nearest) < kBoundary;
    for (int side = 0; side < (onBoundary ? 2 : 1); ++side) {
        // On a boundary: the layers below and above it; otherwise the fragment's own.
        vec3 g = vec3(gl_FragCoord.xy, onBoundary ? nearest - 0.5 + float(side) : depth);
        vec3 u = uAxis == 0 ? vec3(g.z, g.y, g.x) : uAxis == 1 ? vec3(g.x, g.z, g.y) : g;
        markVoxel(clamp(ivec3(floor(u)), ivec3(0), ivec3(uResolution - 1)), albedo);
    }
}
