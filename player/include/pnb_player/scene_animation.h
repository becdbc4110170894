// pnb_player/scene_animation.h — what a loaded scene needs to play its clips (docs/PLAYER.md
// "Animation"): the node graph, skins, clips and morph weights (copied out of the mapping), and
// per deformed node (pnb::isDeformed) its posed mesh: a buffer the deform pass writes each frame
// with the posed F32 position/normal/tangent streams, and a vertex array that reads those from it
// and the UVs, colours and indices from the container's mesh. The node's draw items draw the
// posed mesh, so every pass sees the animated geometry with no shader variant of its own.
//
// A scene with neither clips nor deformed nodes has none of this (GpuScene::animation is null):
// no posed buffer, no deform program, no pass.
//
// Does NOT do: sample clips (pnb/animation_pose.h does, in renderer/animate_scene.cpp), dispatch
// the deform pass (anim/pass_deform.cpp).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "pnb/animation_pose.h"
#include "pnb/scene.h"
#include "pnb_player/gl_handles.h"

namespace pnb::player {

// One deformed node: where its streams are, in 32-bit words (PNB_DEFORM_ABSENT: none), and
// where its joint matrices and morph weights go in the frame's deform buffer (floats).
struct DeformedNode {
    uint32_t node = 0, sourceMesh = 0, posedMesh = 0; // container node and mesh; GpuScene::meshes index
    uint32_t vertexCount = 0;
    std::vector<uint32_t> items; // its draw items (GpuScene::items), re-placed with every pose
    uint32_t position = 0, normal = 0, tangent = 0, joints = 0, weights = 0; // in the source buffer
    bool jointsU16 = false;
    uint32_t posedNormal = 0, posedTangent = 0; // in the posed buffer (positions at 0)
    uint32_t skin = 0xFFFFFFFFu;                // index into SceneAnimation::scene.skins, or none
    uint32_t jointCount = 0, jointBase = 0;     // matrices (16 floats each) from jointBase
    uint32_t targetCount = 0, weightBase = 0, morphAttributes = 0;
    GlHandle morphDeltas; // [target][attribute: position, normal?, tangent?][vertex] x 3 floats
    uint64_t posedBytes = 0;
    DeformBounds bounds;  // pnb::deformBounds, once at load
    Aabb bindBounds;      // the stored vertices' box (drawn when anim.enabled = false)
};

struct SceneAnimation {
    // The animation's part of the container: nodes, skins, clips, morph targets (their default
    // weights and target counts; no delta data): what pnb::poseAt and jointMatrices read.
    Scene scene;
    std::vector<std::string> clipNames;
    std::vector<double> clipDurations;
    std::vector<bool> clipMovesNodes; // per clip: animates some translation/rotation/scale
    std::vector<Matrix4d> restWorld;  // nodeWorldMatrices at rest
    std::vector<DeformedNode> deformed;
    std::vector<uint32_t> itemCopy;   // per draw item: its index in meshInstances() order
    std::vector<uint32_t> lightNodes, cameraNodes; // per GpuScene light / camera: its node
    uint32_t frameFloats = 0;         // the deform buffer's size: every node's joints and weights
    std::optional<uint32_t> deformProgram; // PROG "deform" (compiled when a node deforms)

    // This frame's motion, for the caches that assume still geometry (local-shadow tiles, GI's
    // occupancy grid and probes, the sky's height map): the world boxes the moved items swept
    // (their bounds before and after, united), empty when the pose did not change; and a count
    // of the pose changes that moved some item.
    struct Box {
        glm::dvec3 min, max;
    };
    std::vector<Box> movedBoxes;
    uint64_t poseVersion = 0;
};

// Whether an item that moved this frame swept through the box [min, max], or within `radius` of
// `centre` (a light's reach); false for a scene without animation.
bool movedWithin(const SceneAnimation* a, const glm::dvec3& min, const glm::dvec3& max);
bool movedNear(const SceneAnimation* a, const glm::dvec3& centre, double radius);

// The clip `setting` (anim.clip: an index, a clip's name, or "none") names in `a`: nullopt for
// "none", for a scene without clips, or for an index or name that matches none (`known` false).
std::optional<uint32_t> resolveClip(const SceneAnimation& a, std::string_view setting, bool* known = nullptr);

} // namespace pnb::player
