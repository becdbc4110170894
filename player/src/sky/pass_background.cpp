// The environment behind the scene: one full-screen triangle at the far plane (reversed-Z depth
// 0), depth-tested GL_GEQUAL against the depth the deferred layers left, so only pixels no
// surface covered are shaded. Drawn before the forward materials: opaque ones overwrite it,
// blended ones blend over it.
#include <algorithm>
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "frame/frame_context.h"
#include "sky/ibl.h"

namespace pnb::player {

void runBackground(FrameContext& ctx, const IblContext& ibl) {
    const GpuScene& scene = ctx.scene;
    const RenderSettings& s = ctx.settings;
    if (!ibl.active || !s.iblBackground || !ctx.builtins.background || !scene.environment ||
        !scene.environment->radiance || ibl.capture)
        return;
    ctx.timer.mark("background");
    const GpuTexture& radiance = scene.textures[*scene.environment->radiance];
    glBindFramebuffer(GL_FRAMEBUFFER, ctx.targets.hdrFb.id());
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GEQUAL);
    glDepthMask(GL_FALSE);
    glDisable(GL_BLEND);
    const GLuint p = ctx.builtins.background.id();
    glUseProgram(p);
    glProgramUniformMatrix4fv(p, 0, 1, GL_FALSE, glm::value_ptr(ctx.view.inverseViewProjection));
    // The level whose texel spans what a pixel does: texel 2 pi / width radians, pixel about
    // (vertical field of view) / (viewport height) at the centre.
    const double angle = double(s.iblRotationDeg) * (3.14159265358979323846 / 180.0);
    const double pixel = double(ctx.view.yfov) / double(std::max(ctx.targets.height, 1u));
    const double texel = 2.0 * 3.14159265358979323846 / double(std::max(radiance.width, 1u));
    const double level = std::clamp(std::log2(pixel / texel), 0.0, double(radiance.mipCount - 1));
    glProgramUniform4f(p, 1, float(std::cos(angle)), float(std::sin(angle)), s.iblIntensity,
                       float(std::max(0.0, level - double(radiance.firstLevel))));
    glBindTextureUnit(0, radiance.texture.id());
    drawFullscreenTriangle();
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_GREATER);
}

} // namespace pnb::player
