// frame.cpp — the frame, pass by pass, in the order it runs. A new pass is a folder entry (its
// pass_*.cpp) and one line here; the test of the order (tests/player/frame_passes_test.cpp) then
// checks its declared reads and writes against every other pass's.
#include "renderer/frame.h"

#include <iterator>

#include "gl/gl_allocation.h"

#include "gi/gi.h"
#include "lights/light_clusters.h"
#include "post/post.h"
#include "shading/shading.h"
#include "shadows/local_shadows.h"
#include "shadows/shadow_maps.h"
#include "sky/ibl.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)

namespace pnb::player {

namespace {

bool always(const FrameShape&) { return true; }
// SDSM fits to the first deferred layer's depth, between that layer's G-buffer and its lighting;
// without deferred geometry it fits to the previous frame's depth before the clear.
bool sunMapsEarly(const FrameShape& s) { return s.shadows && !(s.sdsm && s.deferred); }
bool sdsmOnPreviousDepth(const FrameShape& s) { return s.shadows && s.sdsm && !s.deferred; }
bool sdsmOnThisDepth(const FrameShape& s) { return s.shadows && s.sdsm && s.deferred; }
bool giRsm(const FrameShape& s) { return s.gi; }
bool giVolumes(const FrameShape& s) { return s.gi && !s.giProbes; }
bool giProbes(const FrameShape& s) { return s.gi && s.giProbes; }
// The camera's blocking surfels come from the first deferred layer's G-buffer; without one (or
// without gi.camera_occlusion) the volumes are finished before the frame's targets are drawn.
bool giFinishEarly(const FrameShape& s) { return giVolumes(s) && !(s.deferred && s.giCameraSurfels); }
bool giFinishOnGBuffer(const FrameShape& s) { return giVolumes(s) && s.deferred && s.giCameraSurfels; }
bool deferred(const FrameShape& s) { return s.deferred; }

void clearTargets(Frame& f) {
    FrameContext& ctx = f.ctx;
    glViewport(0, 0, GLsizei(ctx.targets.width), GLsizei(ctx.targets.height));
    const float black[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(ctx.targets.hdrFb.id(), GL_COLOR, 0, black);
    glDepthMask(GL_TRUE);
    glClearNamedFramebufferfi(ctx.targets.hdrFb.id(), GL_DEPTH_STENCIL, 0, 0.0f, 0); // reversed-Z far
    glBindVertexArray(ctx.builtins.emptyVao.id());
    // Writes to the sRGB attachments (G-buffer base colour, output) are encoded by the hardware;
    // linear targets are unaffected.
    glEnable(GL_FRAMEBUFFER_SRGB);
}

void otherDeferredLayers(Frame& f) {
    for (size_t i = 1; i < f.deferredLayers.size(); ++i) {
        runGBuffer(f.ctx, f.deferredLayers[i]);
        runDeferredLighting(f.ctx);
    }
}

// The surfaces lighting reads, besides the targets.
constexpr uint32_t kLit = kLightList | kLightClusters | kShadowMaps | kLocalShadowMaps | kGiVolumes;

constexpr FramePass kPasses[] = {
    // name                        reads                           writes
    // The clusters read the lights' bounding spheres, written beside the list by the prepare step.
    {"lights.clusters",            0,                              kLightClusters,        always,
     [](Frame& f) { runLightClusters(f.ctx, f.lights); }},
    {"shadows.sdsm_fit(previous)", kPreviousDepth,                 kShadowFit,            sdsmOnPreviousDepth,
     [](Frame& f) { runSdsmFit(f.ctx, f.shadows); }},
    {"shadows.maps",               kShadowFit,                     kShadowMaps,           sunMapsEarly,
     [](Frame& f) { runShadowPass(f.ctx, f.shadows); }},
    {"shadows.bind",               0,                              0,                     always,
     [](Frame& f) { bindShadowsForLighting(f.ctx, f.shadows); }},
    {"lights.local_shadows",       kLightList,                     kLightList | kLocalShadowMaps, always,
     [](Frame& f) { runLocalShadows(f.ctx, f.localShadows, f.shadows, f.lights); }},
    {"gi.rsm",                     0,                              kGiRsm,                giRsm,
     [](Frame& f) { runGiRsm(f.ctx, f.gi); }},
    {"gi.inject",                  kGiRsm,                         kGiInjected,           giVolumes,
     [](Frame& f) { runGiInject(f.ctx, f.gi); }},
    {"gi.probes",                  kGiRsm,                         kGiVolumes,            giProbes,
     [](Frame& f) {
         runGiProbes(f.ctx, f.gi);
         bindGiForLighting(f.ctx, f.gi);
     }},
    {"gi.finish",                  kGiInjected,                    kGiVolumes,            giFinishEarly,
     [](Frame& f) { finishGi(f.ctx, f.gi); }},
    {"frame.clear",                0,                              kHdr | kDepth,         always, clearTargets},
    {"deferred.gbuffer(first)",    kDepth,                         kGBuffer | kDepth,     deferred,
     [](Frame& f) { runGBuffer(f.ctx, f.deferredLayers.front()); }},
    {"shadows.sdsm_fit",           kDepth,                         kShadowFit,            sdsmOnThisDepth,
     [](Frame& f) { runSdsmFit(f.ctx, f.shadows); }},
    {"shadows.maps(sdsm)",         kShadowFit,                     kShadowMaps,           sdsmOnThisDepth,
     [](Frame& f) { runShadowPass(f.ctx, f.shadows); }},
    {"gi.finish(camera surfels)",  kGiInjected | kGBuffer | kDepth, kGiVolumes,           giFinishOnGBuffer,
     [](Frame& f) { finishGi(f.ctx, f.gi); }},
    {"deferred.lighting(first)",   kGBuffer | kDepth | kLit,       kHdr,                  deferred,
     [](Frame& f) { runDeferredLighting(f.ctx); }},
    {"deferred.layers(rest)",      kGBuffer | kDepth | kLit,       kGBuffer | kDepth | kHdr, deferred,
     otherDeferredLayers},
    {"sky.background",             kDepth,                         kHdr,                  always,
     [](Frame& f) { runBackground(f.ctx, f.ibl); }},
    {"forward",                    kDepth | kLit,                  kHdr | kDepth,         always,
     [](Frame& f) { runForward(f.ctx); }},
    {"tonemap",                    kHdr,                           kOutput,               always,
     [](Frame& f) {
         glBindVertexArray(f.ctx.builtins.emptyVao.id());
         runTonemap(f.ctx);
     }},
    {"debug_view",                 kOutput | kDepth | kGBuffer | kShadowMaps | kGiRsm | kGiVolumes, kOutput, always,
     [](Frame& f) {
         runDebugView(f.ctx, f.shadows, f.gi);
         glBindVertexArray(f.ctx.builtins.emptyVao.id());
     }},
};

std::string resourceNames(uint32_t bits) {
    static const char* const names[] = {"light list", "shadow fit", "shadow maps", "local shadow maps",
                                        "GI RSM", "GI injection", "GI volumes", "previous depth",
                                        "depth", "G-buffer", "HDR target", "output", "light clusters"};
    std::string text;
    for (uint32_t i = 0; i < std::size(names); ++i)
        if (bits & (1u << i)) text += (text.empty() ? "" : ", ") + std::string(names[i]);
    return text;
}

} // namespace

// Each subsystem's state for this frame (CPU fits, culling, the light list, GI's cascades, the
// sky), the frame block, and the storage the passes draw into.
PlayResult<Done> prepareFrame(Frame& f) {
    FrameContext& ctx = f.ctx;
    prepareLights(ctx, f.lights);
    prepareShadows(ctx, f.shadows);
    prepareGi(ctx, f.gi, f.shadows);
    if (wantsSkyHeightMap(frameView(ctx))) renderSkyHeightMap(ctx, f.ibl); // once, then on edits
    prepareIbl(ctx, f.ibl, f.gi);
    const RenderSettings& s = ctx.settings;
    FrameBlock fb;
    fb.viewProjection = ctx.view.viewProjection;
    fb.view = ctx.view.view;
    fb.cameraPosition = glm::vec4(glm::vec3(ctx.view.position), 1);
    const float w = float(ctx.targets.width), h = float(ctx.targets.height);
    fb.viewport = {w, h, 1.0f / w, 1.0f / h};
    // a: the GI cascades lighting reads (0: GI off, gi_lookup.glsl returns at once).
    fb.ambient = glm::vec4(glm::vec3(s.ambient), float(f.gi.frame.cascades.size()));
    ctx.frameBlockOffset = ctx.ring.push(&fb, sizeof fb);
    glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_FRAME_BLOCK, ctx.ring.buffer(), GLintptr(ctx.frameBlockOffset),
                      sizeof fb);
    const ShadowFrame& shadowFrame = f.shadows.frame;
    ShadowResources& maps = f.shadows.resources;
    if (shadowFrame.active) {
        const uint64_t shadowBytes = maps.mapBytes + maps.bufferBytes + maps.translucent.bytes;
        auto ok = maps.ensure(s.shadowResolution, shadowFrame.cascades, shadowFrame.gpuFit, shadowFrame.translucent,
                              1u << s.shadowTranslucentDivisorLog2,
                              f.shadows.casters, ctx.scene);
        if (ok && maps.mapBytes + maps.bufferBytes + maps.translucent.bytes != shadowBytes)
            ok = checkGlAllocation("the shadow maps (shadows.resolution " + std::to_string(s.shadowResolution) + ")",
                                   maps.mapBytes + maps.translucent.bytes);
        if (!ok) return ok.error();
    } else if (maps.resolution) {
        maps = ShadowResources{}; // nothing drawn: nothing allocated
    }
    return Done{};
}

FrameShape frameShape(const Frame& f) {
    FrameShape shape;
    shape.shadows = f.shadows.frame.active;
    shape.sdsm = f.shadows.frame.gpuFit;
    shape.deferred = !f.deferredLayers.empty();
    shape.gi = f.gi.frame.active;
    shape.giProbes = f.ctx.settings.giTechnique == GiTechnique::Probes;
    shape.giCameraSurfels = f.ctx.settings.giCameraOcclusion;
    return shape;
}

std::span<const FramePass> framePasses() { return kPasses; }

std::vector<std::string> framePassNames(const FrameShape& shape) {
    std::vector<std::string> names;
    for (const FramePass& p : kPasses)
        if (p.runs(shape)) names.emplace_back(p.name);
    return names;
}

std::string checkFrameOrder(std::span<const FramePass> passes, const FrameShape& shape) {
    uint32_t written = kFrameInputs, read = 0;
    for (const FramePass& p : passes) {
        if (!p.runs(shape)) continue;
        // Resources a pass may read without anything in the frame writing them: those a
        // technique leaves unwritten this frame (no shadows, no GI) are bound empty, so only
        // a resource some running pass writes must be written before it is read.
        uint32_t writtenSomewhere = kFrameInputs;
        for (const FramePass& q : passes)
            if (q.runs(shape)) writtenSomewhere |= q.writes;
        if (uint32_t missing = p.reads & writtenSomewhere & ~written)
            return std::string(p.name) + " reads " + resourceNames(missing) + " before any pass writes it";
        if (uint32_t late = p.writes & read & ~kAccumulatedResources)
            return std::string(p.name) + " writes " + resourceNames(late) + " after a pass has read it";
        written |= p.writes;
        read |= p.reads;
    }
    return {};
}

void runFrame(Frame& frame, const FrameShape& shape) {
    for (const FramePass& p : kPasses)
        if (p.runs(shape)) p.run(frame);
}

} // namespace pnb::player
