// Culling, per-draw uniform data and the sort orders of seed 003 (opaque front-to-back for early
// depth rejection; translucent back-to-front so blending composes in order).
#include <algorithm>
#include <cstring>
#include <unordered_map>

#include <glm/gtc/matrix_transform.hpp>

#include "frame/frame_context.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)
#include "shared/instance_data.h" // InstanceData (GLSL and C++)
#include "shared/material_block.h" // MaterialBlock (GLSL and C++)
#include "shared/object_block.h" // ObjectBlock (GLSL and C++)

namespace pnb::player {

namespace {

constexpr uint32_t kNoGroup = 0xFFFFFFFFu;

ObjectBlock objectBlock(const GpuScene& scene, const DrawItem& item, const glm::dmat4& toCamera,
                        float casterIndex) {
    const GpuMesh& mesh = scene.meshes[item.mesh];
    ObjectBlock block;
    block.model = glm::mat4(toCamera * item.world); // relative in double, then float
    block.normalMatrix = glm::mat4(item.normalMatrix);
    block.dequantScale = glm::vec4(mesh.dequantScale, 0);
    block.dequantOffset = glm::vec4(mesh.dequantOffset, 0);
    block.params = {mesh.octahedralNormals ? 1.0f : 0.0f, casterIndex, item.mirrored ? -1.0f : 1.0f, 0};
    return block;
}

bool layerHasTranslucency(const GpuScene& scene, std::span<const DrawRef> refs) {
    return std::any_of(refs.begin(), refs.end(), [&](const DrawRef& r) {
        return scene.materials[scene.items[r.item].material].translucent();
    });
}

} // namespace

size_t pushObjectBlock(const GpuScene& scene, const DrawItem& item, const glm::dmat4& toCamera,
                       StreamRing& ring, float casterIndex) {
    const ObjectBlock block = objectBlock(scene, item, toCamera, casterIndex);
    return ring.push(&block, sizeof block);
}

void buildDrawLists(const GpuScene& scene, const ViewMatrices& view, const LodState& lod, bool cull,
                    StreamRing& ring, DrawLists& lists) {
    lists.layers.resize(scene.deferredLayers.size());
    for (auto& layer : lists.layers) layer.clear();
    lists.forwardOpaque.clear();
    lists.forwardBlended.clear();
    lists.visible = lists.culled = 0;
    glm::dvec3 forward = glm::dvec3(glm::transpose(glm::dmat3(view.view)) * glm::dvec3(0, 0, -1));
    glm::dmat4 toCamera = glm::translate(glm::dmat4(1.0), -view.position);
    for (uint32_t i = 0; i < scene.items.size(); ++i) {
        const DrawItem& item = scene.items[i];
        if (cull && !intersectsFrustum(view, item.boundsMin, item.boundsMax)) {
            ++lists.culled;
            continue;
        }
        ++lists.visible;
        DrawRef ref;
        ref.item = i;
        ref.viewDepth = float(glm::dot((item.boundsMin + item.boundsMax) * 0.5 - view.position, forward));
        ref.objectOffset = pushObjectBlock(scene, item, toCamera, ring, 0.0f);
        ref.level = drawLevel(scene, lod, i);
        const Material& m = scene.materials[item.material].desc;
        if (m.shadingPath == ShadingPath::Deferred) {
            auto layer = std::lower_bound(scene.deferredLayers.begin(), scene.deferredLayers.end(),
                                          m.layerPriority);
            lists.layers[size_t(layer - scene.deferredLayers.begin())].push_back(ref);
        } else if (m.alphaMode == AlphaMode::Blend) {
            lists.forwardBlended.push_back(ref);
        } else {
            lists.forwardOpaque.push_back(ref);
        }
    }
    // Opaque lists go front to back by instance group: the visible copies of one instanced
    // submesh sit together at their nearest copy's depth, so the main view draws them as one
    // instanced draw (drawItems); any other item is a group of its own.
    std::unordered_map<uint32_t, float> groupDepth;
    auto frontToBack = [&](const DrawRef& a, const DrawRef& b) {
        const uint32_t ga = scene.items[a.item].instanceGroup, gb = scene.items[b.item].instanceGroup;
        const float da = ga == kNoGroup ? a.viewDepth : groupDepth[ga];
        const float db = gb == kNoGroup ? b.viewDepth : groupDepth[gb];
        if (da != db) return da < db;
        if (ga != gb) return ga < gb;
        return a.viewDepth != b.viewDepth ? a.viewDepth < b.viewDepth : a.item < b.item;
    };
    auto nearestOfGroups = [&](const std::vector<DrawRef>& list) {
        for (const DrawRef& r : list)
            if (const uint32_t g = scene.items[r.item].instanceGroup; g != kNoGroup) {
                auto [it, added] = groupDepth.emplace(g, r.viewDepth);
                if (!added) it->second = std::min(it->second, r.viewDepth);
            }
    };
    auto backToFront = [](const DrawRef& a, const DrawRef& b) {
        return a.viewDepth != b.viewDepth ? a.viewDepth > b.viewDepth : a.item < b.item;
    };
    for (auto& layer : lists.layers) {
        if (layerHasTranslucency(scene, layer)) {
            std::sort(layer.begin(), layer.end(), backToFront);
        } else {
            nearestOfGroups(layer);
            std::sort(layer.begin(), layer.end(), frontToBack);
        }
    }
    nearestOfGroups(lists.forwardOpaque);
    std::sort(lists.forwardOpaque.begin(), lists.forwardOpaque.end(), frontToBack);
    std::sort(lists.forwardBlended.begin(), lists.forwardBlended.end(), backToFront);
}

void drawItems(FrameContext& ctx, std::span<const DrawRef> refs, GLuint program,
               uint32_t GpuMaterial::*materialProgram, bool twoSided) {
    const GpuScene& scene = ctx.scene;
    GLuint boundProgram = ~0u, boundVao = ~0u;
    uint32_t boundMaterial = kNone;
    int cullState = -1;
    bool clockwise = false; // glFrontFace: a mirrored item's triangles wind the other way
    // Consecutive copies of one instanced submesh at one level draw as one instanced draw, in
    // the passes whose programs are the materials' own (surface.vert reads the copies): those
    // draw the main view's lists, whose object blocks are relative to ctx.view's position.
    const bool batching = program == 0 && materialProgram == &GpuMaterial::program;
    const glm::dmat4 toCamera = glm::translate(glm::dmat4(1.0), -ctx.view.position);
    for (size_t r = 0; r < refs.size();) {
        const DrawRef& ref = refs[r];
        const DrawItem& item = scene.items[ref.item];
        size_t copies = 1;
        if (batching && item.instanceGroup != kNoGroup)
            while (r + copies < refs.size()) {
                const DrawRef& next = refs[r + copies];
                const DrawItem& other = scene.items[next.item];
                if (other.instanceGroup != item.instanceGroup || next.level != ref.level ||
                    other.mirrored != item.mirrored)
                    break;
                ++copies;
            }
        const GpuMesh& mesh = scene.meshes[item.mesh];
        const GpuMaterial& material = scene.materials[item.material];
        GLuint p = program ? program : scene.programs[material.*materialProgram].id();
        if (p != boundProgram) glUseProgram(boundProgram = p);
        if (item.material != boundMaterial) {
            boundMaterial = item.material;
            glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_MATERIAL_BLOCK, scene.materialBuffer.id(),
                              GLintptr(material.uniformOffset), sizeof(MaterialBlock));
            for (size_t slot = 0; slot < material.desc.textures.size(); ++slot) {
                uint32_t t = material.desc.textures[slot].texture;
                glBindTextureUnit(GLuint(slot), t == kNone ? 0 : scene.textures[t].texture.id());
            }
            int wantCull = material.desc.doubleSided || twoSided ? 0 : 1;
            if (wantCull != cullState) {
                (cullState = wantCull) ? glEnable(GL_CULL_FACE) : glDisable(GL_CULL_FACE);
            }
        }
        if (item.mirrored != clockwise) glFrontFace((clockwise = item.mirrored) ? GL_CW : GL_CCW);
        size_t objectOffset = ref.objectOffset;
        if (copies > 1) {
            // The copies' matrices packed into the array surface.vert indexes with
            // gl_InstanceID; the first copy's object block, flagged (params.w), says so. (Built
            // again rather than read back: the ring's mapping is write-only.)
            std::byte* array = nullptr;
            const size_t arrayOffset = ctx.ring.allocate(copies * sizeof(InstanceData), array);
            for (size_t k = 0; k < copies; ++k) {
                const ObjectBlock b = objectBlock(scene, scene.items[refs[r + k].item], toCamera, 0.0f);
                const InstanceData d{b.model, b.normalMatrix, b.params};
                std::memcpy(array + k * sizeof d, &d, sizeof d);
            }
            ObjectBlock head = objectBlock(scene, item, toCamera, 0.0f);
            head.params.w = 1.0f;
            objectOffset = ctx.ring.push(&head, sizeof head);
            glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_INSTANCES, ctx.ring.buffer(),
                              GLintptr(arrayOffset), GLsizeiptr(copies * sizeof(InstanceData)));
        }
        glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_OBJECT_BLOCK, ctx.ring.buffer(), GLintptr(objectOffset),
                          GLsizeiptr(ctx.objectBlockBytes));
        if (mesh.vertexArray.id() != boundVao) glBindVertexArray(boundVao = mesh.vertexArray.id());
        const DrawLevel& level = scene.levels[ref.level];
        glDrawElementsInstanced(mesh.primitive, GLsizei(warmUpCount(ctx, level.indexCount)), mesh.indexType,
                                reinterpret_cast<const void*>(mesh.indexOffset +
                                                              uint64_t(level.firstIndex) * mesh.indexSize),
                                GLsizei(copies));
        ++ctx.stats.drawCalls;
        ctx.stats.triangles += level.triangles * copies;
        r += copies;
    }
    if (clockwise) glFrontFace(GL_CCW);
    glEnable(GL_CULL_FACE);
}

std::vector<DrawRef> opaqueDrawRefs(FrameContext& ctx, const glm::dmat4& toView) {
    const GpuScene& scene = ctx.scene;
    std::vector<DrawRef> refs;
    for (uint32_t i = 0; i < scene.items.size(); ++i) {
        if (scene.materials[scene.items[i].material].translucent()) continue;
        DrawRef ref;
        ref.item = i;
        ref.objectOffset = pushObjectBlock(scene, scene.items[i], toView, ctx.ring, 0.0f);
        ref.level = drawLevel(scene, ctx.lod, i);
        refs.push_back(ref);
    }
    return refs;
}

void drawFullscreenTriangle() { glDrawArrays(GL_TRIANGLES, 0, 3); }

} // namespace pnb::player
