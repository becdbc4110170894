#version 450 core
// deform.comp — the deform pass: one invocation poses one vertex of one deformed node's mesh,
// once per frame, into that node's posed buffer, which every pass then draws (G-buffer, forward,
// every shadow cascade and local-light tile, the RSM, GI's occupancy, the sky's height map):
// a vertex shader would skin it again in each of those draws.
//
// What it computes is pnb::deformVertices (format/src/animation_pose.cpp), so the ray-traced
// truth and the tests agree with the frame: morph targets first (base + sum_k w_k delta_k, for
// positions, normals and tangents), then the skin: M = sum_i (w_i / sum w) J[joint_i], position
// by M, normal and tangent.xyz by M's 3x3; weights summing to 0 leave the vertex where the morph
// put it. Normals and tangents are renormalised (0 length or not finite: +Z), tangent.w kept; a
// position that is not finite after all that is the stored one.
//
// Defines: SKIN (the scene has skinned nodes), MORPH (it has morph targets). One program serves
// both kinds of node: a morph-only node runs with uJointCount 0, a skin-only one with
// uTargetCount 0.
#include "shared/deform_params.h"

layout(local_size_x = PNB_DEFORM_GROUP_SIZE) in;

layout(std430, binding = PNB_BINDING_DEFORM_SOURCE) readonly buffer Source { uint uSource[]; };
layout(std430, binding = PNB_BINDING_DEFORM_POSED) writeonly buffer Posed { uint uPosed[]; };
layout(std430, binding = PNB_BINDING_DEFORM_FRAME) readonly buffer DeformFrame { float uFrame[]; };
#ifdef MORPH
layout(std430, binding = PNB_BINDING_DEFORM_MORPH) readonly buffer Morph { float uMorph[]; };
#endif

layout(location = PNB_DEFORM_LOC_VERTEX_COUNT) uniform uint uVertexCount;
layout(location = PNB_DEFORM_LOC_SOURCE_POSITION) uniform uint uSourcePosition;
layout(location = PNB_DEFORM_LOC_SOURCE_NORMAL) uniform uint uSourceNormal;
layout(location = PNB_DEFORM_LOC_SOURCE_TANGENT) uniform uint uSourceTangent;
layout(location = PNB_DEFORM_LOC_SOURCE_JOINTS) uniform uint uSourceJoints;
layout(location = PNB_DEFORM_LOC_JOINTS_U16) uniform uint uJointsU16;
layout(location = PNB_DEFORM_LOC_SOURCE_WEIGHTS) uniform uint uSourceWeights;
layout(location = PNB_DEFORM_LOC_JOINT_BASE) uniform uint uJointBase;
layout(location = PNB_DEFORM_LOC_JOINT_COUNT) uniform uint uJointCount;
layout(location = PNB_DEFORM_LOC_TARGET_COUNT) uniform uint uTargetCount;
layout(location = PNB_DEFORM_LOC_WEIGHT_BASE) uniform uint uWeightBase;
layout(location = PNB_DEFORM_LOC_MORPH_STRIDE) uniform uint uMorphStride;
layout(location = PNB_DEFORM_LOC_MORPH_ATTRIBUTES) uniform uint uMorphAttributes;
layout(location = PNB_DEFORM_LOC_POSED_NORMAL) uniform uint uPosedNormal;
layout(location = PNB_DEFORM_LOC_POSED_TANGENT) uniform uint uPosedTangent;

vec3 source3(uint base, uint v) {
    const uint i = base + 3u * v;
    return vec3(uintBitsToFloat(uSource[i]), uintBitsToFloat(uSource[i + 1u]), uintBitsToFloat(uSource[i + 2u]));
}
vec4 source4(uint base, uint v) {
    const uint i = base + 4u * v;
    return vec4(uintBitsToFloat(uSource[i]), uintBitsToFloat(uSource[i + 1u]), uintBitsToFloat(uSource[i + 2u]),
                uintBitsToFloat(uSource[i + 3u]));
}
void write3(uint base, uint v, vec3 x) {
    const uint i = base + 3u * v;
    uPosed[i] = floatBitsToUint(x.x);
    uPosed[i + 1u] = floatBitsToUint(x.y);
    uPosed[i + 2u] = floatBitsToUint(x.z);
}
vec3 normalised(vec3 v) {
    const float l = length(v);
    return l > 0.0 && !isinf(l) && !isnan(l) ? v / l : vec3(0, 0, 1);
}

#ifdef MORPH
vec3 delta(uint target, uint slot, uint v) {
    const uint i = (target * uMorphAttributes + slot) * uMorphStride + 3u * v;
    return vec3(uMorph[i], uMorph[i + 1u], uMorph[i + 2u]);
}
#endif

#ifdef SKIN
mat4 joint(uint j) {
    const uint b = uJointBase + 16u * min(j, uJointCount - 1u);
    return mat4(uFrame[b], uFrame[b + 1u], uFrame[b + 2u], uFrame[b + 3u], uFrame[b + 4u], uFrame[b + 5u],
                uFrame[b + 6u], uFrame[b + 7u], uFrame[b + 8u], uFrame[b + 9u], uFrame[b + 10u], uFrame[b + 11u],
                uFrame[b + 12u], uFrame[b + 13u], uFrame[b + 14u], uFrame[b + 15u]);
}
uvec4 joints(uint v) {
    if (uJointsU16 == 0u) {
        const uint w = uSource[uSourceJoints + v];
        return uvec4(w & 0xFFu, (w >> 8) & 0xFFu, (w >> 16) & 0xFFu, w >> 24);
    }
    const uint a = uSource[uSourceJoints + 2u * v], b = uSource[uSourceJoints + 2u * v + 1u];
    return uvec4(a & 0xFFFFu, a >> 16, b & 0xFFFFu, b >> 16);
}
#endif

void main() {
    const uint v = gl_GlobalInvocationID.x;
    if (v >= uVertexCount) return;
    const bool hasNormal = uSourceNormal != PNB_DEFORM_ABSENT, hasTangent = uSourceTangent != PNB_DEFORM_ABSENT;
    vec3 position = source3(uSourcePosition, v);
    vec3 normal = hasNormal ? source3(uSourceNormal, v) : vec3(0);
    vec4 tangent = hasTangent ? source4(uSourceTangent, v) : vec4(0);
#ifdef MORPH
    for (uint k = 0u; k < uTargetCount; ++k) {
        const float w = uFrame[uWeightBase + k];
        if (w == 0.0) continue;
        uint a = 0u;
        position += w * delta(k, a++, v);
        if (hasNormal) normal += w * delta(k, a++, v);
        if (hasTangent) tangent.xyz += w * delta(k, a, v);
    }
#endif
#ifdef SKIN
    if (uJointCount > 0u) {
        const vec4 weights = source4(uSourceWeights, v);
        // Summed in the CPU's order so the two agree to the last bit where they can.
        const float sum = ((weights.x + weights.y) + weights.z) + weights.w;
        if (sum > 0.0) {
            const uvec4 j = joints(v);
            mat4 m = (weights.x / sum) * joint(j.x);
            m += (weights.y / sum) * joint(j.y);
            m += (weights.z / sum) * joint(j.z);
            m += (weights.w / sum) * joint(j.w);
            position = (m * vec4(position, 1.0)).xyz;
            normal = mat3(m) * normal;
            tangent.xyz = mat3(m) * tangent.xyz;
        }
    }
#endif
    // A vertex carried beyond float (extreme but finite joints or deltas) stays where the
    // container stores it: no frame ever draws a NaN (FORMAT.md "SKIN"), as deformVertices does.
    if (any(isnan(position)) || any(isinf(position))) position = source3(uSourcePosition, v);
    write3(0u, v, position);
    if (hasNormal) write3(uPosedNormal, v, normalised(normal));
    if (hasTangent) {
        const uint i = uPosedTangent + 4u * v;
        const vec3 t = normalised(tangent.xyz);
        uPosed[i] = floatBitsToUint(t.x);
        uPosed[i + 1u] = floatBitsToUint(t.y);
        uPosed[i + 2u] = floatBitsToUint(t.z);
        uPosed[i + 3u] = floatBitsToUint(tangent.w);
    }
}
