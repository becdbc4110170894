// upload.h — GL object creation for the loader: one function per resource kind, each taking the
// decoded chunk (whose blobs still point into the mapping).
#pragma once

#include "pnb/scene.h"
#include "pnb_player/gpu_scene.h"

namespace pnb::player {

// Immutable storage for all levels; no texels yet (mips arrive as separate TMIP chunks).
PlayResult<GpuTexture> createTexture(const TextureDesc& desc, uint32_t index);
// One level (all faces of a cube map) from the chunk's bytes.
void uploadTextureMip(const GpuTexture& texture, const TextureDesc& desc, const TextureMip& mip);

// One buffer holding every stream and the indices, and a vertex array describing them.
PlayResult<GpuMesh> uploadMesh(const Mesh& mesh, uint32_t index);

} // namespace pnb::player
