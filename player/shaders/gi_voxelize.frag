#version 450 core
// gi_voxelize.frag — the scene into the probes' occupancy grid (gi.technique = probes): drawn
// three times, once along each axis, with an orthographic view whose clip x, y and depth are the
// grid's other two axes and this one, so every surface is rasterised along the axis it faces most
// (a wall edge-on to one view is face-on to another). A fragment marks its voxel; writes are
// idempotent (no atomics, any order gives the same grid).
//
// ALBEDO (gi.bounces > 1): also the surface's diffuse albedo into an RGBA8 volume beside the grid
// (a = 1 where a surface is), for the probes' further bounces (gi_probe_gather.comp, BOUNCE):
// the material's base-colour factor x (1 - metallic), without its texture or vertex colours (a
// texture's mean is not at hand here: a textured surface bounces its factor's light). Two
// surfaces in one voxel keep either's.
layout(r8ui, binding = 0) writeonly uniform uimage3D uVoxels;
layout(location = 0) uniform int uAxis;      // 0: viewed along x, 1: along y, 2: along z
layout(location = 1) uniform int uResolution; // voxels along each side
#ifdef ALBEDO
#include "shared/material_block.h"
layout(rgba8, binding = 2) writeonly uniform image3D uAlbedo;
#endif

void main() {
    vec3 f = vec3(gl_FragCoord.xy / float(uResolution), gl_FragCoord.z); // [0, 1]^3 in view order
    vec3 u = uAxis == 0 ? vec3(f.z, f.y, f.x) : uAxis == 1 ? vec3(f.x, f.z, f.y) : f;
    ivec3 v = clamp(ivec3(floor(u * float(uResolution))), ivec3(0), ivec3(uResolution - 1));
    imageStore(uVoxels, v, uvec4(1u));
#ifdef ALBEDO
    float metallic = clamp(uMaterialParams.x, 0.0, 1.0);
    imageStore(uAlbedo, v, vec4(clamp(uBaseColorFactor.rgb * (1.0 - metallic), 0.0, 1.0), 1.0));
#endif
}
