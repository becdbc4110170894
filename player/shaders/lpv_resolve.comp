#version 450 core
// lpv_resolve.comp — the injection's accumulation buffers into the volumes' textures.
//   RESOLVE_LIGHT     per cell: 3 x 4 SH coefficients -> the propagation source (images 0-2) and
//                     the accumulated volume (images 3-5, iteration 0 of the sum);
//   RESOLVE_GEOMETRY  per corner: the geometry volume seen from the light (slot 0) and from the
//                     camera (slot 1) merged by keeping the vector with the larger band-0
//                     coefficient (each surface counted once, not once per view that saw it);
//   RESOLVE_TRANSMITTANCE  per cell: the fraction of light each of its six faces lets in, from
//                     the geometry volume interpolated at the face centre and evaluated against
//                     the travel direction. The geometry does not change between propagation
//                     steps, so this is done once per frame instead of once per step.
// Cascades are stacked along z: cascade c is slices [c * side, (c + 1) * side).
#ifdef FLOAT_ATOMICS
#define ACC float
#define VALUE(x) (x)
#else
#define ACC int
#define VALUE(x) (float(x) * uInverseScale)
#endif
#include "shared/bindings.h"
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

layout(std430, binding = PNB_BINDING_LPV_LIGHT) readonly buffer LightAccumulation { ACC uLight[]; };
layout(std430, binding = PNB_BINDING_LPV_GEOMETRY) readonly buffer GeometryAccumulation { ACC uGeometry[]; };

layout(location = 0) uniform ivec3 uVolume; // side (cells or corners), stacked depth, geometry slots
layout(location = 1) uniform float uInverseScale;

#ifdef RESOLVE_TRANSMITTANCE
layout(binding = 0) uniform sampler3D uGeometryVolume; // (cells + 1)^3 per cascade, linear filter
layout(rgba8, binding = 0) writeonly uniform image3D uTransmit0; // from the -x, +x, -y, +y neighbours
layout(rgba8, binding = 1) writeonly uniform image3D uTransmit1; // from the -z, +z neighbours
const ivec3 kDirections[6] = ivec3[](ivec3(1, 0, 0), ivec3(-1, 0, 0), ivec3(0, 1, 0),
                                     ivec3(0, -1, 0), ivec3(0, 0, 1), ivec3(0, 0, -1));
#elif defined(RESOLVE_LIGHT)
layout(rgba16f, binding = 0) writeonly uniform image3D uSourceR;
layout(rgba16f, binding = 1) writeonly uniform image3D uSourceG;
layout(rgba16f, binding = 2) writeonly uniform image3D uSourceB;
layout(rgba16f, binding = 3) writeonly uniform image3D uSumR;
layout(rgba16f, binding = 4) writeonly uniform image3D uSumG;
layout(rgba16f, binding = 5) writeonly uniform image3D uSumB;
#else
layout(rgba16f, binding = 0) writeonly uniform image3D uGeometryVolume;
#endif

void main() {
    ivec3 id = ivec3(gl_GlobalInvocationID);
    int side = uVolume.x;
    if (id.x >= side || id.y >= side || id.z >= uVolume.y) return;
    int at = (id.z * side + id.y) * side + id.x;
#ifdef RESOLVE_TRANSMITTANCE
    // side = cells, uVolume.z = cascades. Travel direction d: from the neighbour id - d.
    int cascade = id.z / side, corners = side + 1;
    vec3 local = vec3(id.xy, id.z - cascade * side);
    float t[6];
    for (int i = 0; i < 6; ++i) {
        vec3 d = vec3(kDirections[i]);
        // The face between the neighbour and this cell, in corner units of the geometry volume
        // (whose texel centres are this volume's corners): texel coordinate = position + 0.5.
        vec3 face = local + 0.5 - 0.5 * d;
        vec3 uvw = (face + 0.5 + vec3(0.0, 0.0, float(cascade * corners))) /
                   vec3(corners, corners, corners * uVolume.z);
        vec4 b = textureLod(uGeometryVolume, uvw, 0.0);
        // Surfaces facing against the travel direction block it: evaluate at -d.
        vec4 y = vec4(0.282094792, 0.488602512 * d.y, -0.488602512 * d.z, 0.488602512 * d.x);
        t[i] = 1.0 - clamp(dot(b, y), 0.0, 1.0);
    }
    imageStore(uTransmit0, id, vec4(t[0], t[1], t[2], t[3]));
    imageStore(uTransmit1, id, vec4(t[4], t[5], 0.0, 0.0));
#elif defined(RESOLVE_LIGHT)
    vec4 sh[3];
    for (int ch = 0; ch < 3; ++ch)
        for (int k = 0; k < 4; ++k) sh[ch][k] = VALUE(uLight[at * 12 + ch * 4 + k]);
    imageStore(uSourceR, id, sh[0]);
    imageStore(uSourceG, id, sh[1]);
    imageStore(uSourceB, id, sh[2]);
    imageStore(uSumR, id, sh[0]);
    imageStore(uSumG, id, sh[1]);
    imageStore(uSumB, id, sh[2]);
#else
    int slot = side * side * uVolume.y; // corners per slot
    vec4 best = vec4(0.0);
    for (int s = 0; s < uVolume.z; ++s) {
        vec4 v;
        for (int k = 0; k < 4; ++k) v[k] = VALUE(uGeometry[(s * slot + at) * 4 + k]);
        if (v.x > best.x) best = v;
    }
    imageStore(uGeometryVolume, id, best);
#endif
}
