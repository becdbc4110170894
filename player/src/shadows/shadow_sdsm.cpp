// SDSM on the GPU (player/shaders/sdsm.comp): reduce the depth buffer as it is now, partition,
// bound the samples per cascade, build the matrices and cull the casters. The results stay in GPU
// buffers that the shadow pass (indirect draws, masks) and lighting (the ShadowBlock) read
// directly: no read-back, so the CPU never waits for the GPU in the frame loop.
#include <cstddef>

#include <glm/gtc/type_ptr.hpp>

#include "frame/frame_context.h"
#include "shadows/shadow_maps.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)
#include "shared/sdsm_state.h" // SdsmState (GLSL and C++)

namespace pnb::player {

void runSdsmFit(FrameContext& ctx, ShadowContext& shadows) {
    ShadowFrame& f = shadows.frame;
    if (!f.active || !f.gpuFit) return;
    const ShadowResources& r = shadows.resources;
    const RenderSettings& s = ctx.settings;
    ctx.timer.mark("reduce");

    // Reset: min depth = FLT_MAX, max/count/histogram = 0 (the members from depthMaxBits up to
    // cascadeRange, which the partition writes).
    const uint32_t floatMax = 0x7f7fffffu, zero = 0;
    glClearNamedBufferSubData(r.sdsmState.id(), GL_R32UI, offsetof(SdsmState, depthMinBits),
                              sizeof(uint32_t), GL_RED_INTEGER, GL_UNSIGNED_INT, &floatMax);
    glClearNamedBufferSubData(r.sdsmState.id(), GL_R32UI, offsetof(SdsmState, depthMaxBits),
                              offsetof(SdsmState, cascadeRange) - offsetof(SdsmState, depthMaxBits),
                              GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);

    // The depth buffer -> camera-relative position through the inverse view-projection holds for
    // both projections (orthographic: w = 1, depth linear); view depth is along `forward`.
    glm::dvec3 forward = ctx.view.forward();
    const bool ortho = ctx.view.orthographic;
    glm::mat3 rotation(f.lightRotation);
    // Only the quantile partition and the histogram view read the histogram, which costs one
    // shared atomic per sample; the log partition skips it.
    const bool histogram =
        s.sdsmPartition == SdsmPartition::Quantile || s.debugView == DebugView::Histogram;
    auto setCommon = [&](GLuint p) {
        glProgramUniformMatrix4fv(p, 0, 1, GL_FALSE, glm::value_ptr(ctx.view.inverseViewProjection));
        glProgramUniform3f(p, 1, float(forward.x), float(forward.y), float(forward.z));
        glProgramUniform2f(p, 2, f.splits[0], f.splits[1]);
        glProgramUniform1i(p, 3, int(f.cascades));
        // An orthographic view has no perspective aliasing: uniform splits instead of logarithmic
        // ones, and the quantile partition's practical fractions uniform too (lambda 0).
        glProgramUniform1i(p, 4, s.sdsmPartition == SdsmPartition::Quantile ? 1 : ortho ? 2 : 0);
        glProgramUniform1f(p, 5, ortho ? 0.0f : s.shadowLambda);
        glProgramUniformMatrix3fv(p, 6, 1, GL_FALSE, glm::value_ptr(rotation));
        glProgramUniform2f(p, 7, float(f.sceneLightDepth.x), float(f.sceneLightDepth.y));
        glProgramUniform1f(p, 8, s.shadowBlend);
        glProgramUniform1i(p, 9, int(f.casters.size()));
        glProgramUniform1ui(p, 10, r.sdsmCasterCapacity);
        glProgramUniform1i(p, 11, histogram ? 1 : 0);
    };
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_SDSM_STATE, r.sdsmState.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_SDSM_SHADOW_OUT, r.sdsmBlock.id());
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_SDSM_SHADOW_IN, ctx.ring.buffer(),
                      GLintptr(f.blockOffset), sizeof(ShadowBlock));
    glBindTextureUnit(0, ctx.targets.depth.id());
    // 16 x 16 invocations of 4 x 4 pixels each (sdsm.comp's TILE).
    GLuint groupsX = (ctx.targets.width + 63) / 64, groupsY = (ctx.targets.height + 63) / 64;

    setCommon(r.sdsmReduce.id());
    glUseProgram(r.sdsmReduce.id());
    glDispatchCompute(groupsX, groupsY, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    setCommon(r.sdsmPartition.id());
    glUseProgram(r.sdsmPartition.id());
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    setCommon(r.sdsmBounds.id());
    glUseProgram(r.sdsmBounds.id());
    glDispatchCompute(groupsX, groupsY, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    setCommon(r.sdsmFinalize.id());
    glUseProgram(r.sdsmFinalize.id());
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

    if (!f.casters.empty()) {
        setCommon(r.sdsmCull.id());
        // The masks go where the shadow pass reads them. The casters: bounds and the index
        // range of the level each caster draws this frame.
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_SDSM_COMMANDS, r.sdsmCommands.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_CASTER_MASKS, r.sdsmMasks.id());
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_SDSM_CASTERS, ctx.ring.buffer(),
                          GLintptr(f.boundsOffset),
                          GLsizeiptr(f.casterBounds.size() * sizeof(SdsmCasterData)));
        glUseProgram(r.sdsmCull.id());
        glDispatchCompute(GLuint((f.casters.size() + 63) / 64), 1, 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_UNIFORM_BARRIER_BIT);
    glBindTextureUnit(0, 0);
}

} // namespace pnb::player
