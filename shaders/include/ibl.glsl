// ibl.glsl — light from the environment (IBL permutation: a container with an ENVM chunk,
// docs/FORMAT.md "ENVM"). Diffuse: the irradiance SH the converter baked (9 coefficients per
// colour, rotated and scaled on the CPU each frame: no per-pixel cost beyond the polynomial).
// Specular: the split-sum approximation (Karis 2013) — the GGX-prefiltered cube at the
// roughness' level times (F0 A + B) from the BRDF table. The diffuse part is weighted by
// 1 - (F0 A + B), the light the specular lobe took (single scattering, Fdez-Agüera 2019): a white
// dielectric in a white environment then reflects exactly the environment (the white furnace).
// IBL can be switched off at run time (ibl.enabled): uIblParams.x is then 0 and nothing here
// (block or textures) is read.
#ifndef PNB_IBL_GLSL
#define PNB_IBL_GLSL

#include "brdf.glsl"

#include "../shared/ibl_block.h"
layout(binding = 13) uniform samplerCube uIblSpecular;
layout(binding = 14) uniform sampler2D uIblBrdf;

bool iblActive() { return uIblParams.x > 0.5; }
bool iblCaptureSky() { return uIblParams.y > 0.5; }

// E(n), lux: the basis of FORMAT.md "ENVM" (never negative by the converter's window; the max
// only guards half-precision rounding).
vec3 iblIrradiance(vec3 n) {
    vec3 e = uIblSh[0].rgb * 0.282094792 +
             (uIblSh[1].rgb * n.z + uIblSh[2].rgb * n.y + uIblSh[3].rgb * n.x) * 0.488602512 +
             (uIblSh[4].rgb * (n.x * n.z) + uIblSh[5].rgb * (n.y * n.z) + uIblSh[7].rgb * (n.x * n.y)) * 1.092548431 +
             uIblSh[6].rgb * (0.315391565 * (3.0 * n.y * n.y - 1.0)) +
             uIblSh[8].rgb * (0.546274215 * (n.x * n.x - n.z * n.z));
    return max(e, vec3(0.0));
}

// A world direction -> where it looks in the stored environment: the environment is turned by
// +angle about +Y, so a world direction w sees it at R_y(-angle) w (sh9RotateY's convention).
vec3 iblToEnvironment(vec3 w) {
    float c = uIblRotation.x, s = uIblRotation.y;
    return vec3(c * w.x - s * w.z, w.y, s * w.x + c * w.z);
}

// The specular lobe's albedo F0 A + B at this view and roughness (0 with ibl.specular off).
vec3 iblSpecularAlbedo(vec3 f0, float nDotV, float roughness) {
    if (uIblRotation.w < 0.5) return vec3(0.0);
    vec2 ab = textureLod(uIblBrdf, vec2(nDotV, roughness), 0.0).rg;
    return f0 * ab.x + ab.y;
}

// Radiance reflected towards v from the environment, before occlusion. `n` unit, `v` from the
// surface to the eye.
vec3 iblShade(vec3 baseColor, float metallic, float roughness, vec3 n, vec3 v) {
    float nDotV = clamp(dot(n, v), 1e-4, 1.0);
    vec3 f0 = mix(vec3(0.04), baseColor, metallic);
    vec3 specularAlbedo = iblSpecularAlbedo(f0, nDotV, roughness);
    vec3 diffuse = (1.0 - specularAlbedo) * (1.0 - metallic) * baseColor * iblIrradiance(n) / PNB_PI;
    if (uIblRotation.w < 0.5) return diffuse;
    vec3 r = iblToEnvironment(reflect(-v, n));
    vec3 prefiltered = textureLod(uIblSpecular, r, roughness * uIblRotation.z).rgb * uIblParams.w;
    return diffuse + prefiltered * specularAlbedo;
}

#endif
