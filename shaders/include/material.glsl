// material.glsl — evaluates a glTF metallic-roughness material at a fragment. The HAS_* defines
// are the permutation: the converter emits only the combinations the scene's materials use.
#ifndef PNB_MATERIAL_GLSL
#define PNB_MATERIAL_GLSL

#include "interface.glsl"
#include "octahedral.glsl"

#ifdef HAS_BASE_COLOR_MAP
layout(binding = PNB_TEX_BASE_COLOR) uniform sampler2D uBaseColorMap;
#endif
#ifdef HAS_METALLIC_ROUGHNESS_MAP
layout(binding = PNB_TEX_METALLIC_ROUGHNESS) uniform sampler2D uMetallicRoughnessMap;
#endif
#ifdef HAS_NORMAL_MAP
layout(binding = PNB_TEX_NORMAL) uniform sampler2D uNormalMap;
#endif
#ifdef HAS_OCCLUSION_MAP
layout(binding = PNB_TEX_OCCLUSION) uniform sampler2D uOcclusionMap;
#endif
#ifdef HAS_EMISSIVE_MAP
layout(binding = PNB_TEX_EMISSIVE) uniform sampler2D uEmissiveMap;
#endif

struct SurfaceInput {
    vec3 normal;    // interpolated, camera-relative world space
    vec4 tangent;   // xyz + handedness (HAS_TANGENT)
    vec2 uv0, uv1;
    vec4 color;     // vertex colour (1 if none)
    bool frontFacing;
};

struct Surface {
    vec3 baseColor;
    float alpha;
    vec3 normal;    // unit, world space, facing the viewer for double-sided materials
    float metallic;
    float roughness;
    float occlusion;
    vec3 emissive;
};

// KHR_texture_transform: uv' = T * R * S * uv with the extension's rotation matrix
// R = (cos r, sin r; -sin r, cos r) written row by row, i.e. u' = c u + s v, v' = -s u + c v: a
// positive rotation turns the image counter-clockwise in UV space (v runs down the image).
// GLSL's mat2 takes columns, hence (c, -s), (s, c). The CPU copy is pnb::textureTransformUv.
vec2 slotUv(int slot, SurfaceInput s) {
    vec4 a = uTexTransform[slot * 2];
    vec4 b = uTexTransform[slot * 2 + 1];
    vec2 uv = b.y > 0.5 ? s.uv1 : s.uv0;
    float c = cos(b.x), sn = sin(b.x);
    uv = mat2(c, -sn, sn, c) * (uv * a.zw);
    return uv + a.xy;
}

Surface evaluateSurface(SurfaceInput s) {
    Surface o;
    vec4 base = uBaseColorFactor * s.color;
#ifdef HAS_BASE_COLOR_MAP
    base *= texture(uBaseColorMap, slotUv(PNB_TEX_BASE_COLOR, s));
#endif
    o.baseColor = base.rgb;
    o.alpha = base.a;
#ifdef ALPHA_MASK
    if (o.alpha < uAlphaParams.x) discard;
    o.alpha = 1.0;
#endif
    if (uAlphaParams.y < 0.5) o.alpha = 1.0; // OPAQUE ignores alpha (glTF)
    o.metallic = uMaterialParams.x;
    o.roughness = uMaterialParams.y;
#ifdef HAS_METALLIC_ROUGHNESS_MAP
    vec4 mr = texture(uMetallicRoughnessMap, slotUv(PNB_TEX_METALLIC_ROUGHNESS, s));
    o.roughness *= mr.g;
    o.metallic *= mr.b;
#endif
    o.roughness = clamp(o.roughness, 0.03, 1.0); // avoids a singular GGX lobe
    o.metallic = clamp(o.metallic, 0.0, 1.0);

    vec3 n = normalize(s.normal);
    if (!s.frontFacing) n = -n; // double-sided: light the back face as a front face
#ifdef HAS_NORMAL_MAP
    vec3 t = normalize(s.tangent.xyz - n * dot(n, s.tangent.xyz));
    vec3 b = cross(n, t) * (s.tangent.w < 0.0 ? -1.0 : 1.0);
    // A rotated normal texture (KHR_texture_transform) stores its normals along the rotated UV
    // axes: u' = c u + s v means dP/du' = c t - s b and "up the image" b' = s t + c b (b is up
    // the image, -dP/dv), so the frame turns with the texture (TextureTransformMultiTest).
    float rn = uTexTransform[PNB_TEX_NORMAL * 2 + 1].x;
    if (rn != 0.0) {
        float cr = cos(rn), sr = sin(rn);
        vec3 tr = cr * t - sr * b;
        b = sr * t + cr * b;
        t = tr;
    }
    vec3 tn = texture(uNormalMap, slotUv(PNB_TEX_NORMAL, s)).xyz * 2.0 - 1.0;
    tn.xy *= uMaterialParams.z;
    n = normalize(mat3(t, b, n) * tn);
#endif
    o.normal = n;

    o.occlusion = 1.0;
#ifdef HAS_OCCLUSION_MAP
    float ao = texture(uOcclusionMap, slotUv(PNB_TEX_OCCLUSION, s)).r;
    o.occlusion = 1.0 + uMaterialParams.w * (ao - 1.0);
#endif
    o.emissive = uEmissive.rgb;
#ifdef HAS_EMISSIVE_MAP
    o.emissive *= texture(uEmissiveMap, slotUv(PNB_TEX_EMISSIVE, s)).rgb;
#endif
    return o;
}

#endif
