// Layered deferred shading (seed 003, §2.4): for each deferred layer in ascending priority,
// clear the G-buffer colour but keep the shared depth, draw the layer with blending off and
// depth writes on, then compose its lighting into the HDR target with alpha blending and depth
// writes off. The depth buffer thus ends up exactly as forward-rendering the same objects would
// leave it, so forward objects drawn afterwards are depth-correct. Layers without visible items
// are skipped entirely (no clear, no compose) — unlike the baseline, which cleared and composed
// up to the highest priority of any material.
// The first layer's G-buffer and its lighting are two passes of the frame list
// (renderer/frame.cpp) because SDSM fits to that layer's depth and GI takes the camera's surfels
// from it between them.
#include <glm/gtc/type_ptr.hpp>

#include "shading/shading.h"

namespace pnb::player {

void deferredLayersToDraw(const FrameContext& ctx, std::vector<size_t>& layers) {
    layers.clear();
    if (ctx.scene.deferredLayers.empty() || !ctx.scene.deferredLightingProgram) return;
    for (size_t layer = 0; layer < ctx.lists.layers.size(); ++layer)
        if (!ctx.lists.layers[layer].empty()) layers.push_back(layer);
}

void runGBuffer(FrameContext& ctx, size_t layer) {
    ++ctx.stats.deferredLayersDrawn;
    ctx.timer.mark("gbuffer");
    glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.gbufferFb.id());
    const float zero[4] = {0, 0, 0, 0};
    for (GLint rt = 0; rt < 3; ++rt) glClearNamedFramebufferfv(ctx.targets.gbufferFb.id(), GL_COLOR, rt, zero);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_TRUE);
    drawItems(ctx, ctx.lists.layers[layer]);
}

void runDeferredLighting(FrameContext& ctx) {
    const GLuint lighting = ctx.scene.programs[*ctx.scene.deferredLightingProgram].id();
    ctx.timer.mark("lighting");
    glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.composeFb.id());
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(lighting);
    glProgramUniformMatrix4fv(lighting, 0, 1, GL_FALSE, glm::value_ptr(ctx.view.inverseViewProjection));
    for (GLuint unit = 0; unit < 3; ++unit) glBindTextureUnit(unit, ctx.targets.gbuffer[unit].id());
    glBindTextureUnit(3, ctx.targets.depth.id());
    drawFullscreenTriangle();
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
}

} // namespace pnb::player
