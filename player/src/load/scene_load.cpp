// Loads a container onto the GPU (see gpu_scene.h for the phases and what each one costs).
#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include <glm/gtc/type_ptr.hpp>

#include "pnb/mesh_levels.h"
#include "pnb/node_transform.h"
#include "pnb/scene.h"
#include "pnb_lighting/scene_lights.h"
#include "gl/gl_allocation.h"
#include "load/place_item.h"
#include "gl/program_compile.h"
#include "load/scene_upload.h"
#include "load/upload.h"
#include "gl/upload_heap.h"
#include "shared/material_block.h" // MaterialBlock (GLSL and C++)

namespace pnb::player {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

MaterialBlock materialBlock(const Material& m) {
    MaterialBlock b{};
    b.baseColorFactor = {m.baseColorFactor.x, m.baseColorFactor.y, m.baseColorFactor.z,
                         m.baseColorFactor.w};
    b.emissive = glm::vec4(m.emissiveFactor.x, m.emissiveFactor.y, m.emissiveFactor.z, 0) *
                 m.emissiveStrength;
    b.params = {m.metallicFactor, m.roughnessFactor, m.normalScale, m.occlusionStrength};
    b.alphaParams = {m.alphaCutoff, m.alphaMode == AlphaMode::Blend ? 1.0f : 0.0f,
                     m.receivesShadows ? 1.0f : 0.0f, m.unlit ? 1.0f : 0.0f};
    for (size_t i = 0; i < m.textures.size(); ++i) {
        const TextureSlot& s = m.textures[i];
        b.texTransform[i * 2] = {s.offset.x, s.offset.y, s.scale.x, s.scale.y};
        b.texTransform[i * 2 + 1] = {s.rotationRadians, float(s.texCoord), 0, 0};
    }
    return b;
}

// Deferred layer priorities and whether anything is forward, over the drawn items (materials
// nothing draws cost nothing).
void updatePipelineLayout(GpuScene& gpu) {
    std::set<uint16_t> layers;
    gpu.hasForward = false;
    for (const DrawItem& item : gpu.items) {
        const Material& m = gpu.materials[item.material].desc;
        if (m.shadingPath == ShadingPath::Deferred) layers.insert(m.layerPriority);
        else gpu.hasForward = true;
    }
    gpu.deferredLayers.assign(layers.begin(), layers.end());
}

} // namespace

PlayResult<Done> compileNeededPrograms(const Scene& scene, GpuScene& gpu) {
    gpu.programs.resize(scene.programs.size());
    size_t labelled = gpu.programLabels.size();
    gpu.programLabels.resize(scene.programs.size());
    std::set<uint32_t> wanted;
    for (const GpuMaterial& m : gpu.materials)
        if (m.program != kNone) wanted.insert(m.program);
    gpu.deferredLightingProgram.reset();
    gpu.tonemapProgram.reset();
    gpu.shadowProgram.reset();
    gpu.shadowSources.clear();
    gpu.shadowMaskProgram.reset();
    gpu.shadowTranslucentProgram.reset();
    gpu.translucentLighting = false;
    auto hasDefine = [&](uint32_t p, std::string_view define) {
        for (StringRef d : scene.programs[p].defines)
            if (scene.str(d) == define) return true;
        return false;
    };
    // A file the editor changed may hold lighting programs with and without TRANSLUCENT_SHADOWS
    // (it adds, never removes): deferred lighting is the one matching the shadow programs.
    bool translucentShadows = false;
    for (uint32_t i = 0; i < scene.programs.size(); ++i)
        translucentShadows |= scene.str(scene.programs[i].name) == "shadow" && hasDefine(i, "TRANSLUCENT");
    for (uint32_t i = 0; i < scene.programs.size(); ++i) {
        if (i >= labelled) gpu.programLabels[i] = programLabel(scene, i);
        std::string_view name = scene.str(scene.programs[i].name);
        if (name == "deferred_lighting" && !gpu.deferredLayers.empty() &&
            (!gpu.deferredLightingProgram ||
             (hasDefine(i, "TRANSLUCENT_SHADOWS") == translucentShadows &&
              hasDefine(*gpu.deferredLightingProgram, "TRANSLUCENT_SHADOWS") != translucentShadows))) {
            if (gpu.deferredLightingProgram) wanted.erase(*gpu.deferredLightingProgram);
            gpu.deferredLightingProgram = i;
            wanted.insert(i);
        }
        if (name == "shadow") {
            std::optional<uint32_t>& slot = hasDefine(i, "TRANSLUCENT")   ? gpu.shadowTranslucentProgram
                                            : hasDefine(i, "ALPHA_MASK") ? gpu.shadowMaskProgram
                                                                          : gpu.shadowProgram;
            if (!slot) {
                slot = i;
                wanted.insert(i);
                GpuScene::KeptProgram kept;
                kept.label = gpu.programLabels[i];
                for (uint32_t sh : scene.programs[i].shaders) {
                    const ShaderSource& src = scene.shaders[sh];
                    kept.stages.emplace_back(src.stage == ShaderStage::Vertex ? GL_VERTEX_SHADER : GL_FRAGMENT_SHADER,
                                             std::string(reinterpret_cast<const char*>(src.source.data()),
                                                         src.source.size()));
                }
                for (StringRef d : scene.programs[i].defines) kept.defines.emplace_back(scene.str(d));
                gpu.shadowSources.emplace_back(i, std::move(kept));
            }
        }
        // The deform pass's program, where a node deforms (scene_animation.h).
        if (name == "deform" && gpu.animation && !gpu.animation->deformed.empty() && !gpu.animation->deformProgram) {
            gpu.animation->deformProgram = i;
            wanted.insert(i);
        }
        if (name == "tonemap" && !gpu.tonemapProgram) {
            gpu.tonemapProgram = i;
            wanted.insert(i);
        }
    }
    // GI: lighting built with it, and the G-buffer program each opaque or masked material's
    // surfels enter the reflective shadow map with (a forward material's: the G-buffer variant
    // with its features, which the converter packs with GI).
    auto defines = [&](uint32_t p) {
        std::set<std::string_view> d;
        for (StringRef r : scene.programs[p].defines)
            if (scene.str(r) != "SHADOWS" && scene.str(r) != "TRANSLUCENT_SHADOWS" && scene.str(r) != "GI" &&
                scene.str(r) != "IBL")
                d.insert(scene.str(r));
        return d;
    };
    gpu.giPrograms = gpu.iblPrograms = false;
    for (uint32_t i = 0; i < scene.programs.size(); ++i)
        for (StringRef r : scene.programs[i].defines) {
            gpu.giPrograms |= scene.str(r) == "GI";
            gpu.iblPrograms |= scene.str(r) == "IBL";
            gpu.translucentLighting |= scene.str(r) == "TRANSLUCENT_SHADOWS";
        }
    for (GpuMaterial& m : gpu.materials) {
        m.rsmProgram = kNone;
        if (!gpu.giPrograms || m.program == kNone || m.translucent()) continue;
        if (scene.str(scene.programs[m.program].name) == "gbuffer") {
            m.rsmProgram = m.program;
            continue;
        }
        auto features = defines(m.program);
        for (uint32_t i = 0; i < scene.programs.size() && m.rsmProgram == kNone; ++i)
            if (scene.str(scene.programs[i].name) == "gbuffer" && defines(i) == features) m.rsmProgram = i;
        if (m.rsmProgram != kNone) wanted.insert(m.rsmProgram);
    }
    for (uint32_t i : wanted) {
        if (gpu.programs[i]) continue;
        auto p = compileSceneProgram(scene, i);
        if (!p) return p.error();
        gpu.programs[i] = std::move(*p);
    }
    return Done{};
}

namespace {

// Each mesh's level chains (pnb/mesh_levels.h) as DrawLevels in gpu.levels, shared by its instances.
struct MeshChain {
    uint32_t material = 0, firstLevel = 0, levelCount = 0;
};
// Appends mesh m's chains to gpu.levels.
std::vector<MeshChain> appendMeshLevels(GpuScene& gpu, size_t m) {
    std::vector<MeshChain> out;
    const GpuMesh& mesh = gpu.meshes[m];
    for (const SubmeshChain& chain : buildLevelChains(mesh.submeshes)) {
        MeshChain mc{chain.material, uint32_t(gpu.levels.size()), uint32_t(chain.levels.size())};
        float error = 0;
        for (size_t l = 0; l < chain.levels.size(); ++l) {
            const Submesh& sm = mesh.submeshes[chain.levels[l]];
            DrawLevel level;
            level.submesh = chain.levels[l];
            level.firstIndex = sm.firstIndex;
            level.indexCount = sm.indexCount;
            level.triangles = mesh.primitive == GL_TRIANGLES ? sm.indexCount / 3 : 0;
            // Level 0 is exact by definition; a NaN or negative error from another writer
            // counts as unbounded / zero.
            if (l > 0) error = std::max(error, std::isnan(sm.lodError) ? FLT_MAX : std::max(sm.lodError, 0.0f));
            level.error = error;
            gpu.levels.push_back(level);
        }
        out.push_back(mc);
    }
    return out;
}

// World transforms (double) for every node; draw items, lights and cameras from them. Returns
// each item's copy: its index in meshInstances() order (animation re-places items by it).
std::vector<uint32_t> buildSceneGraph(const Scene& scene, GpuScene& gpu) {
    std::vector<uint32_t> itemCopy;
    uint32_t copyIndex = 0;
    std::vector<std::vector<MeshChain>> meshLevels;
    for (size_t m = 0; m < gpu.meshes.size(); ++m) meshLevels.push_back(appendMeshLevels(gpu, m));
    const std::vector<Matrix4d> worldMatrices = nodeWorldMatrices(scene.nodes);
    // Draw items: one per drawn copy of a mesh (pnb/node_transform.h meshInstances: a node, or
    // each of its EXT_mesh_gpu_instancing copies), so culling, LOD, shadows and GI see every copy.
    std::vector<bool> instanced(scene.nodes.nodes.size(), false);
    for (const NodeInstances& in : scene.nodes.instances) instanced[in.node] = true;
    uint32_t groups = 0, groupNode = kNone;
    for (const MeshInstance& copy : meshInstances(scene.nodes, worldMatrices)) {
        const uint32_t thisCopy = copyIndex++;
        const Node& n = scene.nodes.nodes[copy.node];
        if (instanced[copy.node] && copy.node != groupNode) { // a new instanced node: its chains
            groupNode = copy.node;                             // get groups [groups, groups + n)
            groups += uint32_t(meshLevels[n.mesh].size());
        }
        uint32_t chainIndex = 0;
        const glm::dmat4 placed = glm::make_mat4(copy.world.data());
        const GpuMesh& mesh = gpu.meshes[n.mesh];
        for (const MeshChain& chain : meshLevels[n.mesh]) {
            const DrawLevel& level0 = gpu.levels[chain.firstLevel];
            DrawItem item;
            item.node = copy.node;
            item.mesh = item.containerMesh = n.mesh;
            item.material = chain.material;
            item.firstLevel = chain.firstLevel;
            item.levelCount = chain.levelCount;
            if (instanced[copy.node])
                item.instanceGroup = groups - uint32_t(meshLevels[n.mesh].size()) + chainIndex;
            ++chainIndex;
            // The coarser levels reuse level 0's vertices, so its bounds hold them all.
            placeItem(item, placed, mesh.submeshes[level0.submesh].bounds);
            item.triangles = level0.triangles;
            gpu.triangles += item.triangles;
            if (item.levelCount > 1) gpu.lodItems.push_back(uint32_t(gpu.items.size()));
            gpu.items.push_back(item);
            itemCopy.push_back(thisCopy);
        }
    }
    std::vector<glm::dmat4> world(worldMatrices.size());
    for (size_t i = 0; i < scene.nodes.nodes.size(); ++i) {
        const Node& n = scene.nodes.nodes[i];
        world[i] = glm::make_mat4(worldMatrices[i].data());
        if (n.light != kNone) {
            SceneLight l;
            l.desc = scene.lights.lights[n.light];
            l.name = scene.str(l.desc.name);
            l.position = glm::dvec3(world[i][3]);
            l.direction = glm::vec3(lighting::lightTravel(world[i]));
            gpu.lights.push_back(l);
        }
        if (n.camera != kNone) {
            SceneCamera c;
            c.desc = scene.cameras.cameras[n.camera];
            c.name = scene.str(c.desc.name);
            c.position = glm::dvec3(world[i][3]);
            glm::dmat3 r(world[i]);
            for (int k = 0; k < 3; ++k) r[k] = glm::normalize(r[k]);
            c.rotation = glm::normalize(glm::quat_cast(r));
            gpu.cameras.push_back(c);
        }
    }
    return itemCopy;
}

} // namespace

void replaceMeshLevels(GpuScene& gpu, uint32_t mesh) {
    const std::vector<MeshChain> chains = appendMeshLevels(gpu, mesh);
    // A node's items of a mesh are its chains, in order (buildSceneGraph); validateMeshDetail
    // made the new mesh's chains those of the old one, by material and order.
    uint32_t node = kNone;
    size_t k = 0;
    for (uint32_t i = 0; i < gpu.items.size(); ++i) {
        DrawItem& item = gpu.items[i];
        if (item.containerMesh != mesh) continue;
        if (item.node != node) {
            node = item.node;
            k = 0;
        }
        if (k >= chains.size()) continue;
        const MeshChain& chain = chains[k++];
        gpu.triangles -= item.triangles;
        item.firstLevel = chain.firstLevel;
        item.levelCount = chain.levelCount;
        item.triangles = gpu.levels[chain.firstLevel].triangles;
        gpu.triangles += item.triangles;
        auto at = std::lower_bound(gpu.lodItems.begin(), gpu.lodItems.end(), i);
        if (item.levelCount > 1 && (at == gpu.lodItems.end() || *at != i)) gpu.lodItems.insert(at, i);
    }
    ++gpu.materialsVersion; // renderers rebuild their caster lists
}

const ScenePath* GpuScene::findPath(std::string_view pathName) const {
    for (const ScenePath& p : paths)
        if (pathName.empty() || p.name == pathName) return &p;
    return nullptr;
}

PlayResult<std::unique_ptr<GpuScene>> loadScene(const std::string& path,
                                                const LoadOptions& options, LoadStats* statsOut) {
    LoadStats stats;
    auto start = Clock::now();

    // Open: map + table of contents. Checksums are verified below, once, in the read phase.
    ReadOptions readOptions;
    readOptions.verifyChecksums = false;
    auto container = Container::open(path, readOptions);
    if (!container) return inputError(container.error());
    if (options.afterOpen) options.afterOpen();
    // Another program may truncate the mapped file at any moment: the reads below then see zero
    // pages instead of dying of SIGBUS, and this names the true cause instead of their symptom.
    auto fail = [&](const Error& e) {
        const Status shrank = container->intact();
        return inputError(isOk(shrank) ? e : shrank);
    };
    stats.openMs = msSince(start);
    stats.fileBytes = container->bytes().size();
    stats.chunks = uint32_t(container->chunks().size());

    // Read: touch every payload page and check its checksum.
    auto phase = Clock::now();
    for (const ChunkInfo& chunk : container->chunks()) {
        auto stored = container->stored(chunk);
        if (!stored) return fail(stored.error());
        if (options.verifyChecksums && chunk.header.hasChecksum() &&
            checksum(*stored) != chunk.header.payloadChecksum)
            return fail(makeError(FormatError::ChecksumMismatch, chunk.payloadOffset,
                                        "chunk %u '%s': payload checksum does not match its "
                                        "bytes (the file is damaged)",
                                        chunk.header.sequence, chunk.header.tag.str().c_str()));
        if (chunk.header.compression() == Compression::None) stats.zeroCopyBytes += stored->size();
        else stats.decompressedBytes += chunk.header.rawSize;
    }
    stats.readMs = msSince(phase);

    // Decode: decompress, decode every chunk, check order and cross-references.
    phase = Clock::now();
    auto decoded = readScene(*container);
    if (!decoded) return fail(decoded.error());
    const Scene& scene = *decoded;
    stats.unknownChunks = scene.unknownChunks;
    stats.decodeMs = msSince(phase);

    auto gpu = uploadScene(scene, &stats);
    if (Status shrank = container->intact(); !isOk(shrank)) return inputError(shrank);
    if (!gpu) return gpu.error();
    stats.totalMs = msSince(start);
    if (statsOut) *statsOut = stats;
    return std::move(*gpu);
}

PlayResult<std::unique_ptr<GpuScene>> uploadSceneWithoutTexels(const Scene& scene,
                                                                const std::vector<uint32_t>& firstLevels,
                                                                bool meshDetails) {
    auto gpu = std::make_unique<GpuScene>();
    gpu->name = std::string(scene.str(scene.info.name));
    gpu->bounds = scene.info.bounds;
    for (const Setting& s : scene.settings.entries)
        gpu->settings.emplace_back(std::string(scene.str(s.key)), std::string(scene.str(s.value)));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1); // RGB8 and R8 rows are tightly packed
    clearGlErrors();
    for (uint32_t i = 0; i < scene.textures.size(); ++i) {
        auto t = createTexture(scene.textures[i], i, i < firstLevels.size() ? firstLevels[i] : 0);
        if (!t) return t.error();
        gpu->memory.textureBytes += t->bytes;
        gpu->textures.push_back(std::move(*t));
    }
    for (uint32_t i = 0; i < scene.meshes.size(); ++i) {
        auto m = uploadMesh(meshDetails ? fullDetailMesh(scene, i) : scene.meshes[i], i);
        if (!m) return m.error();
        gpu->memory.meshBytes += m->bytes;
        gpu->meshes.push_back(std::move(*m));
    }

    // Materials: one std140 block each, at the UBO offset alignment. Dynamic storage: the
    // material editor rewrites blocks in place (updateMaterials).
    GLint alignment = 256;
    glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &alignment);
    gpu->materialStride =
        uint32_t((sizeof(MaterialBlock) + size_t(alignment) - 1) / size_t(alignment) * size_t(alignment));
    std::vector<std::byte> blocks(std::max<size_t>(scene.materials.size(), 1) * gpu->materialStride);
    for (uint32_t i = 0; i < scene.materials.size(); ++i) {
        GpuMaterial m;
        m.desc = scene.materials[i];
        m.name = std::string(scene.str(m.desc.name));
        m.program = m.desc.program;
        m.uniformOffset = i * gpu->materialStride;
        MaterialBlock b = materialBlock(m.desc);
        std::memcpy(blocks.data() + m.uniformOffset, &b, sizeof b);
        gpu->materials.push_back(m);
    }
    gpu->materialBuffer = createBuffer();
    glNamedBufferStorage(gpu->materialBuffer.id(), GLsizeiptr(blocks.size()), blocks.data(),
                         GL_DYNAMIC_STORAGE_BIT);
    gpu->memory.uniformBytes += blocks.size();
    if (auto ok = checkGlAllocation("the scene's textures, meshes and materials",
                                    gpu->memory.textureBytes + gpu->memory.meshBytes +
                                        gpu->memory.uniformBytes);
        !ok)
        return ok.error();

    for (const CameraPath& p : scene.cameraPaths) {
        ScenePath sp{std::string(scene.str(p.name)), p};
        sp.path.name = kNone;
        gpu->paths.push_back(std::move(sp));
    }
    if (const auto& e = scene.environment) {
        GpuEnvironment env;
        env.name = std::string(scene.str(e->name));
        auto ref = [](uint32_t r) { return r == kNone ? std::nullopt : std::optional<uint32_t>(r); };
        env.radiance = ref(e->radiance);
        env.specular = ref(e->specular);
        env.brdfLut = ref(e->brdfLut);
        for (size_t k = 0; k < 9; ++k)
            env.irradianceSh[k] = {e->irradianceSh[k].x, e->irradianceSh[k].y, e->irradianceSh[k].z};
        if (env.specular) env.specularLevels = scene.textures[*env.specular].mipCount;
        gpu->environment = std::move(env);
    }
    const std::vector<uint32_t> itemCopy = buildSceneGraph(scene, *gpu);
    if (auto a = setUpAnimation(scene, itemCopy, *gpu); !a) return a.error();
    updatePipelineLayout(*gpu);
    return gpu;
}

PlayResult<std::unique_ptr<GpuScene>> uploadScene(const Scene& scene, LoadStats* statsOut) {
    LoadStats local;
    LoadStats& stats = statsOut ? *statsOut : local;
    // Upload, in file order: textures (storage), meshes, then texels (smallest mips first).
    auto phase = Clock::now();
    UploadHeap heap(estimateUploadBytes(scene));
    stats.hugePageBytes = heap.hugePageBytes();
    stats.uploadPages = heap.describe();
    auto gpu = uploadSceneWithoutTexels(scene, {}, true);
    if (!gpu) return gpu.error();
    for (const TextureMip& mip : scene.textureMips)
        uploadTextureMip((*gpu)->textures[mip.texture], scene.textures[mip.texture], mip);
    glFinish();
    stats.uploadMs = msSince(phase);

    // Programs last: on a real driver they compile in parallel with the uploads above.
    phase = Clock::now();
    if (auto r = compileNeededPrograms(scene, **gpu); !r) return r.error();
    stats.compileMs = msSince(phase);
    return std::move(*gpu);
}

PlayResult<Done> updateMaterials(GpuScene& gpu, const Scene& scene) {
    ++gpu.materialsVersion;
    // Only the blocks that changed are rewritten; layout and programs are settled once.
    for (uint32_t i = 0; i < gpu.materials.size(); ++i) {
        GpuMaterial& m = gpu.materials[i];
        const Material& desc = scene.materials[i];
        if (encodeChunk(desc) == encodeChunk(m.desc)) continue;
        m.desc = desc;
        m.program = desc.program;
        MaterialBlock b = materialBlock(desc);
        glNamedBufferSubData(gpu.materialBuffer.id(), GLintptr(m.uniformOffset), sizeof b, &b);
    }
    updatePipelineLayout(gpu);
    return compileNeededPrograms(scene, gpu);
}

int shadowingSun(const GpuScene& scene) {
    return lighting::shadowingSunIndex(scene.lights.size(),
                                       [&](size_t i) -> const Light& { return scene.lights[i].desc; });
}

glm::vec3 towardShadowingSun(const GpuScene& scene) {
    const int sun = shadowingSun(scene);
    return sun >= 0 ? -scene.lights[size_t(sun)].direction : glm::vec3(0, 1, 0);
}

} // namespace pnb::player
