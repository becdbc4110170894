// The renderer: its state between frames, and one frame as stages — the targets, culling and
// sorting into draw lists, each subsystem's prepare step, then the pass list (frame.cpp).
#include "pnb_player/renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>

#include <glm/gtc/type_ptr.hpp>

#include "post/post.h"
#include "renderer/frame.h"
#include "renderer/renderer_impl.h"
#include "shading/shading.h"
#include "gl/gl_allocation.h"
#include "gl/program_compile.h"

namespace pnb::player {

namespace {

constexpr size_t kObjectBlockBytes = 176;

double threadCpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

} // namespace

PlayResult<std::unique_ptr<Renderer>> Renderer::create(GpuScene& scene, const RenderSettings& settings) {
    std::unique_ptr<Renderer> r(new Renderer());
    r->mImpl = std::make_unique<Impl>();
    Impl& impl = *r->mImpl;
    impl.scene = &scene;
    GLint uboAlign = 256, ssboAlign = 256;
    glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &uboAlign);
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &ssboAlign);
    impl.alignment = size_t(std::max({uboAlign, ssboAlign, 16}));
    impl.builtins.emptyVao = createVertexArray();
    r->setSettings(settings);
    // Reversed-Z: depth in [0, 1] with 1 at the near plane.
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS); // the prefiltered environment's rough levels are tiny
    // The most one frame pushes: frame blocks (the view, the RSM, the sky's height map, the GI
    // probes' three axis views of the occupancy grid), the light list, the shadow, GI and IBL
    // blocks, and per item one object block for every pass that draws it (the view, the shadow
    // casters, the RSM, the height map, the occupancy grid) with its caster mask or bounds.
    // Every push is aligned: one alignment of slack per block.
    // Point and spot light shadows add their casters' object blocks, a ShadowBlock per light and
    // the tiles' data (local_shadows.h), for at most 64 lights of 6 tiles.
    constexpr size_t kFrameBlocks = 6, kObjectBlocksPerItem = 6;
    constexpr size_t kLocalShadowBytes = 64 * (sizeof(ShadowBlock) + 6 * 80) + 16;
    // The light list and, when clustering, one view-space sphere per light.
    size_t lightBytes = 16 + (sizeof(GpuLight) + sizeof(glm::vec4)) * std::max<size_t>(scene.lights.size(), 1);
    size_t objectStride = (kObjectBlockBytes + impl.alignment - 1) / impl.alignment * impl.alignment;
    const bool ringMade = impl.ring.reserve(kFrameBlocks * (sizeof(FrameBlock) + impl.alignment) + lightBytes + impl.alignment + sizeof(ShadowBlock) +
                          sizeof(GiBlock) + sizeof(IblBlock) + impl.alignment * 8 +
                          kLocalShadowBytes + 64 * impl.alignment +
                          scene.items.size() * (kObjectBlocksPerItem * objectStride + 4 + 32) +
                          // instanced batches (draw_lists.cpp): per copy its packed InstanceData,
                          // per batch a flagged object block; both passes that batch
                          2 * scene.items.size() * (144 + objectStride + impl.alignment),
                      impl.alignment);
    if (!ringMade)
        return PlayError{PlayErrorKind::Gl, "the GL cannot allocate the per-frame stream ring (" +
                                                std::to_string(scene.items.size()) +
                                                " draw items): out of GPU memory"};
    impl.targets.memory.streamingBytes = impl.ring.totalBytes();
    return r;
}

Renderer::~Renderer() = default;

RenderSettings settingsForCurrentDriver() {
    const char* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    auto s = resolveSettings(driverDefaults(name ? name : ""), {});
    return s ? *s : RenderSettings{};
}

void Renderer::setSettings(const RenderSettings& settings) {
    mSettings = settings;
    BuiltinPrograms& b = mImpl->builtins;
    // Built-in programs exist only while a setting uses them.
    auto ensure = [](GlHandle& program, bool needed, std::string_view vert, std::string_view frag) {
        if (!needed) {
            program = {};
            return;
        }
        if (program) return;
        auto p = compileEmbeddedProgram(vert, frag);
        if (p) program = std::move(*p);
        else std::fprintf(stderr, "pnb-play: %s\n", p.error().message.c_str());
    };
    if (settings.anisotropy != mImpl->appliedAnisotropy &&
        epoxy_has_gl_extension("GL_EXT_texture_filter_anisotropic")) {
        mImpl->appliedAnisotropy = settings.anisotropy;
        for (const GpuTexture& t : mImpl->scene->textures)
            if (t.trilinear) glTextureParameterf(t.texture.id(), GL_TEXTURE_MAX_ANISOTROPY_EXT, settings.anisotropy);
    }
    ensure(b.fxaa, settings.fxaa, "fullscreen.vert", "fxaa.frag");
    const GpuScene& scene = *mImpl->scene;
    ensure(b.background,
           settings.iblEnabled && settings.iblBackground && scene.iblPrograms && scene.environment &&
               scene.environment->radiance,
           "fullscreen.vert", "background.frag");
    ensure(b.depthOnly,
           settings.iblEnabled && resolvedSkyVisibility(settings) == SkyVisibility::Height && scene.iblPrograms &&
               scene.environment,
           "flat.vert", "depth_only.frag");
    bool shadowDebug = settings.debugView == DebugView::ShadowMap || settings.debugView == DebugView::Histogram;
    ensure(b.shadowDebug, shadowDebug, "fullscreen.vert", "shadow_debug.frag");
    bool debug = settings.debugView != DebugView::None && settings.debugView != DebugView::Cascades &&
                 settings.debugView != DebugView::GiIndirect && !shadowDebug;
    ensure(b.debugView, debug, "fullscreen.vert", "debug_view.frag");
    ensure(b.flat, settings.debugView == DebugView::Layer || settings.debugView == DebugView::Overdraw ||
                       settings.debugView == DebugView::Lod,
           "flat.vert", "flat.frag");
}

TargetMemory Renderer::targetMemory() const {
    TargetMemory m = mImpl->targets.memory;
    m.shadowMapBytes = mImpl->shadows.resources.mapBytes;
    m.localShadowBytes = uint64_t(mImpl->localShadows.atlasSize) * mImpl->localShadows.atlasSize * 4;
    m.lightClusterBytes = mImpl->lights.maskCapacity;
    m.shadowBufferBytes = mImpl->shadows.resources.bufferBytes;
    m.shadowTranslucentBytes = mImpl->shadows.resources.translucent.bytes + mImpl->localShadows.translucent.bytes;
    m.giBytes = mImpl->gi.resources.bytes;
    m.iblBytes = mImpl->ibl.heightBytes;
    return m;
}

void Renderer::setAnimationClock(double seconds) { mImpl->deform.clock = seconds; }
double Renderer::animationClock() const { return mImpl->deform.clock; }
double Renderer::animationTime() const { return mImpl->deform.state.time; }

DrawnPose Renderer::drawnPose() const {
    DrawnPose p;
    const auto& posed = mImpl->deform.state.posed;
    if (!posed || !posed->enabled || !mImpl->scene->animation) return p;
    p.enabled = true;
    p.clip = posed->clip;
    p.clipTime = posed->clipTime;
    if (p.clip) p.clipName = mImpl->scene->animation->clipNames[*p.clip];
    return p;
}

const CameraState& Renderer::lastCamera() const { return mImpl->lastCamera; }
const std::string& Renderer::debugViewNote() const { return mImpl->debugViewNote; }

GLuint Renderer::outputTexture() const { return mImpl->targets.output.id(); }

PlayResult<Done> Renderer::render(const CameraState& camera, uint32_t width, uint32_t height) {
    auto cpuStart = std::chrono::steady_clock::now();
    const double threadStart = threadCpuMs();
    Impl& impl = *mImpl;
    const GpuScene& scene = *impl.scene;
    if (width == 0 || height == 0)
        return PlayError{PlayErrorKind::Usage, "render size must be at least 1x1"};
    mStats = {};
    mStats.frame = impl.frame++;
    impl.lastCamera = camera;
    // Captures and the warm-up frame keep their GPU times out of the benchmark's.
    GpuTimer& timer = impl.capturing || impl.warming ? impl.captureTimer : mTimer;

    CameraState cam = camera;
    if (mSettings.nearPlane > 0) cam.znear = mSettings.nearPlane;
    if (mSettings.farPlane >= 0) cam.zfar = mSettings.farPlane;
    cam = validOrthographic(cam, scene.bounds); // a far plane where it has none
    if (cam.zfar > 0 && cam.zfar <= cam.znear)
        return PlayError{PlayErrorKind::Usage, "camera.far must exceed camera.near"};
    mView = makeViewMatrices(cam, float(width) / float(height));

    bool debugTargets = mSettings.debugView == DebugView::Layer ||
                        mSettings.debugView == DebugView::Overdraw || mSettings.debugView == DebugView::Lod;
    // Storage is checked only when it was made (glGetError can stall a threaded driver, so not
    // every frame): the targets' bytes change with every allocation.
    const uint64_t targetBytes = impl.targets.memory.total();
    impl.targets.ensure(width, height, !scene.deferredLayers.empty(),
                        mSettings.fxaa && impl.builtins.fxaa, debugTargets);
    if (impl.targets.memory.total() != targetBytes)
        if (auto ok = checkGlAllocation("the frame's render targets at " + std::to_string(width) +
                                            "x" + std::to_string(height),
                                        impl.targets.memory.total());
            !ok)
            return ok.error();

    timer.beginFrame(mStats.frame);
    timer.mark("setup");
    impl.ring.beginFrame();

    // Playback, before anything culls or draws: the pose moves items, lights and cameras, then
    // the deform pass poses the deformed meshes once for every pass of the frame.
    impl.deform.update = animateScene(*impl.scene, mSettings, impl.deform.clock, impl.deform.state);
    if (impl.deform.update.posed) ++impl.deform.poseVersion;
    mStats.movedItems = uint32_t(impl.deform.update.movedItems.size());
    mStats.animationTime = impl.deform.state.clipTime;
    runDeformPass(scene, impl.deform, timer, mStats);

    DrawLists& lists = impl.lists;
    selectLevels(scene, mView, height, mSettings, impl.lod, mStats);
    buildDrawLists(scene, mView, impl.lod, mSettings.frustumCulling && !impl.warming, impl.ring, lists);
    mStats.visibleItems = lists.visible;
    mStats.culledItems = lists.culled;

    FrameContext ctx{scene, mSettings, mView, impl.targets, impl.ring, lists, mStats, timer,
                     impl.builtins, kObjectBlockBytes, impl.lod};
    ctx.warmUp = impl.warming;
    if (impl.shadowsForMaterials != scene.materialsVersion) {
        initShadowContext(scene, impl.shadows);
        impl.shadowsForMaterials = scene.materialsVersion;
    }
    deferredLayersToDraw(ctx, impl.deferredLayers);
    Frame frame{ctx, impl.shadows, impl.gi, impl.ibl, impl.lights, impl.localShadows, impl.deferredLayers};
    if (auto prepared = prepareFrame(frame); !prepared) return prepared.error();
    impl.debugViewNote = player::debugViewNote(ctx, impl.shadows, impl.gi);
    runFrame(frame, frameShape(frame));

    timer.endFrame();
    if (impl.capturing || impl.warming) timer.completed().clear();
    impl.ring.endFrame();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    mStats.cpuMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cpuStart).count();
    mStats.threadCpuMs = threadCpuMs() - threadStart;
    return Done{};
}

PlayResult<Done> Renderer::warmUp(const CameraState& camera, uint32_t width, uint32_t height) {
    if (!mSettings.warmUp) return Done{};
    Impl& impl = *mImpl;
    impl.warming = true;
    // Scissoring keeps the full-screen passes from shading every pixel; no driver keys shader
    // variants on the scissor rectangle (llvmpipe applies it when binning).
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, 1, 1);
    auto r = render(camera, width, height);
    glDisable(GL_SCISSOR_TEST);
    impl.warming = false;
    glFinish();
    return r;
}

void Renderer::presentToWindow(int windowWidth, int windowHeight) {
    const FrameTargets& t = mImpl->targets;
    glDisable(GL_FRAMEBUFFER_SRGB); // copy the encoded bytes as they are
    const float black[4] = {0, 0, 0, 1};
    glClearNamedFramebufferfv(0, GL_COLOR, 0, black);
    glBlitNamedFramebuffer(t.outputFb.id(), 0, 0, 0, GLint(t.width), GLint(t.height), 0, 0,
                           windowWidth, windowHeight, GL_COLOR_BUFFER_BIT, GL_LINEAR);
}

} // namespace pnb::player
