// sdsm_state.h — SDSM's working buffer (std430 SdsmState, binding PNB_BINDING_SDSM_STATE): what
// the compute stages of player/shaders/sdsm.comp hand each other within a frame, and what the
// histogram debug view (player/shaders/shadow_debug.frag) shows. Only the GPU writes it; the
// player sizes it (pnb::player::SdsmState, shadows/shadow_resources.cpp) and clears its counters
// each frame (shadows/shadow_sdsm.cpp). gpu_layout.h says how one list serves both languages.
#ifndef PNB_SHARED_SDSM_STATE_H
#define PNB_SHARED_SDSM_STATE_H

#include "gpu_layout.h"
#include "shadow_block.h" // PNB_MAX_CASCADES

#define PNB_SDSM_BINS 256 // of the view-depth histogram: one per invocation of a reduce group

#define PNB_SDSM_STATE_MEMBERS(FIELD, ARRAY)                                                       \
    FIELD(uint, depthMinBits, depthMinBits) /* nearest sampled view depth (float bits: positive    \
                                               floats order as their bits) */                      \
    FIELD(uint, depthMaxBits, depthMaxBits) /* farthest */                                         \
    FIELD(uint, sampleCount, sampleCount)   /* pixels within the shadowed depth range */           \
    FIELD(uint, pad0, pad0)                                                                        \
    ARRAY(uint, histogram, histogram, PNB_SDSM_BINS) /* samples per logarithmic depth bin over     \
                                                        the shadowed range */                      \
    ARRAY(vec4, cascadeRange, cascadeRange, PNB_MAX_CASCADES) /* view depth start, end, 0, 0 */    \
    ARRAY(uint, lightBounds, lightBounds, PNB_MAX_CASCADES * 8) /* per cascade: light-space min x, \
                                                                   y, z, max x, y, z (sortable     \
                                                                   bits), 2 unused */

// The shaders declare the members straight in their storage block (no struct in GLSL); C++ has
// the struct for its size and offsets.
PNB_NAMESPACE_BEGIN
#ifdef __cplusplus
struct SdsmState {
    PNB_SDSM_STATE_MEMBERS(PNB_DECLARE_FIELD, PNB_DECLARE_ARRAY)
};
#endif
PNB_CHECK_LAYOUT(Std430, SdsmState, PNB_SDSM_STATE_MEMBERS)
PNB_NAMESPACE_END

#endif
