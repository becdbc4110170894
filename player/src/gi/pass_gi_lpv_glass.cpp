// LPV light through glass (issue 43; gi.h): the translucent casters are drawn into each cascade's
// cells (GiResources::lpvGlass, rgb = the pane's T, a = 1 where a pane is) with gi_transmit.frag's
// VOXELIZE path, the same three axis views as the probes' transmittance grid
// (pass_gi_probes.cpp), one cascade after the other at its z in the stack. Propagation
// (lpv_propagate.comp, GLASS) then dims and tints the flux that enters a pane's cell.
// The panes are not in the geometry volume: that one holds opaque surfels from the RSM and the
// camera, and a pane's partial, coloured blocking needs three channels anyway.
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "frame/frame_context.h"
#include "gi/gi.h"

namespace pnb::player {

namespace {

// The cascades as lpvGlass holds them: equal = nothing to draw again (they follow the camera by
// whole cells, so most frames they stay put).
std::vector<glm::dvec4> cascadeBoxes(const GiFrame& f) {
    std::vector<glm::dvec4> boxes;
    for (const LpvCascade& c : f.cascades) boxes.emplace_back(c.origin, c.cellSize);
    return boxes;
}

} // namespace

void voxelizeLpvGlass(FrameContext& ctx, GiContext& gi) {
    GiResources& r = gi.resources;
    const GiFrame& f = gi.frame;
    const GpuScene& scene = ctx.scene;
    std::vector<glm::dvec4> boxes = cascadeBoxes(f);
    if (r.lpvGlassVersion == scene.materialsVersion && r.lpvGlassBoxes == boxes) return;
    ctx.timer.mark("gi_lpv_glass");
    const float clear[4] = {1, 1, 1, 0}; // everything through, no pane
    glClearTexImage(r.lpvGlass.id(), 0, GL_RGBA, GL_FLOAT, clear);
    const GLsizei side = GLsizei(r.cells);
    bindVoxelTarget(r.lpvGlassFb.id(), uint32_t(side));
    glBindImageTexture(1, r.lpvGlass.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
    const GLuint p = r.transmitVoxelize.id();
    glProgramUniform1i(p, 1, GLint(side));
    for (size_t c = 0; c < f.cascades.size(); ++c) {
        const LpvCascade& box = f.cascades[c];
        std::vector<DrawRef> glass = glassDrawRefs(ctx, glm::translate(glm::dmat4(1.0), -box.origin));
        glProgramUniform1i(p, 3, GLint(c * r.cells)); // gi_transmit.frag's uLayer
        for (int axis = 0; axis < 3; ++axis) {
            bindAxisFrameBlock(ctx, axis, box.cellSize * double(box.cells), uint32_t(side));
            glProgramUniform1i(p, 0, axis);
            drawTranslucentCasters(ctx, glass, p);
        }
    }
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindImageTexture(1, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glBindBufferRange(GL_UNIFORM_BUFFER, 0, ctx.ring.buffer(), GLintptr(ctx.frameBlockOffset), sizeof(FrameBlock));
    glEnable(GL_DEPTH_TEST); // as the RSM left it (runGiInject calls this right after it)
    glViewport(0, 0, GLsizei(ctx.targets.width), GLsizei(ctx.targets.height));
    // The warm-up frame draws cut (Renderer::warmUp): only a real frame's cells are kept.
    r.lpvGlassVersion = ctx.warmUp ? ~0ull : scene.materialsVersion;
    r.lpvGlassBoxes = std::move(boxes);
}

} // namespace pnb::player
