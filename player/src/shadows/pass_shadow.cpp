// The shadow pass: every listed caster into the cascade array, depth only, depth clamp on (casters
// nearer the light than the map's near plane are flattened onto it rather than clipped, the
// "pancaking" of seed 000's canyon case). Two strategies (shadows.render):
//   layered    one draw per caster, instanced once per cascade it touches; the vertex shader
//              picks the cascade from the caster's mask and writes gl_Layer (no geometry shader);
//   multipass  one pass per cascade over that layer, each caster drawn where its mask has the bit.
// Per-cascade culling decides the masks (CPU fits) or the GPU writes them with indirect draws
// (SDSM), so the layered path never rasterises a caster into a cascade the multi-pass would skip.
// Where the vertex shader cannot write gl_Layer (or shadows.layer_from = geometry), the layered
// pass links a geometry shader that replicates each triangle into its cascades instead.
// Faces are not culled: open, single-sided geometry casts too; receiver offsets handle acne.
// Blended casters (issue 43) come after the opaque ones, in a second round over the same layers
// (its own timer section, "shadow_translucent"): into the colour companions, depth-tested
// against the opaque depths without writing any (shadow_maps.h).
#include <algorithm>
#include <bit>
#include <cstdio>

#include "frame/frame_context.h"
#include "shadows/shadow_maps.h"
#include "gl/program_compile.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)
#include "shared/material_block.h" // MaterialBlock (GLSL and C++)

namespace pnb::player {

namespace {

constexpr size_t kIndirectCommandBytes = 20;

// The program drawing `caster`: the container's, or its geometry-shader variant (linked on first
// use) when the layered pass takes gl_Layer from a geometry shader.
GLuint casterProgram(FrameContext& ctx, ShadowContext& shadows, const ShadowCaster& caster, bool geometryLayers) {
    const GpuScene& scene = ctx.scene;
    if (!geometryLayers) return scene.programs[caster.program].id();
    auto& cache = shadows.geometryLayerPrograms;
    for (const auto& [index, program] : cache)
        if (index == caster.program) return program.id();
    for (const auto& [index, kept] : scene.shadowSources) {
        if (index != caster.program) continue;
        std::vector<StageSource> stages;
        for (const auto& [stage, text] : kept.stages) {
            stages.push_back({stage, text});
            if (stage == GL_VERTEX_SHADER) stages.push_back({GL_GEOMETRY_SHADER, embeddedSource("shadow_layers.geom")});
        }
        std::vector<std::string_view> defines(kept.defines.begin(), kept.defines.end());
        defines.push_back("LAYER_FROM_GEOMETRY");
        auto p = compileProgram(kept.label + " + shadow_layers.geom", stages, defines);
        if (!p) {
            std::fprintf(stderr, "pnb-play: %s\n", p.error().message.c_str());
            cache.emplace_back(index, GlHandle{});
            return 0;
        }
        cache.emplace_back(index, std::move(*p));
        return cache.back().second.id();
    }
    return 0;
}

} // namespace

void bindCasterMaterial(const GpuScene& scene, const ShadowCaster& caster, GLuint program) {
    const DrawItem& item = scene.items[caster.item];
    const GpuMaterial& material = scene.materials[item.material];
    glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_MATERIAL_BLOCK, scene.materialBuffer.id(),
                      GLintptr(material.uniformOffset), sizeof(MaterialBlock));
    uint32_t t = material.desc.textures.empty() ? kNone : material.desc.textures[0].texture;
    glBindTextureUnit(0, t == kNone ? 0 : scene.textures[t].texture.id());
    if (caster.translucent) glProgramUniform1i(program, 1, t == kNone ? 0 : 1); // shadow.frag's TRANSLUCENT
}

void setTranslucentTarget(GLuint program, int depthLayer, uint32_t divisor, bool reversedDepth) {
    glProgramUniform1i(program, 2, reversedDepth ? 1 : 0);
    glProgramUniform1i(program, 3, depthLayer);
    glProgramUniform1i(program, 4, GLint(divisor));
}

namespace {

// The listed casters of one round: the opaque and masked ones, or the blended ones.
void drawCasters(FrameContext& ctx, ShadowContext& shadows, int passCascade, bool geometryLayers,
                 bool translucent) {
    const ShadowFrame& f = shadows.frame;
    const GpuScene& scene = ctx.scene;
    const std::vector<ShadowCaster>& casters = shadows.casters;
    GLuint boundProgram = ~0u, boundVao = ~0u;
    uint32_t boundMaterial = kNone;
    for (size_t i = 0; i < f.casters.size(); ++i) {
        uint32_t copies = 1; // cascades this draw rasterises the caster into
        if (!f.gpuFit) {
            uint32_t mask = f.masks[i];
            if (passCascade >= 0 && !(mask & (1u << passCascade))) continue;
            copies = passCascade >= 0 ? 1u : uint32_t(std::popcount(mask));
        }
        // Instancing replicates in the vertex-layer path, the geometry shader in the other.
        uint32_t instances = geometryLayers ? 1u : copies;
        const ShadowCaster& caster = casters[f.casters[i]];
        if (caster.translucent != translucent) continue;
        const DrawItem& item = scene.items[caster.item];
        const GpuMesh& mesh = scene.meshes[item.mesh];
        const DrawLevel& level = scene.levels[f.levels[i]];
        const uint64_t firstIndex = mesh.indexOffset / mesh.indexSize + level.firstIndex;
        GLuint program = casterProgram(ctx, shadows, caster, geometryLayers);
        if (!program) continue;
        if (program != boundProgram) {
            glUseProgram(boundProgram = program);
            glProgramUniform1i(program, 0, passCascade);
            if (translucent)
                setTranslucentTarget(program, passCascade, shadows.resources.translucentDivisor, false);
        }
        const bool materialRead = caster.translucent || (scene.shadowMaskProgram && caster.program == *scene.shadowMaskProgram);
        if (materialRead && item.material != boundMaterial) {
            boundMaterial = item.material;
            bindCasterMaterial(scene, caster, program);
        }
        glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_OBJECT_BLOCK, ctx.ring.buffer(),
                          GLintptr(f.objectOffsets[i]), GLsizeiptr(ctx.objectBlockBytes));
        if (mesh.vertexArray.id() != boundVao) glBindVertexArray(boundVao = mesh.vertexArray.id());
        if (f.gpuFit && ctx.warmUp) {
            // The GPU cull may leave a draw empty, and a driver may skip an empty draw before
            // generating code: the warm-up draws the caster's first triangle directly.
            glDrawElementsInstanced(mesh.primitive, GLsizei(warmUpCount(ctx, level.indexCount)), mesh.indexType,
                                    reinterpret_cast<const void*>(firstIndex * mesh.indexSize), 1);
        } else if (f.gpuFit) {
            size_t slot = passCascade < 0 ? i : (size_t(passCascade) + 1) * shadows.resources.sdsmCasterCapacity + i;
            glDrawElementsIndirect(mesh.primitive, mesh.indexType,
                                   reinterpret_cast<const void*>(slot * kIndirectCommandBytes));
        } else {
            glDrawElementsInstanced(mesh.primitive, GLsizei(warmUpCount(ctx, level.indexCount)), mesh.indexType,
                                    reinterpret_cast<const void*>(firstIndex * mesh.indexSize),
                                    GLsizei(instances));
        }
        ++ctx.stats.shadowDraws;
        ctx.stats.shadowTriangles += uint64_t(level.triangles) * copies;
    }
}

} // namespace

void runShadowPass(FrameContext& ctx, ShadowContext& shadows) {
    const ShadowFrame& f = shadows.frame;
    if (!f.active) return;
    const ShadowResources& r = shadows.resources;
    ctx.timer.mark("shadow");
    ctx.stats.shadowCasters = uint32_t(f.casters.size());
    bindShadowsForLighting(ctx, shadows); // the vertex shader reads the ShadowBlock too
    glBindTextureUnit(8, 0);     // not sampled while being written
    glBindTextureUnit(9, 0);
    glBindTextureUnit(20, 0); // the companions likewise
    glBindTextureUnit(21, 0);
    if (f.gpuFit) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_CASTER_MASKS, r.sdsmMasks.id());
        glBindBuffer(GL_DRAW_INDIRECT_BUFFER, r.sdsmCommands.id());
    } else if (f.maskBytes) {
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_CASTER_MASKS, ctx.ring.buffer(),
                          GLintptr(f.maskOffset), GLsizeiptr(f.maskBytes));
    }
    glViewport(0, 0, GLsizei(r.resolution), GLsizei(r.resolution));
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_CLAMP);
    const float far = 1.0f;
    const bool translucent = f.translucent && r.translucent;
    // gl_Layer from the vertex shader needs ARB_shader_viewport_layer_array.
    static const bool vertexLayers = epoxy_has_gl_extension("GL_ARB_shader_viewport_layer_array");
    const bool layered = ctx.settings.shadowRender == ShadowRender::Layered;
    const bool geometry = ctx.settings.shadowLayerSource == LayerSource::Geometry || !vertexLayers;
    // One round of casters (opaque, or blended) over every cascade.
    const GLsizei companionSide = GLsizei(std::max(r.resolution / r.translucentDivisor, 1u));
    auto round = [&](bool blended) {
        if (layered) {
            GLuint fb = blended ? r.translucentLayeredFb.id() : r.layeredFb.id();
            glBindFramebuffer(GL_FRAMEBUFFER, fb);
            if (blended) clearTranslucentMaps(fb);
            else glClearNamedFramebufferfv(fb, GL_DEPTH, 0, &far);
            drawCasters(ctx, shadows, -1, geometry, blended);
            return;
        }
        for (uint32_t c = 0; c < f.cascades; ++c) {
            GLuint fb = blended ? r.translucentLayerFbs[c].id() : r.layerFbs[c].id();
            glBindFramebuffer(GL_FRAMEBUFFER, fb);
            if (blended) clearTranslucentMaps(fb);
            else glClearNamedFramebufferfv(fb, GL_DEPTH, 0, &far);
            drawCasters(ctx, shadows, int(c), false, blended);
        }
    };
    round(false);
    if (translucent) {
        ctx.timer.mark("shadow_translucent");
        glViewport(0, 0, companionSide, companionSide);
        glBindTextureUnit(9, r.depthView.id()); // the opaque depths, read by shadow.frag's test
        beginTranslucentCasters();
        round(true);
        restoreOpaqueCasterState();
        glBindTextureUnit(9, 0);
    }
    glDisable(GL_DEPTH_CLAMP);
    glEnable(GL_CULL_FACE);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glViewport(0, 0, GLsizei(ctx.targets.width), GLsizei(ctx.targets.height));
    bindShadowsForLighting(ctx, shadows);
}

} // namespace pnb::player
