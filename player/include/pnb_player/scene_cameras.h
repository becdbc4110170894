// pnb_player/scene_cameras.h — the cameras a run starts from, taken from the container.
//
// Pure camera logic (no GL, no files): the renderer's users (pnb-play's window and benchmark, the
// tests) all start from the same view, so it lives in the renderer, not in the harness.
#pragma once

#include <cstddef>
#include <string>

#include "pnb_player/camera.h"
#include "pnb_player/gpu_scene.h"

namespace pnb::player {

// The container's camera `index` (precondition: index < scene.cameras.size()).
CameraState sceneCamera(const GpuScene& scene, size_t index);

// The camera a run starts from: the path's first key, else the container's first camera, else
// one framing the scene bounds.
CameraState initialCamera(const GpuScene& scene, const std::string& pathName);

} // namespace pnb::player
