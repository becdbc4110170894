// The scene's animation at load (scene_upload.h setUpAnimation; scene_animation.h says what it
// holds): copied out of the mapping, a posed mesh per deformed node, the deform bounds.
#include <cstring>

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_allocation.h"
#include "load/place_item.h"
#include "load/scene_upload.h"
#include "load/upload.h"
#include "shared/deform_params.h" // PNB_DEFORM_ABSENT

namespace pnb::player {

namespace {

bool movesNodes(const Animation& clip) {
    for (const AnimationChannel& c : clip.channels)
        if (c.property != AnimatedProperty::Weights) return true;
    return false;
}

// One target's deltas for the deform pass: [attribute][vertex] x 3 floats, the mesh's position,
// normal (if it has normals) and tangent (if it has tangents) in that order, zero where the
// target moves an attribute not.
void appendTargetDeltas(const MorphTarget& target, uint32_t vertexCount, bool normals, bool tangents,
                        std::vector<float>& out) {
    const VertexSemantic order[] = {VertexSemantic::Position, VertexSemantic::Normal, VertexSemantic::Tangent};
    for (VertexSemantic s : order) {
        if ((s == VertexSemantic::Normal && !normals) || (s == VertexSemantic::Tangent && !tangents)) continue;
        const size_t at = out.size();
        out.resize(at + size_t(vertexCount) * 3, 0.0f);
        for (const VertexStream& d : target.deltas)
            if (d.semantic == s && d.data.size() >= size_t(vertexCount) * 12)
                std::memcpy(out.data() + at, d.data.data(), size_t(vertexCount) * 12);
    }
}

} // namespace

PlayResult<Done> setUpAnimation(const Scene& scene, const std::vector<uint32_t>& itemCopy, GpuScene& gpu) {
    bool deforms = false;
    for (uint32_t n = 0; n < scene.nodes.nodes.size() && !deforms; ++n) deforms = isDeformed(scene, n);
    if (scene.animations.empty() && !deforms) return Done{};
    auto a = std::make_unique<SceneAnimation>();
    a->scene.nodes = scene.nodes;
    a->scene.skins = scene.skins;
    a->scene.animations = scene.animations;
    for (const MorphTargets& t : scene.morphTargets) {
        MorphTargets kept;
        kept.mesh = t.mesh;
        kept.weights = t.weights;
        kept.targets.resize(t.targets.size()); // counts only: the deltas live on the GPU
        a->scene.morphTargets.push_back(std::move(kept));
    }
    for (Node& n : a->scene.nodes.nodes) n.name = kNone; // the string table stays behind
    for (Skin& s : a->scene.skins) s.name = kNone;
    for (Animation& clip : a->scene.animations) {
        a->clipNames.emplace_back(scene.str(clip.name));
        clip.name = kNone;
        a->clipDurations.push_back(clipDuration(clip));
        a->clipMovesNodes.push_back(movesNodes(clip));
    }
    a->restWorld = nodeWorldMatrices(scene.nodes);
    a->itemCopy = itemCopy;
    for (uint32_t n = 0; n < scene.nodes.nodes.size(); ++n) {
        if (scene.nodes.nodes[n].light != kNone) a->lightNodes.push_back(n);
        if (scene.nodes.nodes[n].camera != kNone) a->cameraNodes.push_back(n);
    }

    // A posed mesh per deformed node; its items draw it.
    std::vector<std::vector<uint32_t>> itemsOf(scene.nodes.nodes.size());
    for (uint32_t i = 0; i < gpu.items.size(); ++i) itemsOf[gpu.items[i].node].push_back(i);
    for (uint32_t n = 0; n < scene.nodes.nodes.size(); ++n) {
        if (!isDeformed(scene, n)) continue;
        const uint32_t meshIndex = scene.nodes.nodes[n].mesh;
        const Mesh& mesh = scene.meshes[meshIndex];
        DeformedNode d;
        d.node = n;
        d.sourceMesh = meshIndex;
        d.posedMesh = uint32_t(gpu.meshes.size());
        auto posed = createPosedMesh(mesh, gpu.meshes[meshIndex], d, d.posedMesh);
        if (!posed) return posed.error();
        if (const Skin* skin = skinOf(scene, n); skin && d.joints != PNB_DEFORM_ABSENT && d.weights != PNB_DEFORM_ABSENT) {
            d.skin = uint32_t(skin - scene.skins.data());
            d.jointCount = uint32_t(skin->joints.size());
            d.jointBase = a->frameFloats;
            a->frameFloats += 16 * d.jointCount;
        }
        if (const MorphTargets* targets = morphTargetsOf(scene, meshIndex)) {
            const bool normals = d.normal != PNB_DEFORM_ABSENT, tangents = d.tangent != PNB_DEFORM_ABSENT;
            d.targetCount = uint32_t(targets->targets.size());
            d.morphAttributes = 1 + (normals ? 1 : 0) + (tangents ? 1 : 0);
            d.weightBase = a->frameFloats;
            a->frameFloats += d.targetCount;
            std::vector<float> deltas;
            deltas.reserve(size_t(d.targetCount) * d.morphAttributes * mesh.vertexCount * 3);
            for (const MorphTarget& t : targets->targets) appendTargetDeltas(t, mesh.vertexCount, normals, tangents, deltas);
            d.morphDeltas = createBuffer();
            glNamedBufferStorage(d.morphDeltas.id(), GLsizeiptr(std::max<size_t>(deltas.size() * 4, 16)),
                                 deltas.empty() ? nullptr : deltas.data(), 0);
            posed->bytes += deltas.size() * 4;
        }
        d.bounds = deformBounds(scene, n);
        d.bindBounds = mesh.bounds;
        const glm::dmat4 drawing = glm::make_mat4(drawingMatrix(scene, n, a->restWorld).data());
        d.items = std::move(itemsOf[n]);
        for (uint32_t i : d.items) {
            gpu.items[i].mesh = d.posedMesh;
            placeItem(gpu.items[i], drawing, d.bindBounds);
        }
        gpu.memory.meshBytes += posed->bytes;
        gpu.meshes.push_back(std::move(*posed));
        a->deformed.push_back(std::move(d));
    }
    if (auto ok = checkGlAllocation("the posed meshes of the deformed nodes", gpu.memory.meshBytes); !ok)
        return ok.error();
    gpu.animation = std::move(a);
    return Done{};
}

} // namespace pnb::player
