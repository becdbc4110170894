// The scene posed at the traced instant (posed_scene.h).
#include "posed_scene.h"

#include <cmath>
#include <string>

#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "mesh_decode.h"

namespace pnb::reference::detail {

TracerResult<PosedScene> PosedScene::make(const Scene& scene, const FramePose& at) {
    PosedScene out;
    out.mScene = &scene;
    out.mAnimated = at.animated;
    if (at.animated) {
        if (at.clip && *at.clip >= scene.animations.size())
            return TracerError{TracerErrorKind::Input, "clip " + std::to_string(*at.clip) + " does not exist: the scene has " +
                                                           std::to_string(scene.animations.size()) + " clip(s) (ANIM)"};
        if (!std::isfinite(at.clipTime))
            return TracerError{TracerErrorKind::Input, "the clip time must be finite"};
        // The time as the player sampled it (already looped): applied as is, not looped again.
        out.mPose = restPose(scene);
        if (at.clip) applyClip(scene, scene.animations[*at.clip], at.clipTime, out.mPose);
        out.mWorld = nodeWorldMatrices(out.mPose.graph);
        out.mInstances = meshInstances(out.mPose.graph, out.mWorld);
        for (MeshInstance& copy : out.mInstances) {
            if (!out.deforms(copy.node)) continue;
            // A deformed node's vertices are in its drawing space; an instanced copy keeps its
            // own transform relative to the node.
            const Matrix4d drawing = drawingMatrix(scene, copy.node, out.mWorld);
            if (copy.world == out.mWorld[copy.node]) {
                copy.world = drawing;
            } else {
                const glm::dmat4 local = glm::inverse(glm::make_mat4(out.mWorld[copy.node].data())) *
                                         glm::make_mat4(copy.world.data());
                const glm::dmat4 placed = glm::make_mat4(drawing.data()) * local;
                for (int i = 0; i < 16; ++i) copy.world[size_t(i)] = glm::value_ptr(placed)[i];
            }
        }
    } else {
        out.mWorld = nodeWorldMatrices(scene.nodes);
        out.mInstances = meshInstances(scene.nodes, out.mWorld);
    }
    out.mDecoded.resize(scene.meshes.size());
    out.mDeformed.resize(scene.nodes.nodes.size());
    return out;
}

} // namespace pnb::reference::detail

namespace pnb::reference {

FramePose effectivePose(const Scene& scene, const FramePose& at) {
    // Without a skin or morph target, the rest pose is the container as stored.
    const bool deforms = !scene.skins.empty() || !scene.morphTargets.empty();
    if (!at.animated || (!deforms && !at.clip)) return FramePose{};
    FramePose out = at;
    if (!out.clip) out.clipTime = 0;
    return out;
}

} // namespace pnb::reference

namespace pnb::reference::detail {

bool PosedScene::deforms(uint32_t node) const {
    return mAnimated && node < mScene->nodes.nodes.size() && isDeformed(*mScene, node);
}

TracerResult<std::span<const glm::dvec4>> PosedScene::positions(uint32_t node) {
    const uint32_t mesh = mScene->nodes.nodes[node].mesh;
    if (!deforms(node)) {
        if (!mDecoded[mesh]) {
            auto p = decodeStream(*mScene, mesh, VertexSemantic::Position, true);
            if (!p) return p.error();
            mDecoded[mesh] = std::make_unique<std::vector<glm::dvec4>>(std::move(*p));
        }
        return std::span<const glm::dvec4>(*mDecoded[mesh]);
    }
    if (!mDeformed[node]) {
        auto d = std::make_unique<Deformed>();
        d->vertices = deformVertices(*mScene, node, mPose, mWorld);
        if (d->vertices.positions.size() != fullDetailMesh(*mScene, mesh).vertexCount)
            return TracerError{TracerErrorKind::Input,
                               meshName(*mScene, mesh) + " is deformed (" + nodeName(*mScene, node) +
                                   ") but its positions are not F32 x 3 (FORMAT.md: a deformed mesh's are)"};
        d->positions.reserve(d->vertices.positions.size());
        for (const Vec3& p : d->vertices.positions) d->positions.emplace_back(p.x, p.y, p.z, 1.0);
        mDeformed[node] = std::move(d);
    }
    return std::span<const glm::dvec4>(mDeformed[node]->positions);
}

const DeformedVertices* PosedScene::deformed(uint32_t node) const {
    return node < mDeformed.size() && mDeformed[node] ? &mDeformed[node]->vertices : nullptr;
}

} // namespace pnb::reference::detail
