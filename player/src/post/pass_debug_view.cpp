// Debug views: a G-buffer channel or depth straight from the frame's targets, or — for the layer
// and overdraw views — the visible draws re-rendered with the flat program into a debug target
// (nearest surface's layer colour; additive fragment counts), as for the level-of-detail view
// (nearest surface's level colour), then mapped to the output.
// G-buffer views show the last deferred layer drawn (the G-buffer is reused per layer).
#include <algorithm>

#include <glm/glm.hpp>

#include "gi/gi.h"
#include "post/post.h"
#include "shadows/shadow_maps.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)

namespace pnb::player {

std::string debugViewNote(const FrameContext& ctx, const ShadowContext& shadowContext,
                          const GiContext& giContext) {
    const DebugView v = ctx.settings.debugView;
    if (v == DebugView::None) return {}; // every frame of a normal run: no string built
    const std::string view = "debug.view=" + std::string(toString(v));
    const ShadowFrame& shadows = shadowContext.frame;
    const GiFrame& gi = giContext.frame;
    switch (v) {
    case DebugView::Cascades:
    case DebugView::ShadowMap:
    case DebugView::Histogram:
        if (!shadows.active && shadows.off) return view + " shows nothing: " + shadows.off;
        if (v == DebugView::Histogram && !shadows.gpuFit)
            return view + " shows nothing: the depth histogram is SDSM's (shadows.technique=sdsm)";
        break;
    case DebugView::GiIndirect:
        if (!gi.active && gi.off) return view + " shows the lit image unchanged: GI is off: " + gi.off;
        break;
    case DebugView::GiRsm:
    case DebugView::GiVolume:
        if (!gi.active && gi.off) return view + " shows nothing: GI is off: " + gi.off;
        break;
    case DebugView::Lod:
        if (std::none_of(ctx.scene.items.begin(), ctx.scene.items.end(),
                         [](const DrawItem& i) { return i.levelCount > 1; }))
            return view + " shows one colour: no item has levels of detail (convert with "
                          "pnb-convert --lods N)";
        break;
    default: break;
    }
    return {};
}

namespace {

glm::vec4 layerColor(size_t index) {
    static const glm::vec4 palette[] = {{0.2f, 0.4f, 1.0f, 1}, {0.1f, 0.8f, 0.2f, 1},
                                        {1.0f, 0.8f, 0.1f, 1}, {0.9f, 0.3f, 0.8f, 1},
                                        {0.1f, 0.8f, 0.8f, 1}, {0.6f, 0.4f, 0.2f, 1}};
    return palette[index % std::size(palette)];
}

// The flat-colour views draw into the cleared debug target, nearest surface winning (reversed Z).
void beginFlatColourView(FrameContext& ctx) {
    glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.debugFb.id());
    const float zero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(ctx.targets.debugFb.id(), GL_COLOR, 0, zero);
    glClearNamedFramebufferfi(ctx.targets.debugFb.id(), GL_DEPTH_STENCIL, 0, 0.0f, 0);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
}

void renderLayerColors(FrameContext& ctx) {
    GLuint flat = ctx.builtins.flat.id();
    beginFlatColourView(ctx);
    for (size_t layer = 0; layer < ctx.lists.layers.size(); ++layer) {
        glProgramUniform4fv(flat, 1, 1, &layerColor(layer)[0]);
        drawItems(ctx, ctx.lists.layers[layer], flat);
    }
    const glm::vec4 forward(1.0f, 0.25f, 0.1f, 1);
    glProgramUniform4fv(flat, 1, 1, &forward[0]);
    drawItems(ctx, ctx.lists.forwardOpaque, flat);
    drawItems(ctx, ctx.lists.forwardBlended, flat);
}

// The level of detail each visible item draws: level 0 blue, then green, yellow, orange, red,
// magenta (5 and coarser); items without LODs grey, so "full detail because near" and "full
// detail because there is nothing else" differ. Nearest surface wins, as in the layer view.
glm::vec4 lodColor(uint32_t level, bool hasLevels) {
    static const glm::vec4 palette[] = {{0.15f, 0.35f, 1.0f, 1}, {0.1f, 0.8f, 0.2f, 1},
                                        {1.0f, 0.9f, 0.1f, 1},   {1.0f, 0.5f, 0.05f, 1},
                                        {0.9f, 0.1f, 0.1f, 1},   {0.9f, 0.2f, 0.9f, 1}};
    if (!hasLevels) return {0.5f, 0.5f, 0.5f, 1};
    return palette[std::min<size_t>(level, std::size(palette) - 1)];
}

void renderLodColors(FrameContext& ctx) {
    GLuint flat = ctx.builtins.flat.id();
    beginFlatColourView(ctx);
    const GpuScene& scene = ctx.scene;
    auto drawList = [&](std::span<const DrawRef> refs) {
        for (const DrawRef& ref : refs) {
            const DrawItem& item = scene.items[ref.item];
            glProgramUniform4fv(flat, 1, 1, &lodColor(ref.level - item.firstLevel, item.levelCount > 1)[0]);
            drawItems(ctx, std::span(&ref, 1), flat);
        }
    };
    for (const auto& layer : ctx.lists.layers) drawList(layer);
    drawList(ctx.lists.forwardOpaque);
    drawList(ctx.lists.forwardBlended);
}

void renderOverdraw(FrameContext& ctx) {
    GLuint flat = ctx.builtins.flat.id();
    glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.debugFb.id());
    const float zero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(ctx.targets.debugFb.id(), GL_COLOR, 0, zero);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    const glm::vec4 one(1, 0, 0, 0);
    glProgramUniform4fv(flat, 1, 1, &one[0]);
    for (const auto& layer : ctx.lists.layers) drawItems(ctx, layer, flat);
    drawItems(ctx, ctx.lists.forwardOpaque, flat);
    drawItems(ctx, ctx.lists.forwardBlended, flat);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
}

// The shadow-map array viewer and the SDSM depth histogram (shadow_debug.frag).
void renderShadowDebug(FrameContext& ctx, const ShadowContext& shadows, DebugView mode) {
    const ShadowFrame& f = shadows.frame;
    const ShadowResources& r = shadows.resources;
    glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.outputFb.id());
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_FRAMEBUFFER_SRGB);
    GLuint p = ctx.builtins.shadowDebug.id();
    glUseProgram(p);
    glProgramUniform1i(p, 0, mode == DebugView::ShadowMap ? 0 : 1);
    glProgramUniform1i(p, 1, int(std::min(ctx.settings.debugShadowLayer, std::max(f.cascades, 1u) - 1)));
    glProgramUniform2f(p, 2, f.splits[0], f.gpuFit ? f.splits[1] : f.splits[f.cascades]);
    glProgramUniform1i(p, 3, int(f.cascades));
    glProgramUniform1fv(p, 4, GLsizei(f.splits.size()), f.splits.data());
    glProgramUniform1i(p, 13, f.gpuFit ? 1 : 0);
    glBindTextureUnit(0, r.depthView.id());
    if (f.gpuFit) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_SDSM_STATE, r.sdsmState.id());
    const float black[4] = {0, 0, 0, 1};
    glClearNamedFramebufferfv(ctx.targets.outputFb.id(), GL_COLOR, 0, black);
    if (f.active) drawFullscreenTriangle();
    glEnable(GL_FRAMEBUFFER_SRGB);
    glEnable(GL_DEPTH_TEST);
}

} // namespace

void runDebugView(FrameContext& ctx, const ShadowContext& shadows, const GiContext& giContext) {
    DebugView mode = ctx.settings.debugView;
    // The cascade tint is drawn by lighting itself (shadow_sampling.glsl).
    // GI's indirect light alone is written by lighting itself (gi_lookup.glsl).
    if (mode == DebugView::None || mode == DebugView::Cascades || mode == DebugView::GiIndirect) return;
    ctx.timer.mark("debug");
    if (mode == DebugView::ShadowMap || mode == DebugView::Histogram) {
        renderShadowDebug(ctx, shadows, mode);
        return;
    }
    if (mode == DebugView::Layer) renderLayerColors(ctx);
    if (mode == DebugView::Overdraw) renderOverdraw(ctx);
    if (mode == DebugView::Lod) renderLodColors(ctx);
    glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.outputFb.id());
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_FRAMEBUFFER_SRGB); // values are shown as stored, not as colours
    GLuint p = ctx.builtins.debugView.id();
    glUseProgram(p);
    glProgramUniform1i(p, 0, int(mode));
    glProgramUniform3f(p, 1, ctx.view.znear, ctx.view.zfar, ctx.view.orthographic ? 1.0f : 0.0f);
    for (GLuint unit = 0; unit < 3; ++unit)
        glBindTextureUnit(unit, ctx.targets.gbuffer[0] ? ctx.targets.gbuffer[unit].id() : 0);
    glBindTextureUnit(3, ctx.targets.depth.id());
    glBindTextureUnit(4, ctx.targets.debugColor ? ctx.targets.debugColor.id() : 0);
    // GI views: the RSM on unit 4, the summed volume on 5-7 (black while GI is off).
    const GiResources& gi = giContext.resources;
    const bool giOn = giContext.frame.active;
    if (mode == DebugView::GiRsm) glBindTextureUnit(4, giOn ? gi.rsmColor.id() : 0);
    for (GLuint ch = 0; ch < 3; ++ch) glBindTextureUnit(5 + ch, giOn ? gi.sum[ch].id() : 0);
    uint32_t slices = giOn ? gi.cells * gi.cascades : 1;
    glProgramUniform2f(p, 2, (float(std::min(ctx.settings.debugGiSlice, slices - 1)) + 0.5f) / float(slices),
                       giOn ? 1.0f : 0.0f);
    drawFullscreenTriangle();
    glEnable(GL_FRAMEBUFFER_SRGB);
    glEnable(GL_DEPTH_TEST);
}

} // namespace pnb::player
