// make_stream_scene.h — what pnb-make-stream-scene's files share: the options
// (make_stream_scene_main.cpp parses them), the texel generator (make_stream_scene_textures.cpp),
// the meshes and rocks (make_stream_scene_geometry.cpp) and the layout and writing of the scene
// (make_stream_scene_layout.cpp). Internal to the tool; make_stream_scene_main.cpp's header
// comment describes what it makes.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "pnb/chunks.h"
#include "pnb/scene.h"
#include "pnb/scene_builder.h"
#include "pnb_converter/mesh_processing.h"

namespace stream_scene {

using namespace pnb;

inline constexpr int kExitUsage = 1;
inline constexpr int kExitWrite = 2;
inline constexpr int kExitInternal = 3;

// [SECTION] command line (make_stream_scene_main.cpp)

struct Options {
    std::string output;
    uint64_t sizeBytes = 0;    // 0 = use textures
    uint32_t textures = 0;     // 0 = derive from sizeBytes
    uint32_t textureSize = 2048;
    float spacing = 6.0f;
    float speed = 5.0f;
    bool shadows = true;
    bool checksums = true;
    unsigned threads = 2;
    bool quiet = false;
    bool lodRocks = false;
    uint32_t rockTriangles = 20000;
    bool rockTrianglesGiven = false;
};

// [SECTION] the scene (make_stream_scene_layout.cpp)

// Lays out the scene for `o`, writes it to o.output and prints the summary unless o.quiet.
// Returns an exit code (0, kExitUsage, kExitWrite or kExitInternal).
int run(const Options& o);

// [SECTION] texels (make_stream_scene_textures.cpp)

// Levels of a full mip chain of `size` texels a side (1 for size 1).
uint32_t mipCountFor(uint32_t size);

// Bytes one TMIP chunk adds to the file: chunk header + payload (16 bytes of fields, the blob's
// u64 size, padding to 16, texels), aligned, plus its TOC entry.
inline constexpr uint64_t kTmipPrefix = 32;
inline constexpr uint64_t kTocEntryBytes = 40;
uint64_t tmipFileBytes(uint32_t w, uint32_t h);

// Linear [0,1] -> sRGB byte, through a table fine enough that every byte is reachable.
class SrgbEncoder {
public:
    SrgbEncoder() {
        for (size_t i = 0; i < kSteps; ++i) {
            double l = double(i) / double(kSteps - 1);
            double s = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
            mTable[i] = uint8_t(std::lround(std::clamp(s, 0.0, 1.0) * 255.0));
        }
    }
    uint8_t operator()(float linear) const {
        float c = std::clamp(linear, 0.0f, 1.0f);
        return mTable[size_t(c * float(kSteps - 1) + 0.5f)];
    }

private:
    static constexpr size_t kSteps = 16384;
    std::array<uint8_t, kSteps> mTable{};
};

// One TMIP payload, built in place: the fields, the blob header, then the texels generated
// straight into the payload (no second copy). The layout is checked against encodeChunk for
// every small level (see checkPayload).
struct MipJob {
    uint32_t texture = 0, level = 0, size = 0;
    std::vector<std::byte> payload;
};

// Fills job.payload for job.texture, job.level and job.size (the texels at their own
// resolution, no full chain held). Reentrant: the producer thread calls it.
void buildMip(MipJob& job, uint32_t textureSize, const SrgbEncoder& srgb);

// The hand-made layout must be encodeChunk's.
bool checkPayload(const MipJob& job);

// [SECTION] geometry (make_stream_scene_geometry.cpp)

inline Vec3 add(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 scale(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// The rotation taking unit vector a to unit vector b (not antiparallel).
Vec4 rotationBetween(Vec3 a, Vec3 b);
// A turn of `radians` about +Y.
inline Vec4 yawRotation(float radians) {
    return {0, std::sin(radians / 2), 0, std::cos(radians / 2)};
}

struct MeshData {
    std::vector<float> positions, normals, uvs;
    std::vector<uint16_t> indices;
    Aabb bounds;
};

// A box centred on the origin with half extents h; every face shows the whole texture upright
// as seen from outside (v = 0 at the top, glTF convention).
MeshData makeBox(Vec3 h);

// The ground quad from (x0, z0) to (x1, z1) at y = 0, facing +Y (z1 < z0).
MeshData makeGround(float x0, float x1, float z0, float z1);

// A container mesh of `d` with one submesh of `material`; the streams are kept in `b`.
Mesh toMesh(SceneBuilder& b, const std::string& name, const MeshData& d, uint32_t material);

// The world box of `local` turned by `yaw` about +Y, then moved by t.
Aabb placed(Aabb local, float yaw, Vec3 t);

// [SECTION] rocks (--lod-rocks; make_stream_scene_geometry.cpp)

using ProcessedRock = Result<converter::ProcessedMesh, converter::ConvertError>;

// Rock `index` (made from the index alone: the same on any thread) through the converter's mesh
// pipeline with pnb-convert's --lods 4 settings.
ProcessedRock processRock(uint32_t index, uint32_t triangles, uint32_t material);

} // namespace stream_scene
