// brdf.glsl — the glTF 2.0 metallic-roughness BRDF (Appendix B of the glTF specification):
// GGX distribution, height-correlated Smith visibility, Schlick Fresnel, Lambert diffuse.
// Mirrored on the CPU by lighting/include/pnb_lighting/brdf.h (the whole-frame truth shades with
// it): change both together.
#ifndef PNB_BRDF_GLSL
#define PNB_BRDF_GLSL

const float PNB_PI = 3.14159265358979;

float distributionGgx(float nDotH, float alpha) {
    float a2 = alpha * alpha;
    float d = nDotH * nDotH * (a2 - 1.0) + 1.0;
    return a2 / (PNB_PI * d * d);
}

float visibilitySmithGgxCorrelated(float nDotV, float nDotL, float alpha) {
    float a2 = alpha * alpha;
    float gv = nDotL * sqrt(nDotV * nDotV * (1.0 - a2) + a2);
    float gl = nDotV * sqrt(nDotL * nDotL * (1.0 - a2) + a2);
    return 0.5 / max(gv + gl, 1e-6);
}

vec3 fresnelSchlick(vec3 f0, float vDotH) {
    // pow() of a negative base is undefined (NaN on Mesa): a light at the camera gives h = v,
    // and dot(v, v) can round to just above 1.
    return f0 + (1.0 - f0) * pow(max(1.0 - vDotH, 0.0), 5.0);
}

// Outgoing radiance towards v from one light of radiance `lightColor` arriving along l.
vec3 shadeBrdf(vec3 baseColor, float metallic, float roughness, vec3 n, vec3 v, vec3 l,
               vec3 lightColor) {
    float nDotL = max(dot(n, l), 0.0);
    if (nDotL <= 0.0) return vec3(0.0);
    vec3 h = normalize(v + l);
    float nDotV = max(dot(n, v), 1e-4);
    float nDotH = clamp(dot(n, h), 0.0, 1.0);
    float vDotH = clamp(dot(v, h), 0.0, 1.0);
    float alpha = roughness * roughness;
    vec3 f0 = mix(vec3(0.04), baseColor, metallic);
    vec3 f = fresnelSchlick(f0, vDotH);
    vec3 diffuse = (1.0 - f) * (1.0 - metallic) * baseColor / PNB_PI;
    vec3 specular = f * distributionGgx(nDotH, alpha) *
                    visibilitySmithGgxCorrelated(nDotV, nDotL, alpha);
    return (diffuse + specular) * lightColor * nDotL;
}

#endif
