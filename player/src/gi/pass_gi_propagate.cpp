// Propagation (seed 004 §4.4; player/shaders/lpv_propagate.comp): gi.iterations gather steps,
// ping-ponging between two volumes and adding each step to the sum that lighting reads, after a
// dispatch that scales the injection into the steps' source form. The geometry volume blocks
// light (gi.occlusion) at the face each step crosses; translucent casters' cells dim and tint it
// (issue 43, pass_gi_lpv_glass.cpp).
#include <utility>

#include "frame/frame_context.h"
#include "gi/gi.h"

namespace pnb::player {

void runGiPropagate(FrameContext& ctx, GiContext& gi) {
    const GiFrame& f = gi.frame;
    GiResources& r = gi.resources;
    ctx.timer.mark("gi_propagate");
    // With translucent casters, the variant that dims and tints at the panes' cells (GLASS).
    GLuint p = ctx.settings.giOcclusion ? (r.lpvGlass ? r.propagateOccludedGlass : r.propagateOccluded).id()
                                        : (r.lpvGlass ? r.propagateGlass : r.propagate).id();
    const GLint cells = GLint(r.cells), cascades = GLint(f.cascades.size());
    glProgramUniform2i(p, 0, cells, cascades);
    glUseProgram(p);
    glBindTextureUnit(3, r.transmittance[0].id());
    glBindTextureUnit(4, r.transmittance[1].id());
    if (r.lpvGlass) glBindTextureUnit(5, r.lpvGlass.id());
    for (GLuint ch = 0; ch < 3; ++ch)
        glBindImageTexture(3 + ch, r.sum[ch].id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA16F);
    std::array<GlHandle, 3>* from = &r.source;
    std::array<GlHandle, 3>* to = &r.next;
    const GLuint g = GLuint(cells + 3) / 4, gz = GLuint(cells * cascades + 3) / 4;
    // Dispatch 0 only scales the injection into a propagation source (the sum keeps it as it is);
    // every step after writes its result so scaled.
    const uint32_t dispatches = ctx.settings.giIterations > 0 ? ctx.settings.giIterations + 1 : 0;
    for (uint32_t i = 0; i < dispatches; ++i) {
        for (GLuint ch = 0; ch < 3; ++ch) {
            glBindTextureUnit(ch, (*from)[ch].id());
            glBindImageTexture(ch, (*to)[ch].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        }
        glProgramUniform1i(p, 1, i == 0);
        glDispatchCompute(g, g, gz);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
        std::swap(from, to);
    }
    for (GLuint unit = 0; unit < (r.lpvGlass ? 6u : 5u); ++unit) glBindTextureUnit(unit, 0);
}

void finishGi(FrameContext& ctx, GiContext& gi) {
    GiFrame& f = gi.frame;
    if (!f.active) return;
    bool camera = ctx.settings.giCameraOcclusion && ctx.settings.giOcclusion && ctx.targets.gbuffer[0] &&
                  ctx.stats.deferredLayersDrawn > 0;
    if (camera) runGiCameraGeometry(ctx, gi);
    runGiResolve(ctx, gi, camera);
    runGiPropagate(ctx, gi);
    // Lighting's state: its frame block, the volumes.
    glUseProgram(0);
    bindGiForLighting(ctx, gi);
}

} // namespace pnb::player
