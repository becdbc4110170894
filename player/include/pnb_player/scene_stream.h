// pnb_player/scene_stream.h — streaming playback: the first frame is drawn as soon as the
// container's structure and each texture's smallest mip are in, and the texels stream in while
// frames are drawn (docs/PLAYER.md "Streaming").
//
// The container's order makes this possible (docs/FORMAT.md §4.1): everything but the texels
// comes first, and the texels (TMIP) come last, smallest level first across all textures. A
// loader thread reads the file front to back — a pipe or socket as well ("-": standard input) —
// and decodes and checks each chunk (stream_loader.h). open() takes the structure: meshes and
// materials are uploaded, programs compiled, and each texture's smallest level uploaded. From
// then on update(), once per frame before rendering, moves at most `uploadBytesPerFrame` of
// texels through a persistently mapped staging ring into the textures. A texture's
// GL_TEXTURE_BASE_LEVEL is its finest complete level, so a level becomes visible in the frame
// its last rows are uploaded (GL orders the copy before the draws) and never half-done.
//
// With a texture budget, each texture keeps storage only for the levels a view needs (a CPU
// estimate from the camera: player/math/mip_need.h) — a GL texture is re-created with a longer
// or shorter chain and its levels copied on the GPU — and the least recently needed levels are
// given up when the budget is short (player/math/texture_residency.h). Levels given up, or
// skipped as they streamed past, are read again from the file when needed; from a pipe they
// cannot be (StreamStatus::lostLevels).
//
// Meshes: the first frame draws each MESH chunk; a mesh the converter wrote with levels of
// detail is there a coarse proxy (its coarsest level), and its full detail (MDET, right after
// the textures' smallest levels) replaces it during the following frames, uploaded through the
// same staging ring within the same per-frame bytes, before any texels. Under a budget such a
// mesh is a two-level chain beside the textures' (the proxy always resident, the detail with
// it): the detail is needed while the LOD rule at the camera would draw any of its items finer
// than the proxy (its coarsest level's error, projected, over lod.threshold_px); a detail not
// needed is skipped as it streams past or given up (the proxy drawn again), and read again
// from the file when needed.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "pnb_player/camera.h"
#include "pnb_player/gpu_scene.h"

namespace pnb::player {

struct RenderSettings;

struct StreamOptions {
    bool verifyChecksums = true;
    uint64_t uploadBytesPerFrame = uint64_t(8) << 20; // stream.upload_mib
    uint64_t budgetBytes = 0; // stream.budget_mib: texture storage + LOD meshes' buffers; 0: no limit
    uint64_t readAheadBytes = uint64_t(64) << 20;      // decoded texels waiting, at most
    // The renderer's LOD rule (lod.threshold_px, lod.bias, lod.force): under a budget, a mesh's
    // detail is needed where the rule would draw finer than its proxy. A negative bias or a
    // forced level needs every detail (conservative).
    float lodThresholdPx = 1.0f;
    int lodBias = 0, lodForce = -1;

    // Sets budgetBytes, uploadBytesPerFrame (at least 1) and the LOD rule from the settings.
    void applySettings(const RenderSettings& settings);
};

// What one update() did.
struct StreamFrameStats {
    uint64_t uploadedBytes = 0; // texels copied through the staging ring
    uint64_t evictedBytes = 0;  // storage given back (texture levels, mesh details)
    uint32_t levelsCompleted = 0, evictions = 0, growths = 0, refetches = 0;
    uint32_t meshesCompleted = 0; // proxies replaced by their full detail
};

struct StreamStatus {
    uint64_t fileBytes = 0;  // 0 when unknown (a pipe)
    uint64_t bytesRead = 0;  // by the forward pass so far
    uint64_t firstFrameBytesRead = 0; // when markFirstFrame() was called
    // The budget's measure: texture storage, and the buffers of the meshes with levels of detail
    // whose full detail has been seen (proxy, and detail while resident).
    uint64_t residentBytes = 0;     // alive now
    uint64_t residentMeshBytes = 0; // of which the meshes'
    uint64_t neededBytes = 0;       // what the current view needs
    uint64_t peakBytes = 0;         // most alive at once, re-creations included
    uint64_t fullBytes = 0;         // every texture's whole chain, every such mesh at full detail
    uint64_t uploadedBytes = 0, evictedBytes = 0;
    uint32_t evictions = 0, refetches = 0;
    uint32_t meshesReplaced = 0; // proxies replaced by their full detail (MDET) so far
    uint32_t lostLevels = 0; // texture levels or mesh details needed again after being skipped,
                             // but the input is a pipe
    bool readDone = false;   // the forward pass reached the end of the container, intact
    // Full quality: with a budget, every texture holds the levels the view needs and every mesh
    // whose detail it needs has it; without one, every level of every texture and every mesh's
    // full detail is in (the forward pass has ended).
    bool complete = false;
    StreamFrameStats frame;  // the last update()
};

class SceneStream {
public:
    // Reads `path` ("-": standard input) until the first frame can be drawn: the scene's
    // structure uploaded, its programs compiled, every texture's smallest level in. Fills the
    // phases of `stats` it has (open, decode = waiting for the structure, upload, compile;
    // totalMs = all of them). Errors: Input (a damaged container: the chunk and its offset), Gl.
    struct Opened;
    static PlayResult<Opened> open(const std::string& path, const StreamOptions& options,
                                   LoadStats* stats = nullptr);
    ~SceneStream();
    SceneStream(const SceneStream&) = delete;
    SceneStream& operator=(const SceneStream&) = delete;

    // Once per frame before rendering `camera` at width x height: plans residency, takes the
    // levels read since, uploads up to the per-frame bytes. Errors: Input when the loader met a
    // damaged or truncated chunk (the chunk and offset): stop drawing; nothing damaged was
    // uploaded.
    PlayResult<Done> update(const CameraState& camera, uint32_t width, uint32_t height);
    const StreamStatus& status() const { return mStatus; }
    // Records how much of the container had been read when the first frame was finished.
    void markFirstFrame();
    const StreamOptions& options() const { return mOptions; }
    // Takes the budget, the per-frame bytes and the LOD rule from `settings` (stream.*, lod.*);
    // takes effect next update.
    void setLimits(const RenderSettings& settings);

private:
    struct Impl;
    SceneStream();
    std::unique_ptr<Impl> mImpl;
    StreamOptions mOptions;
    StreamStatus mStatus;
};

// The scene and the stream that fills it: the stream holds a reference to the scene, so it is
// declared after it (destroyed first).
struct SceneStream::Opened {
    std::unique_ptr<GpuScene> scene;
    std::unique_ptr<SceneStream> stream;
};

} // namespace pnb::player
