// frame_context.h — what every pass of one frame shares: the scene, the settings, the view, the
// targets, the stream ring, the visible draws sorted into lists, the timer and the built-in
// programs. Subsystem state (shadows, GI, lights, sky) is not here: a pass receives the
// subsystems it uses as arguments from the frame list (renderer/frame.cpp), so what each pass
// reads and writes shows in its signature. Passes are free functions (pass_*.cpp), one per file.
#pragma once

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "frame/frame_targets.h"
#include "gl/stream_ring.h"
#include "pnb_player/renderer.h"
#include "shared/frame_block.h"   // FrameBlock (GLSL and C++)

namespace pnb::player {

// One visible item: where its ObjectBlock lives in the ring, its view depth for sorting, and the
// level of detail drawn.
struct DrawRef {
    uint32_t item = 0;
    float viewDepth = 0;      // distance of the bounds' centre along the view direction
    size_t objectOffset = 0;  // ObjectBlock in the stream ring
    uint32_t level = 0;       // index into GpuScene::levels (not the item's level number)
};

// Levels of detail (lod_selection.cpp). One choice per item and frame, made for the main view
// and used by every pass that draws the item (main, shadow maps, RSM): the shadow maps then hold
// the very surface that is lit, so receiver biases tuned for full detail still hold, and a
// caster stays one draw for all its cascades. Both vectors stay empty while the scene has no
// LODs (nothing is selected; every item draws level 0).
struct LodState {
    std::vector<uint8_t> selected; // per item: the rule's level, hysteresis applied (its state)
    std::vector<uint8_t> drawn;    // per item: `selected` after lod.bias / lod.force
};

// Updates `lod` for this frame's view (the viewport height and vertical field of view) and
// counts the items whose drawn level changed into stats.lodSwitches. Visits GpuScene::lodItems
// only; a scene without LODs returns at once.
void selectLevels(const GpuScene& scene, const ViewMatrices& view, uint32_t viewportHeight,
                  const RenderSettings& settings, LodState& lod, FrameStats& stats);

// The direction light `l` travels this frame: directional lights turned about +Y by
// lighting.sun_turn_deg, the rest as the container placed them.
inline glm::vec3 lightDirection(const SceneLight& l, const RenderSettings& s) {
    if (l.desc.type != LightType::Directional || s.sunTurnDeg == 0.0f) return l.direction;
    const float a = glm::radians(s.sunTurnDeg), c = std::cos(a), sn = std::sin(a);
    return {c * l.direction.x + sn * l.direction.z, l.direction.y, -sn * l.direction.x + c * l.direction.z};
}

// The GpuScene::levels index item `item` draws this frame.
inline uint32_t drawLevel(const GpuScene& scene, const LodState& lod, uint32_t item) {
    return scene.items[item].firstLevel + (lod.drawn.empty() ? 0u : uint32_t(lod.drawn[item]));
}

struct DrawLists {
    std::vector<std::vector<DrawRef>> layers; // parallel to GpuScene::deferredLayers
    std::vector<DrawRef> forwardOpaque;       // front to back
    std::vector<DrawRef> forwardBlended;      // back to front
    uint32_t visible = 0, culled = 0;
};

// Culls, writes one ObjectBlock per visible item into the ring, and sorts into `lists` (reused
// frame to frame, so its vectors keep their capacity).
void buildDrawLists(const GpuScene& scene, const ViewMatrices& view, const LodState& lod, bool cull,
                    StreamRing& ring, DrawLists& lists);

// One ObjectBlock (interface.glsl) for `item` into the ring; `casterIndex` is the shadow pass's
// index into the caster masks (uObjectParams.y). Returns its ring offset.
size_t pushObjectBlock(const GpuScene& scene, const DrawItem& item, const glm::dmat4& toCamera,
                       StreamRing& ring, float casterIndex);

struct BuiltinPrograms {
    GlHandle fxaa, debugView, flat, shadowDebug, background, depthOnly;
    GlHandle emptyVao; // full-screen passes draw without attributes
};

// The CPU side of a frame: what the subsystems' plan steps read. Holds no GL object, so a plan
// step is tested without a context (tests/player/frame_plan_test.cpp).
struct FrameView {
    const GpuScene& scene;
    const RenderSettings& settings;
    const ViewMatrices& view;
    const LodState& lod;
    uint32_t width = 0, height = 0; // the render size
    bool warmUp = false;
};

struct FrameContext {
    const GpuScene& scene;
    const RenderSettings& settings;
    const ViewMatrices& view;
    FrameTargets& targets;
    StreamRing& ring;
    const DrawLists& lists;
    FrameStats& stats;
    GpuTimer& timer;
    BuiltinPrograms& builtins;
    size_t objectBlockBytes = 0;
    const LodState& lod;
    size_t frameBlockOffset = 0; // this frame's FrameBlock in the ring (binding 0)
    // Renderer::warmUp's frame: nothing culled, every draw cut to its first triangle.
    bool warmUp = false;
};

// Binds material state and draws `refs` with each material's own program (or the one
// `materialProgram` names: the RSM's), or with `program` if non-zero (depth-only and debug
// draws). Back faces are culled where the material is single-sided, unless `twoSided` (the RSM:
// what the sun hits first is what it lights, whichever side). Counts draws and triangles.
void drawItems(FrameContext& ctx, std::span<const DrawRef> refs, GLuint program = 0,
               uint32_t GpuMaterial::*materialProgram = &GpuMaterial::program, bool twoSided = false);

// Every opaque or masked item (translucent ones let light and sky through) at the main view's
// level of detail, its object block pushed with `toView` (scene-wide passes: the sky's height
// map, the GI probes' occupancy grid).
std::vector<DrawRef> opaqueDrawRefs(FrameContext& ctx, const glm::dmat4& toView);

// The indices a draw of `count` issues: all, or the first primitive's in a warm-up frame (the
// driver generates code at the draw, whatever it rasterises).
inline uint32_t warmUpCount(const FrameContext& ctx, uint32_t count) {
    return ctx.warmUp ? std::min(count, 3u) : count;
}

// Full-screen triangle (fullscreen.vert: no vertex buffer).
void drawFullscreenTriangle();

inline FrameView frameView(const FrameContext& ctx) {
    return {ctx.scene, ctx.settings, ctx.view, ctx.lod, ctx.targets.width, ctx.targets.height, ctx.warmUp};
}

} // namespace pnb::player
