// pnb_player/renderer.h — draws a GpuScene: layered deferred + forward shading (seed 003) into an
// HDR target, tone mapping to sRGB, optional FXAA and debug views.
//
// The frame (one pass per file, src/pass_*.cpp):
//   0. pick each draw item's level of detail by its projected simplification error (scenes
//      converted with --lods; one choice per item, used by every pass: player/math/lod_select.h);
//   1. cull draw items against the view frustum (world AABBs, camera-relative);
//   2. for each deferred layer in ascending priority that has visible items: clear the G-buffer
//      colour but keep the shared depth, draw the layer (opaque front-to-back, layers holding
//      translucent materials back-to-front), compose its lighting into the HDR target with
//      alpha blending and depth writes off. Empty layers cost nothing;
//   3. forward materials against the same depth: opaque front-to-back, then blended
//      back-to-front with depth writes off;
//   4. tone map (exposure, ACES fit) into an sRGB target; FXAA; or a debug view instead.
//
// Allocation follows the scene: no G-buffer without deferred materials, no FXAA target unless
// enabled, debug-view targets only while a debug view is on. GPU memory is accounted by category.
//
// Threading: one GL context, one thread.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pnb_player/camera.h"
#include "pnb_player/gpu_scene.h"
#include "pnb_player/gpu_timer.h"
#include "pnb_player/settings.h"

namespace pnb::player {

struct FrameStats {
    uint64_t frame = 0;
    double cpuMs = 0;          // CPU time to record and submit the frame
    // CPU time of the calling thread inside render(): the driver's work on this thread (state
    // validation, shader code generation at a state's first draw; on llvmpipe also vertex
    // processing) but not rasterisation, which runs on the driver's own threads. Unlike cpuMs it
    // barely moves when other processes compete for the cores, so code-generation spikes stand out.
    double threadCpuMs = 0;
    uint32_t drawCalls = 0;
    uint64_t triangles = 0;    // submitted, at the levels of detail drawn
    uint32_t lodSwitches = 0;  // items whose level of detail changed since the last frame
    uint32_t visibleItems = 0, culledItems = 0;
    uint32_t deferredLayersDrawn = 0; // layers with visible items (each: one clear, one compose)
    // Shadows: draw calls and triangles of the shadow pass (triangles counted once per cascade
    // they are rasterised into; SDSM's GPU-culled draws count as issued), casters drawn.
    uint32_t shadowDraws = 0, shadowCasters = 0;
    uint64_t shadowTriangles = 0;
    uint32_t gpuReadbacks = 0; // GPU->CPU reads that wait for the GPU (captures only)
    // Light clusters (lights.*): tiles x slices this frame; 0 when every pixel shaded every light.
    uint32_t lightClusters = 0;
    // Point and spot light shadows: tiles in use and tiles drawn this frame (cached ones are not).
    uint32_t localShadowTiles = 0, localShadowTilesDrawn = 0;
    uint32_t localShadowDraws = 0; // their draws and triangles (not in shadowDraws/Triangles: the sun's)
    uint64_t localShadowTriangles = 0;
    // Animation (docs/PLAYER.md "Animation"): the deform pass's dispatches and vertices (0 when
    // the pose did not change), and the draw items the pose moved this frame.
    uint32_t deformDispatches = 0;
    uint64_t deformVertices = 0;
    uint32_t movedItems = 0;
    double animationTime = 0; // the pose's clip time, seconds (0 without a clip)
};

struct TargetMemory {
    uint64_t gbufferBytes = 0;   // colour attachments of the one G-buffer (depth is shared)
    uint64_t depthBytes = 0;
    uint64_t hdrBytes = 0;
    uint64_t outputBytes = 0;    // sRGB output (+ FXAA intermediate)
    uint64_t debugBytes = 0;
    uint64_t streamingBytes = 0; // per-frame uniform/storage ring
    uint64_t shadowMapBytes = 0; // the cascade array: resolution^2 x cascades x 4 B (D32F)
    uint64_t shadowBufferBytes = 0; // SDSM state, GPU-written block, masks, indirect draws
    uint64_t giBytes = 0;           // RSM, light and geometry volumes, injection buffers
    uint64_t iblBytes = 0;          // the sky-visibility height map (ibl.visibility = height)
    uint64_t localShadowBytes = 0;  // point and spot light shadow atlas (D32F side^2), 0 if none
    // Blended casters' colour companions of the cascade array and the local atlas (RGBA8
    // transmittance + R32F nearest depth: 8 B a texel), 0 without blended casters
    uint64_t shadowTranslucentBytes = 0;
    uint64_t lightClusterBytes = 0; // light cluster masks, 0 while every pixel shades every light
    uint64_t total() const {
        return gbufferBytes + depthBytes + hdrBytes + outputBytes + debugBytes + streamingBytes +
               shadowMapBytes + shadowBufferBytes + giBytes + iblBytes + localShadowBytes +
               lightClusterBytes + shadowTranslucentBytes;
    }
};

// Exact buffers for comparison with ground truth (rows bottom-up, as GL returns them).
enum class CaptureBuffer {
    Color,  // sRGB output, RGBA8 (what is shown)
    Hdr,    // linear HDR radiance, RGBA float
    Depth,  // reversed-Z depth buffer, 1 float
    LinearDepth, // view-space distance along -Z, 1 float (infinity where nothing was drawn)
    Normal, // world normal of the last deferred layer, 3 floats (0 where none)
    Position, // camera-relative world position from depth, 3 floats (NaN where nothing was drawn)
    Shadow, // re-renders the last frame's view with lighting writing, per pixel: sun visibility
            // (1 lit .. 0 shadowed; -1 unclassified: no geometry or facing away), cascade index
            // (-1 none) and shadow-texel / screen-pixel world size; 4 floats (alpha 1). With
            // blended casters (issue 43) the visibility is the opaque one x the mean transmittance
    ShadowColor, // re-renders the last frame's view with lighting writing the colour visibility of
                 // the judged light (the sun, or shadows.judged_light): opaque visibility x the
                 // transmittance of the blended casters toward it, rgb (-1: unclassified, as
                 // Shadow), at the surface whose depth the frame kept; 4 floats
    Indirect, // re-renders the last frame's view with lighting writing the irradiance GI adds
              // (rgb, lux like the sun's intensity; 0 without GI or geometry); 4 floats
    Sky,      // re-renders the last frame's view with lighting writing the sky irradiance it
              // applies: the environment's irradiance SH (rotated, times ibl.intensity) times
              // the sky-visibility term, before albedo and material occlusion (rgb, lux);
              // 0 without an active environment or where nothing was drawn; 4 floats
    GiVolume, // the summed light volume GI's look-up reads: width = cells, height =
              // cells * cells * cascades (x fastest, then y, then z; cascades stacked along z),
              // 12 floats per cell (R, G, B x 4 SH coefficients, radiance / sun irradiance);
              // empty (0 x 0) while GI is off
};

struct CapturedImage {
    uint32_t width = 0, height = 0, channels = 0;
    std::vector<uint8_t> u8;
    std::vector<float> f32;
};

// Pixels of a float capture with a NaN or infinite channel (0 for 8-bit captures): the frame
// check of headless runs (a light the shaders overflow on shows up here, not as a black image).
size_t nonFinitePixels(const CapturedImage& image);

// RenderSettings defaults with driverDefaults() of the current context's GL_RENDERER applied.
RenderSettings settingsForCurrentDriver();

// The instant a frame was drawn at (docs/PLAYER.md "Animation"): what a dump's frame.json
// records as "anim" and the ray-traced truth poses (docs/REFERENCE.md "Moving frames").
struct DrawnPose {
    bool enabled = false;         // the scene was posed (anim.enabled, a scene with animation);
                                  // false: the container as stored
    std::optional<uint32_t> clip; // the clip played; none: the rest pose
    std::string clipName;
    double clipTime = 0;          // seconds into the clip, as sampled (looped)
};

class Renderer {
public:
    // Compiles the player's built-in programs the scene needs; errors name the program. The
    // renderer poses an animated scene's items, lights and cameras each frame (the scene's
    // animation: scene_animation.h), so it takes the scene to change; a static scene is only read.
    static PlayResult<std::unique_ptr<Renderer>> create(GpuScene& scene, const RenderSettings& settings);
    ~Renderer();

    void setSettings(const RenderSettings& settings);

    // The playback clock: seconds since playback started, for the next frames (the pose is at
    // anim.time + anim.speed x clock while anim.play). Headless and benchmark runs set it to the
    // frame's fixed-step time, the window to its played wall time. Starts at 0.
    void setAnimationClock(double seconds);
    double animationClock() const;
    // The pose of the last frame: its time (anim.time + speed x clock) and its clip's time.
    double animationTime() const;
    DrawnPose drawnPose() const;
    const RenderSettings& settings() const { return mSettings; }

    // Renders one frame at width x height into the output target.
    PlayResult<Done> render(const CameraState& camera, uint32_t width, uint32_t height);

    // Makes the driver generate code for everything a frame of this scene can draw, before the
    // first frame (drivers such as llvmpipe compile a shader variant for the state a program is
    // first drawn with: framebuffer formats, blend, depth, bound texture formats, vertex layout).
    // Renders one frame at width x height through the real passes, with frustum culling off (so
    // every draw item, shadow caster and RSM item is drawn), each draw cut to its first triangle
    // and rasterisation scissored to one pixel; then waits for it (glFinish). Built-in and
    // lazily linked programs the settings use are made here too. Leaves nothing visible: the
    // next render() clears every target. Does nothing when startup.warmup is off. Later setting
    // changes (a debug view, another shadow technique) and a render size whose dimensions differ
    // in being powers of two are not covered.
    PlayResult<Done> warmUp(const CameraState& camera, uint32_t width, uint32_t height);

    // Copies the output to the default framebuffer of a window (after render()).
    void presentToWindow(int windowWidth, int windowHeight);

    PlayResult<CapturedImage> capture(CaptureBuffer buffer);

    // The sRGB output texture of the last frame (for a UI that shows it as an image), or 0.
    GLuint outputTexture() const;

    const FrameStats& lastFrame() const { return mStats; }
    // Why debug.view shows nothing in the last frame, naming what is missing ("" when it shows
    // something): pnb-play prints it, its window overlay shows it.
    const std::string& debugViewNote() const;
    GpuTimer& timer() { return mTimer; }
    TargetMemory targetMemory() const;
    // Debug-view helpers need the view of the last frame.
    const ViewMatrices& lastView() const { return mView; }
    // The camera of the last render() (to draw the same view again with other settings).
    const CameraState& lastCamera() const;

    struct Impl;

private:
    Renderer() = default;
    RenderSettings mSettings;
    FrameStats mStats;
    GpuTimer mTimer;
    ViewMatrices mView;
    std::unique_ptr<Impl> mImpl;
};

} // namespace pnb::player
