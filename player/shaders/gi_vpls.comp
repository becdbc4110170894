#version 450 core
// gi_vpls.comp — the reflective shadow map's texels clustered into virtual point lights for the
// probes' gather (gi.technique = probes): one invocation per block of uBlock x uBlock texels.
// Each lit texel reflects flux rho A_t (over the sun's irradiance E; rho = base colour x
// (1 - metallic), A_t the texel's perpendicular area, as LPV injection). A block's VPL carries
// their summed flux per colour at their luminance-weighted mean position and normal, so the gather
// costs VPLs x probes, not texels x probes; its disc-like area (texels / cos) is kept for the
// near-field clamp. Empty blocks write zero flux.
#include "shared/bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2D uBaseColor;      // sRGB: decoded on fetch
layout(binding = 1) uniform sampler2D uNormalMaterial; // octahedral normal, roughness, metallic|occlusion
layout(binding = 2) uniform sampler2D uDepth;

struct Vpl {
    vec4 position; // camera-relative world, w: the lit area it stands for (world units^2)
    vec4 normal;   // xyz unit normal
    vec4 flux;     // rgb: flux over the sun's irradiance (world units^2)
};
layout(std430, binding = PNB_BINDING_GI_VPLS) writeonly buffer Vpls { Vpl uVpls[]; };

layout(location = 0) uniform mat4 uInverseMatrix; // map clip -> camera-relative world
layout(location = 1) uniform vec3 uToward;        // toward the sun
layout(location = 2) uniform ivec3 uSize;         // map side in texels, block side, VPLs per side
layout(location = 3) uniform float uTexelArea;    // perpendicular world area of one texel

vec3 octDecode(vec2 e) {
    vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (v.z < 0.0) v.xy = (1.0 - abs(v.yx)) * vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
    return normalize(v);
}

void main() {
    ivec2 block = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(block, ivec2(uSize.z)))) return;
    vec3 flux = vec3(0.0), position = vec3(0.0), normal = vec3(0.0);
    float weight = 0.0, area = 0.0;
    for (int j = 0; j < uSize.y; ++j)
        for (int i = 0; i < uSize.y; ++i) {
            ivec2 texel = block * uSize.y + ivec2(i, j);
            if (any(greaterThanEqual(texel, ivec2(uSize.x)))) continue;
            vec4 base = texelFetch(uBaseColor, texel, 0);
            if (base.a <= 0.0) continue; // nothing drawn here
            vec4 nm = texelFetch(uNormalMaterial, texel, 0);
            vec3 n = octDecode(nm.xy * 2.0 - 1.0);
            float cosine = dot(n, uToward);
            if (cosine <= 0.0) continue; // faces away from the sun: lit by nothing
            vec2 ndc = (vec2(texel) + 0.5) / float(uSize.x) * 2.0 - 1.0;
            vec4 h = uInverseMatrix * vec4(ndc, texelFetch(uDepth, texel, 0).r, 1.0);
            vec3 p = h.xyz / h.w;
            if (any(isnan(p)) || any(isinf(p))) continue;
            float packedBits = floor(nm.w * 65535.0 + 0.5);
            float metallic = floor(packedBits / 256.0) / 255.0;
            vec3 f = base.rgb * (1.0 - metallic) * uTexelArea;
            float w = dot(f, vec3(0.2126, 0.7152, 0.0722)) + 1e-30;
            flux += f;
            position += w * p;
            normal += w * n;
            weight += w;
            area += uTexelArea / max(cosine, 0.05);
        }
    int at = block.y * uSize.z + block.x;
    if (weight <= 1e-30 || dot(normal, normal) <= 0.0) {
        uVpls[at] = Vpl(vec4(0.0), vec4(0.0), vec4(0.0));
        return;
    }
    uVpls[at] = Vpl(vec4(position / weight, area), vec4(normalize(normal), 0.0), vec4(flux, 0.0));
}
