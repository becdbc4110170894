// The height map for sky visibility (ibl.visibility = height): every opaque or masked surface
// drawn from straight above into one depth texture over the scene's ground plan, keeping the
// highest (GL_GREATER on a depth that grows with height). Lighting marches its sky rays through
// it (shaders/include/sky_visibility.glsl), so a street canyon's walls hide the sky wherever
// they are on screen or not — what the screen-space term cannot know. Drawn once, again only
// when the scene's geometry or materials change (GpuScene::materialsVersion: edits, streamed
// mesh details) or the resolution does; costs one depth pass of the scene at that moment and
// resolution² × 4 bytes.
#include <algorithm>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "frame/frame_context.h"
#include "sky/ibl.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)

namespace pnb::player {

void renderSkyHeightMap(FrameContext& ctx, IblContext& ibl) {
    const GpuScene& scene = ctx.scene;
    const uint32_t res = ctx.settings.iblHeightResolution;
    if (ibl.heightMap && ibl.heightVersion == geometryVersion(scene) && ibl.heightResolution == res) return;
    if (!ctx.builtins.depthOnly) return;
    ctx.timer.mark("sky_height");
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (const DrawItem& item : scene.items) {
        lo = glm::min(lo, item.boundsMin);
        hi = glm::max(hi, item.boundsMax);
    }
    if (!(lo.x <= hi.x)) return; // nothing to draw
    hi = glm::max(hi, lo + 1e-3);
    if (!ibl.heightMap || ibl.heightResolution != res) {
        ibl.heightMap = createTexture(GL_TEXTURE_2D);
        glTextureStorage2D(ibl.heightMap.id(), 1, GL_DEPTH_COMPONENT32F, GLsizei(res), GLsizei(res));
        glTextureParameteri(ibl.heightMap.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(ibl.heightMap.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTextureParameteri(ibl.heightMap.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(ibl.heightMap.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        ibl.heightFb = createFramebuffer();
        glNamedFramebufferTexture(ibl.heightFb.id(), GL_DEPTH_ATTACHMENT, ibl.heightMap.id(), 0);
        glNamedFramebufferDrawBuffer(ibl.heightFb.id(), GL_NONE);
        ibl.heightResolution = res;
    }
    ibl.heightMin = lo;
    ibl.heightMax = hi;
    // Relative to the top centre; clip x, y = ground-plan x, z over the box, depth = 1 at the top
    // falling to 0 at the bottom (cleared to 0: no surface = the bottom of the box).
    const glm::dvec3 eye((lo.x + hi.x) * 0.5, hi.y, (lo.z + hi.z) * 0.5);
    const glm::dvec3 half = (hi - lo) * 0.5;
    glm::dmat4 m(0.0);
    m[0][0] = 1.0 / half.x;            // clip.x from x
    m[2][1] = 1.0 / half.z;            // clip.y from z
    m[1][2] = 1.0 / (hi.y - lo.y);     // clip.z from y (relative to the top: y <= 0)
    m[3][2] = 1.0;
    m[3][3] = 1.0;
    FrameBlock fb{};
    fb.viewProjection = glm::mat4(m);
    size_t fbOffset = ctx.ring.push(&fb, sizeof fb);
    glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_FRAME_BLOCK, ctx.ring.buffer(), GLintptr(fbOffset), sizeof fb);
    const glm::dmat4 toEye = glm::translate(glm::dmat4(1.0), -eye);
    const std::vector<DrawRef> refs = opaqueDrawRefs(ctx, toEye); // glass lets light through
    glBindFramebuffer(GL_FRAMEBUFFER, ibl.heightFb.id());
    glViewport(0, 0, GLsizei(res), GLsizei(res));
    glClearNamedFramebufferfi(ibl.heightFb.id(), GL_DEPTH_STENCIL, 0, 0.0f, 0);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    drawItems(ctx, refs, ctx.builtins.depthOnly.id(), &GpuMaterial::program, true);
    // The warm-up frame draws cut and scissored (Renderer::warmUp): only the real one counts.
    ibl.heightVersion = ctx.warmUp ? ~0ull : geometryVersion(scene);
    ibl.heightBytes = uint64_t(res) * res * 4;
}

} // namespace pnb::player
