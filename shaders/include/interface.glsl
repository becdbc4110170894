// interface.glsl — the binding contract between the player and every surface shader.
// Attribute locations and sampler units are fixed here, the blocks' bindings in shared/bindings.h,
// so the player can bind once per draw without querying programs. Changing a number breaks
// existing containers' shaders: bump the PROG chunk version if you do.
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

// Per frame (PNB_BINDING_FRAME_BLOCK): the camera. Declared once for GLSL and C++ in shared/.
#include "../shared/frame_block.h"

// The unit vector from camera-relative `p` toward the viewer (the V of the BRDF, the reverse of
// the view ray through p): -p for a perspective camera, the constant -forward for an
// orthographic one, whose view rays are parallel. uViewProjection's w row tells them apart: it
// is (forward, 0) for perspective (w = view depth) and (0, 0, 0, 1) for orthographic (w = 1).
bool pnbOrthographic() { return uViewProjection[3][3] != 0.0; }
vec3 viewVector(vec3 p) {
    return pnbOrthographic() ? vec3(uView[0][2], uView[1][2], uView[2][2]) : normalize(-p);
}

// Per draw (PNB_BINDING_OBJECT_BLOCK).
#include "../shared/object_block.h"

// Per material (PNB_BINDING_MATERIAL_BLOCK): the MATL chunk's factors.
#include "../shared/material_block.h"

#endif
