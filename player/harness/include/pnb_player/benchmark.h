// pnb_player/benchmark.h — deterministic fly-throughs that write timings, plots and images.
//
// In pnb_play_harness (player/harness/), beside the tools: the renderer library pnb_player writes
// no file and starts no process; this harness does both (tests/player/renderer_writes_test.py).
//
// The camera follows one of the container's camera paths. With a fixed time step, frame k is
// always rendered at path time k*dt, so two configurations can be compared frame by frame and
// image by image; without it, the path advances with the wall clock (what a viewer would see).
//
// Output directory:
//   frames.csv     one row per frame: path time, CPU ms, GPU ms per pass and total, draw calls,
//                  triangles, visible/culled items, deferred layers drawn, camera position and
//                  vertical field of view (camera_x/y/z, camera_yfov_deg), the render thread's
//                  CPU time (thread_cpu_ms: where shader code generation shows, FrameStats),
//                  items whose level of detail changed (lod_switches); the wall time from this
//                  frame's start to the next one's (frame_ms: what stalls are counted on); with
//                  streaming (BenchOptions::stream), the stream's update time (stream_ms), texel
//                  bytes uploaded and storage given back (stream_upload_bytes,
//                  stream_evicted_bytes), budgeted storage (textures, LOD meshes) resident and needed
//                  (resident_bytes, needed_bytes), bytes of the container read so
//                  far (bytes_read) and whether it was still streaming (streaming: 1 until the
//                  stream is complete)
//   summary.json   min/median/p95/max per pass and for CPU time; load-time split; time to first
//                  frame and its split (startup_times.h, when given); GPU memory by category;
//                  machine, GL vendor/renderer/version; resolution; every setting; triangles
//                  and shadow triangles per frame (min/median/p95/max, sum); LOD switches; peak
//                  resident memory of the process (peak_rss_bytes); with streaming, "streaming":
//                  time to full quality, bytes read at the first frame, uploads per frame,
//                  evictions, re-reads, mesh proxies replaced by their detail, stalls (frames over 2x the median frame_ms) and frame_ms
//                  p95 while streaming and after, peak budgeted storage (textures, LOD meshes), and
//                  peak GPU bytes (that peak plus meshes, material blocks and frame targets)
//   frame_times.png  per-pass stacked GPU time and CPU time along the path (player/tools/
//                  plot_frames.py, needs python3-matplotlib; skipped with a warning otherwise)
//   screenshots and dumps asked for (PNG for colour, EXR for float buffers)
//   quality.csv    with a QualityHook: the hook's metrics for the frames it measured, taken on a
//                  replay of the same frames after the timed run (so measuring costs no timing);
//                  summary.json then has mean/median/p95/max of each under "quality"
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pnb_player/gl_context.h"
#include "pnb_player/gpu_scene.h"
#include "pnb_player/renderer.h"
#include "pnb_player/save_capture.h"  // saveCapture, for the captures asked for
#include "pnb_player/scene_cameras.h" // initialCamera, where a run starts
#include "pnb_player/scene_stream.h"
#include "pnb_player/startup_times.h"

namespace pnb::player {

struct CaptureRequest {
    CaptureBuffer buffer = CaptureBuffer::Color;
    uint32_t frame = 0;
    std::string path; // .png for Color, .exr otherwise
};

// Image-quality metrics a caller computes on a replay of the run (pnb-play: shadows against the
// ray-traced reference). Every `every`-th frame k is rendered again and measured, then the view
// 1/60 s later along the path is measured with followUp = true (for temporal metrics such as
// flicker between consecutive displayed frames).
struct QualityHook {
    uint32_t every = 0; // 0: no quality pass
    std::function<PlayResult<std::vector<std::pair<std::string, double>>>(uint32_t frame, Renderer&,
                                                                          bool followUp)>
        measure;
};

struct BenchOptions {
    std::string pathName;        // "" = the container's first camera path
    std::optional<CameraState> staticCamera; // set: no path, this camera for every frame
    uint32_t frames = 0;         // 0 = as many as the path (or `seconds`) takes
    double seconds = 0;          // stop after this much path time; 0 = the whole path
    uint32_t lastFrame = ~0u;    // stop after this frame (captures without a full run)
    bool fixedDt = false;        // frame k at path time k * dt
    double dt = 1.0 / 60.0;      // with fixedDt (when `frames` is given: duration / frames)
    uint32_t width = 512, height = 288;
    std::string outDir;          // "" = no files (tests)
    std::vector<CaptureRequest> captures;
    bool plot = true;
    std::string sceneFile, commandLine; // recorded in the summary
    QualityHook quality;
    std::optional<StartupTimes> startup; // pnb-play's time to first frame, for summary.json
    SceneStream* stream = nullptr;       // streaming: update() before every frame, and its figures
    // Called after every frame with (frames done, frames planned; 0 when the path's time decides)
    // and the seconds since the run began: pnb-play shows progress on a terminal.
    std::function<void(uint32_t done, uint32_t planned, double seconds)> progress;
};

struct PassSummary {
    std::string pass;
    double min = 0, median = 0, p95 = 0, max = 0;
};

struct BenchResult {
    uint32_t frames = 0;
    std::vector<PassSummary> gpu; // per pass, then "total"
    PassSummary cpu;
    std::vector<std::string> written; // files, in the order written
    // The frame check: pixels of the last frame's HDR buffer that are NaN or infinite (also in
    // summary.json "frame_check"), and one warning per frame or buffer found with any.
    size_t nonFinitePixels = 0;
    std::vector<std::string> warnings;
};

// Renders the fly-through with `renderer` in the current context. `present` (optional) shows
// each frame (window mode) and returns false to stop early.
PlayResult<BenchResult> runBenchmark(const GpuScene& scene, Renderer& renderer,
                                     const BenchOptions& options, const LoadStats& load,
                                     const GlInfo& gl,
                                     const std::function<bool()>& present = {});

} // namespace pnb::player
