// pnb_player/gpu_scene.h — a container loaded onto the GPU, plus the CPU-side scene description
// the renderer needs each frame (draw items with world bounds, lights, cameras, paths).
//
// Loading (scene_load.cpp): map the file, verify payload checksums ("read"), decompress and
// decode chunks and check every cross-reference ("decode"), then create GL objects in file order
// straight from the mapping — uncompressed mesh and texel payloads are handed to the driver
// without an intermediate copy ("upload"), ending with glFinish so "GPU-ready" is real.
//
// World transforms are kept in double precision; the renderer subtracts the camera position
// before converting to float (camera-relative rendering).
//
// Streaming (scene_stream.h) fills the same GpuScene progressively: the textures' storage
// (GpuTexture::firstLevel, bytes) changes between frames.
//
// Animation (scene_animation.h): a scene with clips or deformed nodes carries what playing them
// needs; the renderer poses the items, lights and cameras each frame (Renderer::render), so
// those fields change between frames for animated nodes.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "pnb/chunks.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_player/gl_handles.h"
#include "pnb_player/play_error.h"
#include "pnb_player/scene_animation.h"

namespace pnb::player {

struct GpuTexture {
    GlHandle texture;
    uint32_t width = 0, height = 0, mipCount = 0; // the container's texture (level 0)
    uint32_t firstLevel = 0; // container level held as GL level 0 (streaming: the finest allocated)
    uint64_t bytes = 0;      // of the storage allocated (levels firstLevel..)
    bool trilinear = false; // mipmapped linear filtering: anisotropic filtering applies
};

struct GpuMesh {
    GlHandle buffer; // all streams, then the indices
    GlHandle vertexArray;
    GLenum indexType = GL_UNSIGNED_INT;
    uint32_t indexSize = 4;
    uint64_t indexOffset = 0; // bytes into `buffer`
    GLenum primitive = GL_TRIANGLES;
    glm::vec3 dequantScale{1}, dequantOffset{0};
    bool octahedralNormals = false;
    std::vector<Submesh> submeshes;
    uint64_t bytes = 0;
};

struct GpuMaterial {
    Material desc;
    std::string name;
    uint32_t program = kNone;    // index into GpuScene::programs (= the PROG chunk index)
    // GI: the G-buffer program the reflective shadow map draws it with (the material's own if
    // deferred; kNone for blended materials or a container without GI).
    uint32_t rsmProgram = kNone;
    uint32_t uniformOffset = 0;  // bytes into GpuScene::materialBuffer
    bool translucent() const { return desc.alphaMode == AlphaMode::Blend; }
};

// One level of detail of a draw item: an index range of its mesh (docs/FORMAT.md "MESH").
struct DrawLevel {
    uint32_t submesh = 0;               // index into GpuMesh::submeshes
    uint32_t firstIndex = 0, indexCount = 0; // as the submesh's
    uint32_t triangles = 0;
    // Submesh::lodError made nondecreasing along the chain (a level is taken to be at least as
    // wrong as any finer one), mesh units; 0 for level 0.
    float error = 0;
};

// One level-0 submesh of one mesh instance, with its simplified levels: the unit the renderer
// culls, sorts, picks a level for and draws. A scene without LODs has levelCount = 1 everywhere.
struct DrawItem {
    uint32_t node = 0, mesh = 0, material = 0; // mesh: GpuScene::meshes, a posed mesh for a
                                               // deformed node (scene_animation.h)
    uint32_t containerMesh = 0; // the container's MESH index (= mesh unless the node deforms)
    uint32_t firstLevel = 0, levelCount = 1; // GpuScene::levels[firstLevel ..], level 0 first
    glm::dmat4 world{1.0};
    glm::mat3 normalMatrix{1.0f}; // inverse-transpose of world's 3x3 (no translation: float is fine)
    glm::dvec3 boundsMin{0.0}, boundsMax{0.0}; // world-space AABB of the level-0 submesh
    double worldScale = 1.0;      // largest stretch of world's 3x3: mesh units -> world units
    bool mirrored = false;        // world's 3x3 has a negative determinant (an odd number of
                                  // negative scales): the winding flips, so front faces are CW
    // The copies of one EXT_mesh_gpu_instancing node's submesh share a group (kNone: none):
    // the main view draws the visible copies of a group that meet in its lists as one instanced
    // draw (draw_lists.cpp); culling, LOD, shadows and GI still see each copy as an item.
    uint32_t instanceGroup = 0xFFFFFFFFu;
    uint32_t triangles = 0;       // at level 0
};

struct SceneLight {
    Light desc;
    std::string name;
    glm::dvec3 position{0.0};
    glm::vec3 direction{0, 0, -1}; // the direction light travels (node's -Z)
};

struct SceneCamera {
    Camera desc;
    std::string name;
    glm::dvec3 position{0.0};
    glm::dquat rotation{1, 0, 0, 0};
};

struct ScenePath {
    std::string name;
    CameraPath path; // keys copied out of the mapping
};

// The container's environment (ENVM): what image-based lighting and the background read.
struct GpuEnvironment {
    std::string name;                       // the image's file name or the sky model
    std::optional<uint32_t> radiance;       // indices into GpuScene::textures
    std::optional<uint32_t> specular, brdfLut;
    std::array<glm::vec3, 9> irradianceSh{}; // lux, FORMAT.md's basis, unrotated, intensity 1
    uint32_t specularLevels = 0;            // the cube's mip count (roughness m / (levels - 1))
};

struct GpuMemory {
    uint64_t meshBytes = 0, textureBytes = 0, uniformBytes = 0;
};

struct LoadStats {
    double openMs = 0;       // mmap + table of contents
    double readMs = 0;       // page in + checksum every payload
    double decodeMs = 0;     // decompress, decode, validate cross-references
    double compileMs = 0;    // shader programs (compile + link)
    double uploadMs = 0;     // buffers and textures, through glFinish
    double totalMs = 0;      // open to GPU-ready
    double firstFrameMs = 0; // time to first frame: exec to the first finished frame (pnb-play;
                             // its split is StartupTimes, startup_times.h)
    uint64_t fileBytes = 0, zeroCopyBytes = 0, decompressedBytes = 0;
    uint64_t hugePageBytes = 0; // heap reserved in 2 MiB pages for the driver's copy (upload_heap.h)
    std::string uploadPages;    // "N MiB in 2 MiB pages", or which pages and why (for the load line)
    uint32_t chunks = 0, unknownChunks = 0;
};

struct LoadOptions {
    bool verifyChecksums = true;
    // Called once the file is mapped and indexed, before any payload is read (progress
    // reporting; tests change the file at that, the worst, moment). Default: none.
    std::function<void()> afterOpen;
};

struct GpuScene {
    std::string name;
    Aabb bounds;
    std::vector<std::pair<std::string, std::string>> settings; // the RSET chunk

    std::vector<std::string> programLabels; // "gbuffer[HAS_UV0 ...]" per PROG chunk
    std::vector<GlHandle> programs;         // per PROG chunk; empty handle if not compiled
    std::optional<uint32_t> deferredLightingProgram, tonemapProgram;
    // The shadow pass's programs (present when the converter found a shadow-casting light and
    // caster; lighting programs are then built with SHADOWS).
    std::optional<uint32_t> shadowProgram, shadowMaskProgram;
    // Blended casters' program (shadow[TRANSLUCENT], issue 43); the lighting programs are then
    // built with TRANSLUCENT_SHADOWS (translucentLighting).
    std::optional<uint32_t> shadowTranslucentProgram;
    bool translucentLighting = false;
    // The lighting programs were built with GI (pnb-convert --gi): gi.enabled can take effect.
    bool giPrograms = false;
    // The lighting programs were built with IBL (a container with an environment).
    bool iblPrograms = false;
    std::optional<GpuEnvironment> environment;
    // Their stage sources and defines, kept so the player can link a geometry-shader variant
    // when the vertex shader cannot write gl_Layer (shadows.layer_from).
    struct KeptProgram {
        std::string label;
        std::vector<std::pair<GLenum, std::string>> stages;
        std::vector<std::string> defines;
    };
    std::vector<std::pair<uint32_t, KeptProgram>> shadowSources;

    std::vector<GpuTexture> textures;
    std::vector<GpuMaterial> materials;
    GlHandle materialBuffer; // one std140 MaterialBlock per material, at uniformOffset
    uint32_t materialStride = 0;
    std::vector<GpuMesh> meshes;
    std::vector<DrawItem> items;
    std::vector<DrawLevel> levels;   // every item's levels (DrawItem::firstLevel)
    std::vector<uint32_t> lodItems;  // items with more than one level: all LOD selection visits
    std::vector<SceneLight> lights;
    std::vector<SceneCamera> cameras;
    std::vector<ScenePath> paths;
    // Clips, skins and morph targets, and the deformed nodes' posed meshes (appended to
    // `meshes` after the container's); null for a scene that neither moves nor deforms.
    std::unique_ptr<SceneAnimation> animation;
    GpuMemory memory;
    uint64_t triangles = 0; // at level 0

    // Distinct deferred layer priorities in drawing order (ascending), and whether the scene
    // has forward materials: what the frame needs to allocate and run.
    std::vector<uint16_t> deferredLayers;
    bool hasForward = false;
    uint64_t materialsVersion = 0; // incremented by updateMaterials (renderers rebuild caster lists)
    uint64_t texelsVersion = 0;    // incremented when streaming changes a texture's resident levels

    const ScenePath* findPath(std::string_view pathName) const; // "" = the first
};

// What a cache of the whole scene's geometry compares (the sky's height map): changes with
// material edits and streamed levels (materialsVersion) and whenever the pose moves an item.
inline uint64_t geometryVersion(const GpuScene& scene) {
    return scene.materialsVersion + (scene.animation ? scene.animation->poseVersion : 0);
}

// Needs a current GL 4.5 context. Errors: Input (damaged or inconsistent container, naming the
// chunk and byte offset), Gl (a program does not compile).
PlayResult<std::unique_ptr<GpuScene>> loadScene(const std::string& path,
                                                const LoadOptions& options = {},
                                                LoadStats* stats = nullptr);

// The upload and compile phases alone, from a scene already decoded and validated (the
// material editor's document). Fills stats->uploadMs and compileMs.
PlayResult<std::unique_ptr<GpuScene>> uploadScene(const Scene& scene, LoadStats* stats = nullptr);

// Materials of `scene` changed (values, path, layer, program): rewrites the uniform blocks that
// differ, recomputes the layer layout once and compiles programs now needed from `scene` (which
// may hold more PROG chunks than when uploaded; existing indices must not change). Texture
// references must name uploaded textures.
PlayResult<Done> updateMaterials(GpuScene& gpu, const Scene& scene);

// Index of the light whose shadows the player renders (lighting::shadowingSunIndex: the first
// directional light that casts them), or -1.
int shadowingSun(const GpuScene& scene);

// Unit vector toward that light, +Y when the scene has none: what the benchmark's dumps and the
// truth judges give the ray tracer.
glm::vec3 towardShadowingSun(const GpuScene& scene);

} // namespace pnb::player
