// gpu_light.h — one punctual light as lighting reads it from the light buffer (std430 element of
// shaders/include/lights.glsl's LightBuffer) and the player writes it (pnb::player::GpuLight,
// lights/light_clusters.h). gpu_layout.h says how one list serves both languages.
#ifndef PNB_SHARED_GPU_LIGHT_H
#define PNB_SHARED_GPU_LIGHT_H

#include "gpu_layout.h"

#define PNB_GPU_LIGHT_MEMBERS(FIELD, ARRAY)                                                        \
    FIELD(vec4, positionRange, positionRange) /* camera-relative position, range (0: directional,  \
                                                 or no light) */                                   \
    FIELD(vec4, directionType, directionType) /* direction the light travels (unit), type */       \
    FIELD(vec4, colorIntensity, colorIntensity) /* linear rgb, intensity (lux or candela) */       \
    FIELD(vec4, cone, cone) /* cos(outer), 1 / max(cos(inner) - cos(outer), 1e-4), first shadow    \
                               tile (-1: no shadow this frame), 0 */

PNB_NAMESPACE_BEGIN
PNB_STRUCT(GpuLight, GpuLight) {
    PNB_GPU_LIGHT_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
PNB_CHECK_LAYOUT(Std430, GpuLight, PNB_GPU_LIGHT_MEMBERS)
PNB_NAMESPACE_END

#endif
