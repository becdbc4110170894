// sdsm_caster.h — one shadow caster as SDSM's GPU cull reads it (player/shaders/sdsm.comp,
// CasterBounds) and the player writes it (pnb::player::SdsmCasterData, shadow_setup.cpp).
// gpu_layout.h says how one list serves both languages.
#ifndef PNB_SHARED_SDSM_CASTER_H
#define PNB_SHARED_SDSM_CASTER_H

#include "gpu_layout.h"

// SDSM's cull reads one per caster (std430, sdsm.comp CasterBounds): camera-relative bounds and
// the index range of the level of detail drawn this frame, which it writes into the draws.
#define PNB_SDSM_CASTER_MEMBERS(FIELD, ARRAY)                                                      \
    FIELD(vec3, lo, lo)                                                                            \
    FIELD(uint, indexCount, indexCount)                                                            \
    FIELD(vec3, hi, hi)                                                                            \
    FIELD(uint, firstIndex, firstIndex) /* in indices from the start of the mesh buffer */

PNB_NAMESPACE_BEGIN
PNB_STRUCT(SdsmCasterData, Caster) {
    PNB_SDSM_CASTER_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
PNB_CHECK_LAYOUT(Std430, SdsmCasterData, PNB_SDSM_CASTER_MEMBERS)
PNB_NAMESPACE_END

#endif
