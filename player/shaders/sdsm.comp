#version 450 core
// sdsm.comp — Sample Distribution Shadow Maps (Lauritzen, Salvi, Lefohn 2011) fitted entirely on
// the GPU: five stages of one file, selected by a define, dispatched in this order with storage
// barriers between them (player/src/shadow_sdsm.cpp). Nothing is read back by the CPU.
//   SDSM_REDUCE     per pixel of the depth buffer: tight min/max view depth and, when something
//                   reads it, a 256-bin logarithmic depth histogram
//   (REDUCE and BOUNDS give each invocation a TILE x TILE block of pixels reduced in registers,
//   then one shared atomic per invocation and one global atomic per group; on llvmpipe this
//   halved the reduction of a per-pixel version, 138 -> 69 ms at 1280 x 720)
//   SDSM_PARTITION  one thread: split depths — logarithmic over [zmin, zmax] (uniform for an
//                   orthographic view), or quantiles of the histogram at the practical scheme's
//                   fractions (seed 000's variant)
//   SDSM_BOUNDS     per pixel: light-space bounds of the samples of each cascade (and of the next
//                   cascade inside the blend band)
//   SDSM_FINALIZE   per cascade: a square orthographic map around those bounds, depth from the
//                   scene's top toward the light; writes the ShadowBlock lighting reads
//   SDSM_CULL       per caster: which cascades it touches; masks and indirect draws
#include "shared/bindings.h"
#include "shared/shadow_block.h"
#include "shared/sdsm_caster.h"
#include "shared/sdsm_state.h"
#define MAX_CASCADES PNB_MAX_CASCADES
#define BINS PNB_SDSM_BINS

// The stages' working state (shared/sdsm_state.h): depth range, histogram, cascade ranges and
// light-space bounds.
layout(std430, binding = PNB_BINDING_SDSM_STATE) buffer SdsmState {
    PNB_SDSM_STATE_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};

// The ShadowBlock (shared/shadow_block.h) as std430 storage: the same members (the same offsets
// under both rules, which the header checks), by the C++ names, which this file reads.
#define SDSM_FIELD(type, cppName, glslName) type cppName;
#define SDSM_ARRAY(type, cppName, glslName, count) type cppName[count];
struct ShadowBlockData {
    PNB_SHADOW_BLOCK_MEMBERS(SDSM_FIELD, SDSM_ARRAY)
};

layout(location = 0) uniform mat4 uInverseViewProjection; // camera-relative
layout(location = 1) uniform vec3 uForward;
layout(location = 2) uniform vec2 uDepthRange;             // shadowed view depths [near, far]
layout(location = 3) uniform int uCascades;
layout(location = 4) uniform int uPartition;               // 0 log, 1 quantile, 2 uniform (orthographic)
layout(location = 5) uniform float uLambda;
layout(location = 6) uniform mat3 uLightRotation;          // world -> light (rows x, y, z)
layout(location = 7) uniform vec2 uSceneLightDepth;        // scene's light-space z interval
layout(location = 8) uniform float uBlend;
layout(location = 9) uniform int uCasterCount;
layout(location = 10) uniform uint uCommandStride;         // casters per command array
layout(location = 11) uniform int uHistogram;              // 1: quantile partition or debug view

// Order-preserving float <-> uint, for atomicMin/Max on signed floats.
uint sortable(float f) {
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}
float unsortable(uint u) {
    return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7fffffffu : ~u);
}

#if defined(SDSM_REDUCE) || defined(SDSM_BOUNDS)
#define TILE 4 // pixels per invocation along x and y; a group covers 64 x 64 pixels
layout(local_size_x = 16, local_size_y = 16) in;
layout(binding = 0) uniform sampler2D uDepth;

// Camera-relative position and view depth of a pixel; false for sky or beyond the range.
bool samplePixel(ivec2 pixel, out vec3 p, out float depth) {
    ivec2 size = textureSize(uDepth, 0);
    if (any(greaterThanEqual(pixel, size))) return false;
    float d = texelFetch(uDepth, pixel, 0).r;
    if (d <= 0.0) return false; // reversed-Z: nothing drawn
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec4 h = uInverseViewProjection * vec4(ndc, d, 1.0);
    p = h.xyz / h.w;
    depth = dot(p, uForward);
    return depth >= uDepthRange.x && depth <= uDepthRange.y;
}
#endif

#ifdef SDSM_REDUCE
shared uint sMin, sMax, sCount;
shared uint sHistogram[BINS];

void main() {
    uint local = gl_LocalInvocationIndex;
    if (local == 0u) {
        sMin = 0x7f7fffffu;
        sMax = 0u;
        sCount = 0u;
    }
    sHistogram[local] = 0u; // 256 invocations, 256 bins
    barrier();
    float lo = 3.0e38, hi = 0.0;
    uint count = 0u;
    float logRange = log(uDepthRange.y / uDepthRange.x);
    for (int j = 0; j < TILE * TILE; ++j) {
        vec3 p;
        float depth;
        if (!samplePixel(ivec2(gl_GlobalInvocationID.xy) * TILE + ivec2(j % TILE, j / TILE), p, depth))
            continue;
        lo = min(lo, depth);
        hi = max(hi, depth);
        ++count;
        if (uHistogram != 0) {
            float t = log(depth / uDepthRange.x) / logRange;
            atomicAdd(sHistogram[clamp(int(t * float(BINS)), 0, BINS - 1)], 1u);
        }
    }
    if (count != 0u) {
        atomicMin(sMin, floatBitsToUint(lo)); // positive floats order as their bits
        atomicMax(sMax, floatBitsToUint(hi));
        atomicAdd(sCount, count);
    }
    barrier();
    if (sHistogram[local] != 0u) atomicAdd(histogram[local], sHistogram[local]);
    if (local == 0u && sCount != 0u) {
        atomicMin(depthMinBits, sMin);
        atomicMax(depthMaxBits, sMax);
        atomicAdd(sampleCount, sCount);
    }
}
#endif

#ifdef SDSM_PARTITION
layout(local_size_x = 1) in;

float binEnd(int bin) {
    return uDepthRange.x * pow(uDepthRange.y / uDepthRange.x, float(bin + 1) / float(BINS));
}

void main() {
    float n = uDepthRange.x, f = uDepthRange.y;
    float zmin = n, zmax = f;
    if (sampleCount > 0u) {
        zmin = clamp(uintBitsToFloat(depthMinBits), n, f);
        zmax = clamp(uintBitsToFloat(depthMaxBits), zmin, f);
    }
    // A single depth (one pixel, a flat wall) still needs a non-empty range; relative, so the
    // partition is the same in any unit of length (zmin >= near > 0).
    zmax = max(zmax, zmin * 1.001);
    float start = zmin;
    uint cumulative = 0u;
    int bin = 0;
    for (int i = 0; i < uCascades; ++i) {
        float s = float(i + 1) / float(uCascades);
        float end;
        if (uPartition == 2) {
            end = zmin + (zmax - zmin) * s;
        } else if (uPartition == 0 || sampleCount == 0u) {
            end = zmin * pow(zmax / zmin, s);
        } else {
            // The practical scheme's fraction of the range, as a fraction of the samples.
            float practical = uLambda * n * pow(f / n, s) + (1.0 - uLambda) * (n + (f - n) * s);
            float fraction = (practical - n) / (f - n);
            uint target = uint(ceil(fraction * float(sampleCount)));
            while (bin < BINS && cumulative < target) cumulative += histogram[bin++];
            end = clamp(binEnd(max(bin - 1, 0)), start, zmax);
        }
        if (i == uCascades - 1) end = zmax;
        cascadeRange[i] = vec4(start, end, 0.0, 0.0);
        start = end;
    }
    for (int i = 0; i < MAX_CASCADES; ++i) {
        for (int k = 0; k < 3; ++k) {
            lightBounds[i * 8 + k] = 0xffffffffu;
            lightBounds[i * 8 + 3 + k] = 0u;
        }
    }
}
#endif

#ifdef SDSM_BOUNDS
shared uint sBounds[MAX_CASCADES * 6];

void main() {
    uint local = gl_LocalInvocationIndex;
    if (local < uint(MAX_CASCADES * 6)) sBounds[local] = (local % 6u) < 3u ? 0xffffffffu : 0u;
    barrier();
    vec3 lo[MAX_CASCADES], hi[MAX_CASCADES];
    for (int c = 0; c < MAX_CASCADES; ++c) {
        lo[c] = vec3(3.0e38);
        hi[c] = vec3(-3.0e38);
    }
    for (int j = 0; j < TILE * TILE; ++j) {
        vec3 p;
        float depth;
        if (!samplePixel(ivec2(gl_GlobalInvocationID.xy) * TILE + ivec2(j % TILE, j / TILE), p, depth))
            continue;
        vec3 l = uLightRotation * p;
        for (int c = 0; c < uCascades; ++c) {
            vec4 range = cascadeRange[c];
            bool inside = depth >= range.x && depth <= range.y;
            // The band at the end of cascade c - 1 also reads cascade c.
            if (c > 0) {
                vec4 prev = cascadeRange[c - 1];
                inside = inside || (depth <= prev.y && depth >= prev.y - uBlend * (prev.y - prev.x));
            }
            if (inside) {
                lo[c] = min(lo[c], l);
                hi[c] = max(hi[c], l);
            }
        }
    }
    for (int c = 0; c < uCascades; ++c) {
        if (lo[c].x > hi[c].x) continue; // no sample of this cascade here
        for (int k = 0; k < 3; ++k) {
            atomicMin(sBounds[c * 6 + k], sortable(lo[c][k]));
            atomicMax(sBounds[c * 6 + 3 + k], sortable(hi[c][k]));
        }
    }
    barrier();
    if (local < uint(MAX_CASCADES * 6)) {
        uint c = local / 6u, k = local % 6u;
        if (k < 3u) {
            if (sBounds[local] != 0xffffffffu) atomicMin(lightBounds[c * 8u + k], sBounds[local]);
        } else if (sBounds[local] != 0u) {
            atomicMax(lightBounds[c * 8u + k], sBounds[local]);
        }
    }
}
#endif

#if defined(SDSM_FINALIZE) || defined(SDSM_CULL)
layout(std430, binding = PNB_BINDING_SDSM_SHADOW_OUT) buffer ShadowOut { ShadowBlockData outBlock; };
#endif

#ifdef SDSM_FINALIZE
layout(local_size_x = MAX_CASCADES) in;
// The CPU's ShadowBlock: the parameters.
layout(std430, binding = PNB_BINDING_SDSM_SHADOW_IN) readonly buffer ShadowIn { ShadowBlockData cpuBlock; };

void main() {
    int c = int(gl_LocalInvocationIndex);
    if (c == 0) {
        outBlock.light = cpuBlock.light;
        outBlock.params = cpuBlock.params;
        outBlock.bias = cpuBlock.bias;
        outBlock.mapInfo = cpuBlock.mapInfo;
        outBlock.view = cpuBlock.view;
    }
    if (c >= MAX_CASCADES) return;
    vec4 range = cascadeRange[c];
    bool empty = c >= uCascades || lightBounds[c * 8] == 0xffffffffu;
    if (empty) {
        // Never selected by depth (end < 0) and outside by bounds (x = 3).
        outBlock.matrix[c] = mat4(vec4(0), vec4(0), vec4(0), vec4(3, 3, 0.5, 1));
        outBlock.cascade[c] = vec4(-2.0, -1.0, 1.0, 0.0);
        return;
    }
    vec3 lo = vec3(unsortable(lightBounds[c * 8 + 0]), unsortable(lightBounds[c * 8 + 1]),
                   unsortable(lightBounds[c * 8 + 2]));
    vec3 hi = vec3(unsortable(lightBounds[c * 8 + 3]), unsortable(lightBounds[c * 8 + 4]),
                   unsortable(lightBounds[c * 8 + 5]));
    float resolution = cpuBlock.mapInfo.x;
    // Square texels (the filters work in texels), padded by the filter footprint. The floor (a
    // cascade over a single point) is relative to the shadowed depth range, not a length.
    float extent = max(max(hi.x - lo.x, hi.y - lo.y), 1e-6 * uDepthRange.y);
    float pad = (cpuBlock.params.w * 8.0 + 2.0) / resolution; // PCSS search reaches 8x the radius
    extent *= 1.0 + 2.0 * pad;
    vec2 centre = 0.5 * (lo.xy + hi.xy);
    float zHigh = uSceneLightDepth.y, zLow = max(lo.z, uSceneLightDepth.x);
    if (!(zHigh > zLow)) zLow = zHigh - extent; // receivers only at the top: as deep as wide
    float margin = (zHigh - zLow) * 1e-3;
    zHigh += margin;
    zLow -= margin;
    float scale = 2.0 / extent, depthScale = 1.0 / (zHigh - zLow);
    mat3 axes = transpose(uLightRotation); // columns: light x, y, z in world
    mat4 m = mat4(0.0);
    for (int col = 0; col < 3; ++col) {
        m[col][0] = scale * axes[0][col];
        m[col][1] = scale * axes[1][col];
        m[col][2] = -depthScale * axes[2][col];
    }
    m[3] = vec4(-scale * centre.x, -scale * centre.y, zHigh * depthScale, 1.0);
    outBlock.matrix[c] = m;
    outBlock.cascade[c] = vec4(range.x, range.y, extent / resolution, 0.0);
}
#endif

#ifdef SDSM_CULL
layout(local_size_x = 64) in;
// Per caster: Caster (shared/sdsm_caster.h, SdsmCasterData in C++): camera-relative bounds and
// the index range of the level of detail it draws this frame.
layout(std430, binding = PNB_BINDING_SDSM_CASTERS) readonly buffer CasterBounds { Caster casters[]; };
layout(std430, binding = PNB_BINDING_CASTER_MASKS) writeonly buffer CasterMasks { uint casterMask[]; };
struct DrawCommand {
    uint count, instanceCount, firstIndex;
    int baseVertex;
    uint baseInstance;
};
layout(std430, binding = PNB_BINDING_SDSM_COMMANDS) writeonly buffer Commands { DrawCommand commands[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uint(uCasterCount)) return;
    vec3 lo = casters[i].lo, hi = casters[i].hi;
    uint mask = 0u;
    for (int c = 0; c < uCascades; ++c) {
        vec3 nlo = vec3(1e30), nhi = vec3(-1e30);
        for (int k = 0; k < 8; ++k) {
            vec3 p = vec3((k & 1) != 0 ? hi.x : lo.x, (k & 2) != 0 ? hi.y : lo.y, (k & 4) != 0 ? hi.z : lo.z);
            vec3 s = (outBlock.matrix[c] * vec4(p, 1.0)).xyz; // orthographic: w = 1
            nlo = min(nlo, s);
            nhi = max(nhi, s);
        }
        if (nhi.x >= -1.0 && nlo.x <= 1.0 && nhi.y >= -1.0 && nlo.y <= 1.0 && nlo.z <= 1.0)
            mask |= 1u << uint(c);
    }
    casterMask[i] = mask;
    uvec2 info = uvec2(casters[i].indexCount, casters[i].firstIndex);
    commands[i] = DrawCommand(info.x, uint(bitCount(mask)), info.y, 0, 0u);
    for (int c = 0; c < MAX_CASCADES; ++c)
        commands[uint(c + 1) * uCommandStride + i] = DrawCommand(info.x, (mask >> uint(c)) & 1u, info.y, 0, 0u);
}
#endif
