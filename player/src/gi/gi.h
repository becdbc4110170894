// gi.h — one-bounce diffuse global illumination from the sun: reflective shadow map (RSM) ->
// injection into cascaded light propagation volumes (L1 SH per colour) and a geometry volume ->
// propagation -> look-up in lighting (shaders/include/gi_lookup.glsl). Seed 004; Kaplanyan &
// Dachsbacher 2010. gi.technique = probes replaces injection and propagation by a grid of
// probes that gather the RSM's clustered lights through an occupancy grid (pass_gi_probes.cpp)
// into the same volume format, so lighting reads both alike.
//
// Per frame, when gi.enabled and the container's lighting was built with GI:
//   prepareGi      places the cascades (player/math/lpv_math), fits the RSM over the outer one
//                  with the shadow code's light fitting, writes the GiBlock into the ring;
//   runGiRsm       draws opaque and masked surfaces from the sun with their G-buffer programs
//                  (pass_gi_rsm.cpp): base colour, normal, depth; then the translucent casters
//                  (BLEND materials that cast shadows) multiply its base colour by what they
//                  let through (gi_transmit.frag), so light behind glass bounces tinted;
//   runGiInject    RSM texels -> light and geometry accumulation buffers (pass_gi_inject.cpp);
//   finishGi       the camera's G-buffer -> geometry (gi.camera_occlusion), resolve the buffers
//                  into volumes, propagate (pass_gi_propagate.cpp). Runs after the first deferred
//                  layer's G-buffer is drawn, or straight away when nothing deferred is visible.
// Nothing of this exists while GI is off: no program, texture or buffer; nothing of the
// translucent casters' (GiResources::transmit*) while no BLEND material casts shadows.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "lpv_math.h"
#include "pnb_player/gl_handles.h"
#include "pnb_player/renderer.h"
#include "shadow_fit.h"
#include "shared/gi_block.h" // kMaxGiCascades, GiBlock (GLSL and C++)

namespace pnb::player {

struct DrawRef;
struct FrameContext;
struct FrameView;
struct ShadowContext;

// What each technique allocates (gi.technique): only its own. Both: the RSM and the `sum`
// volumes lighting reads (L1 SH per colour, cascades stacked along z).
struct GiResources {
    GiTechnique technique = GiTechnique::Lpv;
    uint32_t cells = 0, cascades = 0, rsmResolution = 0;
    bool floatAtomics = false;
    // RSM: RT0 base colour (sRGB), RT1 normal + material (as the G-buffer), depth.
    GlHandle rsmColor, rsmNormal, rsmDepth, rsmFb;
    // Translucent casters (issue 43), only while some BLEND material casts shadows: the program
    // multiplying the RSM's flux by their transmittance; probes: the transmittance grid (RGBA8,
    // rgb = T, a = 1 where a pane is, beside the occupancy grid), its voxelisation and, with
    // gi.probe_visibility = depth, each probe's map of what its depth rays pass through (RGBA8,
    // rgb = T, a = distance to the first pane over the grid's diagonal).
    // LPV: each cascade's cells' panes (RGBA8, cells x cells x cells*cascades like the volumes,
    // rgb = T, a = 1 where a pane is; gi_transmit.frag VOXELIZE), drawn again only when the
    // cascades move or a material changes, and the propagation variants reading them (GLASS).
    bool glass = false;
    GlHandle transmitRsm, transmitVoxelize, transmitVoxels, probeTransmit;
    GlHandle lpvGlass, lpvGlassFb, propagateGlass, propagateOccludedGlass;
    uint64_t lpvGlassVersion = ~0ull;
    std::vector<glm::dvec4> lpvGlassBoxes; // the cascades' origins and cell sizes lpvGlass holds
    std::array<GlHandle, 3> sum;
    // LPV: volumes (cells x cells x cells*cascades), RGBA16F per colour: two propagation
    // buffers beside the sum. Geometry: (cells+1)^3 per cascade.
    std::array<GlHandle, 3> source, next;
    GlHandle geometry;
    std::array<GlHandle, 2> transmittance; // per cell, the six faces' transmittance (RGBA8 x 2)
    GlHandle lightAccumulation, geometryAccumulation; // injection's atomic buffers
    GlHandle injectRsm, injectCamera, resolveLight, resolveGeometry, resolveTransmittance, propagate,
        propagateOccluded;
    // Probes (cells = probes per side, cascades = 1): the occupancy grid over the probes' box,
    // drawn again only when the geometry or the box changes; the clustered VPLs.
    uint32_t voxelSide = 0, vplSide = 0;
    GlHandle voxels, voxelFb, vpls, voxelize, clusterVpls, gatherProbes;
    uint64_t voxelVersion = ~0ull;
    // gi.probe_visibility = depth: every probe's 16x16 depth map with its border (an R16F 2D
    // array of 18x18 tiles) and whether lighting can read it (a word each), traced again only
    // when the occupancy grid is redrawn; `exact` has neither.
    ProbeVisibility gatherVisibility = ProbeVisibility::Depth; // the variant gatherProbes is
    GlHandle probeDepth, probeNeeded, traceDepth;
    bool depthCurrent = false;
    // ibl.visibility = probes: per probe the L1 SH of the directions in which it sees out of the
    // grid (RGBA16F, probes^3), traced again only when the occupancy grid is redrawn.
    GlHandle skyVisibility, traceSky;
    bool skyCurrent = false;
    // gi.bounces > 1 (pass_gi_bounce.cpp), none of it at 1: the voxels' albedo (R32UI sums of
    // r, g, b and the fragments' count, 4 texels per voxel along x, drawn with the occupancy grid
    // by the ALBEDO voxelisation), the VPLs' gather and the last
    // pass's volumes (copies of `sum`) and the gather variant that adds one bounce to the first
    // from the second.
    GlHandle albedoVoxels, voxelizeAlbedo, bounceGather;
    std::array<GlHandle, 3> gathered, previous;
    uint32_t albedoSide = 0, previousCells = 0;
    ProbeVisibility bounceVisibility = ProbeVisibility::Depth; // the variant bounceGather is
    bool bounceGlass = false;                                  // compiled with TRANSMITTANCE
    // What the probes were last gathered from (sun, grid, sizes, scene versions, RSM items' levels
    // of detail): equal this frame = the volume is still right (gi.probe_cache).
    std::vector<uint64_t> probeInputs;
    glm::dvec3 voxelOrigin{0.0};
    double voxelCell = 0;
    uint64_t bytes = 0;

    // `glass`: some translucent caster is drawn (GiFrame::rsmGlassItems or the probes' grid).
    PlayResult<Done> ensure(const RenderSettings& settings, uint32_t cascades, bool glass);
};

// This frame's GI state (prepareGi).
struct GiFrame {
    bool active = false;
    const char* off = nullptr; // why GI is off this frame (nullptr while active): debug-view notes
    std::vector<LpvCascade> cascades;
    bool following = false;    // the outer cascade follows the camera (its border fades out)
    ShadowFit rsm;             // camera-relative world -> RSM clip
    double rsmTexelArea = 0;   // perpendicular world area of one RSM texel
    glm::dvec3 toward{0, 1, 0}; // toward the sun
    std::vector<uint32_t> rsmItems;
    std::vector<size_t> rsmObjectOffsets;
    // The translucent casters whose bounds reach the RSM (drawn after rsmItems, multiplying), and
    // whether the scene has any at all (the probes' grid holds them wherever they are).
    std::vector<uint32_t> rsmGlassItems;
    std::vector<size_t> rsmGlassOffsets;
    bool sceneGlass = false;
    size_t rsmFrameOffset = 0, blockOffset = 0;
    float lightScale = 0, geometryScale = 0; // fixed-point units per 1.0
    std::vector<uint64_t> probeInputs; // probes: this frame's inputs (GiResources::probeInputs)
    // The pose version at which something last moved inside the probes' grid (kept across
    // frames): the occupancy grid and the probes follow moving geometry within it only.
    uint64_t poseInGrid = 0;
    uint64_t geometryVersion = 0; // materialsVersion + poseInGrid: the occupancy grid's key
    bool probesCurrent = false;        // probes: the volume already holds them (no RSM, no gather)
};

struct GiContext {
    GiResources resources;
    GiFrame frame;
    bool capture = false; // lighting writes indirect irradiance (CaptureBuffer::Indirect)
    bool warned = false;  // "gi.enabled, but ..." said once
    // Whether some opaque surface has diffuse albedo (gi_setup.cpp), for this materialsVersion:
    // looked at again only after a material edit, not every frame.
    uint64_t diffuseVersion = ~0ull;
    bool diffuse = false;
};

// A translucent caster (issue 43): a blended material that casts shadows lets light through
// tinted, T = base colour x (1 - alpha) (gi_transmit.frag); one that does not lets all through.
inline bool translucentCaster(const GpuMaterial& m) { return m.translucent() && m.desc.castsShadows; }

// The CPU step, without GL: GI's cascades (or the probes' grid) around the camera, or why GI is
// off (gi.frame.off); the sun's RSM fit, what it draws, the probes' inputs and the GiBlock.
void planGi(const FrameView& in, GiContext& gi, const ShadowContext& shadows, GiBlock& block);
// planGi, then the volumes' storage, the RSM's object blocks and frame block, the GiBlock.
void prepareGi(FrameContext& ctx, GiContext& gi, const ShadowContext& shadows);                 // gi_setup.cpp
void runGiRsm(FrameContext& ctx, GiContext& gi);                  // pass_gi_rsm.cpp
// Draws translucent casters with a gi_transmit program (`refs` sorted by material on the way:
// the program is told per material whether its base colour unit holds a texture). pass_gi_rsm.cpp
void drawTranslucentCasters(FrameContext& ctx, std::vector<DrawRef>& refs, GLuint program);
void runGiInject(FrameContext& ctx, GiContext& gi);               // pass_gi_inject.cpp: RSM texels
void runGiCameraGeometry(FrameContext& ctx, GiContext& gi);       // pass_gi_inject.cpp: G-buffer surfels
void runGiResolve(FrameContext& ctx, GiContext& gi, bool cameraGeometry); // pass_gi_inject.cpp: -> volumes
void runGiPropagate(FrameContext& ctx, GiContext& gi);            // pass_gi_propagate.cpp
// LPV with translucent casters: the panes into each cascade's cells (GiResources::lpvGlass) when
// the cascades moved or a material changed. pass_gi_lpv_glass.cpp
void voxelizeLpvGlass(FrameContext& ctx, GiContext& gi);
// Grid-relative world [0, extent]^3 -> clip: x, y the other two axes, depth (0..1) along `axis`
// (the voxelisations' three views). pass_gi_probes.cpp
glm::dmat4 giAxisView(int axis, double extent);

// Binds `framebuffer` (no attachments: the voxelisations write images) as a side x side target,
// depth test and blending off.
void bindVoxelTarget(GLuint framebuffer, uint32_t side);
// The probes' gather programs (the VPL gather and the bounces) read the same grid: its origin and
// spacing (uniform 0), sizes (1), occupancy (unit 0), depth maps and their needed flags (unit 1),
// the panes' maps (units 2, 3) when they exist.
void bindProbeGatherInputs(const GiResources& r, GLuint program, const glm::vec3& origin, float spacing);
// A frame block with giAxisView(axis, extent) for a side x side voxelisation target, pushed into
// the ring and bound at the frame block's binding (the caller binds the frame's own back after).
void bindAxisFrameBlock(FrameContext& ctx, int axis, double extent, uint32_t side);
// Every translucent caster, its object block relative to a grid's corner. pass_gi_probes.cpp
std::vector<DrawRef> glassDrawRefs(FrameContext& ctx, const glm::dmat4& toGrid);
// gi.technique = probes, after the RSM: occupancy grid when stale, VPLs, gather into `sum`.
void runGiProbes(FrameContext& ctx, GiContext& gi);               // pass_gi_probes.cpp
// gi.bounces > 1: the objects of the further bounces (GiResources::albedoVoxels ...), made for
// the grid's sizes, or dropped at 1. Returns their bytes. pass_gi_bounce.cpp
PlayResult<uint64_t> ensureGiBounce(GiResources& r, const RenderSettings& s);
// After the probes' gather into `sum` (its images and the VPLs bound): gi.bounces - 1 more
// gathers, each adding the light one more bounce brings from the last. pass_gi_bounce.cpp
void runGiProbeBounces(FrameContext& ctx, GiContext& gi, const glm::vec3& origin, float spacing);
// A side x side x depth 3D texture (RGBA16F unless said), linearly filtered (the look-up is
// trilinear, propagation interpolates the geometry volume), clamped at its edges. gi_resources.cpp
GlHandle giVolume(uint32_t side, uint32_t depth, const char* label, GLenum format = GL_RGBA16F);
// The rest of the frame's GI once the camera's G-buffer is there (or will not be): camera
// geometry, resolve, propagation (gi.technique = lpv). The frame list (renderer/frame.cpp) runs it
// once, before the targets or after the first deferred layer's G-buffer.
void finishGi(FrameContext& ctx, GiContext& gi);
// Binds the GiBlock (binding 6) and the summed volumes (units 10-12) for lighting.
void bindGiForLighting(FrameContext& ctx, const GiContext& gi);

} // namespace pnb::player
