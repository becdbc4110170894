// upload.h — GL object creation for the loader: one function per resource kind, each taking the
// decoded chunk (whose blobs still point into the mapping).
#pragma once

#include "pnb/scene.h"
#include "pnb_player/gpu_scene.h"

namespace pnb::player {

// Immutable storage for the levels firstLevel.. of the container's texture (a streaming player
// keeps only the coarse end of a chain resident; GL level 0 is then container level
// firstLevel); no texels yet (mips arrive as separate TMIP chunks).
PlayResult<GpuTexture> createTexture(const TextureDesc& desc, uint32_t index, uint32_t firstLevel = 0);
// Bytes of one container level (all faces).
uint64_t textureLevelBytes(const TextureDesc& desc, uint32_t level);
// Rows firstRow.. of one face of container level `level` (rows of 4-pixel blocks for compressed
// formats: firstRow and rows are then multiples of 4, except a last partial block row), from
// `pixels` — client memory, or an offset into the bound GL_PIXEL_UNPACK_BUFFER.
void uploadTextureRows(const GpuTexture& texture, const TextureDesc& desc, uint32_t level,
                       uint32_t face, uint32_t firstRow, uint32_t rows, const void* pixels);
// One level (all faces of a cube map) from the chunk's bytes.
void uploadTextureMip(const GpuTexture& texture, const TextureDesc& desc, const TextureMip& mip);

// Where each of a mesh's byte ranges goes in its GL buffer: every stream at a 16-byte aligned
// offset, then the indices (the last segment).
struct MeshLayout {
    struct Segment {
        uint64_t offset = 0;
        Blob bytes;
    };
    std::vector<Segment> segments;
    uint64_t indexOffset = 0, size = 0;
};
MeshLayout meshLayout(const Mesh& mesh);

// One buffer holding every stream and the indices (meshLayout), and a vertex array describing
// them. Without data the buffer is left for the caller to fill (streaming: from its staging ring).
PlayResult<GpuMesh> uploadMesh(const Mesh& mesh, uint32_t index, bool withData = true);

// A deformed node's posed mesh (scene_animation.h): a buffer for the posed F32 position, normal
// and tangent streams, holding the stored ones until the deform pass first writes it, and a
// vertex array reading those from it and every other stream and the indices from `source` (the
// container's mesh, uploaded). Fills d's stream offsets (source and posed) and vertex count.
PlayResult<GpuMesh> createPosedMesh(const Mesh& mesh, const GpuMesh& source, DeformedNode& d, uint32_t index);

} // namespace pnb::player
