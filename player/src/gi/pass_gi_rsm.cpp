// The reflective shadow map (seed 004 §4): the sun's view of every opaque or masked surface in the
// outer cascade, drawn with the surfaces' own G-buffer programs (base colour, normal, metallic
// exactly as the camera's G-buffer gets them; no RSM-specific shader variants) under a frame block
// holding the RSM's matrix. Depth clamp flattens surfaces above the map's near plane onto it, as in
// the shadow pass, and, as there, no face is culled: a single-sided roof seen from above still
// stops the sun (the reference's casters and reflectors are two-sided too); its back face's normal
// is turned towards the sun as the G-buffer shader turns every back face's.
//
// Then the translucent casters (issue 43: BLEND materials that cast shadows), when there are any
// in the map: gi_transmit.frag multiplies the map's base colour by each one's transmittance where
// it lies in front of the opaque surface there (depth test, no depth write), so the flux the VPLs
// and the LPV's injection take from the map behind a window is tinted and dimmed, panes along one
// ray multiplying. The panes are not in the opaque draw: their own surface never becomes a VPL.
#include <algorithm>

#include "frame/frame_context.h"
#include "gi/gi.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)

namespace pnb::player {

namespace {

// The translucent casters over the map's opaque surfaces: base colour (flux) x transmittance,
// blended in linear (GL_FRAMEBUFFER_SRGB is on), the normal target and depth left as they are.
void multiplyByGlass(FrameContext& ctx, const GiContext& gi) {
    const GiFrame& f = gi.frame;
    ctx.timer.mark("gi_rsm_glass");
    std::vector<DrawRef> refs;
    for (size_t i = 0; i < f.rsmGlassItems.size(); ++i)
        refs.push_back({f.rsmGlassItems[i], 0.0f, f.rsmGlassOffsets[i], drawLevel(ctx.scene, ctx.lod, f.rsmGlassItems[i])});
    glDepthMask(GL_FALSE);
    glColorMaski(1, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glEnablei(GL_BLEND, 0);
    glBlendFuncSeparate(GL_ZERO, GL_SRC_COLOR, GL_ZERO, GL_ONE); // rgb: dst x T; alpha: dst
    drawTranslucentCasters(ctx, refs, gi.resources.transmitRsm.id());
    glDisablei(GL_BLEND, 0);
    glBlendFunc(GL_ONE, GL_ZERO);
    glColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
}

} // namespace

void drawTranslucentCasters(FrameContext& ctx, std::vector<DrawRef>& refs, GLuint program) {
    const GpuScene& scene = ctx.scene;
    std::stable_sort(refs.begin(), refs.end(), [&](const DrawRef& a, const DrawRef& b) {
        return scene.items[a.item].material < scene.items[b.item].material;
    });
    for (size_t first = 0; first < refs.size();) {
        const uint32_t material = scene.items[refs[first].item].material;
        size_t end = first;
        while (end < refs.size() && scene.items[refs[end].item].material == material) ++end;
        const bool map = scene.materials[material].desc.textures[size_t(TextureSlotKind::BaseColor)].texture != kNone;
        glProgramUniform1i(program, 2, map ? 1 : 0); // gi_transmit.frag's uHasBaseColorMap
        drawItems(ctx, std::span(refs).subspan(first, end - first), program, &GpuMaterial::program, true);
        first = end;
    }
}

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
    if (!f.rsmGlassItems.empty()) multiplyByGlass(ctx, gi);
    glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_FRAME_BLOCK, ctx.ring.buffer(), GLintptr(ctx.frameBlockOffset),
                      sizeof(FrameBlock));
    glDisable(GL_DEPTH_CLAMP);
    glViewport(0, 0, GLsizei(ctx.targets.width), GLsizei(ctx.targets.height));
}

} // namespace pnb::player
