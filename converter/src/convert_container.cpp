// converter/src/convert_container.cpp — convertScene's last stage (convert_internal.h): every
// stage's result into one container Scene, in streamable order, and its atomic write.

#include <algorithm>
#include <filesystem>
#include <memory>
#include <set>

#include "convert_internal.h"
#include "pnb/animation_pose.h"
#include "pnb/compression_memo.h"
#include "pnb/mesh_levels.h"
#include "pnb/writer.h"

namespace pnb::converter::convert_detail {

namespace {

namespace fs = std::filesystem;

constexpr const char* kGenerator = "pnb-convert 0.1";

ConvertError outputError(std::string message) {
    return ConvertError{ConvertErrorKind::Output, std::move(message)};
}

void appendInfoAndSettings(const ConvertSettings& s, const Aabb& sceneBounds, SceneBuilder& b) {
    Scene& out = b.scene;
    out.info.name = b.intern(fs::path(s.input).stem().string());
    out.info.generator = b.intern(kGenerator);
    out.info.source = b.intern(fs::path(s.input).filename().string());
    out.info.bounds = sceneBounds;
    for (const auto& [key, value] : s.renderSettings)
        out.settings.entries.push_back({b.intern(key), b.intern(value)});
}

void appendTextures(const std::vector<ProcessedTexture>& textures,
                    const ResolvedMaterials& materials, SceneBuilder& b, ConvertSummary& sum) {
    Scene& out = b.scene;
    for (size_t i = 0; i < textures.size(); ++i) {
        const ProcessedTexture& t = textures[i];
        TextureDesc desc = t.desc;
        desc.name = b.intern(materials.textures[i].name);
        out.textures.push_back(desc);
        for (uint32_t level = 0; level < t.levels.size(); ++level)
            out.textureMips.push_back({uint32_t(i), level, std::max(1u, desc.width >> level),
                                       std::max(1u, desc.height >> level), Blob(t.levels[level])});
        for (const auto& l : t.levels)
            sum.textureBytes += l.size();
        if (t.psnrDb > 0)
            sum.minTexturePsnrDb =
                sum.minTexturePsnrDb == 0 ? t.psnrDb : std::min(sum.minTexturePsnrDb, t.psnrDb);
    }
}

void appendEnvironmentOf(const BakedEnvironment& environment, SceneBuilder& b,
                         ConvertSummary& sum) {
    sum.environment = appendEnvironment(b, environment, environment.summary.name);
    // The default one is baked once per process: this conversion's time is its stage's.
    if (sum.defaultEnvironment)
        for (const StageTiming& t : sum.stages)
            if (t.stage == "environment") sum.environment->seconds = t.seconds;
}

void appendMaterials(const ResolvedMaterials& materials, const ShaderPlan& plan, SceneBuilder& b,
                     ConvertSummary& sum) {
    std::set<uint16_t> layers;
    for (size_t i = 0; i < materials.materials.size(); ++i) {
        Material m = materials.materials[i];
        m.name = b.intern(materials.names[i]);
        m.program = plan.materialProgram[i];
        b.scene.materials.push_back(m);
        if (m.shadingPath == ShadingPath::Deferred) {
            ++sum.deferredMaterials;
            layers.insert(m.layerPriority);
        } else {
            ++sum.forwardMaterials;
        }
    }
    sum.deferredLayers.assign(layers.begin(), layers.end());
}

void appendMeshes(const ConvertSettings& s, const std::vector<ProcessedMesh>& meshes,
                  int defaultMaterial, SceneBuilder& b, ConvertSummary& sum) {
    Scene& out = b.scene;
    for (size_t i = 0; i < meshes.size(); ++i) {
        const ProcessedMesh& pm = meshes[i];
        Mesh m =
            toContainerMesh(pm, b.intern(pm.name.empty() ? "mesh" + std::to_string(i) : pm.name));
        for (const OwnedStream& st : pm.streams)
            sum.meshBytes += st.bytes.size();
        sum.meshBytes += pm.indices.size();
        for (Submesh& sm : m.submeshes)
            if (sm.material == kNone) sm.material = uint32_t(defaultMaterial);
        sum.submeshes += m.submeshes.size();
        // A deformed mesh has no proxy: the deforming pass moves the one mesh it has (its LOD
        // levels stay, they index the same vertices).
        if (s.mesh.proxies && hasLevelChains(m) && !pm.deformed) {
            // Coarse first: the proxy for the first frame, the detail once it is drawn.
            out.meshes.push_back(buildCoarseProxy(m, b));
            out.meshDetails.push_back({uint32_t(i), m});
        } else {
            out.meshes.push_back(m);
        }
    }
}

// MRPH: each morphed mesh's targets, their deltas views of the processed mesh's bytes.
void appendMorphTargets(const std::vector<ProcessedMesh>& meshes, SceneBuilder& b) {
    for (size_t i = 0; i < meshes.size(); ++i) {
        const ProcessedMesh& pm = meshes[i];
        if (pm.morphTargets.empty()) continue;
        MorphTargets out;
        out.mesh = uint32_t(i);
        out.weights = pm.morphWeights;
        for (const ProcessedMorphTarget& t : pm.morphTargets) {
            MorphTarget target;
            target.name = t.name.empty() ? kNone : b.intern(t.name);
            for (const OwnedStream& d : t.deltas) {
                VertexStream vs = d.desc;
                vs.data = d.bytes;
                target.deltas.push_back(vs);
            }
            out.targets.push_back(std::move(target));
        }
        b.scene.morphTargets.push_back(std::move(out));
    }
}

// SKIN: each skin with the nodes it deforms (those that still draw a mesh), ANIM: each clip,
// less the weights channels of nodes whose mesh lost its morph targets (dropped with it).
void appendSkinsAndAnimations(const IrScene& scene, const std::vector<ProcessedMesh>& meshes,
                              SceneBuilder& b, ConvertSummary& sum) {
    for (size_t k = 0; k < scene.skins.size(); ++k) {
        const IrSkin& src = scene.skins[k];
        Skin skin;
        skin.name = src.name.empty() ? kNone : b.intern(src.name);
        for (int j : src.joints) skin.joints.push_back(uint32_t(j));
        skin.inverseBindMatrices = src.inverseBindMatrices;
        for (size_t n = 0; n < scene.nodes.size(); ++n)
            if (scene.nodes[n].skin == int(k) && scene.nodes[n].mesh >= 0) skin.nodes.push_back(uint32_t(n));
        if (skin.nodes.empty()) continue;
        b.scene.skins.push_back(std::move(skin));
    }
    for (const IrAnimation& src : scene.animations) {
        Animation clip;
        clip.name = src.name.empty() ? kNone : b.intern(src.name);
        for (const IrAnimationChannel& c : src.channels) {
            if (c.property == AnimatedProperty::Weights) {
                const int mesh = scene.nodes[size_t(c.node)].mesh;
                if (mesh < 0 || meshes[size_t(mesh)].morphTargets.empty()) continue;
            }
            clip.channels.push_back(AnimationChannel{uint32_t(c.node), c.property, c.interpolation,
                                                     c.times, c.values});
        }
        if (clip.channels.empty()) {
            sum.warnings.push_back("animation '" + src.name + "': every channel animated a dropped mesh; dropped");
            continue;
        }
        b.scene.animations.push_back(std::move(clip));
    }
}

void appendLightsAndCameras(const IrScene& scene, const std::vector<bool>& generatedLight,
                            SceneBuilder& b) {
    Scene& out = b.scene;
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const IrLight& l = scene.lights[i];
        out.lights.lights.push_back(Light{b.intern(l.name), l.type, l.color, l.intensity, l.range,
                                          l.innerConeRadians, l.outerConeRadians, l.castsShadows,
                                          generatedLight[i]});
    }
    for (const IrCamera& c : scene.cameras)
        out.cameras.cameras.push_back(Camera{b.intern(c.name), c.projection, c.yfovRadians,
                                             c.aspectRatio, c.znear, c.zfar, c.xmag, c.ymag});
}

void appendNodes(const IrScene& scene, const NodePlacement& placement, SceneBuilder& b,
                 ConvertSummary& sum) {
    Scene& out = b.scene;
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const IrNode& n = scene.nodes[i];
        Node node;
        node.name = b.intern(n.name);
        node.parent = n.parent >= 0 ? uint32_t(n.parent) : kNone;
        node.translation = n.translation;
        node.rotation = n.rotation;
        node.scale = n.scale;
        node.mesh = n.mesh >= 0 ? uint32_t(n.mesh) : kNone;
        node.light = n.light >= 0 ? uint32_t(n.light) : kNone;
        node.camera = n.camera >= 0 ? uint32_t(n.camera) : kNone;
        node.worldBounds = placement.nodeBounds[i];
        node.worldSphere = placement.nodeSpheres[i];
        out.nodes.nodes.push_back(node);
        if (!n.instances.empty() && node.mesh != kNone) {
            out.nodes.instances.push_back(NodeInstances{uint32_t(i), n.instances});
            sum.instances += n.instances.size();
        }
    }
}

} // namespace

Result<bool, ConvertError> assembleContainer(const ConvertSettings& s, const ContainerParts& parts,
                                             SceneBuilder& b, ConvertSummary& sum) {
    appendInfoAndSettings(s, parts.graph.placement.sceneBounds, b);
    if (auto r = appendShaderPrograms(parts.plan, builtinShaderFiles(), b); !r) return r.error();
    appendTextures(parts.textures, parts.materials, b, sum);
    // The environment's textures follow the materials' (whose indices materials already hold).
    if (parts.environment) appendEnvironmentOf(*parts.environment, b, sum);
    appendMaterials(parts.materials, parts.plan, b, sum);
    appendMeshes(s, parts.meshes, parts.materials.defaultMaterial, b, sum);
    appendMorphTargets(parts.meshes, b);
    appendLightsAndCameras(parts.scene, parts.graph.generatedLight, b);
    appendNodes(parts.scene, parts.graph.placement, b, sum);
    appendSkinsAndAnimations(parts.scene, parts.meshes, b, sum);
    for (const PathSpec& p : parts.graph.paths)
        b.scene.cameraPaths.push_back(
            CameraPath{b.intern(p.name), p.interpolation, p.loop, p.keys});
    return true;
}

Result<bool, ConvertError> writeContainer(const ConvertSettings& s, const Scene& out,
                                          const std::vector<RoleFile>& outputs,
                                          ConvertSummary& sum) {
    // The format library re-checks every cross-reference before anything reaches the disk.
    if (Status st = validateScene(out); !isOk(st))
        return ConvertError{ConvertErrorKind::Input,
                            s.input + ": internal consistency check failed: " + st.message};

    WriteOptions wo;
    wo.checksums = s.checksums;
    // Shared by every conversion of the process: a batch compresses the shader sources, which
    // most inputs share, once (compression_memo.h; the bytes written are the same).
    static const auto memo = std::make_shared<CompressionMemo>();
    wo.compressionMemo = memo;
    wo.lock = s.outputLock;
    std::vector<RoleFile> read;
    for (const std::string& d : sum.dependencies)
        read.push_back({d, "a file the conversion read"});
    if (Status st = checkOutputs(read, outputs); !isOk(st)) return outputError(st.message);
    auto writer = Writer::create(s.output, wo);
    if (!writer) return outputError(writer.error().message);
    Status st = writeScene(*writer, out, s.compressBulk ? Compression::Zstd : Compression::None);
    if (isOk(st)) st = writer->commit();
    if (!isOk(st)) return outputError(st.message);
    sum.outputBytes = writer->size();
    return true;
}

void countContainer(const Scene& out, ConvertSummary& sum) {
    sum.meshes = out.meshes.size();
    sum.nodes = out.nodes.nodes.size();
    sum.materials = out.materials.size();
    sum.textures = out.textures.size();
    sum.lights = out.lights.lights.size();
    sum.cameras = out.cameras.cameras.size();
    sum.cameraPaths = out.cameraPaths.size();
    sum.skins = out.skins.size();
    for (const Skin& k : out.skins) sum.joints += k.joints.size();
    sum.clips = out.animations.size();
    for (const Animation& a : out.animations) sum.longestClipSeconds = std::max(sum.longestClipSeconds, clipDuration(a));
    sum.morphedMeshes = out.morphTargets.size();
}

} // namespace pnb::converter::convert_detail
