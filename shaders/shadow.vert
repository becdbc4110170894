#version 450 core
// shadow.vert — depth-only draw into the shadow-map array. Layered (one draw for all cascades):
// instance k goes to the k-th cascade set in the caster's mask, written to gl_Layer from the
// vertex shader (ARB_shader_viewport_layer_array), so no geometry shader runs. Where that
// extension is missing (or LAYER_FROM_GEOMETRY is defined) the player links a geometry shader
// (player/shaders/shadow_layers.geom) that replicates each triangle into the mask's cascades, and
// this shader hands it camera-relative positions. Multi-pass: the player attaches one layer and
// names its cascade in uPassCascade.
#extension GL_ARB_shader_viewport_layer_array : enable
#include "include/interface.glsl"
#include "include/shadow_block.glsl"
#include "shared/bindings.h"

#if defined(LAYER_FROM_GEOMETRY) || !defined(GL_ARB_shader_viewport_layer_array)
#define PNB_LAYERS_IN_GEOMETRY_SHADER
#endif

layout(location = PNB_ATTR_POSITION) in vec3 inPosition;
#if defined(ALPHA_MASK) || defined(TRANSLUCENT)
layout(location = PNB_ATTR_UV0) in vec2 inUv0;
layout(location = 3) out vec2 vUv0;
#endif

layout(location = 0) uniform int uPassCascade; // >= 0: multi-pass, this cascade; < 0: layered

// Per caster (uObjectParams.y), the cascades whose light volume it touches (bit c = cascade c).
layout(std430, binding = PNB_BINDING_CASTER_MASKS) readonly buffer CasterMasks {
    uint uCasterMask[];
};

#ifdef PNB_LAYERS_IN_GEOMETRY_SHADER
layout(location = 4) flat out uint vCascadeMask; // the geometry shader emits one copy per bit
#endif

void main() {
    vec3 objectPosition = inPosition * uDequantScale.xyz + uDequantOffset.xyz;
    vec4 world = uModel * vec4(objectPosition, 1.0);
#if defined(ALPHA_MASK) || defined(TRANSLUCENT)
    vUv0 = inUv0;
#endif
#ifdef PNB_LAYERS_IN_GEOMETRY_SHADER
    uint mask = uPassCascade >= 0 ? (1u << uint(uPassCascade)) : uCasterMask[uint(uObjectParams.y)];
    vCascadeMask = gl_InstanceID == 0 ? mask : 0u; // one instance carries every cascade
    gl_Position = world;
#else
    int cascade = uPassCascade;
    if (cascade < 0) {
        uint mask = uCasterMask[uint(uObjectParams.y)];
        for (int k = 0; k < gl_InstanceID; ++k) mask &= mask - 1u; // drop the lowest k set bits
        cascade = findLSB(mask);
        gl_Layer = cascade;
    }
    gl_Position = uShadowMatrix[cascade] * world;
#endif
}
