// interface.glsl — the binding contract between the player and every surface shader.
// Attribute locations, uniform-block bindings and sampler units are fixed here so the player can
// bind once per draw without querying programs. Changing a number breaks existing containers'
// shaders: bump the PROG chunk version if you do.
#ifndef PNB_INTERFACE_GLSL
#define PNB_INTERFACE_GLSL

#define PNB_ATTR_POSITION 0
#define PNB_ATTR_NORMAL 1
#define PNB_ATTR_TANGENT 2
#define PNB_ATTR_UV0 3
#define PNB_ATTR_UV1 4
#define PNB_ATTR_COLOR 5

#define PNB_TEX_BASE_COLOR 0
#define PNB_TEX_METALLIC_ROUGHNESS 1
#define PNB_TEX_NORMAL 2
#define PNB_TEX_OCCLUSION 3
#define PNB_TEX_EMISSIVE 4

// Per frame: camera-relative rendering. Positions reach the shader relative to the camera
// (the player subtracts the camera position in double precision on the CPU), so a scene 10^6
// units from the origin keeps full float precision near the viewer.
layout(std140, binding = 0) uniform FrameBlock {
    mat4 uViewProjection;   // camera-relative world -> clip (reversed-Z; perspective or orthographic)
    mat4 uView;             // camera-relative world -> view
    vec4 uCameraPosition;   // xyz world (for reference only; shading uses camera-relative)
    vec4 uViewport;         // width, height, 1/width, 1/height
    vec4 uAmbient;          // rgb: uniform ambient radiance; a: GI cascades this frame (0 = GI off)
};

// The unit vector from camera-relative `p` toward the viewer (the V of the BRDF, the reverse of
// the view ray through p): -p for a perspective camera, the constant -forward for an
// orthographic one, whose view rays are parallel. uViewProjection's w row tells them apart: it
// is (forward, 0) for perspective (w = view depth) and (0, 0, 0, 1) for orthographic (w = 1).
bool pnbOrthographic() { return uViewProjection[3][3] != 0.0; }
vec3 viewVector(vec3 p) {
    return pnbOrthographic() ? vec3(uView[0][2], uView[1][2], uView[2][2]) : normalize(-p);
}

// Per draw.
layout(std140, binding = 1) uniform ObjectBlock {
    mat4 uModel;            // object -> camera-relative world
    mat4 uNormalMatrix;     // inverse-transpose of uModel's upper 3x3 (in a mat4 for std140)
    vec4 uDequantScale;     // position = stored * scale + offset (identity for float streams)
    vec4 uDequantOffset;
    vec4 uObjectParams;     // x: 1 if normals are octahedral-encoded (2 components), y: caster
                            // index (shadow passes), z: -1 if the model matrix mirrors, else 1,
                            // w: 1 for an instanced batch (surface.vert reads InstanceBlock)
};

// Per material: the MATL chunk's factors.
layout(std140, binding = 2) uniform MaterialBlock {
    vec4 uBaseColorFactor;
    vec4 uEmissive;         // rgb * strength, a unused
    vec4 uMaterialParams;   // metallic, roughness, normalScale, occlusionStrength
    vec4 uAlphaParams;      // alphaCutoff, 1 if BLEND (else alpha is forced to 1),
                            // 1 if the surface receives shadows (deferred: a G-buffer bit),
                            // 1 if unlit (KHR_materials_unlit; deferred: a G-buffer bit)
    vec4 uTexTransform[5 * 2]; // per slot: (offset.xy, scale.xy), (rotation, texCoord, 0, 0)
};

#endif
