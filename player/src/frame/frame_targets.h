// frame_targets.h — the render targets of a frame, allocated for what the scene and settings use.
//
//   depth     D32F, reversed-Z, shared by G-buffer, forward and debug passes
//   hdr       RGBA16F lit radiance
//   gbuffer   RT0 SRGB8_A8 base+alpha, RT1 RGBA16 octahedral normal/roughness/metallic+AO,
//             RT2 R11G11B10F emissive: 16 B/px of colour + the shared 4 B/px depth = 20 B/px.
//             One set, reused by every deferred layer; absent without deferred materials.
//   output    SRGB8_A8, what is shown or saved; `fxaa` is its pre-FXAA twin when FXAA is on
//   debug     RGBA16F accumulation (+ its own depth) for the layer/overdraw views, on demand
#pragma once

#include <cstdint>

#include "pnb_player/gl_handles.h"
#include "pnb_player/renderer.h"

namespace pnb::player {

struct FrameTargets {
    uint32_t width = 0, height = 0;
    GlHandle depth, hdr, gbuffer[3], output, fxaaInput, debugColor, debugDepth;
    GlHandle gbufferFb, composeFb, hdrFb, outputFb, fxaaInputFb, debugFb;
    TargetMemory memory;

    // Recreates what changed: size, or whether a G-buffer, FXAA or debug targets are needed.
    void ensure(uint32_t w, uint32_t h, bool needGbuffer, bool needFxaa, bool needDebug);
};

} // namespace pnb::player
