// Layered deferred shading (seed 003, §2.4): for each deferred layer in ascending priority,
// clear the G-buffer colour but keep the shared depth, draw the layer with blending off and
// depth writes on, then compose its lighting into the HDR target with alpha blending and depth
// writes off. The depth buffer thus ends up exactly as forward-rendering the same objects would
// leave it, so forward objects drawn afterwards are depth-correct. Layers without visible items
// are skipped entirely (no clear, no compose) — unlike the baseline, which cleared and composed
// up to the highest priority of any material.
#include <glm/gtc/type_ptr.hpp>

#include "frame/frame_context.h"

namespace pnb::player {

void runDeferredLayers(FrameContext& ctx) {
    const GpuScene& scene = ctx.scene;
    if (scene.deferredLayers.empty() || !scene.deferredLightingProgram) return;
    const GLuint lighting = scene.programs[*scene.deferredLightingProgram].id();
    for (size_t layer = 0; layer < ctx.lists.layers.size(); ++layer) {
        const std::vector<DrawRef>& refs = ctx.lists.layers[layer];
        if (refs.empty()) continue;
        ++ctx.stats.deferredLayersDrawn;
        ctx.timer.mark("gbuffer");
        glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.gbufferFb.id());
        const float zero[4] = {0, 0, 0, 0};
        for (GLint rt = 0; rt < 3; ++rt) glClearNamedFramebufferfv(ctx.targets.gbufferFb.id(), GL_COLOR, rt, zero);
        glDisable(GL_BLEND);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_GREATER);
        glDepthMask(GL_TRUE);
        drawItems(ctx, refs);
        if (ctx.shadows.frame.pending) { // SDSM: fit to the depth just written, then draw the maps
            ctx.shadows.frame.pending = false;
            runSdsmFit(ctx);
            runShadowPass(ctx);
        }
        if (ctx.gi.frame.pending) finishGi(ctx); // GI's camera surfels: this layer's G-buffer

        ctx.timer.mark("lighting");
        glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.composeFb.id());
        glDisable(GL_DEPTH_TEST);
        glDepthMask(GL_FALSE);
        glEnable(GL_BLEND);
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        glUseProgram(lighting);
        glProgramUniformMatrix4fv(lighting, 0, 1, GL_FALSE,
                                  glm::value_ptr(ctx.view.inverseViewProjection));
        for (GLuint unit = 0; unit < 3; ++unit)
            glBindTextureUnit(unit, ctx.targets.gbuffer[unit].id());
        glBindTextureUnit(3, ctx.targets.depth.id());
        drawFullscreenTriangle();
        glDepthMask(GL_TRUE);
    }
    glDisable(GL_BLEND);
}

} // namespace pnb::player
