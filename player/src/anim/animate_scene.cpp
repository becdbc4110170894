// The CPU half of playback (animate_scene.h): clock -> pose -> items, lights, cameras, and the
// deform pass's joint matrices and morph weights.
#include "anim/animate_scene.h"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <limits>

#include <glm/gtc/type_ptr.hpp>

#include "load/place_item.h"
#include "pnb_lighting/scene_lights.h"

namespace pnb::player {

namespace {

glm::dmat4 toGlm(const Matrix4d& m) { return glm::make_mat4(m.data()); }

} // namespace

std::optional<uint32_t> resolveClip(const SceneAnimation& a, std::string_view setting, bool* known) {
    if (known) *known = true;
    if (setting == "none") return std::nullopt;
    uint32_t index = 0;
    auto [end, ec] = std::from_chars(setting.data(), setting.data() + setting.size(), index);
    if (ec == std::errc() && end == setting.data() + setting.size()) {
        if (index < a.clipNames.size()) return index;
        if (known) *known = index == 0; // "0" in a scene without clips: the default, no clip
        return std::nullopt;
    }
    for (uint32_t i = 0; i < a.clipNames.size(); ++i)
        if (a.clipNames[i] == setting) return i;
    if (known) *known = false;
    return std::nullopt;
}

bool movedWithin(const SceneAnimation* a, const glm::dvec3& min, const glm::dvec3& max) {
    if (!a) return false;
    for (const SceneAnimation::Box& b : a->movedBoxes)
        if (glm::all(glm::lessThanEqual(b.min, max)) && glm::all(glm::lessThanEqual(min, b.max))) return true;
    return false;
}

bool movedNear(const SceneAnimation* a, const glm::dvec3& centre, double radius) {
    if (!a) return false;
    for (const SceneAnimation::Box& b : a->movedBoxes) {
        const glm::dvec3 closest = glm::clamp(centre, b.min, b.max);
        if (!(glm::length(closest - centre) > radius)) return true; // a NaN radius: moved
    }
    return false;
}

AnimationUpdate animateScene(GpuScene& scene, const RenderSettings& s, double clock, AnimationState& state) {
    AnimationUpdate up;
    if (!scene.animation) return up;
    SceneAnimation& a = *scene.animation;
    const std::optional<uint32_t> clip = resolveClip(a, s.animClip);
    const double t = s.animTime + (s.animPlay ? double(s.animSpeed) * clock : 0.0);
    PoseKey key{s.animEnabled, s.animEnabled ? clip : std::nullopt, 0.0};
    if (key.clip) key.clipTime = clipTime(a.clipDurations[*key.clip], t);
    state.time = t;
    state.clipTime = key.clipTime;
    a.movedBoxes.clear();
    if (state.posed && *state.posed == key) return up;
    const bool wasEnabled = state.posed ? state.posed->enabled : false;
    state.posed = key;
    up.posed = true;

    Pose pose = key.clip ? poseAt(a.scene, key.clip, t) : restPose(a.scene);
    std::vector<Matrix4d> world = key.clip && a.clipMovesNodes[*key.clip] ? nodeWorldMatrices(pose.graph) : a.restWorld;
    const bool first = state.world.empty();
    std::vector<bool> nodeMoved(world.size(), first);
    if (!first)
        for (size_t n = 0; n < world.size(); ++n) nodeMoved[n] = world[n] != state.world[n];

    std::vector<SceneAnimation::Box> bounds(scene.items.size()); // before this pose
    for (size_t i = 0; i < scene.items.size(); ++i) bounds[i] = {scene.items[i].boundsMin, scene.items[i].boundsMax};

    // Rigid items: re-placed where their node (or an ancestor) moved.
    std::vector<bool> deformedNode(world.size(), false);
    for (const DeformedNode& d : a.deformed) deformedNode[d.node] = true;
    std::vector<MeshInstance> copies;
    bool anyRigidMoved = false;
    for (uint32_t i = 0; i < scene.items.size() && !anyRigidMoved; ++i)
        anyRigidMoved = !deformedNode[scene.items[i].node] && nodeMoved[scene.items[i].node];
    if (anyRigidMoved) copies = meshInstances(pose.graph, world);
    for (uint32_t i = 0; i < scene.items.size(); ++i) {
        DrawItem& item = scene.items[i];
        if (deformedNode[item.node] || !nodeMoved[item.node]) continue;
        const GpuMesh& mesh = scene.meshes[item.mesh];
        placeItem(item, toGlm(copies[a.itemCopy[i]].world), mesh.submeshes[scene.levels[item.firstLevel].submesh].bounds);
        up.movedItems.push_back(i);
    }

    // Deformed nodes: drawn at pnb::drawingMatrix, bounded by pnb::deformedBounds of this pose;
    // their joint matrices and weights for the deform pass.
    state.frameData.assign(a.frameFloats, 0.0f);
    for (const DeformedNode& d : a.deformed) {
        const glm::dmat4 drawing = toGlm(drawingMatrix(a.scene, d.node, world));
        Aabb local = d.bindBounds;
        if (key.enabled) {
            std::vector<std::array<float, 16>> joints;
            if (d.skin != kNone) joints = jointMatrices(a.scene.skins[d.skin], world, d.node);
            for (size_t j = 0; j < joints.size() && j < d.jointCount; ++j)
                std::memcpy(&state.frameData[d.jointBase + 16 * j], joints[j].data(), 64);
            const std::vector<float>& w = pose.weights[d.node];
            for (size_t k = 0; k < w.size() && k < d.targetCount; ++k) state.frameData[d.weightBase + k] = w[k];
            local = deformedBounds(d.bounds, joints, w);
        }
        for (uint32_t i : d.items) {
            placeItem(scene.items[i], drawing, local);
            up.movedItems.push_back(i);
        }
    }
    up.deform = key.enabled && !a.deformed.empty();
    up.restore = !key.enabled && wasEnabled && !a.deformed.empty();

    // Lights and cameras on nodes that moved.
    for (size_t l = 0; l < a.lightNodes.size() && l < scene.lights.size(); ++l) {
        const uint32_t n = a.lightNodes[l];
        if (!nodeMoved[n]) continue;
        const glm::dmat4 w = toGlm(world[n]);
        scene.lights[l].position = glm::dvec3(w[3]);
        scene.lights[l].direction = glm::vec3(lighting::lightTravel(w));
        up.lightsMoved = true;
    }
    for (size_t c = 0; c < a.cameraNodes.size() && c < scene.cameras.size(); ++c) {
        const uint32_t n = a.cameraNodes[c];
        if (!nodeMoved[n]) continue;
        const glm::dmat4 w = toGlm(world[n]);
        scene.cameras[c].position = glm::dvec3(w[3]);
        glm::dmat3 r(w);
        for (int k = 0; k < 3; ++k) r[k] = glm::normalize(r[k]);
        scene.cameras[c].rotation = glm::normalize(glm::quat_cast(r));
    }
    std::sort(up.movedItems.begin(), up.movedItems.end());
    up.movedItems.erase(std::unique(up.movedItems.begin(), up.movedItems.end()), up.movedItems.end());
    for (uint32_t i : up.movedItems) {
        const DrawItem& item = scene.items[i];
        const auto& [before, after] = std::pair(bounds[i], SceneAnimation::Box{item.boundsMin, item.boundsMax});
        a.movedBoxes.push_back({glm::min(before.min, after.min), glm::max(before.max, after.max)});
    }
    if (!up.movedItems.empty()) ++a.poseVersion;
    state.world = std::move(world);
    return up;
}

} // namespace pnb::player
