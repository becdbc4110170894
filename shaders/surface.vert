#version 450 core
// surface.vert — every mesh draw (G-buffer and forward). Streams are optional per permutation:
// HAS_UV0/HAS_UV1/HAS_TANGENT/HAS_VERTEX_COLOR are defined only when a material reads them.
#include "include/interface.glsl"
#include "include/octahedral.glsl"
#include "shared/bindings.h"
#include "shared/instance_data.h"

layout(location = PNB_ATTR_POSITION) in vec3 inPosition;
layout(location = PNB_ATTR_NORMAL) in vec3 inNormal;
#ifdef HAS_TANGENT
layout(location = PNB_ATTR_TANGENT) in vec4 inTangent;
#endif
#ifdef HAS_UV0
layout(location = PNB_ATTR_UV0) in vec2 inUv0;
#endif
#ifdef HAS_UV1
layout(location = PNB_ATTR_UV1) in vec2 inUv1;
#endif
#ifdef HAS_VERTEX_COLOR
layout(location = PNB_ATTR_COLOR) in vec4 inColor;
#endif

// The copies of an instanced batch (EXT_mesh_gpu_instancing; the player's draw_lists.cpp packs
// them), read when uObjectParams.w is 1: each copy's own model and normal matrices and params
// (InstanceData, shared/instance_data.h).
layout(std430, binding = PNB_BINDING_INSTANCES) readonly buffer InstanceBlock {
    InstanceData uInstances[];
};

layout(location = 0) out vec3 vPosition; // camera-relative world
layout(location = 1) out vec3 vNormal;
layout(location = 2) out vec4 vTangent;
layout(location = 3) out vec2 vUv0;
layout(location = 4) out vec2 vUv1;
layout(location = 5) out vec4 vColor;

void main() {
    mat4 model = uModel;
    mat3 normalMatrix = mat3(uNormalMatrix);
    float mirror = uObjectParams.z;
    if (uObjectParams.w > 0.5) {
        model = uInstances[gl_InstanceID].model;
        normalMatrix = mat3(uInstances[gl_InstanceID].normalMatrix);
        mirror = uInstances[gl_InstanceID].params.z;
    }
    vec3 objectPosition = inPosition * uDequantScale.xyz + uDequantOffset.xyz;
    vec4 world = model * vec4(objectPosition, 1.0);
    vPosition = world.xyz;
    // Quantised meshes store normals as two octahedral components (the third reads as 0).
    vec3 normal = uObjectParams.x > 0.5 ? octDecode(inNormal.xy) : inNormal;
    vNormal = normalMatrix * normal;
#ifdef HAS_TANGENT
    // The bitangent is cross(N, T) * w in object space; a mirroring model matrix flips the
    // handedness of the transformed frame, so w carries the mirror's sign too (glTF's
    // NormalTangentMirrorTest and NegativeScaleTest).
    vTangent = vec4(mat3(model) * inTangent.xyz, inTangent.w * mirror);
#else
    vTangent = vec4(1.0, 0.0, 0.0, 1.0);
#endif
#ifdef HAS_UV0
    vUv0 = inUv0;
#else
    vUv0 = vec2(0.0);
#endif
#ifdef HAS_UV1
    vUv1 = inUv1;
#else
    vUv1 = vec2(0.0);
#endif
#ifdef HAS_VERTEX_COLOR
    vColor = inColor;
#else
    vColor = vec4(1.0);
#endif
    gl_Position = uViewProjection * world;
}
