#version 450 core
// gbuffer.frag — writes one deferred layer's G-buffer: 16 bytes of colour targets + 4 of depth
// (20 B/px; UberRender used 36). Position is not stored: the lighting pass reconstructs it from
// depth.
//   RT0 RGBA8 sRGB   base colour, alpha (the layer's blend weight; 0 = no surface)
//   RT1 RGBA16       octahedral normal xy, roughness (14 bit) + unlit (1 bit) + receives
//                    shadows (1 bit), metallic (8 bit) + occlusion (8 bit)
//   RT2 R11G11B10F   emissive radiance
#include "include/surface_input.glsl"

layout(location = 0) out vec4 outBaseColor;
layout(location = 1) out vec4 outNormalMaterial;
layout(location = 2) out vec3 outEmissive;

void main() {
    Surface s = evaluateSurface(surfaceInput());
    outBaseColor = vec4(s.baseColor, s.alpha);
    float metallic8 = floor(clamp(s.metallic, 0.0, 1.0) * 255.0 + 0.5);
    float occlusion8 = floor(clamp(s.occlusion, 0.0, 1.0) * 255.0 + 0.5);
    // receives_shadows and unlit are per material, the lighting pass per layer: the flags ride
    // in the roughness channel's two lowest bits (roughness keeps 14 bits, steps of 6e-5).
    float roughness14 = floor(clamp(s.roughness, 0.0, 1.0) * 16383.0 + 0.5);
    float receives = uAlphaParams.z > 0.5 ? 1.0 : 0.0;
    float unlit = uAlphaParams.w > 0.5 ? 1.0 : 0.0;
    outNormalMaterial = vec4(octEncode(s.normal) * 0.5 + 0.5,
                             (roughness14 * 4.0 + unlit * 2.0 + receives) / 65535.0,
                             (metallic8 * 256.0 + occlusion8) / 65535.0);
    outEmissive = s.emissive;
}
