#version 450 core
// gi_probe_gather.comp — irradiance probes at the grid cells' centres and their rays through the
// scene's occupancy grid (gi_voxelize.frag). Three variants:
//
// (default) The gather (gi.technique = probes): eight probes a work group, each with eight
// threads sharing the VPLs (gi_vpls.comp). A VPL y with normal n_y and flux Phi (over the sun's
// irradiance) lights the probe x with irradiance Phi max(0, n_y . w) / (pi (r^2 + a)) straight
// on, w = (x - y) / r, where a (the VPL's area over 2 pi) keeps the bound of a lit disc instead
// of the point light's 1/r^2 pole. Visibility (gi.probe_visibility): `depth` looks the VPL up in
// the probe's depth map (PROBE_DEPTH below: a fetch, not a walk); `exact` (EXACT_VISIBILITY)
// walks the grid from the VPL to the probe (3D-DDA): any solid voxel between them blocks it, but
// those within a cell of the probe (kPassThroughVoxels: both variants). The result is stored as
// the L1 SH of radiance over travel direction, the LPV's own format, so lighting's look-up
// (shaders/include/gi_lookup.glsl) reads probes and propagation volumes alike. There is no
// propagation: light reaches the far wall in one step, at 1/r^2, and nowhere else.
//
// PROBE_DEPTH: a work group per probe. Whether a look-up can read it (kReach) and, if so, its
// depth map, DDGI's visibility data: a 16 x 16 octahedral map (y up) of how far the probe sees
// before a solid voxel (past those within a cell: kPassThroughVoxels), one ray through each
// texel's centre. Traced only when the grid is redrawn (it depends on the geometry alone), so the
// gather, which runs whenever the sun moves, makes one filtered fetch per probe-VPL pair instead
// of a walk (measured: docs/PLAYER.md). The gather interpolates the map bilinearly at the VPL's
// exact direction: a floor seen at a grazing angle, the common case, is hit at h / sin(angle),
// convex in the angle, so the interpolated depth errs long and a VPL on it stays seen (a texel
// spans ~13 degrees; the nearest texel's depth, or the min/max of rays through the texel, hid
// a quarter of the box room's light).
//
// SKY_VISIBILITY (ibl.visibility = probes): a work group per probe; every probe traces kSkyRays directions
// spread evenly over the sphere (a spherical Fibonacci set) through the same grid and stores the
// L1 SH of the set it sees out of the grid through (V(w) projected: sum of basis(w) 4 pi / N);
// lighting turns that into the cosine-weighted visible fraction around a normal
// (shaders/include/sky_visibility.glsl). A probe whose own voxel is solid stores c0 = -1: the
// look-up leaves it out (it sees through a wall both ways and would let the outside's sky in).
//
// BOUNCE (gi.bounces > 1; pass_gi_bounce.cpp): the gather's result (uGathered*, kept from the
// gather) plus the light of one more bounce. Each probe walks the 16 x 16 directions of its
// depth map's texel centres through the grid to the first solid voxel past its own (past
// kPassThroughVoxels only, not a cell as the depth maps: a probe within a cell of the floor has
// to see the floor, whose light its neighbours on the walls read; with the depth maps' cell the
// colour room kept 0.70 of the converged truth's light, walking 0.89), reads there the previous gather's irradiance (uPrev*: the volume lighting reads, copied) on
// the voxel face the ray entered by, half a cell in front of it as lighting's look-up does, and
// times the voxel's mean albedo (gi_voxelize.frag, ALBEDO) over pi: the radiance that surface sends
// back. Projected onto L1 SH with each texel's solid angle (the octahedral map's dA / r^3), that
// is the light after one more bounce (irradiance-field methods' recurrence: V_k+1 = gather +
// bounce(V_k)). With TRANSMITTANCE the panes a ray crosses before its hit dim and tint what it
// brings back (with the depth maps, read from the probe's transmittance map: transmitTowards);
// rays leaving the grid bring nothing (the sky is ibl's).
//
// TRANSMITTANCE (with any of the three; only while some BLEND material casts shadows, issue 43):
// the panes' transmittance grid beside the occupancy grid (gi_transmit.frag, VOXELIZE) dims and
// tints what a ray passes: the exact walk multiplies a VPL's flux by the panes between it and the
// probe; PROBE_DEPTH also stores, per depth texel, the product of the panes its ray crosses before
// its hit and the distance to the first (RGBA8), which the gather applies to VPLs beyond that
// distance; SKY_VISIBILITY stores one SH per colour (red, green, blue stacked along z). A run of
// pane voxels along a ray counts as one surface: a pane one voxel thick crossed at a grazing angle
// steps through several of its voxels, and light passes it once. Two panes within one voxel keep
// one's transmittance.
#include "shared/bindings.h"
#if defined(SKY_VISIBILITY) || defined(PROBE_DEPTH)
layout(local_size_x = 64) in; // a work group per probe, its threads sharing the rays
#else
// 8 probes along x a group, 8 threads each sharing its VPLs (x: the VPL lane, y: the probe). A
// group per probe with 64 threads and a 6-step reduction cost 38 ms of the box room's 80 ms on
// llvmpipe whatever the VPL count; a thread per probe, no reduction, made the pairs slower (its
// SIMD lanes, 8 probes, fetch 8 depth maps; here they are one probe's 8 VPLs).
layout(local_size_x = 8, local_size_y = 8) in;
const int kLanes = 8;
#endif

layout(binding = 0) uniform usampler3D uVoxels;
#ifdef TRANSMITTANCE
layout(binding = 3) uniform sampler3D uTransmitVoxels; // rgb: T, a: 1 where a pane is
#endif
#ifdef SKY_VISIBILITY
layout(rgba16f, binding = 0) writeonly uniform image3D uSky;
const int kSkyRays = 256;
#ifdef TRANSMITTANCE
const int kSkyColours = 3; // one SH per colour, stacked along z
#else
const int kSkyColours = 1;
#endif
#elif defined(PROBE_DEPTH)
// The depth maps: probe (x, y, z) is the tile at (x, y) * kTile in layer z, its 16 x 16 texels
// inside a one-texel border that repeats the octahedral map's folded neighbours, so that the
// gather's hardware bilinear fetch is right across the map's edges (DDGI's layout). R16F, voxels.
layout(r16f, binding = 0) writeonly uniform image2DArray uDepthMaps;
// Per probe (x + n (y + n z)): 1 if lighting's look-up can read it (kReach).
layout(std430, binding = PNB_BINDING_GI_PROBE_NEEDED) writeonly buffer ProbeNeeded { uint uNeeded[]; };
shared uint sNeeded;
#ifdef TRANSMITTANCE
layout(rgba8, binding = 1) writeonly uniform image2DArray uTransmitMaps; // the depth maps' layout
#endif
#else
struct Vpl {
    vec4 position; // camera-relative world, w: lit area
    vec4 normal;
    vec4 flux;     // rgb over the sun's irradiance
};
layout(std430, binding = PNB_BINDING_GI_VPLS) readonly buffer Vpls { Vpl uVpls[]; };

layout(rgba16f, binding = 0) writeonly uniform image3D uSumR;
layout(rgba16f, binding = 1) writeonly uniform image3D uSumG;
layout(rgba16f, binding = 2) writeonly uniform image3D uSumB;
#ifdef BOUNCE
layout(binding = 4) uniform sampler3D uPrevR; // the previous gather's volumes (L1 SH per colour)
layout(binding = 5) uniform sampler3D uPrevG;
layout(binding = 6) uniform sampler3D uPrevB;
// Per voxel four texels along x: the sums of its fragments' albedo (r, g, b, fixed point) and
// their count (gi_voxelize.frag, ALBEDO).
layout(binding = 7) uniform usampler3D uAlbedoSums;
const float kAlbedoScale = 1024.0; // gi_voxelize.frag's
layout(binding = 8) uniform sampler3D uGatheredR; // the VPLs' gather (one bounce), per colour
layout(binding = 9) uniform sampler3D uGatheredG;
layout(binding = 10) uniform sampler3D uGatheredB;
#endif
#ifndef EXACT_VISIBILITY
layout(binding = 1) uniform sampler2DArray uDepthMaps; // PROBE_DEPTH's, filtered bilinearly
#ifdef TRANSMITTANCE
layout(binding = 2) uniform sampler2DArray uTransmitMaps; // PROBE_DEPTH's, filtered bilinearly
#endif
layout(std430, binding = PNB_BINDING_GI_PROBE_NEEDED) readonly buffer ProbeNeeded { uint uNeeded[]; };
#endif
#endif

layout(location = 0) uniform vec4 uGrid;   // camera-relative minimum corner, probe spacing
layout(location = 1) uniform ivec3 uCounts; // probes per side, VPLs, voxels per side

const float kShY0 = 0.282094792, kShY1 = 0.488602512;
const float kInvPi = 0.318309886;
const int kDepthSide = 16, kTile = kDepthSide + 2; // a depth map and its border
const float kClear = 65504.0; // fp16's largest: the ray leaves the grid (nothing beyond blocks)
// A probe sees past the solid voxels within a cell of it (at least a voxel and a half): its depth
// rays pass them, and so does the exact walk at its end. Lighting's look-up blends the 8 probes
// around a point half a cell in front of a surface, so the probes just behind the surface (in
// the wall, under the floor) weigh in too; seeing past it, each holds the light travelling
// towards both of the surface's sides, and each side's look-up reads the half facing it.
// Blocked at the surface they were black and darkened it by how the grid happened to fall
// (atrium at 24^3 probes: 0.70 x the constant's error, energy 0.61; seeing past a cell: 0.49;
// docs/PLAYER.md). A VPL behind a wall within a cell of the probe is seen through it.
const float kPassThroughVoxels = 1.5;
// Lighting reads a surface point's probes through a point half a cell in front of it, blending
// the 8 probes within a cell of that: only probes within 1.5 cells (per axis) of a surface are
// ever read. The others (open air, the inside of a building) are neither traced nor gathered.
const float kReach = 1.5;

#ifdef SKY_VISIBILITY
shared vec4 sSum[kSkyColours][64];
#elif !defined(PROBE_DEPTH)
shared vec4 sSums[3][8][8]; // colour, probe, lane
#endif

// The transmittance maps' distance unit: the grid's diagonal in voxels (no pane: 1).
float paneScale(int side) { return 1.7321 * float(side); }

vec4 basis(vec3 w) { return vec4(kShY0, -kShY1 * w.y, kShY1 * w.z, -kShY1 * w.x); }

bool solid(ivec3 v) { return texelFetch(uVoxels, v, 0).r != 0u; }

// Multiplies `through` by voxel v's pane when a run of pane voxels begins there (TRANSMITTANCE;
// `inPane` carries whether the previous voxel was one). Returns whether it began one.
bool crossPane(ivec3 v, inout vec3 through, inout bool inPane) {
#ifdef TRANSMITTANCE
    vec4 g = texelFetch(uTransmitVoxels, v, 0);
    bool began = g.a > 0.5 && !inPane;
    if (began) through *= g.rgb;
    inPane = g.a > 0.5;
    return began;
#else
    return false;
#endif
}

// Whether the segment from a to b (in voxel units) crosses a solid voxel other than the ones a and
// b are in and those it enters within `passAtB` voxels of b (Amanatides & Woo's traversal);
// `through` is multiplied by the panes it crosses where a solid voxel would count (crossPane).
bool blocked(vec3 a, vec3 b, int side, float passAtB, inout vec3 through) {
    bool inPane = false;
    vec3 d = b - a;
    ivec3 v = ivec3(floor(a)), end = ivec3(floor(b));
    ivec3 stepDir = ivec3(sign(d));
    vec3 inv = 1.0 / max(abs(d), vec3(1e-12));
    vec3 next = (vec3(v) + max(vec3(stepDir), vec3(0.0)) - a) * sign(d) * inv; // t of the next boundary
    next = mix(next, vec3(2.0), equal(stepDir, ivec3(0)));
    vec3 delta = inv;
    float tPass = 1.0 - passAtB / max(length(d), 1e-12);
    for (int i = 0; i < 3 * 256; ++i) {
        // Into the next voxel at the nearest boundary; past b's position it is clear.
        float t = min(min(next.x, next.y), next.z);
        if (t >= 1.0 || t >= tPass) return false;
        if (next.x <= next.y && next.x <= next.z) {
            v.x += stepDir.x;
            next.x += delta.x;
        } else if (next.y <= next.z) {
            v.y += stepDir.y;
            next.y += delta.y;
        } else {
            v.z += stepDir.z;
            next.z += delta.z;
        }
        if (v == end) return false;
        if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, ivec3(side)))) return false;
        if (solid(v)) return true;
        crossPane(v, through, inPane);
    }
    return false;
}

// How far the ray from a (voxel units) along unit w runs before it enters a solid voxel that
// begins at least `pass` voxels along it; kClear if it leaves the grid first. With `panes`,
// `through` is multiplied by the panes it crosses past `pass` before that, `paneAt` is where the
// first begins (a constant at each call: without, the walk fetches no transmittance).
float firstHit(vec3 a, vec3 w, int side, float pass, const bool panes, inout vec3 through, inout float paneAt) {
    bool inPane = false;
    ivec3 v = ivec3(floor(a));
    ivec3 stepDir = ivec3(sign(w));
    vec3 inv = 1.0 / max(abs(w), vec3(1e-12));
    vec3 next = (vec3(v) + max(vec3(stepDir), vec3(0.0)) - a) * sign(w) * inv;
    next = mix(next, vec3(1e30), equal(stepDir, ivec3(0)));
    for (int i = 0; i < 3 * 256; ++i) {
        float t = min(min(next.x, next.y), next.z);
        if (next.x <= next.y && next.x <= next.z) {
            v.x += stepDir.x;
            next.x += inv.x;
        } else if (next.y <= next.z) {
            v.y += stepDir.y;
            next.y += inv.y;
        } else {
            v.z += stepDir.z;
            next.z += inv.z;
        }
        if (any(lessThan(v, ivec3(0))) || any(greaterThanEqual(v, ivec3(side)))) return kClear;
        if (t >= pass && solid(v)) return t;
        if (panes && t >= pass && crossPane(v, through, inPane)) paneAt = min(paneAt, t);
    }
    return kClear;
}

// Octahedral map of the sphere onto [-1, 1]^2 and back (the depth maps' layout), +y at the
// centre: horizontal directions (grazing floors and ceilings) lie on the inner diamond, away
// from the square's folded edges.
vec2 octEncode(vec3 w) {
    w /= abs(w.x) + abs(w.y) + abs(w.z);
    vec2 e = w.xz;
    if (w.y < 0.0) e = (1.0 - abs(w.zx)) * vec2(w.x >= 0.0 ? 1.0 : -1.0, w.z >= 0.0 ? 1.0 : -1.0);
    return e;
}
// The point on the octahedron |x| + |y| + |z| = 1 (unnormalised: its length gives the texel's
// solid angle, dA / r^3).
vec3 octPoint(vec2 e) {
    vec3 w = vec3(e.x, 1.0 - abs(e.x) - abs(e.y), e.y);
    if (w.y < 0.0) w.xz = (1.0 - abs(w.zx)) * vec2(w.x >= 0.0 ? 1.0 : -1.0, w.z >= 0.0 ? 1.0 : -1.0);
    return w;
}
vec3 octDecode(vec2 e) { return normalize(octPoint(e)); }

#ifdef SKY_VISIBILITY
// Where the ray from a (voxel units, inside the grid) along unit w leaves the grid, a hair inside.
vec3 gridExit(vec3 a, vec3 w, int side) {
    vec3 inv = 1.0 / max(abs(w), vec3(1e-12));
    vec3 t = mix(a, float(side) - a, greaterThan(w, vec3(0.0))) * inv;
    float tExit = min(min(t.x, t.y), t.z);
    return clamp(a + w * tExit, vec3(1e-3), vec3(float(side) - 1e-3));
}

void main() {
    ivec3 id = ivec3(gl_WorkGroupID);
    int n = uCounts.x, side = uCounts.z;
    float voxel = uGrid.w * float(n) / float(side);
    vec3 xv = (vec3(id) + 0.5) * uGrid.w / voxel; // the probe, in voxels from the grid's corner
    vec4 acc[kSkyColours];
    for (int c = 0; c < kSkyColours; ++c) acc[c] = vec4(0.0);
    for (int i = int(gl_LocalInvocationID.x); i < kSkyRays; i += 64) {
        float z = 1.0 - (2.0 * float(i) + 1.0) / float(kSkyRays);
        float r = sqrt(max(0.0, 1.0 - z * z)), phi = 2.39996323 * float(i); // golden angle
        vec3 w = vec3(r * cos(phi), z, r * sin(phi));
        vec3 through = vec3(1.0);
        if (blocked(xv, gridExit(xv, w, side), side, 0.0, through)) continue;
#ifdef TRANSMITTANCE
        for (int c = 0; c < kSkyColours; ++c) acc[c] += basis(w) * through[c];
#else
        acc[0] += basis(w);
#endif
    }
    uint lane = gl_LocalInvocationID.x;
    for (int c = 0; c < kSkyColours; ++c) sSum[c][lane] = acc[c];
    barrier();
    for (uint s = 32u; s > 0u; s >>= 1) {
        if (lane < s)
            for (int c = 0; c < kSkyColours; ++c) sSum[c][lane] += sSum[c][lane + s];
        barrier();
    }
    if (lane == 0u) {
        bool inside = solid(ivec3(floor(xv)));
        for (int c = 0; c < kSkyColours; ++c)
            imageStore(uSky, id + ivec3(0, 0, c * n),
                       inside ? vec4(-1.0, 0.0, 0.0, 0.0) : sSum[c][0] * (4.0 * 3.14159265 / float(kSkyRays)));
    }
}
#elif defined(PROBE_DEPTH)
void main() {
    ivec3 id = ivec3(gl_WorkGroupID);
    int n = uCounts.x, side = uCounts.z;
    float voxel = uGrid.w * float(n) / float(side);
    vec3 xv = (vec3(id) + 0.5) * uGrid.w / voxel;
    // Needed: some solid voxel overlaps the box of kReach cells around the probe. Only needed
    // probes trace their map (the gather reads no other): a grid following the camera through a
    // street traces a fraction of its probes each time it moves.
    if (gl_LocalInvocationID.x == 0u) sNeeded = 0u;
    barrier();
    float reach = kReach * float(side) / float(n);
    ivec3 lo = max(ivec3(floor(xv - reach)), ivec3(0)), hi = min(ivec3(floor(xv + reach)), ivec3(side - 1));
    ivec3 span = hi - lo + 1;
    bool near = false;
    for (int i = int(gl_LocalInvocationID.x); i < span.x * span.y * span.z && !near; i += 64)
        near = solid(lo + ivec3(i % span.x, (i / span.x) % span.y, i / (span.x * span.y)));
    if (near) atomicOr(sNeeded, 1u);
    barrier();
    if (gl_LocalInvocationID.x == 0u) uNeeded[id.x + n * (id.y + n * id.z)] = sNeeded;
    if (sNeeded == 0u) return;
    for (int b = int(gl_LocalInvocationID.x); b < kTile * kTile; b += 64) {
        // The texel this tile position shows: inside, its own; on the border, the one across
        // the map's fold (an edge mirrors along itself; a corner is the opposite corner).
        ivec2 t = ivec2(b % kTile, b / kTile) - 1;
        if (t.x < 0 || t.x >= kDepthSide) t = ivec2(clamp(t.x, 0, kDepthSide - 1), kDepthSide - 1 - t.y);
        if (t.y < 0 || t.y >= kDepthSide) t = ivec2(kDepthSide - 1 - t.x, clamp(t.y, 0, kDepthSide - 1));
        vec2 e = (vec2(t) + 0.5) / float(kDepthSide) * 2.0 - 1.0;
        vec3 through = vec3(1.0);
        float paneAt = paneScale(side);
        float d = firstHit(xv, octDecode(e), side, max(kPassThroughVoxels, float(side) / float(n)), true, through, paneAt);
        ivec3 at = ivec3(id.xy * kTile + ivec2(b % kTile, b / kTile), id.z);
        imageStore(uDepthMaps, at, vec4(d));
#ifdef TRANSMITTANCE
        imageStore(uTransmitMaps, at, vec4(through, paneAt / paneScale(side)));
#endif
    }
}
#else
#ifndef EXACT_VISIBILITY
// The probe's depth map bilinearly interpolated at direction w: one filtered fetch in its tile
// (the border makes the filter right across the map's folded edges).
float depthTowards(ivec3 id, vec3 w) {
    vec2 texel = vec2(id.xy * kTile) + 1.0 + (octEncode(w) * 0.5 + 0.5) * float(kDepthSide);
    return textureLod(uDepthMaps, vec3(texel / vec2(textureSize(uDepthMaps, 0).xy), float(id.z)), 0.0).r;
}

#ifdef TRANSMITTANCE
// What the probe's ray towards w passes of the panes before a point rv voxels away: their product
// once the point lies past the first pane (fading over a voxel, as the depth's visibility).
vec3 transmitTowards(ivec3 id, vec3 w, float rv) {
    vec2 texel = vec2(id.xy * kTile) + 1.0 + (octEncode(w) * 0.5 + 0.5) * float(kDepthSide);
    vec4 t = textureLod(uTransmitMaps, vec3(texel / vec2(textureSize(uTransmitMaps, 0).xy), float(id.z)), 0.0);
    return mix(vec3(1.0), t.rgb, clamp(rv - t.a * paneScale(uCounts.z) + 1.0, 0.0, 1.0));
}
#endif
#endif

#ifdef BOUNCE
// The mean albedo of the surfaces in voxel v (none: black).
vec3 albedoAt(ivec3 v) {
    ivec3 at = ivec3(4 * v.x, v.y, v.z);
    uint count = texelFetch(uAlbedoSums, at + ivec3(3, 0, 0), 0).r;
    if (count == 0u) return vec3(0.0);
    uvec3 sum = uvec3(texelFetch(uAlbedoSums, at, 0).r, texelFetch(uAlbedoSums, at + ivec3(1, 0, 0), 0).r,
                      texelFetch(uAlbedoSums, at + ivec3(2, 0, 0), 0).r);
    return vec3(sum) / (kAlbedoScale * float(count));
}

const int kBounceSide = 8; // rays a probe walks per bounce: an octahedral map's texel centres
// This lane's share of the light probe `id` (at xv, voxel units) gets from one more bounce: the
// L1 SH per colour of the radiance the surfaces its rays hit reflect back (see the top).
void gatherBounce(ivec3 id, vec3 xv, int lane, inout vec4 acc[3]) {
    int n = uCounts.x, side = uCounts.z;
    float toCells = float(n) / float(side);
    for (int i = lane; i < kBounceSide * kBounceSide; i += kLanes) {
        ivec2 t = ivec2(i % kBounceSide, i / kBounceSide);
        vec3 wu = octPoint((vec2(t) + 0.5) / float(kBounceSide) * 2.0 - 1.0);
        float r = length(wu);
        vec3 w = wu / r;
        vec3 through = vec3(1.0);
        float paneAt = 0.0;
#if defined(TRANSMITTANCE) && !defined(EXACT_VISIBILITY)
        // The panes before the hit from the probe's transmittance map (one filtered fetch, as the
        // gather's VPLs) instead of a transmittance fetch at every step of the walk: that made
        // the box room's bounce passes 1.5 x slower.
        float d = firstHit(xv, w, side, kPassThroughVoxels, false, through, paneAt);
        if (d >= 0.5 * kClear) continue; // out of the grid
        through = transmitTowards(id, w, d);
#else
        float d = firstHit(xv, w, side, kPassThroughVoxels, true, through, paneAt);
        if (d >= 0.5 * kClear) continue; // out of the grid
#endif
        vec3 albedo = albedoAt(clamp(ivec3(floor(xv + w * (d + 0.01))), ivec3(0), ivec3(side - 1)));
        if (albedo == vec3(0.0)) continue;
        // The hit's normal: the solid voxel's face the ray entered by (the hit lies on it: the
        // coordinate nearest a whole voxel), facing the probe. Lighting's look-up there: half a
        // cell in front, the clamped-cosine lobe along -normal.
        vec3 hit = xv + w * d;
        vec3 off = abs(hit - round(hit));
        int axis = off.x < off.y ? (off.x < off.z ? 0 : 2) : (off.y < off.z ? 1 : 2);
        vec3 normal = vec3(0.0);
        normal[axis] = w[axis] > 0.0 ? -1.0 : 1.0;
        vec3 q = clamp(hit * toCells + 0.5 * normal, vec3(0.5), vec3(float(n) - 0.5)) / float(n);
        vec4 lobe = vec4(0.886226925, 1.023326708 * normal.y, -1.023326708 * normal.z, 1.023326708 * normal.x);
        vec3 e = max(vec3(dot(textureLod(uPrevR, q, 0.0), lobe), dot(textureLod(uPrevG, q, 0.0), lobe),
                          dot(textureLod(uPrevB, q, 0.0), lobe)), vec3(0.0));
        // Radiance albedo E / pi travelling back along -w, over the texel's solid angle.
        vec4 y = basis(-w) * ((4.0 / float(kBounceSide * kBounceSide)) / (r * r * r) * kInvPi);
        // Dimmed and tinted by the panes between the probe and the hit (TRANSMITTANCE: firstHit
        // multiplied `through` by them; without panes it stays 1).
        vec3 reflected = albedo * e * through;
        for (int ch = 0; ch < 3; ++ch) acc[ch] += reflected[ch] * y;
    }
}
#endif

void main() {
    int lane = int(gl_LocalInvocationID.x), slot = int(gl_LocalInvocationID.y);
    ivec3 id = ivec3(gl_WorkGroupID.x * 8u + gl_LocalInvocationID.y, gl_WorkGroupID.yz);
    int n = uCounts.x;
    bool inGrid = id.x < n; // the last group's row may run past the grid (no return: barriers)
    vec3 x = uGrid.xyz + (vec3(id) + 0.5) * uGrid.w;
    float voxel = uGrid.w * float(n) / float(uCounts.z);
    vec3 xv = (x - uGrid.xyz) / voxel;
    vec4 acc[3] = vec4[](vec4(0.0), vec4(0.0), vec4(0.0));
#ifdef EXACT_VISIBILITY
    int vpls = inGrid ? uCounts.y : 0;
#else
    int vpls = inGrid && uNeeded[id.x + n * (id.y + n * id.z)] != 0u ? uCounts.y : 0; // none if no look-up reads it
#endif
#ifdef BOUNCE
    const int gathered = vpls; // the VPLs' light is read from the gather's volumes instead
    vpls = 0;
#endif
    for (int i = lane; i < vpls; i += kLanes) {
        Vpl l = uVpls[i];
        if (l.flux.x + l.flux.y + l.flux.z <= 0.0) continue;
        vec3 d = x - l.position.xyz;
        float r2 = dot(d, d);
        vec3 w = d * inversesqrt(max(r2, 1e-30));
        float cosine = dot(l.normal.xyz, w);
        if (cosine <= 0.0) continue;
        // From a voxel and a half in front of the surface: out of the layer of voxels its surface
        // marked wherever in its voxel it lies, or a ray grazing along the surface (a floor's light
        // towards the foot of a wall) would run through its own surface's voxels.
        vec3 yv = (l.position.xyz + l.normal.xyz * (1.5 * voxel) - uGrid.xyz) / voxel;
        vec3 through = vec3(1.0);
#ifdef EXACT_VISIBILITY
        if (blocked(yv, xv, uCounts.z, max(kPassThroughVoxels, float(uCounts.z) / float(n)), through)) continue;
        const float visible = 1.0;
#else
        // Seen if the probe's depth towards the point a voxel and a half in front of the VPL
        // reaches it: fading over the last voxel, so that a VPL crossing a silhouette as the sun
        // turns fades instead of popping.
        vec3 toVpl = yv - xv;
        float rv = length(toVpl);
        float visible = clamp(depthTowards(id, toVpl / max(rv, 1e-6)) - rv + 1.0, 0.0, 1.0);
        if (visible <= 0.0) continue;
#ifdef TRANSMITTANCE
        through = transmitTowards(id, toVpl / max(rv, 1e-6), rv);
#endif
#endif
        float e = visible * cosine * kInvPi / (r2 + l.position.w * (0.5 * kInvPi));
        vec4 y = basis(w);
#ifdef TRANSMITTANCE
        vec3 flux = l.flux.rgb * through;
#else
        vec3 flux = l.flux.rgb;
#endif
        for (int ch = 0; ch < 3; ++ch) acc[ch] += (flux[ch] * e) * y;
    }
#ifdef BOUNCE
    if (gathered > 0) gatherBounce(id, xv, lane, acc); // the probes the gather gathered
#endif
    for (int ch = 0; ch < 3; ++ch) sSums[ch][slot][lane] = acc[ch];
    barrier();
    for (int s = kLanes / 2; s > 0; s >>= 1) {
        if (lane < s)
            for (int ch = 0; ch < 3; ++ch) sSums[ch][slot][lane] += sSums[ch][slot][lane + s];
        barrier();
    }
    if (lane == 0 && inGrid) {
#ifdef BOUNCE
        sSums[0][slot][0] += texelFetch(uGatheredR, id, 0);
        sSums[1][slot][0] += texelFetch(uGatheredG, id, 0);
        sSums[2][slot][0] += texelFetch(uGatheredB, id, 0);
#endif
        imageStore(uSumR, id, sSums[0][slot][0]);
        imageStore(uSumG, id, sSums[1][slot][0]);
        imageStore(uSumB, id, sSums[2][slot][0]);
    }
}
#endif
