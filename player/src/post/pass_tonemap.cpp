// HDR -> sRGB output: the container's tonemap program (exposure + ACES fit), written through
// GL_FRAMEBUFFER_SRGB (enabled for the whole frame) so the hardware encodes; then optional FXAA from a twin target.
#include "post/post.h"

namespace pnb::player {

void runTonemap(FrameContext& ctx) {
    ctx.timer.mark("tonemap");
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    bool fxaa = ctx.settings.fxaa && ctx.builtins.fxaa;
    glBindFramebuffer(GL_FRAMEBUFFER,
                      fxaa ? ctx.targets.fxaaInputFb.id() : ctx.targets.outputFb.id());
    if (ctx.scene.tonemapProgram) {
        GLuint p = ctx.scene.programs[*ctx.scene.tonemapProgram].id();
        glUseProgram(p);
        glProgramUniform1f(p, 0, ctx.settings.exposure);
        glBindTextureUnit(0, ctx.targets.hdr.id());
        drawFullscreenTriangle();
    } else {
        // A container without a tonemap program: show the HDR target as is.
        glBlitNamedFramebuffer(ctx.targets.hdrFb.id(),
                               fxaa ? ctx.targets.fxaaInputFb.id() : ctx.targets.outputFb.id(), 0, 0,
                               GLint(ctx.targets.width), GLint(ctx.targets.height), 0, 0,
                               GLint(ctx.targets.width), GLint(ctx.targets.height),
                               GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    if (fxaa) {
        ctx.timer.mark("fxaa");
        glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.outputFb.id());
        glUseProgram(ctx.builtins.fxaa.id());
        glBindTextureUnit(0, ctx.targets.fxaaInput.id());
        drawFullscreenTriangle();
    }
    glEnable(GL_DEPTH_TEST);
}

} // namespace pnb::player
