#version 450 core
// deferred_lighting.frag — composes one G-buffer layer into the HDR target. Runs with depth
// writes off and SRC_ALPHA / ONE_MINUS_SRC_ALPHA blending, so translucent layers blend over the
// layers before them (seed 003's layered deferred shading).
#include "include/interface.glsl"
#include "include/octahedral.glsl"
#include "include/lights.glsl"
#ifdef GI
#include "include/gi_lookup.glsl"
#endif

layout(binding = 0) uniform sampler2D uGBaseColor;
layout(binding = 1) uniform sampler2D uGNormalMaterial;
layout(binding = 2) uniform sampler2D uGEmissive;
layout(binding = 3) uniform sampler2D uGDepth;

// Inverse of the camera-relative view-projection: NDC (reversed-Z) -> camera-relative world.
layout(location = 0) uniform mat4 uInverseViewProjection;

#ifdef IBL
#include "include/ibl.glsl"
#include "include/sky_visibility.glsl"
#endif

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

void main() {
    vec4 base = texture(uGBaseColor, vUv);
    if (base.a <= 0.0) discard; // nothing was drawn into this layer here
    vec4 nm = texture(uGNormalMaterial, vUv);
    float depth = texture(uGDepth, vUv).r;
    vec4 p = uInverseViewProjection * vec4(vUv * 2.0 - 1.0, depth, 1.0);
    vec3 position = p.xyz / p.w;
    vec3 n = octDecode(nm.xy * 2.0 - 1.0);
    float packedBits = floor(nm.w * 65535.0 + 0.5);
    float metallic = floor(packedBits / 256.0) / 255.0;
    float occlusion = mod(packedBits, 256.0) / 255.0;
    float roughnessBits = floor(nm.z * 65535.0 + 0.5);
    float roughness = floor(roughnessBits / 4.0) / 16383.0;
    bool unlit = mod(roughnessBits, 4.0) > 1.5;
    bool receivesShadows = mod(roughnessBits, 2.0) > 0.5;
    vec3 v = viewVector(position);
    // The captures describe the surface whose depth the frame kept (the truth is traced there):
    // a translucent layer writes no depth, so it leaves the value below it (alpha 0).
    float captureAlpha = base.a < 1.0 ? 0.0 : 1.0;
#ifdef GI
    if (giCaptureIrradiance()) { // CaptureBuffer::Indirect: the irradiance GI adds, per pixel
        outColor = vec4(giIrradiance(position, n), captureAlpha);
        return;
    }
#endif
#ifdef IBL
    vec3 sky = iblActive() ? skyVisibility(position, n) : vec3(1.0);
    if (iblCaptureSky()) { // CaptureBuffer::Sky: the sky irradiance this pixel receives
        outColor = vec4(iblIrradiance(n) * sky, captureAlpha);
        return;
    }
#endif
    if (unlit) { // KHR_materials_unlit: the colour as authored, no light at all
        outColor = vec4(base.rgb + texture(uGEmissive, vUv).rgb, base.a);
        return;
    }
    // Occlusion darkens indirect light only (glTF's definition): the ambient term (or the
    // environment's light, which replaces it) and GI.
    vec3 indirect = uAmbient.rgb * base.rgb;
#ifdef IBL
    if (iblActive()) indirect = iblShade(base.rgb, metallic, roughness, n, v) * sky;
#endif
#ifdef GI
    indirect += giIrradiance(position, n) * base.rgb * ((1.0 - metallic) / 3.14159265);
#endif
    vec3 color = shadeLights(base.rgb, metallic, roughness, n, position, v, receivesShadows) +
                 indirect * occlusion;
    outColor = vec4(color + texture(uGEmissive, vUv).rgb, base.a);
#ifdef SHADOWS
    outColor = shadowOutput(outColor);
#endif
}
