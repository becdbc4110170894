// The frame's light list and light clusters (light_clusters.h): planned without GL (planLights),
// the lights go into the stream ring camera-relative; where the frame clusters, their view-space
// bounding spheres follow, and light_clusters.comp (the lights.clusters pass) turns them into one
// mask per screen tile and one per depth slice.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <limits>

#include <glm/gtc/type_ptr.hpp>

#include "pnb/light_range.h"
#include "frame/frame_context.h"
#include "lights/light_clusters.h"
#include "gl/program_compile.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)

namespace pnb::player {

void planLights(const FrameView& in, LightContext& lc) {
    const GpuScene& scene = in.scene;
    const ViewMatrices& view = in.view;
    const uint32_t count = uint32_t(scene.lights.size());
    lc.localLights = uint32_t(std::count_if(scene.lights.begin(), scene.lights.end(), [](const SceneLight& l) {
        return l.desc.type != LightType::Directional;
    }));
    lc.clustered = clustersWanted(in.settings, lc.localLights) && view.znear > 0.0f;
    lc.list.resize(count);
    lc.spheres.resize(lc.clustered ? count : 0);
    // View depths local lights reach: the slices span them and no more.
    float nearest = std::numeric_limits<float>::max(), farthest = 0.0f;
    for (uint32_t i = 0; i < count; ++i) {
        const SceneLight& l = scene.lights[i];
        GpuLight& g = lc.list[i];
        // The range lighting uses, windowed to zero at its end: the light's own, or where its
        // illuminance falls to the cut-off (pnb/light_range.h). The same with and without
        // clusters, so culling by it changes no pixel.
        g.positionRange = glm::vec4(glm::vec3(l.position - view.position), pnb::effectiveLightRange(l.desc));
        g.directionType = glm::vec4(lightDirection(l, in.settings), float(int(l.desc.type)));
        g.colorIntensity = glm::vec4(l.desc.color.x, l.desc.color.y, l.desc.color.z, l.desc.intensity);
        const float cosOuter = std::cos(l.desc.outerConeRadians), cosInner = std::cos(l.desc.innerConeRadians);
        g.cone = {cosOuter, 1.0f / std::max(cosInner - cosOuter, 1e-4f), -1, 0}; // z: no shadow tile yet
        if (lc.clustered) {
            const glm::vec4 sphere = lightBoundingSphere(g, view.view);
            lc.spheres[i] = sphere;
            if (sphere.w >= 0.0f) {
                nearest = std::min(nearest, -sphere.z - sphere.w);
                farthest = std::max(farthest, -sphere.z + sphere.w);
            }
        }
    }
    if (!lc.clustered) return;
    // Slices span the view depths lights reach, from the near plane at the nearest: none is
    // spent before the nearest light or beyond the farthest (the first and last slices stay
    // open-ended in light_clusters.comp, so nothing is lost at either end).
    float zNear = std::max(nearest, view.znear);
    float zFar = farthest;
    if (view.zfar > 0.0f) zFar = std::min(zFar, view.zfar);
    // An orthographic near plane may be 0 (glTF allows it): the log slicing needs a start > 0.
    if (!(zNear > 0.0f)) zNear = zFar > 0.0f ? 1e-6f * zFar : 1e-6f;
    lc.grid = lightClusterGrid(in.width, in.height, in.settings.lightTilePx, in.settings.lightSlices, count,
                               zNear, zFar);
}

void prepareLights(FrameContext& ctx, LightContext& lc) {
    planLights(frameView(ctx), lc);
    if (lc.clustered && !lc.clusterProgram) {
        auto p = compileEmbeddedCompute("light_clusters.comp", {});
        if (p) lc.clusterProgram = std::move(*p);
        else std::fprintf(stderr, "pnb-play: %s\n", p.error().message.c_str());
        lc.clustered = bool(lc.clusterProgram); // else every light everywhere: slower, the same image
    }
    if (!lc.clustered) {
        lc.clusterProgram = {};
        lc.masks = {};
        lc.maskCapacity = 0;
    }
    // The light list, written straight into the mapped ring, and the spheres beside it.
    const uint32_t count = uint32_t(lc.list.size());
    lc.listBytes = sizeof(LightListHeader) + sizeof(GpuLight) * count;
    lc.listOffset = ctx.ring.allocate(lc.listBytes, lc.listData);
    LightListHeader header;
    header.count = count;
    header.clustered = lc.clustered ? 1u : 0u;
    std::memcpy(lc.listData, &header, sizeof header);
    if (count) std::memcpy(lc.listData + sizeof header, lc.list.data(), sizeof(GpuLight) * count);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_LIGHT_LIST, ctx.ring.buffer(),
                      GLintptr(lc.listOffset), GLsizeiptr(lc.listBytes));
    if (!lc.clustered) {
        // lights.glsl declares the clusters' block; it is not read while uLightsClustered is 0,
        // but a declared block wants a buffer: the light list stands in (no buffer of its own).
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_LIGHT_CLUSTERS, ctx.ring.buffer(),
                          GLintptr(lc.listOffset), GLsizeiptr(lc.listBytes));
        return;
    }
    std::byte* sphereData = nullptr;
    lc.sphereOffset = ctx.ring.allocate(sizeof(glm::vec4) * count, sphereData);
    std::memcpy(sphereData, lc.spheres.data(), sizeof(glm::vec4) * count);
    ctx.stats.lightClusters = lc.grid.tilesX * lc.grid.tilesY * lc.grid.slices;
    const uint64_t bytes = lc.grid.maskBytes();
    if (bytes > lc.maskCapacity) {
        lc.masks = createBuffer();
        glNamedBufferStorage(lc.masks.id(), GLsizeiptr(bytes), nullptr, 0);
        glObjectLabel(GL_BUFFER, lc.masks.id(), -1, "light cluster masks");
        lc.maskCapacity = bytes;
    }
}

void runLightClusters(FrameContext& ctx, const LightContext& lc) {
    if (!lc.clustered) return;
    ctx.timer.mark("light_clusters");
    const uint32_t count = uint32_t(lc.list.size());
    const GLuint program = lc.clusterProgram.id();
    const LightClusterGrid& g = lc.grid;
    glProgramUniform4ui(program, 0, g.tilesX, g.tilesY, g.slices, g.words);
    glProgramUniform4f(program, 1, g.invTilePx, g.sliceScale, g.sliceBias, 0.0f);
    glProgramUniform1ui(program, 2, count);
    glProgramUniformMatrix4fv(program, 3, 1, GL_FALSE, glm::value_ptr(ctx.view.projection));
    glProgramUniform2f(program, 4, float(ctx.targets.width), float(ctx.targets.height));
    glUseProgram(program);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_CLUSTER_SPHERES, ctx.ring.buffer(),
                      GLintptr(lc.sphereOffset), GLsizeiptr(sizeof(glm::vec4) * count));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_CLUSTER_MASKS_OUT, lc.masks.id());
    const uint64_t invocations = uint64_t(g.tilesX * g.tilesY + g.slices) * g.words;
    glDispatchCompute(GLuint((invocations + 63) / 64), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_LIGHT_CLUSTERS, lc.masks.id(), 0,
                      GLsizeiptr(g.maskBytes()));
}

} // namespace pnb::player
