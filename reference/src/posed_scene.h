// posed_scene.h — where everything is at the instant a tracer traces (pnb_reference/frame_pose.h):
// the one place every tracer of pnb_reference takes its node placement and vertex positions
// from, so that the shadow, translucency, local-light, indirect, sky and whole-frame truths of a
// frame all see the same posed geometry, posed exactly as pnb/animation_pose.h poses it for the
// player. Internal to pnb_reference.
//
// At the default FramePose (the container as stored) this is what the tracers did before issue
// 42: world matrices from the node graph as stored, every copy of a mesh placed by
// meshInstances, positions decoded from the Position stream (decodeStream, once per mesh).
// Animated: the pose's node graph (pnb::poseAt's, at the frame's clip time), and every deformed
// node (a skin or morph targets, pnb::isDeformed) drawn from its own deformVertices, placed by
// pnb::drawingMatrix (its world translation alone for a skinned node).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "pnb/animation_pose.h"
#include "pnb/node_transform.h"
#include "pnb/scene.h"
#include "pnb_reference/frame_pose.h"
#include "pnb_reference/shadow_tracer.h"

namespace pnb::reference::detail {

class PosedScene {
public:
    // Errors: Input (a clip index past the container's clips, a non-finite clip time).
    // `scene` must outlive the PosedScene.
    static TracerResult<PosedScene> make(const Scene& scene, const FramePose& at);

    // Every node's world matrix in the pose.
    const std::vector<Matrix4d>& world() const { return mWorld; }
    // Every drawn copy of every mesh, in meshInstances' order; `world` is where its positions()
    // are placed from (the drawing matrix of a deformed node).
    const std::vector<MeshInstance>& instances() const { return mInstances; }

    // Whether node `node` is drawn from deformed vertices (animated poses only).
    bool deforms(uint32_t node) const;

    // The positions node `node`'s mesh is drawn from (w unused): the mesh's decoded Position
    // stream, shared by its undeformed copies, or the node's deformed positions. Valid while this
    // PosedScene lives. Precondition: the node's mesh index is in range. Errors: decodeStream's;
    // Input for a deformed mesh whose Position stream is not F32 (FORMAT.md requires it).
    TracerResult<std::span<const glm::dvec4>> positions(uint32_t node);

    // The deformed vertices of node `node` (its normals and tangents, in the space of its
    // positions), or null for a node drawn as stored. Computed once, with positions().
    const DeformedVertices* deformed(uint32_t node) const;

private:
    struct Deformed {
        DeformedVertices vertices;
        std::vector<glm::dvec4> positions;
    };
    PosedScene() = default;

    const Scene* mScene = nullptr;
    bool mAnimated = false;
    Pose mPose;
    std::vector<Matrix4d> mWorld;
    std::vector<MeshInstance> mInstances;
    std::vector<std::unique_ptr<std::vector<glm::dvec4>>> mDecoded; // per mesh, on first use
    std::vector<std::unique_ptr<Deformed>> mDeformed;               // per node, on first use
};

} // namespace pnb::reference::detail
