// gi.technique = probes (gi.h): after the RSM, (1) the scene's occupancy grid over the probes'
// box, drawn only when the geometry, materials or the box change (gi_voxelize.frag: three
// orthographic draws, one along each axis); (2) the RSM's texels clustered into gi.vpls^2
// virtual point lights (gi_vpls.comp); (3) every probe gathers every VPL it can see (by its depth
// map, traced with the grid, or a walk through the grid: gi.probe_visibility) into the volumes
// lighting reads (gi_probe_gather.comp). No propagation, no camera surfels:
// nothing here depends on the view but the box when it follows the camera (gi.cell_size > 0), so
// with gi.probe_cache all of it (and the RSM) runs again only when an input changed
// (GiFrame::probeInputs: the sun, the grid, the sizes, geometry, materials, resident texture
// levels, the RSM items' levels of detail). With ibl.visibility = probes, (4) every probe traces
// rays through the grid for the sky it sees (gi_probe_gather.comp, SKY_VISIBILITY), again only
// when the grid was redrawn: it depends on the geometry alone, not on the sun.
// With translucent casters (issue 43: BLEND materials that cast shadows), the panes are drawn
// into a transmittance grid beside the occupancy grid (gi_transmit.frag, VOXELIZE; they stay out
// of the occupancy grid), and every ray of (3) and (4) is dimmed and tinted by the panes it
// crosses (gi_probe_gather.comp, TRANSMITTANCE). With gi.bounces > 1 the grid also holds the
// surfaces' albedo and the gather repeats with one more bounce each time (pass_gi_bounce.cpp).
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "frame/frame_context.h"
#include "gi/gi.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)

namespace pnb::player {

glm::dmat4 giAxisView(int axis, double extent) {
    glm::dmat4 m(0.0);
    const int horizontal = axis == 0 ? 2 : 0, vertical = axis == 1 ? 2 : 1;
    m[horizontal][0] = 2.0 / extent;
    m[3][0] = -1.0;
    m[vertical][1] = 2.0 / extent;
    m[3][1] = -1.0;
    m[axis][2] = 1.0 / extent;
    m[3][3] = 1.0;
    return m;
}

void bindVoxelTarget(GLuint framebuffer, uint32_t side) {
    glNamedFramebufferParameteri(framebuffer, GL_FRAMEBUFFER_DEFAULT_WIDTH, GLint(side));
    glNamedFramebufferParameteri(framebuffer, GL_FRAMEBUFFER_DEFAULT_HEIGHT, GLint(side));
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, GLsizei(side), GLsizei(side));
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
}

void bindProbeGatherInputs(const GiResources& r, GLuint program, const glm::vec3& origin, float spacing) {
    glProgramUniform4f(program, 0, origin.x, origin.y, origin.z, spacing);
    glProgramUniform3i(program, 1, GLint(r.cells), GLint(r.vplSide * r.vplSide), GLint(r.voxelSide));
    glBindTextureUnit(0, r.voxels.id());
    if (r.probeDepth) {
        glBindTextureUnit(1, r.probeDepth.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_GI_PROBE_NEEDED, r.probeNeeded.id());
    }
    if (r.probeTransmit) glBindTextureUnit(2, r.probeTransmit.id());
    if (r.transmitVoxels) glBindTextureUnit(3, r.transmitVoxels.id());
}

void bindAxisFrameBlock(FrameContext& ctx, int axis, double extent, uint32_t side) {
    FrameBlock fb{};
    fb.viewProjection = glm::mat4(giAxisView(axis, extent));
    fb.view = glm::mat4(1.0f);
    fb.viewport = {float(side), float(side), 1.0f / float(side), 1.0f / float(side)};
    const size_t offset = ctx.ring.push(&fb, sizeof fb);
    glBindBufferRange(GL_UNIFORM_BUFFER, 0, ctx.ring.buffer(), GLintptr(offset), sizeof fb);
}

std::vector<DrawRef> glassDrawRefs(FrameContext& ctx, const glm::dmat4& toGrid) {
    const GpuScene& scene = ctx.scene;
    std::vector<DrawRef> refs;
    for (uint32_t i = 0; i < scene.items.size(); ++i) {
        if (!translucentCaster(scene.materials[scene.items[i].material])) continue;
        refs.push_back({i, 0.0f, pushObjectBlock(scene, scene.items[i], toGrid, ctx.ring, 0.0f),
                        drawLevel(scene, ctx.lod, i)});
    }
    return refs;
}

namespace {

void voxelizeScene(FrameContext& ctx, GiContext& gi, const LpvCascade& box) {
    GiResources& r = gi.resources;
    const double cell = box.cellSize * double(box.cells) / double(r.voxelSide);
    if (r.voxelVersion == gi.frame.geometryVersion && r.voxelOrigin == box.origin && r.voxelCell == cell) return;
    const uint8_t zero = 0;
    glClearTexImage(r.voxels.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_BYTE, &zero);
    const glm::dmat4 toGrid = glm::translate(glm::dmat4(1.0), -box.origin);
    const std::vector<DrawRef> refs = opaqueDrawRefs(ctx, toGrid); // glass lets light through
    const GLsizei side = GLsizei(r.voxelSide);
    std::vector<DrawRef> glass;
    if (r.transmitVoxels) {
        const float clear[4] = {1, 1, 1, 0}; // a = 0: no pane
        glClearTexImage(r.transmitVoxels.id(), 0, GL_RGBA, GL_FLOAT, clear);
        glass = glassDrawRefs(ctx, toGrid);
        glBindImageTexture(1, r.transmitVoxels.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
        glProgramUniform1i(r.transmitVoxelize.id(), 1, GLint(side));
    }
    bindVoxelTarget(r.voxelFb.id(), uint32_t(side));
    glBindImageTexture(0, r.voxels.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R8UI);
    std::vector<DrawRef> albedoRefs;
    if (r.albedoVoxels) { // gi.bounces > 1: the surfaces' albedo sums beside their voxels
        const uint32_t none = 0;
        glClearTexImage(r.albedoVoxels.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
        glBindImageTexture(2, r.albedoVoxels.id(), 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
        // A mesh without a colour stream reads the attribute's current value: white, as the
        // G-buffer's vColor without HAS_VERTEX_COLOR (gi_voxelize.vert).
        glVertexAttrib4f(5, 1.0f, 1.0f, 1.0f, 1.0f);
        albedoRefs = refs;
    }
    const GLuint p = r.albedoVoxels ? r.voxelizeAlbedo.id() : r.voxelize.id();
    glProgramUniform1i(p, 1, GLint(side));
    for (int axis = 0; axis < 3; ++axis) {
        bindAxisFrameBlock(ctx, axis, box.cellSize * double(box.cells), uint32_t(side));
        glProgramUniform1i(p, 0, axis);
        if (r.albedoVoxels) // per material: whether its base colour unit holds a texture
            drawTranslucentCasters(ctx, albedoRefs, p);
        else
            drawItems(ctx, refs, p, &GpuMaterial::program, true);
        if (glass.empty()) continue;
        glProgramUniform1i(r.transmitVoxelize.id(), 0, axis);
        drawTranslucentCasters(ctx, glass, r.transmitVoxelize.id());
    }
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindBufferRange(GL_UNIFORM_BUFFER, 0, ctx.ring.buffer(), GLintptr(ctx.frameBlockOffset), sizeof(FrameBlock));
    glEnable(GL_DEPTH_TEST);
    r.skyCurrent = r.depthCurrent = false;
    // The warm-up frame draws cut (Renderer::warmUp): only a real frame's grid is kept.
    r.voxelVersion = ctx.warmUp ? ~0ull : gi.frame.geometryVersion;
    r.voxelOrigin = box.origin;
    r.voxelCell = cell;
}

// One work group per probe tracing rays through the occupancy grid (gi_probe_gather.comp's
// SKY_VISIBILITY and PROBE_DEPTH), its outputs bound by the caller. Returns whether what it traced
// is kept: the warm-up frame's grid is not (voxelizeScene).
bool traceThroughGrid(FrameContext& ctx, GiContext& gi, GLuint program, const glm::vec3& origin, float spacing) {
    GiResources& r = gi.resources;
    glProgramUniform4f(program, 0, origin.x, origin.y, origin.z, spacing);
    glProgramUniform3i(program, 1, GLint(r.cells), 0, GLint(r.voxelSide));
    glBindTextureUnit(0, r.voxels.id());
    if (r.transmitVoxels) glBindTextureUnit(3, r.transmitVoxels.id());
    glUseProgram(program);
    glDispatchCompute(r.cells, r.cells, r.cells);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                    GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindTextureUnit(0, 0);
    glBindTextureUnit(3, 0);
    glUseProgram(0);
    return !ctx.warmUp;
}

// Every probe's view of the sky (ibl.visibility = probes).
void traceSkyVisibility(FrameContext& ctx, GiContext& gi, const glm::vec3& origin, float spacing) {
    GiResources& r = gi.resources;
    glBindImageTexture(0, r.skyVisibility.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    r.skyCurrent = traceThroughGrid(ctx, gi, r.traceSky.id(), origin, spacing);
}

// Every needed probe's depth map, and which probes are needed (gi.probe_visibility = depth).
void traceProbeDepths(FrameContext& ctx, GiContext& gi, const glm::vec3& origin, float spacing) {
    GiResources& r = gi.resources;
    glBindImageTexture(0, r.probeDepth.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R16F);
    if (r.probeTransmit) glBindImageTexture(1, r.probeTransmit.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_GI_PROBE_NEEDED, r.probeNeeded.id());
    r.depthCurrent = traceThroughGrid(ctx, gi, r.traceDepth.id(), origin, spacing);
}

} // namespace

void runGiProbes(FrameContext& ctx, GiContext& gi) {
    const GiFrame& f = gi.frame;
    GiResources& r = gi.resources;
    const bool skyStale = r.skyVisibility && !r.skyCurrent;
    if (f.probesCurrent && !skyStale) return; // nothing they see changed (gi.probe_cache)
    // One timer pass for all of it: llvmpipe runs a dispatch when the next command needs it, so
    // finer marks would put the gather's time into whichever pass came next.
    ctx.timer.mark("gi_probes");
    const LpvCascade& box = f.cascades.front();
    voxelizeScene(ctx, gi, box);
    const glm::vec3 origin(box.origin - ctx.view.position);
    if (r.skyVisibility && !r.skyCurrent) traceSkyVisibility(ctx, gi, origin, float(box.cellSize));
    if (f.probesCurrent) return;
    if (r.probeDepth && !r.depthCurrent) traceProbeDepths(ctx, gi, origin, float(box.cellSize));

    const GLuint cluster = r.clusterVpls.id();
    const glm::mat4 inverse(glm::inverse(f.rsm.matrix));
    const GLint block = GLint((r.rsmResolution + r.vplSide - 1) / r.vplSide);
    glProgramUniformMatrix4fv(cluster, 0, 1, GL_FALSE, glm::value_ptr(inverse));
    glProgramUniform3f(cluster, 1, float(f.toward.x), float(f.toward.y), float(f.toward.z));
    glProgramUniform3i(cluster, 2, GLint(r.rsmResolution), block, GLint(r.vplSide));
    glProgramUniform1f(cluster, 3, float(f.rsmTexelArea));
    glBindTextureUnit(0, r.rsmColor.id());
    glBindTextureUnit(1, r.rsmNormal.id());
    glBindTextureUnit(2, r.rsmDepth.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_GI_VPLS, r.vpls.id());
    glUseProgram(cluster);
    const GLuint groups = (r.vplSide + 7) / 8;
    glDispatchCompute(groups, groups, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    const GLuint gather = r.gatherProbes.id();
    bindProbeGatherInputs(r, gather, origin, float(box.cellSize));
    for (GLuint ch = 0; ch < 3; ++ch)
        glBindImageTexture(ch, r.sum[ch].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glUseProgram(gather);
    glDispatchCompute((r.cells + 7) / 8, r.cells, r.cells); // 8 probes along x a group
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    runGiProbeBounces(ctx, gi, origin, float(box.cellSize)); // gi.bounces > 1
    for (GLuint unit = 0; unit < 4; ++unit) glBindTextureUnit(unit, 0); // voxels, depth maps, panes
    glUseProgram(0);
    r.probeInputs = ctx.warmUp ? std::vector<uint64_t>{} : f.probeInputs;
}

} // namespace pnb::player
