// The per-frame shadow fit on the CPU (single, LiSPSM, PSSM) and the per-cascade caster culling,
// or, for SDSM, the parameters and caster data the GPU fit reads: planned without GL
// (planShadows), then written into the ring (prepareShadows).
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "cascade_splits.h"
#include "frame/frame_context.h"
#include "shadows/shadow_maps.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)

namespace pnb::player {

namespace {

// Does the camera-relative box touch the map of `fit`? Conservative: a box reaching behind a
// perspective map's projection centre counts as touching.
bool boxTouchesMap(const ShadowFit& fit, const glm::dvec3& lo, const glm::dvec3& hi) {
    glm::dvec3 nlo(std::numeric_limits<double>::infinity()), nhi(-std::numeric_limits<double>::infinity());
    for (int c = 0; c < 8; ++c) {
        glm::dvec3 p{(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z};
        glm::dvec4 clip = fit.matrix * glm::dvec4(p, 1.0);
        if (clip.w <= 0) return true;
        glm::dvec3 ndc = glm::dvec3(clip) / clip.w;
        nlo = glm::min(nlo, ndc);
        nhi = glm::max(nhi, ndc);
    }
    // Nearer the light than z = 0 is kept: depth clamp flattens such casters onto the map.
    return nhi.x >= -1 && nlo.x <= 1 && nhi.y >= -1 && nlo.y <= 1 && nlo.z <= 1;
}

FitCamera fitCamera(const ViewMatrices& view) {
    FitCamera c;
    glm::dmat4 v(view.view);
    c.right = glm::dvec3(v[0][0], v[1][0], v[2][0]);
    c.up = glm::dvec3(v[0][1], v[1][1], v[2][1]);
    c.forward = -glm::dvec3(v[0][2], v[1][2], v[2][2]);
    c.tanHalfFovY = view.orthographic ? 0.0 : std::tan(0.5 * double(view.yfov));
    c.halfHeight = view.orthographic ? double(view.ymag) : 0.0;
    c.aspect = double(view.aspect);
    c.position = view.position;
    return c;
}

} // namespace

void initShadowContext(const GpuScene& scene, ShadowContext& shadows) {
    shadows.casters.clear();
    shadows.light = shadowingSun(scene);
    shadows.sceneMin = glm::dvec3(std::numeric_limits<double>::infinity());
    shadows.sceneMax = -shadows.sceneMin;
    for (const DrawItem& item : scene.items) {
        shadows.sceneMin = glm::min(shadows.sceneMin, item.boundsMin);
        shadows.sceneMax = glm::max(shadows.sceneMax, item.boundsMax);
    }
    if (scene.items.empty()) shadows.sceneMin = shadows.sceneMax = glm::dvec3(0.0);
    shadows.translucentCasters = false;
    if (!scene.shadowProgram) return;
    for (uint32_t i = 0; i < scene.items.size(); ++i) {
        const DrawItem& item = scene.items[i];
        const Material& m = scene.materials[item.material].desc;
        if (!m.castsShadows) continue;
        // Blended casters let light through, tinted (issue 43): with a container that has the
        // shadow[TRANSLUCENT] program (older ones: they cast nothing, as before).
        std::optional<uint32_t> program = m.alphaMode == AlphaMode::Blend  ? scene.shadowTranslucentProgram
                                          : m.alphaMode == AlphaMode::Mask ? scene.shadowMaskProgram
                                                                           : scene.shadowProgram;
        if (!program || !scene.programs[*program]) continue;
        ShadowCaster c;
        c.item = i;
        c.program = *program;
        c.translucent = m.alphaMode == AlphaMode::Blend;
        shadows.translucentCasters |= c.translucent;
        shadows.casters.push_back(c);
    }
}

namespace {

const char* whyShadowsAreOff(const FrameView& in, const ShadowContext& sc) {
    return !in.scene.shadowProgram.has_value()                   ? "the container has no shadow programs (no material casts shadows)"
           : in.settings.shadowTechnique == ShadowTechnique::Off ? "shadows.technique is off"
           : sc.light < 0                                        ? "the scene has no shadow-casting directional light"
           : sc.casters.empty()                                  ? "nothing in the scene casts a shadow"
                                                                 : nullptr;
}

glm::dvec3 boxCorner(const FitBox& box, int c) {
    return {(c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y, (c & 4) ? box.max.z : box.min.z};
}

// The view depths the maps cover: the camera's near plane to the far side of the scene (or
// shadows.distance), clipped to the camera's far plane.
glm::dvec2 shadowedDepths(const FrameView& in, const ShadowContext& sc, const FitCamera& cam, const FitBox& box) {
    const ViewMatrices& view = in.view;
    // The camera's own near plane (validated > 0), never an absolute floor: at 10^-6 scale a
    // floor in scene units would move every split.
    double nearDepth = view.znear > 0 ? double(view.znear) : 1e-6 * glm::length(sc.sceneMax - sc.sceneMin);
    double farDepth = in.settings.shadowDistance;
    if (farDepth <= 0) {
        farDepth = 0;
        for (int c = 0; c < 8; ++c) farDepth = std::max(farDepth, glm::dot(boxCorner(box, c), cam.forward));
    }
    if (view.zfar > 0) farDepth = std::min(farDepth, double(view.zfar));
    if (view.orthographic) {
        // An orthographic camera often stands far back from what it shows (its rays are
        // parallel: where it stands changes nothing on screen). The cascades span the depths
        // where its view box meets the scene, so none is spent on the empty stretch before it.
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (const glm::dvec3& v : clipSliceToBox(cam, nearDepth, farDepth, box)) {
            lo = std::min(lo, glm::dot(v, cam.forward));
            hi = std::max(hi, glm::dot(v, cam.forward));
        }
        if (lo <= hi) {
            nearDepth = std::max(nearDepth, lo);
            farDepth = std::min(farDepth, hi);
        }
    }
    return {nearDepth, std::max(farDepth, nearDepth * 1.001)};
}

// Each cascade's fit and its view-depth slice (f.fits, f.splits) for the CPU techniques; SDSM
// keeps only the range its GPU fit reduces.
void fitCascades(const FrameView& in, ShadowFrame& f, const FitCamera& cam, const FitBox& box,
                 const glm::dvec3& toward, glm::dvec2 depths) {
    const RenderSettings& s = in.settings;
    const uint32_t resolution = s.shadowResolution;
    f.splits[0] = float(depths.x);
    switch (s.shadowTechnique) {
    case ShadowTechnique::Single:
        f.fits[0] = fitScene(f.lightRotation, box, resolution);
        f.splits[1] = float(depths.y);
        break;
    case ShadowTechnique::Lispsm:
        f.fits[0] = fitLispsm(cam, depths.x, depths.y, -toward, box, resolution);
        f.splits[1] = float(depths.y);
        break;
    case ShadowTechnique::Pssm: {
        // An orthographic view's pixels have one size at every depth: no perspective aliasing
        // for logarithmic splits to even out, so the splits are uniform (lambda 0).
        std::vector<float> ends = practicalSplitDistances(float(depths.x), float(depths.y), f.cascades,
                                                          in.view.orthographic ? 0.0f : s.shadowLambda);
        FitMode mode = s.shadowFit == CascadeFit::Sphere ? FitMode::Sphere : FitMode::Tight;
        for (uint32_t i = 0; i < f.cascades; ++i) {
            f.splits[i + 1] = ends[i];
            // The blend band at the end of cascade i - 1 also reads cascade i: fit i from there.
            double start = f.splits[i];
            if (i > 0) start -= double(s.shadowBlend) * (f.splits[i] - f.splits[i - 1]);
            f.fits[i] = fitCascade(cam, std::max(start, depths.x), f.splits[i + 1], f.lightRotation, box,
                                   resolution, mode);
        }
        break;
    }
    default: f.splits[1] = float(depths.y); break; // SDSM: the GPU fits within this range
    }
}

// The casters to draw: CPU fits list those touching some cascade, with their cascade masks; SDSM
// lists every caster with its camera-relative bounds for the GPU cull.
void listCasters(const FrameView& in, const ShadowContext& sc, ShadowFrame& f) {
    const GpuScene& scene = in.scene;
    for (uint32_t ci = 0; ci < sc.casters.size(); ++ci) {
        const uint32_t itemIndex = sc.casters[ci].item;
        const DrawItem& item = scene.items[itemIndex];
        const uint32_t level = drawLevel(scene, in.lod, itemIndex);
        glm::dvec3 lo = item.boundsMin - in.view.position, hi = item.boundsMax - in.view.position;
        if (f.gpuFit) {
            const GpuMesh& mesh = scene.meshes[item.mesh];
            SdsmCasterData d;
            d.lo = glm::vec3(lo);
            d.hi = glm::vec3(hi);
            d.indexCount = scene.levels[level].indexCount;
            d.firstIndex = uint32_t(mesh.indexOffset / mesh.indexSize) + scene.levels[level].firstIndex;
            f.casterBounds.push_back(d);
        } else {
            uint32_t mask = 0;
            for (uint32_t c = 0; c < f.cascades; ++c)
                if (in.warmUp || boxTouchesMap(f.fits[c], lo, hi)) mask |= 1u << c;
            if (!mask) continue;
            f.masks.push_back(mask);
        }
        f.casters.push_back(ci);
        f.levels.push_back(level);
    }
}

} // namespace

void planShadows(const FrameView& in, ShadowContext& sc, ShadowBlock& b) {
    ShadowFrame& f = sc.frame;
    const RenderSettings& s = in.settings;
    const GpuScene& scene = in.scene;
    f.sceneHasShadows = scene.shadowProgram.has_value();
    f.active = f.gpuFit = f.translucent = false;
    f.off = whyShadowsAreOff(in, sc);
    f.cascades = 0;
    f.casters.clear();
    f.objectOffsets.clear();
    f.levels.clear();
    f.masks.clear();
    f.casterBounds.clear();
    b = ShadowBlock{};
    if (!f.sceneHasShadows) return;

    glm::dvec3 toward = -glm::dvec3(sc.light >= 0 ? lightDirection(scene.lights[size_t(sc.light)], s)
                                                  : glm::vec3(0, -1, 0));
    toward = glm::normalize(toward);
    const uint32_t resolution = s.shadowResolution;
    b.light = glm::vec4(glm::vec3(toward), float(sc.light));
    b.bias = {s.shadowNormalOffset, s.shadowSlopeBias, s.shadowBlend,
              s.shadowSelect == CascadeSelect::Bounds ? 1.0f : 0.0f};
    float tanLight = std::tan(0.5f * glm::radians(s.shadowLightSize));
    int output = sc.captureColor ? 3 : sc.capture ? 2 : (s.debugView == DebugView::Cascades ? 1 : 0);
    b.mapInfo = {float(resolution), 1.0f / float(resolution), tanLight, float(output)};
    // A pixel's world size at view depth d is 2 (d x + w) / y (shadow_sampling.glsl).
    const bool ortho = in.view.orthographic;
    b.view = {ortho ? 0.0f : std::tan(0.5f * in.view.yfov), float(in.height), float(s.shadowJudgedLight),
              ortho ? in.view.ymag : 0.0f};

    if (!f.off) {
        switch (s.shadowTechnique) {
        case ShadowTechnique::Single:
        case ShadowTechnique::Lispsm: f.cascades = 1; break;
        default: f.cascades = std::clamp(s.shadowCascades, 1u, kMaxCascades);
        }
    }
    b.params = {float(f.cascades), float(int(s.shadowFilter)), float(s.shadowTaps), s.shadowRadius};
    if (f.cascades == 0) return;

    f.active = true;
    f.gpuFit = s.shadowTechnique == ShadowTechnique::Sdsm;
    f.translucent = sc.translucentCasters && s.shadowTranslucent;
    f.lightRotation = lightRotation(-toward);
    const FitBox box{sc.sceneMin - in.view.position, sc.sceneMax - in.view.position};
    const FitCamera cam = fitCamera(in.view);
    const glm::dvec2 depths = shadowedDepths(in, sc, cam, box);
    glm::dvec2 z{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (int c = 0; c < 8; ++c) {
        double d = (f.lightRotation * boxCorner(box, c)).z;
        z = {std::min(z.x, d), std::max(z.y, d)};
    }
    f.sceneLightDepth = z;
    fitCascades(in, f, cam, box, toward, depths);
    if (!f.gpuFit) {
        // The single map covers every depth; a cascade covers its slice.
        bool whole = s.shadowTechnique == ShadowTechnique::Single;
        for (uint32_t i = 0; i < f.cascades; ++i) {
            b.matrix[i] = glm::mat4(f.fits[i].matrix);
            b.cascade[i] = {whole ? 0.0f : f.splits[i], whole ? 3.0e38f : f.splits[i + 1],
                            float(f.fits[i].texelWorld), f.fits[i].warped ? 1.0f : 0.0f};
        }
    } else {
        b.cascade[0] = {float(depths.x), float(depths.y), 0, 0}; // the range SDSM reduces
    }
    listCasters(in, sc, f);
}

void prepareShadows(FrameContext& ctx, ShadowContext& sc) {
    ShadowBlock b;
    planShadows(frameView(ctx), sc, b);
    ShadowFrame& f = sc.frame;
    if (!f.sceneHasShadows) return;
    f.blockOffset = ctx.ring.push(&b, sizeof b);
    if (!f.active) return;
    const GpuScene& scene = ctx.scene;
    const glm::dmat4 toCamera = glm::translate(glm::dmat4(1.0), -ctx.view.position);
    for (size_t i = 0; i < f.casters.size(); ++i)
        f.objectOffsets.push_back(
            pushObjectBlock(scene, scene.items[sc.casters[f.casters[i]].item], toCamera, ctx.ring, float(i)));
    if (f.gpuFit) {
        f.boundsOffset = ctx.ring.push(f.casterBounds.data(), f.casterBounds.size() * sizeof(SdsmCasterData));
    } else if (!f.masks.empty()) {
        f.maskBytes = f.masks.size() * sizeof(uint32_t);
        f.maskOffset = ctx.ring.push(f.masks.data(), f.maskBytes);
    }
}

void bindShadowsForLighting(FrameContext& ctx, const ShadowContext& shadows) {
    const ShadowFrame& f = shadows.frame;
    if (!f.sceneHasShadows) return;
    const ShadowResources& r = shadows.resources;
    if (f.gpuFit)
        glBindBufferBase(GL_UNIFORM_BUFFER, PNB_BINDING_SHADOW_BLOCK, r.sdsmBlock.id());
    else
        glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_SHADOW_BLOCK, ctx.ring.buffer(),
                          GLintptr(f.blockOffset), sizeof(ShadowBlock));
    if (f.active) {
        glBindTextureUnit(8, r.depthArray.id());
        glBindTextureUnit(9, r.depthView.id());
    }
    // Lighting built with TRANSLUCENT_SHADOWS reads units 20 and 21 whenever it reads the maps.
    if (ctx.scene.translucentLighting) bindTranslucentMaps(r.translucent, shadows.neutralTranslucent, 20);
}

} // namespace pnb::player
