#version 450 core
// lpv_inject.comp — surfels into the cascades' accumulation buffers (one invocation per texel).
//   SOURCE_RSM     reflective shadow map texels: each is a virtual point light (flux into the
//                  light volume) and a blocking surfel (into the geometry volume, slot 0);
//   SOURCE_CAMERA  G-buffer pixels (every uStride-th): blocking surfels only (slot 1).
// Values are radiance over the sun's irradiance (see player/math/lpv_math.h): a texel of
// perpendicular area A_t with diffuse albedo rho reflects flux rho E A_t (no cosine: an
// orthographic map's texel already is the perpendicular area), its intensity rho E A_t / pi times
// the clamped-cosine lobe, stored over E s^2. Accumulation is an atomic add, in 32-bit fixed
// point (uFixedScale units per 1.0: order-independent, so the volume is bit-identical frame to
// frame) or with NV_shader_atomic_float (FLOAT_ATOMICS).
#ifdef FLOAT_ATOMICS
#extension GL_NV_shader_atomic_float : require
#define ACC float
#else
#define ACC int
#endif
#include "shared/bindings.h"
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0) uniform sampler2D uBaseColor;     // sRGB: decoded on fetch
layout(binding = 1) uniform sampler2D uNormalMaterial; // octahedral normal, roughness, metallic|occlusion
layout(binding = 2) uniform sampler2D uDepth;

// Light: cascade, cell, rgb x 4. Geometry: slot, cascade, corner, 4.
layout(std430, binding = PNB_BINDING_LPV_LIGHT) buffer LightAccumulation { ACC uLight[]; };
layout(std430, binding = PNB_BINDING_LPV_GEOMETRY) buffer GeometryAccumulation { ACC uGeometry[]; };

layout(location = 0) uniform mat4 uInverseMatrix; // map clip -> camera-relative world
layout(location = 1) uniform vec4 uCascade[4];    // camera-relative origin, cell size
layout(location = 5) uniform ivec4 uGrid;         // cells, cascades, stride, geometry slot
layout(location = 6) uniform vec4 uSurfel;        // texel area (RSM) or 2 tan(fov/2) / height (camera),
                                                  // 0 (RSM) or 2 ymag / height (orthographic camera:
                                                  // x is then 0), fixed-point units per 1.0: geometry, light
layout(location = 7) uniform vec3 uToward;        // RSM: toward the light; camera: view forward
layout(location = 8) uniform ivec2 uSize;         // map or viewport size in texels

const float kLobeC0 = 0.886226925;
const float kLobeC1 = 1.023326708;
const float kPi = 3.14159265;

vec3 octDecode(vec2 e) {
    vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (v.z < 0.0) v.xy = (1.0 - abs(v.yx)) * vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
    return normalize(v);
}

vec4 lobe(vec3 n) { return vec4(kLobeC0, -kLobeC1 * n.y, kLobeC1 * n.z, -kLobeC1 * n.x); }

// Atomic functions take the buffer variable itself, not a function parameter: a macro.
#ifdef FLOAT_ATOMICS
#define ADD(slot, v, fixedScale) atomicAdd(slot, (v))
#else
#define ADD(slot, v, fixedScale) atomicAdd(slot, int(round((v) * (fixedScale))))
#endif

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy) * uGrid.z;
    if (any(greaterThanEqual(texel, uSize))) return;
    vec4 base = texelFetch(uBaseColor, texel, 0);
    if (base.a <= 0.0) return; // nothing drawn here
    vec4 nm = texelFetch(uNormalMaterial, texel, 0);
    float depth = texelFetch(uDepth, texel, 0).r;
    vec2 ndc = (vec2(texel) + 0.5) / vec2(uSize) * 2.0 - 1.0;
    vec4 h = uInverseMatrix * vec4(ndc, depth, 1.0);
    vec3 p = h.xyz / h.w;
    vec3 n = octDecode(nm.xy * 2.0 - 1.0);
    if (any(isnan(p)) || any(isinf(p))) return;
#ifdef SOURCE_CAMERA
    // A pixel's footprint: (distance * pixel angle)^2 over its cosine to the view ray (an
    // orthographic camera's pixels have one size and one ray direction, uToward).
    float z = max(dot(p, uToward), 0.0);
    float side = (z * uSurfel.x + uSurfel.y) * float(uGrid.z);
    vec3 ray = uSurfel.y > 0.0 ? uToward : normalize(p);
    float cosine = max(abs(dot(n, ray)), 0.05);
    float area = side * side / cosine;
#else
    float cosine = dot(n, uToward);
    if (cosine <= 0.0) return; // faces away from the light: receives nothing
    float area = uSurfel.x / max(cosine, 0.05);
    float packedBits = floor(nm.w * 65535.0 + 0.5);
    float metallic = floor(packedBits / 256.0) / 255.0;
    vec3 albedo = base.rgb * (1.0 - metallic); // diffuse albedo: metals reflect specularly
#endif
    vec4 l = lobe(n);
    int cells = uGrid.x, corners = cells + 1;
    for (int c = 0; c < uGrid.y; ++c) {
        float s = uCascade[c].w;
        vec3 q = (p - uCascade[c].xyz) / s; // in cells from the cascade's minimum corner
        // Blocking potential A s^-2 <n|w>+ at the nearest corner (the geometry volume is offset by
        // half a cell: its cell centres are the light volume's corners).
        ivec3 g = ivec3(floor(q + 0.5));
        if (all(greaterThanEqual(g, ivec3(0))) && all(lessThanEqual(g, ivec3(cells)))) {
            // L1's clamped-cosine lobe peaks at c0 y0 + c1 y1 = 0.75, not 1: scaled by 4/3 so that
            // a surface covering the face head-on blocks all of it (K&D's unscaled lobe lets a
            // solid wall pass a quarter of the light on every crossing).
            float blocking = min(area / (s * s), 1.0) * (4.0 / 3.0);
            int at = (((uGrid.w * uGrid.y + c) * corners + g.z) * corners + g.y) * corners + g.x;
            for (int k = 0; k < 4; ++k) ADD(uGeometry[at * 4 + k], blocking * l[k], uSurfel.z);
        }
#ifdef SOURCE_RSM
        // The light moves half a cell along its normal before its cell is chosen, so that a wall's
        // light starts in the cell in front of it (less self-illumination).
        ivec3 cell = ivec3(floor(q + 0.5 * n));
        if (any(lessThan(cell, ivec3(0))) || any(greaterThanEqual(cell, ivec3(cells)))) continue;
        float flux = uSurfel.x / (s * s) / kPi; // rho A_t / (pi s^2), times albedo per channel
        int at = (((c * cells + cell.z) * cells + cell.y) * cells + cell.x) * 12;
        for (int ch = 0; ch < 3; ++ch) {
            float f = flux * albedo[ch];
            if (f <= 0.0) continue;
            for (int k = 0; k < 4; ++k) ADD(uLight[at + ch * 4 + k], f * l[k], uSurfel.w);
        }
#endif
    }
}
