// GI's per-frame set-up (gi.h): planned without GL (planGi): the cascades, the RSM's fit, what it
// draws, the GiBlock; then the volumes' storage and the ring (prepareGi).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include "frame/frame_context.h"
#include "gi/gi.h"
#include "shadows/shadow_maps.h"
#include "gl/gl_allocation.h"
#include "pnb_lighting/scene_lights.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)

namespace pnb::player {

namespace {

// The sun GI bounces: the shadowing light, else the first directional light; -1 if none
// (the GI truth picks it by the same rule).
int giLight(const GpuScene& scene) {
    return lighting::bouncedSunIndex(scene.lights.size(),
                                     [&](size_t i) -> const Light& { return scene.lights[i].desc; });
}

// Whether some drawn surface reflects and receives diffuse light: an opaque or masked material
// whose diffuse albedo, base colour x (1 - metallic), is not black (a texture may lift a zero
// factor: then it counts). One bounce of diffuse light off only metal and black is zero
// everywhere, so GI runs no pass and holds no memory for it.
bool anyDiffuseSurface(const GpuScene& scene) {
    for (const DrawItem& item : scene.items) {
        const Material& m = scene.materials[item.material].desc;
        if (m.alphaMode == AlphaMode::Blend) continue;
        const bool metalTexture = m.textures[size_t(TextureSlotKind::MetallicRoughness)].texture != kNone;
        const bool colourTexture = m.textures[size_t(TextureSlotKind::BaseColor)].texture != kNone;
        const bool colour = colourTexture || m.baseColorFactor.x > 0 || m.baseColorFactor.y > 0 || m.baseColorFactor.z > 0;
        if (colour && (m.metallicFactor < 1.0f || metalTexture)) return true;
    }
    return false;
}

// A power of two of fixed-point units per 1.0 such that `largest` stays below 2^29 (headroom
// for a few of them in one cell), at most 2^27.
float fixedScale(double largest) {
    double e = std::floor(std::log2(std::ldexp(1.0, 29) / std::max(largest, 1e-30)));
    return float(std::ldexp(1.0, int(std::clamp(e, 0.0, 27.0))));
}

// The light-space bounds of the camera-relative box [lo, hi] - camera.
std::pair<glm::dvec3, glm::dvec3> lightBounds(const glm::dmat3& rotation, const glm::dvec3& lo,
                                              const glm::dvec3& hi, const glm::dvec3& camera) {
    glm::dvec3 a(std::numeric_limits<double>::infinity()), b(-std::numeric_limits<double>::infinity());
    for (int c = 0; c < 8; ++c) {
        glm::dvec3 p{(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z};
        glm::dvec3 l = rotation * (p - camera);
        a = glm::min(a, l);
        b = glm::max(b, l);
    }
    return {a, b};
}

} // namespace

namespace {

// The cascades (or the probes' one grid) around the camera, or none with the reason in f.off.
void placeGiCascades(const FrameView& in, GiContext& gi, const ShadowContext& shadows, int sun) {
    GiFrame& f = gi.frame;
    const RenderSettings& s = in.settings;
    const GpuScene& scene = in.scene;
    if (s.giEnabled && gi.diffuseVersion != scene.materialsVersion) {
        gi.diffuse = anyDiffuseSurface(scene);
        gi.diffuseVersion = scene.materialsVersion;
    }
    const bool diffuse = s.giEnabled && scene.giPrograms && sun >= 0 && gi.diffuse;
    f.off = !s.giEnabled          ? "gi.enabled is false"
            : !scene.giPrograms   ? "the container's lighting has no GI (convert with pnb-convert --gi)"
            : sun < 0             ? "the scene has no directional light"
            : !gi.diffuse         ? "no opaque surface reflects diffuse light (all metal or black)"
                                  : nullptr;
    if (s.giEnabled && !diffuse && !gi.warned) {
        gi.warned = true;
        std::fprintf(stderr, "pnb-play: gi.enabled, but %s: no indirect light\n", f.off);
    }
    if (!diffuse) return;
    const ViewMatrices& view = in.view;
    glm::dvec3 forward = view.forward();
    // The camera the following cascades centre on. An orthographic view shows everything on
    // its axis at one size, wherever the camera stands on it (often far back): they centre on
    // the axis point nearest the scene's centre (within the near and far planes) instead.
    glm::dvec3 anchor = view.position;
    if (view.orthographic) {
        const glm::dvec3 centre = 0.5 * (shadows.sceneMin + shadows.sceneMax);
        const double along = std::clamp(glm::dot(centre - anchor, forward), double(view.znear),
                                        double(std::max(view.zfar, view.znear)));
        anchor += forward * along;
    }
    // Probes: one grid (the outer cascade's box, or following the camera with gi.cell_size).
    const bool probes = s.giTechnique == GiTechnique::Probes;
    double cellSize = s.giCellSize;
    if (probes && cellSize == 0)
        cellSize = probeCellSize(s.giProbeCells, s.giProbeMaxSpacing, shadows.sceneMin, shadows.sceneMax);
    f.following = cellSize > 0;
    f.cascades = placeCascades(probes ? 1u : std::min(s.giCascades, kMaxGiCascades),
                               probes ? s.giProbeCells : s.giCells, cellSize, shadows.sceneMin,
                               shadows.sceneMax, anchor, forward);
}

// The RSM: a square in light space over the outer cascade's part of the scene, and the items it
// draws.
void fitGiRsm(const FrameView& in, GiFrame& f, const ShadowContext& shadows) {
    const RenderSettings& s = in.settings;
    const glm::dvec3 cam = in.view.position;
    // The RSM covers the outer cascade's part of the scene, as a square in light space whose
    // centre is snapped to whole texels in absolute light space (it does not swim while the
    // cascade stays put); toward the light it reaches the scene's top (occluders above).
    const LpvCascade& outer = f.cascades.back();
    glm::dvec3 lo = glm::max(outer.origin, shadows.sceneMin), hi = glm::min(outer.max(), shadows.sceneMax);
    lo = glm::min(lo, hi);
    glm::dmat3 rotation = lightRotation(-f.toward);
    auto [llo, lhi] = lightBounds(rotation, lo, hi, cam);
    const uint32_t res = s.giRsmResolution;
    double side = std::max(lhi.x - llo.x, lhi.y - llo.y);
    side = std::max(side, 1e-9 * outer.cellSize * outer.cells);
    double texel = side / double(res);
    side = texel * double(res + 2); // a texel of margin each side for the snap
    glm::dvec2 camLight = glm::dvec2(rotation * cam);
    glm::dvec2 centre = 0.5 * glm::dvec2(llo + lhi);
    // The LPV injects texel by texel and its cascades follow the camera: snapped, sub-cell camera
    // motion leaves the map's texels where they were. The probes' grid does not follow the camera
    // (or moves by whole cells), and they cluster texels in blocks: a snap that jumps by a texel
    // as the sun turns changes every block's texels at once (a pop of 3-4x a frame's usual
    // change, measured), so their map slides with the sun instead.
    if (s.giTechnique == GiTechnique::Lpv) centre = glm::floor((centre + camLight) / texel + 0.5) * texel - camLight;
    FitBox sceneBox{shadows.sceneMin - cam, shadows.sceneMax - cam};
    f.rsm = fitLightRectangle(rotation, centre - 0.5 * side, centre + 0.5 * side, llo.z, sceneBox, res);
    f.rsmTexelArea = (side / res) * (side / res);

    // What the RSM draws: opaque and masked items whose bounds reach its rectangle, then the
    // translucent casters there (multiplying the flux behind them).
    const GpuScene& scene = in.scene;
    for (uint32_t i = 0; i < scene.items.size(); ++i) {
        const DrawItem& item = scene.items[i];
        const GpuMaterial& material = scene.materials[item.material];
        const bool glass = scene.giPrograms && translucentCaster(material);
        if (material.rsmProgram == kNone && !glass) continue;
        f.sceneGlass |= glass;
        auto [ilo, ihi] = lightBounds(rotation, item.boundsMin, item.boundsMax, cam);
        glm::dvec2 rlo = centre - 0.5 * side, rhi = centre + 0.5 * side;
        if (!in.warmUp && (ihi.x < rlo.x || ilo.x > rhi.x || ihi.y < rlo.y || ilo.y > rhi.y)) continue;
        (glass ? f.rsmGlassItems : f.rsmItems).push_back(i);
    }
}

// Probes: what the gather depends on. Not the camera: the volume holds world directions and the
// grid's place is in the list.
void listProbeInputs(const FrameView& in, GiFrame& f) {
    const RenderSettings& s = in.settings;
    f.probeInputs.clear();
    if (s.giTechnique != GiTechnique::Probes) return;
    const LpvCascade& outer = f.cascades.back();
    auto put = [&](double v) { f.probeInputs.push_back(std::bit_cast<uint64_t>(v)); };
    for (int k = 0; k < 3; ++k) put(f.toward[k]), put(outer.origin[k]);
    put(outer.cellSize);
    const glm::dvec3 gridMax = outer.origin + glm::dvec3(outer.cellSize * double(outer.cells));
    if (movedWithin(in.scene.animation.get(), outer.origin, gridMax)) f.poseInGrid = in.scene.animation->poseVersion;
    f.geometryVersion = in.scene.materialsVersion + f.poseInGrid;
    f.probeInputs.insert(f.probeInputs.end(), {outer.cells, s.giRsmResolution, s.giVpls, s.giVoxels,
                                               uint64_t(s.giProbeVisibility), s.giBounces,
                                               f.geometryVersion,
                                               in.scene.texelsVersion});
    for (uint32_t i : f.rsmItems) f.probeInputs.push_back(drawLevel(in.scene, in.lod, i));
    for (uint32_t i : f.rsmGlassItems) f.probeInputs.push_back(drawLevel(in.scene, in.lod, i));
}

} // namespace

void planGi(const FrameView& in, GiContext& gi, const ShadowContext& shadows, GiBlock& block) {
    GiFrame& f = gi.frame;
    const RenderSettings& s = in.settings;
    const GpuScene& scene = in.scene;
    f.active = f.following = false;
    f.cascades.clear();
    f.rsmItems.clear();
    f.rsmObjectOffsets.clear();
    f.rsmGlassItems.clear();
    f.rsmGlassOffsets.clear();
    f.sceneGlass = false;
    f.probeInputs.clear();
    block = GiBlock{};
    const int sun = giLight(scene);
    placeGiCascades(in, gi, shadows, sun);
    if (f.cascades.empty()) return;
    const SceneLight& light = scene.lights[size_t(sun)];
    f.toward = -glm::normalize(glm::dvec3(lightDirection(light, s)));
    fitGiRsm(in, f, shadows);
    listProbeInputs(in, f);
    // Fixed point: the largest value one texel adds is its area over the finest cell's face
    // (times the lobe's 1/pi * c0 < 1), a cell sums a few of them.
    double finest = f.cascades.front().cellSize;
    f.lightScale = fixedScale(4.0 * std::max(1.0, f.rsmTexelArea / (finest * finest)));
    f.geometryScale = float(1 << 20); // a blocking surfel adds at most 4/3 x the lobe

    const glm::dvec3 cam = in.view.position;
    for (size_t c = 0; c < f.cascades.size(); ++c)
        block.cascade[c] = glm::vec4(glm::vec3(f.cascades[c].origin - cam), float(f.cascades[c].cellSize));
    block.grid = {float(f.cascades.back().cells), float(f.cascades.size()), f.following ? 1.0f : 0.0f,
                  gi.capture || s.debugView == DebugView::GiIndirect ? 1.0f : 0.0f};
    glm::vec3 irradiance = glm::vec3(light.desc.color.x, light.desc.color.y, light.desc.color.z) *
                           (light.desc.intensity * s.giIntensity);
    block.irradiance = glm::vec4(irradiance, 0);
}

void prepareGi(FrameContext& ctx, GiContext& gi, const ShadowContext& shadows) {
    GiBlock block;
    planGi(frameView(ctx), gi, shadows, block);
    GiFrame& f = gi.frame;
    if (f.cascades.empty()) {
        gi.resources = GiResources{}; // GI off: nothing allocated, nothing compiled
        return;
    }
    const RenderSettings& s = ctx.settings;
    const uint64_t giBytes = gi.resources.bytes; // checked only when storage was made
    auto ok = gi.resources.ensure(s, uint32_t(f.cascades.size()), f.sceneGlass);
    if (ok && gi.resources.bytes != giBytes) ok = checkGlAllocation("GI's volumes", gi.resources.bytes);
    if (!ok) {
        std::fprintf(stderr, "pnb-play: GI off: %s\n", ok.error().message.c_str());
        gi.resources = GiResources{};
        f.cascades.clear();
        f.off = "its volumes could not be allocated (see the message above)";
        return;
    }
    f.active = true;
    const GpuScene& scene = ctx.scene;
    const glm::dvec3 cam = ctx.view.position;
    const glm::dmat4 toCamera = glm::translate(glm::dmat4(1.0), -cam);
    for (uint32_t i : f.rsmItems) f.rsmObjectOffsets.push_back(pushObjectBlock(scene, scene.items[i], toCamera, ctx.ring, 0.0f));
    for (uint32_t i : f.rsmGlassItems)
        f.rsmGlassOffsets.push_back(pushObjectBlock(scene, scene.items[i], toCamera, ctx.ring, 0.0f));
    f.probesCurrent = s.giTechnique == GiTechnique::Probes && s.giProbeCache && !ctx.warmUp &&
                      f.probeInputs == gi.resources.probeInputs;
    const uint32_t res = s.giRsmResolution;
    FrameBlock rsmFrame{};
    rsmFrame.viewProjection = glm::mat4(f.rsm.matrix);
    rsmFrame.view = glm::mat4(1.0f);
    rsmFrame.cameraPosition = glm::vec4(glm::vec3(cam), 1);
    rsmFrame.viewport = {float(res), float(res), 1.0f / float(res), 1.0f / float(res)};
    f.rsmFrameOffset = ctx.ring.push(&rsmFrame, sizeof rsmFrame);
    f.blockOffset = ctx.ring.push(&block, sizeof block);
}

void bindGiForLighting(FrameContext& ctx, const GiContext& gi) {
    const GiFrame& f = gi.frame;
    if (!f.active) return;
    glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_GI_BLOCK, ctx.ring.buffer(), GLintptr(f.blockOffset),
                      sizeof(GiBlock));
    for (GLuint ch = 0; ch < 3; ++ch) glBindTextureUnit(10 + ch, gi.resources.sum[ch].id());
}

} // namespace pnb::player
