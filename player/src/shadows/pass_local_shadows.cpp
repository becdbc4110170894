// Point and spot light shadows (local_shadows.h): rank the shadow-casting local lights in view,
// place their tiles in the atlas, write the tiles' matrices for lighting (binding 9) and each
// light's first tile into the frame's light list, and draw the tiles whose content changed.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "pnb/light_range.h"
#include "frame/frame_context.h"
#include "shadows/shadow_maps.h"
#include "shadows/local_shadows.h"
#include "lights/light_clusters.h"
#include "shared/bindings.h" // PNB_BINDING_* (GLSL and C++)
#include "shared/light_list.h" // LightListHeader, GpuLight (GLSL and C++)
#include "shared/local_shadow_tile.h" // LocalShadowsHeader, GpuShadowTile (GLSL and C++)
#include "shared/material_block.h" // MaterialBlock (GLSL and C++)

namespace pnb::player {

namespace {

// The atlas's texture unit (local_shadows.glsl): 0-4 materials, 8-9 the sun, 10-18 GI and sky;
// its companions 22 and 23 (20 and 21: the sun's).
constexpr GLuint kLocalShadowUnit = 19;
constexpr GLuint kLocalTranslucentUnit = 22;

// Spot lights up to this half-angle get one tile; wider ones (and point lights) the six faces.
constexpr float kMaxSpotTileRadians = 1.0471976f; // 60 degrees

void dropAtlas(LocalShadowContext& ls) {
    ls.atlas = {};
    ls.framebuffer = {};
    ls.translucentFramebuffer = {};
    ls.depthView = {};
    ls.translucent = {};
    ls.atlasSize = 0;
    ls.drawn.clear();
}

void ensureAtlas(LocalShadowContext& ls, uint32_t size, bool translucent, uint32_t divisor) {
    if (ls.atlasSize == size && translucent == bool(ls.translucent) &&
        (!translucent || divisor == ls.translucentDivisor))
        return;
    dropAtlas(ls);
    ls.atlas = createTexture(GL_TEXTURE_2D);
    glTextureStorage2D(ls.atlas.id(), 1, GL_DEPTH_COMPONENT32F, GLsizei(size), GLsizei(size));
    glTextureParameteri(ls.atlas.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR); // 2x2 PCF per tap
    glTextureParameteri(ls.atlas.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(ls.atlas.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(ls.atlas.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(ls.atlas.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(ls.atlas.id(), GL_TEXTURE_COMPARE_FUNC, GL_GEQUAL); // reversed-Z: lit if nearer or equal
    glObjectLabel(GL_TEXTURE, ls.atlas.id(), -1, "local shadow atlas");
    ls.framebuffer = createFramebuffer();
    glNamedFramebufferTexture(ls.framebuffer.id(), GL_DEPTH_ATTACHMENT, ls.atlas.id(), 0);
    glNamedFramebufferDrawBuffer(ls.framebuffer.id(), GL_NONE);
    if (translucent) {
        // The blended round's own framebuffer, colour only, at 1/divisor of the atlas' side (as
        // the sun's, shadow_resources.cpp); its fragments test the depths through a view of the
        // atlas without comparison, as a one-layer array (shadow.frag reads arrays).
        ls.translucentDivisor = divisor;
        ls.translucent.create(std::max(size / divisor, 1u), std::max(size / divisor, 1u), 1, "local shadow atlas");
        ls.translucentFramebuffer = createFramebuffer();
        attachTranslucentMaps(ls.translucentFramebuffer.id(), ls.translucent, 0);
        GLuint view = 0;
        glGenTextures(1, &view);
        glTextureView(view, GL_TEXTURE_2D_ARRAY, ls.atlas.id(), GL_DEPTH_COMPONENT32F, 0, 1, 0, 1);
        ls.depthView = GlHandle(GlKind::Texture, view);
        glTextureParameteri(view, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(view, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    ls.atlasSize = size;
}

// A placed light's tiles: its range, and their half-angle's tangent — the face's or the cone's,
// widened by the filter radius (+1.5 texels for the 2x2 tap) so a pixel's taps stay in its tile.
struct TileShape {
    float range = 0, tanHalf = 0;
};
TileShape tileShape(const SceneLight& l, const LocalShadowPlacement& p, float filterRadius) {
    const float margin = 1.0f + 2.0f * (filterRadius + 1.5f) / float(p.size);
    return {effectiveLightRange(l.desc), p.faces == 6 ? margin : std::tan(l.desc.outerConeRadians) * margin};
}

// Where tile `face` of a placed light looks: a cube face, or down the spot light's axis.
glm::vec3 tileDirection(const SceneLight& l, const LocalShadowPlacement& p, uint32_t face) {
    return p.faces == 6 ? kCubeFaceDirections[face] : l.direction;
}

bool sphereInView(const ViewMatrices& view, glm::vec3 centre, float radius) {
    for (const glm::vec4& plane : view.frustumPlanes)
        if (glm::dot(glm::vec3(plane), centre) + plane.w < -radius * glm::length(glm::vec3(plane))) return false;
    return true;
}

bool boxTouchesSphere(glm::dvec3 lo, glm::dvec3 hi, glm::dvec3 centre, double radius) {
    const glm::dvec3 nearest = glm::clamp(centre, lo, hi);
    const glm::dvec3 d = nearest - centre;
    return glm::dot(d, d) <= radius * radius;
}

// Draws every caster the light's sphere touches into one tile (`face` of the pushed block): the
// opaque and masked ones, or the blended ones (`translucent`).
void drawTile(FrameContext& ctx, const ShadowContext& shadows, const SceneLight& light, float range, uint32_t face,
              const std::vector<size_t>& objectOffsets, bool translucent, uint32_t divisor = 1) {
    const GpuScene& scene = ctx.scene;
    GLuint boundProgram = ~0u, boundVao = ~0u;
    uint32_t boundMaterial = kNone;
    for (size_t c = 0; c < shadows.casters.size(); ++c) {
        const ShadowCaster& caster = shadows.casters[c];
        if (caster.translucent != translucent) continue;
        const DrawItem& item = scene.items[caster.item];
        if (!boxTouchesSphere(item.boundsMin, item.boundsMax, light.position, double(range))) continue;
        const GLuint program = scene.programs[caster.program].id();
        if (!program) continue;
        if (program != boundProgram) {
            glUseProgram(boundProgram = program);
            if (translucent) setTranslucentTarget(program, 0, divisor, true);
        }
        glProgramUniform1i(program, 0, int(face)); // the tile's matrix in the pushed block
        const bool materialRead = caster.translucent || (scene.shadowMaskProgram && caster.program == *scene.shadowMaskProgram);
        if (materialRead && item.material != boundMaterial) {
            boundMaterial = item.material;
            bindCasterMaterial(scene, caster, program);
        }
        const GpuMesh& mesh = scene.meshes[item.mesh];
        const DrawLevel& level = scene.levels[drawLevel(scene, ctx.lod, caster.item)];
        const uint64_t firstIndex = mesh.indexOffset / mesh.indexSize + level.firstIndex;
        glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_OBJECT_BLOCK, ctx.ring.buffer(), GLintptr(objectOffsets[c]),
                          GLsizeiptr(ctx.objectBlockBytes));
        if (mesh.vertexArray.id() != boundVao) glBindVertexArray(boundVao = mesh.vertexArray.id());
        glDrawElements(mesh.primitive, GLsizei(warmUpCount(ctx, level.indexCount)), mesh.indexType,
                       reinterpret_cast<const void*>(firstIndex * mesh.indexSize));
        ++ctx.stats.localShadowDraws;
        ctx.stats.localShadowTriangles += level.triangles;
    }
}

} // namespace

void runLocalShadows(FrameContext& ctx, LocalShadowContext& ls, const ShadowContext& shadows,
                     const LightContext& lights) {
    const GpuScene& scene = ctx.scene;
    const RenderSettings& s = ctx.settings;
    ls.placements.clear();
    ls.tiles = ls.tilesDrawn = 0;

    std::vector<LocalShadowRequest> requests;
    if (s.shadowLocal && shadows.frame.sceneHasShadows && !shadows.casters.empty()) {
        for (uint32_t i = 0; i < scene.lights.size(); ++i) {
            const SceneLight& l = scene.lights[i];
            const float range = effectiveLightRange(l.desc);
            if (l.desc.type == LightType::Directional || !l.desc.castsShadows || !(range > 0.0f)) continue;
            const glm::vec3 centre(l.position - ctx.view.position);
            if (!sphereInView(ctx.view, centre, range)) continue;
            LocalShadowRequest r;
            r.light = i;
            r.cube = l.desc.type == LightType::Point || l.desc.outerConeRadians > kMaxSpotTileRadians;
            const float d = glm::length(centre);
            // The sphere's radius over the view's half height where it stands (orthographic:
            // the same at any distance).
            r.screenFraction =
                d <= range && !ctx.view.orthographic
                    ? 1.0f
                    : std::min(1.0f, range / float(ctx.view.halfHeightAt(std::sqrt(std::max(d * d - range * range, 0.0f)))));
            requests.push_back(r);
        }
    }
    ls.placements = planLocalShadows(std::move(requests), ctx.targets.height, s, s.shadowLocalAtlas);
    if (ls.placements.empty()) {
        dropAtlas(ls); // no local light casts a shadow in view: no atlas
        // local_shadows.glsl declares the tiles' block; no light points into it (cone.z = -1),
        // but a declared block wants a buffer: the light list stands in.
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_LOCAL_SHADOWS, ctx.ring.buffer(),
                          GLintptr(lights.listOffset), GLsizeiptr(lights.listBytes));
        return;
    }
    const bool translucent = s.shadowTranslucent && shadows.translucentCasters;
    // The atlas' companions keep its side: its tiles are already sized to each light's share
    // of the screen, and only drawn tiles are cleared (shadows.translucent_divisor is the sun's).
    ensureAtlas(ls, s.shadowLocalAtlas, translucent, 1);
    ctx.timer.mark("local_shadows");

    // The tiles' data for lighting, and each light's first tile in the light list (cone.z).
    for (const LocalShadowPlacement& p : ls.placements) ls.tiles += p.faces;
    std::byte* data = nullptr;
    const size_t tileBytes = sizeof(LocalShadowsHeader) + sizeof(GpuShadowTile) * ls.tiles;
    const size_t tileOffset = ctx.ring.allocate(tileBytes, data);
    const float atlas = float(ls.atlasSize);
    LocalShadowsHeader header;
    header.atlas = {1.0f / atlas, float(s.shadowLocalTaps), s.shadowRadius, 0};
    std::memcpy(data, &header, sizeof header);
    uint32_t tile = 0;
    for (const LocalShadowPlacement& p : ls.placements) {
        const SceneLight& l = scene.lights[p.light];
        const TileShape shape = tileShape(l, p, s.shadowRadius);
        const float first = float(tile);
        const size_t coneZ = offsetof(GpuLight, cone) + 2 * sizeof(float);
        std::memcpy(lights.listData + sizeof(LightListHeader) + size_t(p.light) * sizeof(GpuLight) + coneZ,
                    &first, sizeof first);
        for (uint32_t f = 0; f < p.faces; ++f, ++tile) {
            GpuShadowTile t;
            t.matrix = localShadowMatrix(glm::vec3(l.position - ctx.view.position), tileDirection(l, p, f),
                                         shape.tanHalf, shape.range);
            t.rect = {float(p.origins[f].x) / atlas, float(p.origins[f].y) / atlas, float(p.size) / atlas,
                      2.0f * shape.tanHalf / float(p.size)};
            std::memcpy(data + sizeof header + size_t(tile) * sizeof t, &t, sizeof t);
        }
    }
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PNB_BINDING_LOCAL_SHADOWS, ctx.ring.buffer(), GLintptr(tileOffset),
                      GLsizeiptr(tileBytes));

    // Draw the tiles whose light, place or casters changed (all of them without the cache).
    ls.drawn.resize(ls.tiles);
    std::vector<size_t> objectOffsets; // casters' object blocks, pushed once for every tile
    tile = 0;
    for (const LocalShadowPlacement& p : ls.placements) {
        const SceneLight& l = scene.lights[p.light];
        const TileShape shape = tileShape(l, p, s.shadowRadius);
        ShadowBlock block{};
        bool blockPushed = false, casterMoved = false;
        for (uint32_t f = 0; f < p.faces; ++f, ++tile) {
            LocalShadowContext::TileKey key{p.light, p.size, f, p.origins[f], l.position, tileDirection(l, p, f),
                                            shape.range, shape.tanHalf, scene.materialsVersion};
            // A caster that moved (or deformed) within the light's reach this frame redraws
            // the light's tiles (scene_animation.h movedNear).
            if (f == 0) casterMoved = movedNear(scene.animation.get(), l.position, double(shape.range));
            if (s.shadowLocalCache && !ctx.warmUp && ls.drawn[tile] == key && !casterMoved) continue;
            ls.drawn[tile] = ctx.warmUp ? LocalShadowContext::TileKey{} : key;
            if (objectOffsets.empty()) {
                const glm::dmat4 toCamera = glm::translate(glm::dmat4(1.0), -ctx.view.position);
                for (size_t c = 0; c < shadows.casters.size(); ++c)
                    objectOffsets.push_back(pushObjectBlock(scene, scene.items[shadows.casters[c].item], toCamera,
                                                            ctx.ring, float(c)));
                glBindFramebuffer(GL_FRAMEBUFFER, ls.framebuffer.id());
                glBindTextureUnit(kLocalShadowUnit, 0); // not sampled while being written
                glBindTextureUnit(kLocalTranslucentUnit, 0);
                glBindTextureUnit(kLocalTranslucentUnit + 1, 0);
                glEnable(GL_DEPTH_TEST);
                glDepthFunc(GL_GREATER);
                glDepthMask(GL_TRUE);
                glDisable(GL_BLEND);
                glDisable(GL_CULL_FACE); // open, single-sided geometry casts too
                glEnable(GL_SCISSOR_TEST);
            }
            if (!blockPushed) {
                for (uint32_t k = 0; k < p.faces; ++k)
                    block.matrix[k] = localShadowMatrix(glm::vec3(l.position - ctx.view.position),
                                                        tileDirection(l, p, k), shape.tanHalf, shape.range);
                const size_t offset = ctx.ring.push(&block, sizeof block);
                glBindBufferRange(GL_UNIFORM_BUFFER, PNB_BINDING_SHADOW_BLOCK, ctx.ring.buffer(), GLintptr(offset),
                                  sizeof block);
                blockPushed = true;
            }
            glViewport(GLint(p.origins[f].x), GLint(p.origins[f].y), GLsizei(p.size), GLsizei(p.size));
            glScissor(GLint(p.origins[f].x), GLint(p.origins[f].y), GLsizei(p.size), GLsizei(p.size));
            const float far = 0.0f; // reversed-Z
            glClearNamedFramebufferfv(ls.framebuffer.id(), GL_DEPTH, 0, &far);
            drawTile(ctx, shadows, l, shape.range, f, objectOffsets, false);
            if (translucent) { // the tile's place in the companions, 1/divisor the size
                const uint32_t d = ls.translucentDivisor;
                const GLint x = GLint(p.origins[f].x / d), y = GLint(p.origins[f].y / d);
                const GLsizei side = GLsizei(std::max(p.size / d, 1u));
                glViewport(x, y, side, side);
                glScissor(x, y, side, side);
                glBindFramebuffer(GL_FRAMEBUFFER, ls.translucentFramebuffer.id());
                glBindTextureUnit(9, ls.depthView.id());
                clearTranslucentMaps(ls.translucentFramebuffer.id()); // the scissor keeps it in the tile
                beginTranslucentCasters();
                drawTile(ctx, shadows, l, shape.range, f, objectOffsets, true, d);
                restoreOpaqueCasterState();
                glBindTextureUnit(9, 0);
                glBindFramebuffer(GL_FRAMEBUFFER, ls.framebuffer.id());
            }
            ++ls.tilesDrawn;
        }
    }
    if (!objectOffsets.empty()) {
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        if (!ctx.warmUp) glDisable(GL_SCISSOR_TEST); // the warm-up frame keeps its 1x1 scissor
        else glScissor(0, 0, 1, 1);
        glEnable(GL_CULL_FACE);
        glViewport(0, 0, GLsizei(ctx.targets.width), GLsizei(ctx.targets.height));
        bindShadowsForLighting(ctx, shadows); // the sun's block again
    }
    glBindTextureUnit(kLocalShadowUnit, ls.atlas.id());
    if (scene.translucentLighting)
        bindTranslucentMaps(ls.translucent, shadows.neutralTranslucent, kLocalTranslucentUnit);
    ctx.stats.localShadowTiles = ls.tiles;
    ctx.stats.localShadowTilesDrawn = ls.tilesDrawn;
}

} // namespace pnb::player
