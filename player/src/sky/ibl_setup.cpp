// The IblBlock of a frame, planned without GL (planIbl): the environment's irradiance SH turned
// and scaled, the specular cube and BRDF table, and the sky-visibility term with what it reads
// (height map, LPV, probes); prepareIbl binds them and writes the block into the ring.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "frame/frame_context.h"
#include "sky/ibl.h"
#include "gi/gi.h"
#include "pnb_lighting/sh9.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)

namespace pnb::player {

using namespace lighting; // SH9 (pnb_lighting/sh9.h)

bool wantsSkyHeightMap(const FrameView& in) {
    const RenderSettings& s = in.settings;
    return in.scene.iblPrograms && s.iblEnabled && in.scene.environment &&
           resolvedSkyVisibility(s) == SkyVisibility::Height;
}

void planIbl(const FrameView& in, IblContext& ibl, const GiContext& gi, IblBlock& block) {
    const GpuScene& scene = in.scene;
    const RenderSettings& s = in.settings;
    block = IblBlock{};
    ibl.active = false;
    if (!scene.iblPrograms) return; // no environment: nothing bound, nothing read
    if (s.iblEnabled && !scene.environment && !ibl.warned) {
        ibl.warned = true;
        std::fprintf(stderr, "pnb-play: the lighting programs have IBL but the container has no "
                             "environment: no sky light\n");
    }
    ibl.active = s.iblEnabled && scene.environment.has_value();
    if (!wantsSkyHeightMap(in)) { // nothing kept that is not used
        ibl.heightMap = {};
        ibl.heightFb = {};
        ibl.heightResolution = 0;
        ibl.heightBytes = 0;
    }
    if (!ibl.active) return;
    const GpuEnvironment& env = *scene.environment;
    const double angle = double(s.iblRotationDeg) * (3.14159265358979323846 / 180.0);
    Sh9Rgb sh;
    for (size_t k = 0; k < 9; ++k) sh.c[k] = glm::dvec3(env.irradianceSh[k]);
    sh = sh9RotateY(sh, angle);
    for (size_t k = 0; k < 9; ++k) block.sh[k] = glm::vec4(glm::vec3(sh.c[k] * double(s.iblIntensity)), 0.0f);
    ibl.specular = s.iblSpecular && env.specular && env.brdfLut;
    block.rotation = {float(std::cos(angle)), float(std::sin(angle)),
                      float(env.specularLevels > 0 ? env.specularLevels - 1 : 0), ibl.specular ? 1.0f : 0.0f};
    const SkyVisibility asked = resolvedSkyVisibility(s); // auto: probes or none
    float radius = 0;
    if (asked != SkyVisibility::None) {
        const Aabb& b = scene.bounds;
        glm::vec3 diagonal(b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z);
        radius = s.iblVisibilityRadius > 0 ? s.iblVisibilityRadius
                                           : (b.min.x <= b.max.x ? glm::length(diagonal) / 8.0f : 0.0f);
    }
    block.params = {1.0f, ibl.capture ? 1.0f : 0.0f, radius, s.iblIntensity};
    ibl.visibility = asked == SkyVisibility::Screen ? SkyVisibility::Screen : SkyVisibility::None;
    if (asked == SkyVisibility::Height && ibl.heightMap) {
        const glm::dvec3 lo = ibl.heightMin - in.view.position, size = ibl.heightMax - ibl.heightMin;
        block.heightRect = {float(lo.x), float(lo.z), float(1.0 / size.x), float(1.0 / size.z)};
        block.heightRange = {float(lo.y), float(size.y), 0.0f,
                             float(std::max(size.x, size.z) / double(ibl.heightResolution))};
        ibl.visibility = SkyVisibility::Height;
    }
    if (asked == SkyVisibility::Volume) {
        // The LPV's geometry: its face transmittances exist while GI runs with occlusion.
        if (gi.frame.active && s.giOcclusion) {
            ibl.visibility = SkyVisibility::Volume;
        } else if (!ibl.warnedVisibility) {
            ibl.warnedVisibility = true;
            std::fprintf(stderr, "pnb-play: ibl.visibility=volume needs GI with occlusion (gi.enabled, "
                                 "gi.occlusion, a container converted with --gi): no sky visibility\n");
        }
    }
    if (asked == SkyVisibility::Probes) {
        // The probes' own: traced with their occupancy grid (pass_gi_probes.cpp).
        if (gi.frame.active && gi.resources.skyVisibility) {
            ibl.visibility = SkyVisibility::Probes;
        } else if (!ibl.warnedVisibility && s.iblVisibility == SkyVisibility::Probes) { // auto: silent
            ibl.warnedVisibility = true;
            std::fprintf(stderr, "pnb-play: ibl.visibility=probes needs GI probes (gi.enabled, "
                                 "gi.technique=probes, a container converted with --gi, a sun): "
                                 "no sky visibility\n");
        }
    }
    // sky_visibility.glsl's modes: 0 none, 1 screen, 2 height, 3 volume, 4 probes.
    static_assert(int(SkyVisibility::Screen) == 1 && int(SkyVisibility::Probes) == 4);
    block.heightRange.z = float(int(ibl.visibility));
}

void prepareIbl(FrameContext& ctx, IblContext& ibl, const GiContext& gi) {
    IblBlock block;
    planIbl(frameView(ctx), ibl, gi, block);
    if (ibl.active) {
        if (ibl.visibility == SkyVisibility::Height) glBindTextureUnit(15, ibl.heightMap.id());
        if (ibl.visibility == SkyVisibility::Volume) {
            glBindTextureUnit(16, gi.resources.transmittance[0].id());
            glBindTextureUnit(17, gi.resources.transmittance[1].id());
        }
        if (ibl.visibility == SkyVisibility::Probes) glBindTextureUnit(18, gi.resources.skyVisibility.id());
        if (ibl.specular) {
            const GpuEnvironment& env = *ctx.scene.environment;
            glBindTextureUnit(13, ctx.scene.textures[*env.specular].texture.id());
            glBindTextureUnit(14, ctx.scene.textures[*env.brdfLut].texture.id());
        }
    }
    if (!ctx.scene.iblPrograms) return;
    size_t offset = ctx.ring.push(&block, sizeof block);
    glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_IBL_BLOCK, ctx.ring.buffer(), GLintptr(offset), sizeof block);
}

} // namespace pnb::player
