// animate_scene.h — the CPU half of playback (docs/PLAYER.md "Animation"): the clock's time to a
// pose (pnb::poseAt), the pose to the draw items, lights and cameras of the scene, and the joint
// matrices and morph weights the deform pass (pass_deform.cpp) uploads. Holds no GL object, so it
// is tested without a context.
#pragma once

#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "pnb_player/gpu_scene.h"
#include "pnb_player/settings.h"

namespace pnb::player {

// What the last update posed, so an unchanged pose costs nothing (no dispatch, no cache redraw).
struct PoseKey {
    bool enabled = false;
    std::optional<uint32_t> clip;
    double clipTime = 0;
    bool operator==(const PoseKey&) const = default;
};

struct AnimationState {
    std::optional<PoseKey> posed;           // none before the first update
    std::vector<Matrix4d> world;            // the last pose's node world matrices
    std::vector<float> frameData;           // joint matrices then morph weights (DeformedNode bases)
    double time = 0;                        // the clock time of the last update, seconds
    double clipTime = 0;                    // ... within its clip
};

struct AnimationUpdate {
    bool posed = false;      // the pose changed: items, lights or cameras may have moved
    bool deform = false;     // the deform pass must run with state.frameData
    bool restore = false;    // anim.enabled went off: the posed buffers take the stored streams
    std::vector<uint32_t> movedItems; // items whose world matrix or bounds changed
    bool lightsMoved = false;
};

// The pose at clock time `clock` (seconds since playback started: anim.time + anim.speed x
// clock while anim.play, anim.time while paused), applied to `scene`'s items, lights and cameras
// and written into state.frameData. Does nothing (returns posed = false) for a scene without
// animation or when the pose equals the last one.
AnimationUpdate animateScene(GpuScene& scene, const RenderSettings& settings, double clock, AnimationState& state);

} // namespace pnb::player
