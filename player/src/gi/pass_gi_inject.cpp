// Injection (seed 004 §4.2–4.3): RSM texels become virtual point lights in the light volume and
// blocking surfels in the geometry volume; the camera's G-buffer adds blocking surfels of what the
// sun does not see. Both accumulate with atomics into buffers (player/shaders/lpv_inject.comp),
// which the resolve turns into the volumes' textures (lpv_resolve.comp).
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "frame/frame_context.h"
#include "gi/gi.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)

namespace pnb::player {

namespace {

// Camera surfels: every second pixel each way (a quarter of the atomics; each surfel stands for
// its 2x2 pixels).
constexpr int kCameraStride = 2;

void setCascades(GLuint program, const GiFrame& f, const glm::dvec3& camera) {
    glm::vec4 cascades[kMaxGiCascades] = {};
    for (size_t c = 0; c < f.cascades.size(); ++c)
        cascades[c] = glm::vec4(glm::vec3(f.cascades[c].origin - camera), float(f.cascades[c].cellSize));
    glProgramUniform4fv(program, 1, GLsizei(kMaxGiCascades), glm::value_ptr(cascades[0]));
}

} // namespace

void runGiInject(FrameContext& ctx, GiContext& gi) {
    GiFrame& f = gi.frame;
    if (!f.active) return;
    // Before the injection: its own timer section, and the RSM's framebuffer is left anyway.
    if (gi.resources.lpvGlass) voxelizeLpvGlass(ctx, gi);
    const GiResources& r = gi.resources;
    ctx.timer.mark("gi_inject");
    const uint32_t zero = 0;
    glClearNamedBufferData(r.lightAccumulation.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glClearNamedBufferData(r.geometryAccumulation.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    GLuint p = r.injectRsm.id();
    glm::mat4 inverse(glm::inverse(f.rsm.matrix));
    glProgramUniformMatrix4fv(p, 0, 1, GL_FALSE, glm::value_ptr(inverse));
    setCascades(p, f, ctx.view.position);
    glProgramUniform4i(p, 5, GLint(r.cells), GLint(f.cascades.size()), 1, 0);
    glProgramUniform4f(p, 6, float(f.rsmTexelArea), 0, f.geometryScale, f.lightScale);
    glProgramUniform3f(p, 7, float(f.toward.x), float(f.toward.y), float(f.toward.z));
    glProgramUniform2i(p, 8, GLint(r.rsmResolution), GLint(r.rsmResolution));
    glBindTextureUnit(0, r.rsmColor.id());
    glBindTextureUnit(1, r.rsmNormal.id());
    glBindTextureUnit(2, r.rsmDepth.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_LPV_LIGHT, r.lightAccumulation.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_LPV_GEOMETRY, r.geometryAccumulation.id());
    glUseProgram(p);
    GLuint groups = (r.rsmResolution + 7) / 8;
    glDispatchCompute(groups, groups, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void runGiCameraGeometry(FrameContext& ctx, GiContext& gi) {
    const GiFrame& f = gi.frame;
    const GiResources& r = gi.resources;
    const FrameTargets& t = ctx.targets;
    ctx.timer.mark("gi_geometry");
    GLuint p = r.injectCamera.id();
    glProgramUniformMatrix4fv(p, 0, 1, GL_FALSE, glm::value_ptr(ctx.view.inverseViewProjection));
    setCascades(p, f, ctx.view.position);
    glProgramUniform4i(p, 5, GLint(r.cells), GLint(f.cascades.size()), kCameraStride, 1);
    // A pixel's side at view depth z: z * x + y (perspective: x = 2 tan(fov/2) / height, y = 0;
    // orthographic: x = 0, y = 2 ymag / height, parallel rays).
    const float pixel = float(2.0 * ctx.view.halfHeightAt(1.0) / double(t.height));
    const bool ortho = ctx.view.orthographic;
    glProgramUniform4f(p, 6, ortho ? 0.0f : pixel, ortho ? pixel : 0.0f, f.geometryScale, f.lightScale);
    glm::vec3 forward = -glm::vec3(ctx.view.view[0][2], ctx.view.view[1][2], ctx.view.view[2][2]);
    glProgramUniform3f(p, 7, forward.x, forward.y, forward.z);
    glProgramUniform2i(p, 8, GLint(t.width), GLint(t.height));
    glBindTextureUnit(0, t.gbuffer[0].id());
    glBindTextureUnit(1, t.gbuffer[1].id());
    glBindTextureUnit(2, t.depth.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_LPV_LIGHT, r.lightAccumulation.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_LPV_GEOMETRY, r.geometryAccumulation.id());
    glUseProgram(p);
    glDispatchCompute((t.width / kCameraStride + 8) / 8, (t.height / kCameraStride + 8) / 8, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void runGiResolve(FrameContext& ctx, GiContext& gi, bool cameraGeometry) {
    const GiFrame& f = gi.frame;
    const GiResources& r = gi.resources;
    const GLint cells = GLint(r.cells), cascades = GLint(f.cascades.size());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_LPV_LIGHT, r.lightAccumulation.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_LPV_GEOMETRY, r.geometryAccumulation.id());

    GLuint light = r.resolveLight.id();
    glProgramUniform3i(light, 0, cells, cells * cascades, 0);
    glProgramUniform1f(light, 1, 1.0f / f.lightScale);
    for (GLuint ch = 0; ch < 3; ++ch) {
        glBindImageTexture(ch, r.source[ch].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
        glBindImageTexture(3 + ch, r.sum[ch].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    }
    glUseProgram(light);
    GLuint g = GLuint(cells + 3) / 4;
    glDispatchCompute(g, g, GLuint(cells * cascades + 3) / 4);

    GLuint geometry = r.resolveGeometry.id();
    const GLint corners = cells + 1;
    glProgramUniform3i(geometry, 0, corners, corners * cascades, cameraGeometry ? 2 : 1);
    glProgramUniform1f(geometry, 1, 1.0f / f.geometryScale);
    glBindImageTexture(0, r.geometry.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glUseProgram(geometry);
    g = GLuint(corners + 3) / 4;
    glDispatchCompute(g, g, GLuint(corners * cascades + 3) / 4);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);

    if (!ctx.settings.giOcclusion) return;
    GLuint transmit = r.resolveTransmittance.id();
    glProgramUniform3i(transmit, 0, cells, cells * cascades, cascades);
    glBindTextureUnit(0, r.geometry.id());
    glBindImageTexture(0, r.transmittance[0].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glBindImageTexture(1, r.transmittance[1].id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA8);
    glUseProgram(transmit);
    g = GLuint(cells + 3) / 4;
    glDispatchCompute(g, g, GLuint(cells * cascades + 3) / 4);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
}

} // namespace pnb::player
