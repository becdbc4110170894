// shadow_maps.h — the sun's shadow maps: GPU resources, the per-frame fit, and the passes.
//
// One depth texture array holds every cascade (D32F, one layer per cascade). Per frame:
//   - CPU techniques (single, LiSPSM, PSSM) fit the matrices on the CPU (player/math/shadow_fit),
//     cull each caster against every cascade's light volume and write the ShadowBlock, the
//     casters' ObjectBlocks and their cascade masks into the stream ring;
//   - SDSM fits on the GPU (shadow_sdsm.cpp): reduce this frame's depth buffer, partition,
//     bound the samples per cascade in light space, build the matrices, cull the casters and
//     write indirect draws — all in GPU buffers, nothing read back;
//   - the shadow pass (pass_shadow.cpp) draws every caster once for all its cascades (layered:
//     instancing + gl_Layer from the vertex shader) or once per cascade (multi-pass).
// Lighting then reads the array through two views: a comparison sampler (PCF) and raw depth
// (PCSS blocker search).
// Blended casters (issue 43, only when the scene has some and shadows.translucent is on) give the
// array two colour companions on the same framebuffers: transmittance (sRGB8_A8, cleared to 1,
// blended dst x src) and the nearest pane's depth (R32F, cleared to 1, GL_MIN). The pass draws
// the opaque casters first, then the blended ones depth-tested against them without writing
// depth, so glass behind an opaque caster adds nothing.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "pnb_player/gl_handles.h"
#include "pnb_player/renderer.h"
#include "shadow_fit.h"
#include "shared/sdsm_caster.h"  // SdsmCasterData (GLSL and C++)
#include "shared/shadow_block.h" // kMaxCascades, ShadowBlock (GLSL and C++)

namespace pnb::player {

struct FrameContext;
struct FrameView;
class StreamRing;

// A shadow caster: a draw item drawn into the maps with the scene's `shadow` program, at the
// level of detail the main view chose for it this frame (LodState, frame_context.h).
struct ShadowCaster {
    uint32_t item = 0;
    uint32_t program = 0;     // GpuScene::programs index (shadow[], [ALPHA_MASK] or [TRANSLUCENT])
    bool translucent = false; // a blended caster: drawn after the opaque ones, into the companions
};

// The colour companions of a depth map (the cascade array or the local atlas): 2D arrays of the
// map's size and layers, colour attachments 0 and 1 of its framebuffers.
struct TranslucentMaps {
    GlHandle transmittance; // sRGB8_A8 (linear reads): product of the panes' T = baseColor.rgb x (1 - alpha)
    GlHandle nearestDepth;  // R32F: the nearest pane's depth (1 - z where the map is reversed-Z)
    uint64_t bytes = 0;
    explicit operator bool() const { return bool(transmittance); }
    void create(uint32_t width, uint32_t height, uint32_t layers, const char* label);
};

// Attaches `maps`' layer `layer` (or every layer, layer < 0) as colour attachments 0 and 1 of
// `framebuffer`, or detaches them (empty maps): drawing then writes depth only.
void attachTranslucentMaps(GLuint framebuffer, const TranslucentMaps& maps, int layer);

// Clears the companions bound to `framebuffer` to 1 (nothing in the way).
void clearTranslucentMaps(GLuint framebuffer);

// Blending and masks for the blended casters (dst x src; GL_MIN), after the opaque ones have
// drawn into the depth-only framebuffer; restoreOpaqueCasterState undoes it.
void beginTranslucentCasters();
void restoreOpaqueCasterState();

// Binds `maps` for lighting at `firstUnit` and the next unit, or, while they do not exist
// (shadows.translucent off, no blended caster in reach), `neutral`: 1x1 stand-ins (transmittance
// 1, nearest depth 1), created on first use, that lighting built with TRANSLUCENT_SHADOWS reads.
void bindTranslucentMaps(const TranslucentMaps& maps, TranslucentMaps& neutral, GLuint firstUnit);

struct ShadowResources {
    uint32_t resolution = 0, layers = 0;
    GlHandle depthArray;   // D32F array, comparison mode on (sampler2DArrayShadow)
    GlHandle depthView;    // the same texels without comparison (sampler2DArray)
    GlHandle layeredFb;    // the whole array (gl_Layer selects)
    std::vector<GlHandle> layerFbs; // one layer each (multi-pass)
    // SDSM (GPU fit), present only while technique = sdsm.
    GlHandle sdsmState, sdsmBlock, sdsmMasks, sdsmCommands;
    GlHandle sdsmReduce, sdsmPartition, sdsmBounds, sdsmFinalize, sdsmCull;
    uint32_t sdsmCasterCapacity = 0;
    TranslucentMaps translucent; // blended casters' companions (empty: none this frame)
    GlHandle translucentLayeredFb;   // the companions, every layer (the blended round)
    std::vector<GlHandle> translucentLayerFbs; // one layer each (multi-pass)
    uint32_t translucentDivisor = 1; // the companions' side = resolution / this
    uint64_t mapBytes = 0, bufferBytes = 0;

    // (Re)creates the array for `resolution` x `layers`, with the companions iff `translucent`;
    // drops the SDSM objects unless `sdsm`.
    PlayResult<Done> ensure(uint32_t resolution, uint32_t layers, bool sdsm, bool translucent, uint32_t divisor,
                            const std::vector<ShadowCaster>& casters, const GpuScene& scene);
};

// This frame's shadow state, filled by prepareShadows().
struct ShadowFrame {
    bool sceneHasShadows = false; // lighting programs were built with SHADOWS (bind a block)
    bool active = false;          // maps are drawn and read this frame
    const char* off = nullptr;    // why they are not (nullptr while active): debug-view notes
    bool gpuFit = false;          // SDSM: block, masks and draws live in GPU buffers
    bool translucent = false;     // blended casters are drawn into the companions this frame
    uint32_t cascades = 0;
    size_t blockOffset = 0;       // CPU-written ShadowBlock in the ring (SDSM: its parameters)
    size_t maskOffset = 0, maskBytes = 0;
    size_t boundsOffset = 0;      // SDSM: casters' SdsmCasterData in the ring
    // Casters to draw: CPU fits list those touching some cascade (objectOffsets parallel);
    // SDSM lists every caster in the scene (the GPU zeroes the culled ones' instance counts).
    std::vector<uint32_t> casters;       // indices into ShadowContext::casters
    std::vector<size_t> objectOffsets;
    std::vector<uint32_t> levels;        // GpuScene::levels index each listed caster draws
    std::vector<uint32_t> masks;         // CPU fits: cascades each listed caster touches
    std::vector<SdsmCasterData> casterBounds; // SDSM: per caster (camera-relative)
    std::array<ShadowFit, kMaxCascades> fits{};
    std::array<float, kMaxCascades + 1> splits{}; // view depths (CPU fits)
    glm::dmat3 lightRotation{1.0};
    glm::dvec2 sceneLightDepth{0.0};     // scene's light-space z interval (camera-relative)
};

// Everything shadows keep between frames (owned by the renderer).
struct ShadowContext {
    ShadowResources resources;
    std::vector<ShadowCaster> casters;
    int light = -1;                  // index of the shadowing light in GpuScene::lights, or -1
    bool translucentCasters = false; // some caster is blended (its maps get companions)
    glm::dvec3 sceneMin{0.0}, sceneMax{0.0}; // world bounds of every draw item
    ShadowFrame frame;
    bool capture = false;      // lighting writes visibility/cascade/ratio (CaptureBuffer::Shadow)
    bool captureColor = false; // lighting writes the colour visibility (CaptureBuffer::ShadowColor)
    mutable TranslucentMaps neutralTranslucent; // bindTranslucentMaps' stand-ins
    // Layered pass through a geometry shader (shadows.layer_from), per container program.
    std::vector<std::pair<uint32_t, GlHandle>> geometryLayerPrograms;
};

// Casters, the shadowing light (the first directional light that casts shadows) and the scene
// bounds, from `scene`. Call again after materials change.
void initShadowContext(const GpuScene& scene, ShadowContext& shadows);

// The CPU step, without GL: fits and culls (CPU techniques) or lists the casters' bounds for the
// GPU fit (SDSM) into shadows.frame (all but its ring offsets), and fills `block`.
void planShadows(const FrameView& in, ShadowContext& shadows, ShadowBlock& block);

// planShadows, then the block, the listed casters' object blocks and their masks or bounds into
// the ring, where the shadow pass and lighting read them.
void prepareShadows(FrameContext& ctx, ShadowContext& shadows);

// SDSM: the GPU fit from the depth buffer as it is now (shadow_sdsm.cpp): the previous frame's
// before the clear, or the first deferred layer's (renderer/frame.cpp).
void runSdsmFit(FrameContext& ctx, ShadowContext& shadows);

// Binds what a masked or blended caster's shadow program reads of its material (block, base
// colour texture) and, for a blended one, shadow.frag's TRANSLUCENT uniforms on `program`
// (`reversedDepth`: the local atlas). pass_shadow.cpp.
void bindCasterMaterial(const GpuScene& scene, const ShadowCaster& caster, GLuint program);

// Where a blended caster's fragments find the opaque depths they are tested against
// (shadow.frag's TRANSLUCENT uniforms): `depthLayer` of the depth array bound at unit 9 (-1:
// gl_Layer, the layered pass), `divisor` depth texels per companion texel each way,
// `reversedDepth` for the local atlas (nearer is larger).
void setTranslucentTarget(GLuint program, int depthLayer, uint32_t divisor, bool reversedDepth);

// Draws the casters into the array (pass_shadow.cpp).
void runShadowPass(FrameContext& ctx, ShadowContext& shadows);

// Binds the ShadowBlock (binding 4) and the maps (units 8 and 9; the companions 20 and 21) for
// lighting.
void bindShadowsForLighting(FrameContext& ctx, const ShadowContext& shadows);

} // namespace pnb::player
