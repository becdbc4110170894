// Forward materials against the depth the deferred layers left: opaque ones front to back with
// depth writes, blended ones back to front with SRC_ALPHA / ONE_MINUS_SRC_ALPHA and depth writes
// off (they must not hide each other), both tested against the shared depth.
#include "shading/shading.h"

namespace pnb::player {

void runForward(FrameContext& ctx) {
    if (ctx.lists.forwardOpaque.empty() && ctx.lists.forwardBlended.empty()) return;
    ctx.timer.mark("forward");
    glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.hdrFb.id());
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    drawItems(ctx, ctx.lists.forwardOpaque);
    if (!ctx.lists.forwardBlended.empty()) {
        glDepthMask(GL_FALSE);
        glEnable(GL_BLEND);
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        drawItems(ctx, ctx.lists.forwardBlended);
        glDisable(GL_BLEND);
        glDepthMask(GL_TRUE);
    }
}

} // namespace pnb::player
