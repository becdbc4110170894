// gi_lookup.glsl — indirect irradiance from the cascaded light propagation volumes (GI
// permutation; the player's lpv_*.comp passes fill them). The volumes hold radiance over the
// sun's irradiance as L1 SH per colour; irradiance at a surface with normal n is the radiance
// integrated against max(0, -n.w) (light travelling towards the surface), i.e. the dot product
// with the clamped-cosine lobe along -n, times the sun's irradiance.
// GI can be switched off at run time: the frame block's uAmbient.a is then 0 and nothing here
// (block or textures) is touched.
#ifndef PNB_GI_LOOKUP_GLSL
#define PNB_GI_LOOKUP_GLSL

layout(std140, binding = 6) uniform GiBlock {
    vec4 uGiCascade[4];   // camera-relative minimum corner, cell size
    vec4 uGiGrid;         // cells, cascades, 1 if the outer cascade fades out at its border,
                          // 1 if lighting writes the indirect irradiance instead of radiance
    vec4 uGiIrradiance;   // sun irradiance (rgb, lux or W/m^2) times gi.intensity; w: 1 when
                          // the volume holds probes (gi.technique = probes), 0 for the LPV
};
layout(binding = 10) uniform sampler3D uGiR;
layout(binding = 11) uniform sampler3D uGiG;
layout(binding = 12) uniform sampler3D uGiB;

vec3 giSample(int c, vec3 q, vec4 lobe) {
    float cells = uGiGrid.x;
    // Texel coordinates clamped to this cascade's slab so that filtering never reads the next.
    vec3 t = clamp(q, vec3(0.5), vec3(cells - 0.5));
    vec3 uvw = (t + vec3(0.0, 0.0, float(c) * cells)) / vec3(cells, cells, cells * uGiGrid.y);
    return vec3(dot(textureLod(uGiR, uvw, 0.0), lobe), dot(textureLod(uGiG, uvw, 0.0), lobe),
                dot(textureLod(uGiB, uvw, 0.0), lobe));
}

// Probes (one grid, cascade 0): the 8 probes around the look-up point q (in cells), each
// weighted by its trilinear weight times how far it lies in front of the surface at p (n its
// normal), DDGI's ((cos + 1) / 2)^2 + 0.2: a probe behind the surface (outside the room's wall,
// inside a column) saw light and sky this surface cannot receive. DDGI leaves the rest to a
// per-probe depth test, not built here; measured against the truth (camera 0 of the box room /
// atrium, and the tests' views), plain trilinear, this and a hard max(cos, 0) + 0.01 trade
// places by scene: 0.567 / 0.472 / 0.537 / 0.608,
// 0.536 / 0.485 / 0.508 / 0.625, 0.536 / 0.485 / 0.496 / 0.646 of the best constant's error.
// The LPV's cells are not points that see anything: it keeps the plain fetch. Not normalised.
void giProbeCorners(vec3 p, vec3 n, vec3 q, out ivec3 at[8], out float weight[8]) {
    int cells = int(uGiGrid.x);
    vec3 g = q - 0.5; // probe indices: probe i sits at cell centre i + 0.5
    ivec3 base = ivec3(floor(g));
    vec3 f = g - vec3(base);
    for (int i = 0; i < 8; ++i) {
        ivec3 o = ivec3(i & 1, (i >> 1) & 1, i >> 2);
        at[i] = clamp(base + o, ivec3(0), ivec3(cells - 1));
        vec3 tri = mix(1.0 - f, f, vec3(o));
        vec3 toProbe = uGiCascade[0].xyz + (vec3(at[i]) + 0.5) * uGiCascade[0].w - p;
        float facing = dot(toProbe, n) * inversesqrt(max(dot(toProbe, toProbe), 1e-30));
        float front = (facing + 1.0) * (facing + 1.0) * 0.25 + 0.2;
        weight[i] = tri.x * tri.y * tri.z * front;
    }
}

vec3 giProbeSample(vec3 p, vec3 n, vec3 q, vec4 lobe) {
    ivec3 at[8];
    float weight[8];
    giProbeCorners(p, n, q, at, weight);
    vec3 sum = vec3(0.0);
    float total = 0.0;
    for (int i = 0; i < 8; ++i) {
        sum += weight[i] * vec3(dot(texelFetch(uGiR, at[i], 0), lobe), dot(texelFetch(uGiG, at[i], 0), lobe),
                                dot(texelFetch(uGiB, at[i], 0), lobe));
        total += weight[i];
    }
    return sum / max(total, 1e-30);
}

bool giCaptureIrradiance() { return uAmbient.a > 0.0 && uGiGrid.w > 0.5; }

// Irradiance at camera-relative p with unit normal n. Read half a cell in front of the surface
// (where injection put its light), from the finest cascade that holds the point, blended over
// two cells into the next coarser one near its border.
vec3 giIrradiance(vec3 p, vec3 n) {
    if (uAmbient.a <= 0.0) return vec3(0.0);
    vec4 lobe = vec4(0.886226925, 1.023326708 * n.y, -1.023326708 * n.z, 1.023326708 * n.x); // along -n
    int cascades = int(uGiGrid.y);
    float cells = uGiGrid.x;
    vec3 result = vec3(0.0);
    float remaining = 1.0; // weight not yet taken by a finer cascade
    for (int c = 0; c < cascades; ++c) {
        vec4 cascade = uGiCascade[c];
        vec3 q = (p - cascade.xyz) / cascade.w + 0.5 * n;
        float inside = min(min(min(q.x, q.y), q.z), min(min(cells - q.x, cells - q.y), cells - q.z));
        bool outer = c == cascades - 1;
        float w = (outer && uGiGrid.z < 0.5) ? 1.0 : clamp((inside - 0.5) * 0.5, 0.0, 1.0);
        if (inside > 0.5 && remaining > 0.0) {
            result += remaining * w * (uGiIrradiance.w > 0.5 ? giProbeSample(p, n, q, lobe) : giSample(c, q, lobe));
            remaining *= 1.0 - w;
        }
    }
    return max(result, vec3(0.0)) * uGiIrradiance.rgb;
}

#endif
