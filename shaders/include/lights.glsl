// lights.glsl — punctual lights (KHR_lights_punctual semantics) from a storage buffer, so the
// light count is not limited by uniform space (UberRender's cap was 1 + 32 + 32).
#ifndef PNB_LIGHTS_GLSL
#define PNB_LIGHTS_GLSL

#include "brdf.glsl"
#ifdef SHADOWS
#include "shadow_sampling.glsl"
#endif

#define PNB_LIGHT_DIRECTIONAL 0
#define PNB_LIGHT_POINT 1
#define PNB_LIGHT_SPOT 2

struct GpuLight {
    vec4 positionRange;      // camera-relative position, range (0 = unlimited)
    vec4 directionType;      // direction the light travels (unit), type
    vec4 colorIntensity;     // linear rgb, intensity (lux or candela)
    vec4 cone;               // cos(outer), 1 / max(cos(inner) - cos(outer), 1e-4), 0, 0
};

layout(std430, binding = 3) readonly buffer LightBuffer {
    uint uLightCount;
    uint pad0, pad1, pad2;
    GpuLight uLights[];
};

// glTF's recommended range window: smooth falloff to zero at `range`, inverse-square inside.
// The clamp is 1 cm² in glTF's unit (metres; KHR_lights_punctual intensities are candela per
// metre²): a light never gets brighter than at 1 cm from its point. Scenes in other units carry
// their scale in the container's meters_per_unit, not here.
float rangeAttenuation(float distanceSquared, float range) {
    float inverseSquare = 1.0 / max(distanceSquared, 1e-4);
    if (range <= 0.0) return inverseSquare;
    float r = distanceSquared / (range * range);
    float window = clamp(1.0 - r * r, 0.0, 1.0);
    return window * window * inverseSquare;
}

// Radiance reflected towards the viewer by all lights. `p` is camera-relative, `v` points from
// the surface to the camera. `receivesShadows`: the material's flag (forward programs of
// materials that do not receive are built without SHADOWS; deferred ones read a G-buffer bit).
vec3 shadeLights(vec3 baseColor, float metallic, float roughness, vec3 n, vec3 p, vec3 v,
                 bool receivesShadows) {
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < uLightCount; ++i) {
        GpuLight light = uLights[i];
        int type = int(light.directionType.w);
        vec3 l;
        float attenuation = 1.0;
        if (type == PNB_LIGHT_DIRECTIONAL) {
            l = -light.directionType.xyz;
        } else {
            vec3 toLight = light.positionRange.xyz - p;
            float d2 = dot(toLight, toLight);
            l = d2 > 0.0 ? toLight * inversesqrt(d2) : vec3(0.0, 0.0, 1.0); // unit at any scale
            attenuation = rangeAttenuation(d2, light.positionRange.w);
            if (type == PNB_LIGHT_SPOT) {
                float cd = dot(light.directionType.xyz, -l);
                float t = clamp((cd - light.cone.x) * light.cone.y, 0.0, 1.0);
                attenuation *= t * t;
            }
        }
        vec3 radiance = light.colorIntensity.rgb * light.colorIntensity.a * attenuation;
#ifdef SHADOWS
        if (receivesShadows && float(i) == uShadowLight.w) radiance *= shadowVisibility(p, n);
#endif
        sum += shadeBrdf(baseColor, metallic, roughness, n, v, l, radiance);
    }
    return sum;
}

#endif
