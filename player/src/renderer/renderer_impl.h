// renderer_impl.h — the renderer's private state: the frame's shared parts and every subsystem's
// state between frames (renderer.cpp, frame.cpp, frame_capture.cpp). The one header that sees all
// subsystems: renderer/ is the top floor of player/src (docs/ARCHITECTURE.md).
#pragma once

#include <string>

#include "anim/deform.h"
#include "frame/frame_context.h"
#include "gi/gi.h"
#include "lights/light_clusters.h"
#include "pnb_player/renderer.h"
#include "shadows/local_shadows.h"
#include "shadows/shadow_maps.h"
#include "sky/ibl.h"

namespace pnb::player {

// The renderer's private state (renderer.cpp, frame_capture.cpp).
struct Renderer::Impl {
    GpuScene* scene = nullptr;
    DeformContext deform; // playback: the clock, the last pose, the deform pass's buffer
    FrameTargets targets;
    StreamRing ring;
    BuiltinPrograms builtins;
    DrawLists lists;   // this frame's visible draws
    std::vector<size_t> deferredLayers; // this frame's deferred layers with visible items
    ShadowContext shadows;
    GiContext gi;
    IblContext ibl;
    LodState lod;
    LightContext lights;
    LocalShadowContext localShadows;
    uint64_t shadowsForMaterials = ~0ull; // GpuScene::materialsVersion the casters were built for
    CameraState lastCamera;               // re-rendered for CaptureBuffer::Shadow
    GpuTimer captureTimer;                // times of capture renders (discarded)
    bool capturing = false;
    bool warming = false;                 // inside Renderer::warmUp
    float appliedAnisotropy = 1.0f;       // textures' GL_TEXTURE_MAX_ANISOTROPY (1 at upload)
    size_t alignment = 256;
    uint64_t frame = 0;
    std::string debugViewNote; // of the last frame (debugViewNote())
};

} // namespace pnb::player
