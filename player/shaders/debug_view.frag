#version 450 core
// debug_view.frag — shows one buffer. Modes match pnb::player::DebugView.
layout(binding = 0) uniform sampler2D uGBaseColor;
layout(binding = 1) uniform sampler2D uGNormalMaterial;
layout(binding = 2) uniform sampler2D uGEmissive;
layout(binding = 3) uniform sampler2D uDepth;
layout(binding = 4) uniform sampler2D uDebug; // layer or LOD colours, overdraw counts, the RSM
layout(binding = 5) uniform sampler3D uGiR;   // GI's summed volume (gi_volume)
layout(binding = 6) uniform sampler3D uGiG;
layout(binding = 7) uniform sampler3D uGiB;
layout(location = 0) uniform int uMode;
layout(location = 1) uniform vec2 uNearFar; // near, far (0 = infinite)
layout(location = 2) uniform vec2 uGiSlice; // normalised z of the slice, 1 if GI is on

layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

// Same mapping as shaders/include/octahedral.glsl.
vec3 octDecode(vec2 e) {
    vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (v.z < 0.0) v.xy = (1.0 - abs(v.yx)) * vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
    return normalize(v);
}

vec3 heat(float t) { // 0 black .. 1 red .. 2 yellow .. 4 white
    return clamp(vec3(t, t - 1.0, (t - 2.0) * 0.5), 0.0, 1.0);
}

void main() {
    vec4 base = texture(uGBaseColor, vUv);
    vec4 nm = texture(uGNormalMaterial, vUv);
    float packedBits = floor(nm.w * 65535.0 + 0.5);
    vec3 c = vec3(0.0);
    if (uMode == 1) c = base.rgb;
    else if (uMode == 2) c = vec3(base.a);
    else if (uMode == 3) c = base.a > 0.0 ? octDecode(nm.xy * 2.0 - 1.0) * 0.5 + 0.5 : vec3(0.0);
    else if (uMode == 4) c = vec3(nm.z);
    else if (uMode == 5) c = vec3(floor(packedBits / 256.0) / 255.0);
    else if (uMode == 6) c = vec3(mod(packedBits, 256.0) / 255.0);
    else if (uMode == 7) c = texture(uGEmissive, vUv).rgb;
    else if (uMode == 8) {
        float d = texture(uDepth, vUv).r;
        float n = uNearFar.x, f = uNearFar.y;
        // Reversed-Z: d = n / z (infinite) or n (f - z) / (z (f - n)); invert to view distance.
        float z = d <= 0.0 ? 1e30 : (f > 0.0 ? n * f / (d * (f - n) + n) : n / d);
        c = vec3(d <= 0.0 ? 0.0 : 1.0 - clamp(log2(z / n) / 20.0, 0.0, 1.0));
    } else if (uMode == 9) c = texture(uDebug, vUv).rgb;
    else if (uMode == 10) c = heat(texture(uDebug, vUv).r);
    else if (uMode == 15) c = texture(uDebug, vUv).rgb; // RSM (black without GI)
    else if (uMode == 17) c = texture(uDebug, vUv).rgb; // level-of-detail colours
    else if (uMode == 16 && uGiSlice.y > 0.5) { // band 0 = radiance / sun irradiance x 2 sqrt(pi)
        vec3 uvw = vec3(vUv, uGiSlice.x);
        c = 4.0 * vec3(texture(uGiR, uvw).x, texture(uGiG, uvw).x, texture(uGiB, uvw).x); // x4: visible
    }
    outColor = vec4(c, 1.0);
}
