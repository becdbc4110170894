// deform.h — playback's state in the renderer (docs/PLAYER.md "Animation"): the clock, the last
// pose (animate_scene.h) and the deform pass's per-frame buffer.
#pragma once

#include "anim/animate_scene.h"
#include "pnb_player/gpu_timer.h"
#include "pnb_player/renderer.h"

namespace pnb::player {

struct DeformContext {
    double clock = 0;          // seconds of playback (Renderer::setAnimationClock)
    AnimationState state;
    AnimationUpdate update;    // this frame's
    uint64_t poseVersion = 0;  // incremented whenever the pose changes (caches compare it)
    GlHandle frameBuffer;      // joint matrices and morph weights (state.frameData)
    size_t frameBytes = 0;
};

// The deform pass: uploads this frame's joint matrices and morph weights and dispatches
// scene.animation's deform program once per deformed node, writing its posed buffer, then makes
// the writes visible to vertex fetches. Runs only when update.deform (the pose changed); when
// update.restore, copies the stored streams back instead (anim.enabled turned off). Timed as
// "deform". Counts dispatches into stats.
void runDeformPass(const GpuScene& scene, DeformContext& dc, GpuTimer& timer, FrameStats& stats);

} // namespace pnb::player
