// scene_upload.h — the steps of uploadScene that the streaming loader (scene_stream.cpp) shares.
#pragma once

#include <memory>
#include <vector>

#include "pnb/scene.h"
#include "pnb_player/gpu_scene.h"

namespace pnb::player {

// Everything of `scene` but the texels and the programs: texture storage (texture i from
// container level firstLevels[i], or 0 where the vector is shorter), meshes (at full detail with
// `meshDetails`: an MDET replaces its proxy; else the MESH chunks as they are), materials, camera
// paths, draw items, lights and cameras, the layer layout. No glFinish.
PlayResult<std::unique_ptr<GpuScene>> uploadSceneWithoutTexels(const Scene& scene,
                                                                const std::vector<uint32_t>& firstLevels,
                                                                bool meshDetails);

// gpu.meshes[mesh] was replaced (streaming: a proxy by its full detail): its items take the new
// mesh's level chains (appended to gpu.levels), lodItems and triangle counts follow.
void replaceMeshLevels(GpuScene& gpu, uint32_t mesh);

// Compiles what the frame uses and is not compiled yet: the materials' programs, the lighting
// pass if anything is deferred, the tone mapper, the shadow and GI programs.
PlayResult<Done> compileNeededPrograms(const Scene& scene, GpuScene& gpu);

// The animation of `scene` (scene_animation.h), if it has clips or deformed nodes: a posed mesh
// per deformed node (appended to gpu.meshes; the node's items draw it, placed at the rest pose's
// pnb::drawingMatrix), the deform bounds, and which node places each item, light and camera.
// `itemCopy`: per item, its copy in meshInstances() order. Nothing for a static scene.
PlayResult<Done> setUpAnimation(const Scene& scene, const std::vector<uint32_t>& itemCopy, GpuScene& gpu);

} // namespace pnb::player
