// The reflective shadow map (seed 004 §4): the sun's view of every opaque or masked surface in the
// outer cascade, drawn with the surfaces' own G-buffer programs (base colour, normal, metallic
// exactly as the camera's G-buffer gets them; no RSM-specific shader variants) under a frame block
// holding the RSM's matrix. Depth clamp flattens surfaces above the map's near plane onto it, as in
// the shadow pass, and, as there, no face is culled: a single-sided roof seen from above still
// stops the sun (the reference's casters and reflectors are two-sided too); its back face's normal
// is turned towards the sun as the G-buffer shader turns every back face's.
#include "frame/frame_context.h"
#include "gi/gi.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)

namespace pnb::player {

void runGiRsm(FrameContext& ctx, GiContext& gi) {
    const GiFrame& f = gi.frame;
    if (!f.active || f.probesCurrent) return;
    const GiResources& r = gi.resources;
    ctx.timer.mark("gi_rsm");
    std::vector<DrawRef> refs;
    refs.reserve(f.rsmItems.size());
    // At the main view's levels of detail, as the shadow maps (LodState, frame_context.h).
    for (size_t i = 0; i < f.rsmItems.size(); ++i)
        refs.push_back({f.rsmItems[i], 0.0f, f.rsmObjectOffsets[i], drawLevel(ctx.scene, ctx.lod, f.rsmItems[i])});
    glBindFramebuffer(GL_FRAMEBUFFER, r.rsmFb.id());
    glViewport(0, 0, GLsizei(r.rsmResolution), GLsizei(r.rsmResolution));
    const float zero[4] = {0, 0, 0, 0}, far = 1.0f;
    glClearNamedFramebufferfv(r.rsmFb.id(), GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(r.rsmFb.id(), GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(r.rsmFb.id(), GL_DEPTH, 0, &far);
    glEnable(GL_FRAMEBUFFER_SRGB); // base colour is stored sRGB-encoded, like the G-buffer's
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_CLAMP);
    glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_FRAME_BLOCK, ctx.ring.buffer(), GLintptr(f.rsmFrameOffset),
                      sizeof(FrameBlock));
    drawItems(ctx, refs, 0, &GpuMaterial::rsmProgram, true);
    glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_FRAME_BLOCK, ctx.ring.buffer(), GLintptr(ctx.frameBlockOffset),
                      sizeof(FrameBlock));
    glDisable(GL_DEPTH_CLAMP);
    glViewport(0, 0, GLsizei(ctx.targets.width), GLsizei(ctx.targets.height));
}

} // namespace pnb::player
