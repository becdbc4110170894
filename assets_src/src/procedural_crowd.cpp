// crowd: N skinned walkers in an open-roofed room (see procedural_scenes.h), the scene of the
// animated-characters benchmark (scripts/bench-anim).
//
// Size matters at N = 1000, so everything shareable is shared: one walker mesh (one primitive),
// one bind pose (one inverse-bind-matrix accessor, the writer stores identical data once), and
// the walk cycle's joint rotations as kPhaseBuckets x 12 samplers that every walker's joint
// channels point into. What each walker owns: its 13 nodes, its skin (the joint list), and its
// root's translation and rotation samplers (its own lane, start and direction).

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "procedural_scenes_internal.h"

namespace pnb::assets {

using namespace procedural_detail;

namespace {

using gltf::Joints4;

// [SECTION] The walker: skeleton and mesh --------------------------------------------------------

// Joints, in skin order. The character stands at the origin facing +Z (its left is +X).
enum Joint : uint16_t {
    kHips,
    kSpine,
    kChest,
    kHead,
    kUpperArmL,
    kForearmL,
    kUpperArmR,
    kForearmR,
    kThighL,
    kShinL,
    kThighR,
    kShinR,
    kJointCount
};

struct JointSpec {
    const char* name;
    int parent; // joint index, or -1 for the skeleton root (child of the walker's root node)
    Float3 bindPosition; // model space, bind pose (every bind rotation is the identity)
};

constexpr JointSpec kJoints[kJointCount] = {
    {"hips", -1, {0, 0.95f, 0}},
    {"spine", kHips, {0, 1.10f, 0}},
    {"chest", kSpine, {0, 1.30f, 0}},
    {"head", kChest, {0, 1.52f, 0}},
    {"upper-arm-L", kChest, {0.20f, 1.45f, 0}},
    {"forearm-L", kUpperArmL, {0.24f, 1.17f, 0}},
    {"upper-arm-R", kChest, {-0.20f, 1.45f, 0}},
    {"forearm-R", kUpperArmR, {-0.24f, 1.17f, 0}},
    {"thigh-L", kHips, {0.10f, 0.92f, 0}},
    {"shin-L", kThighL, {0.10f, 0.50f, 0}},
    {"thigh-R", kHips, {-0.10f, 0.92f, 0}},
    {"shin-R", kThighR, {-0.10f, 0.50f, 0}},
};

// One ring of a tube: its centre, half-extents across (along the ring frame's U and V axes) and
// its skin weights: joint a with 1 - wb, joint b with wb.
struct Ring {
    Float3 centre;
    float ru, rv;
    uint16_t a, b;
    float wb;
};

constexpr uint32_t kSides = 10;

Joints4 jointsOf(const Ring& r) {
    if (r.wb <= 0.0f || r.a == r.b) return {r.a, 0, 0, 0};
    if (r.wb >= 1.0f) return {r.b, 0, 0, 0};
    return {r.a, r.b, 0, 0};
}
Float4 weightsOf(const Ring& r) {
    if (r.wb <= 0.0f || r.a == r.b) return {1, 0, 0, 0};
    if (r.wb >= 1.0f) return {1, 0, 0, 0};
    return {1.0f - r.wb, r.wb, 0, 0};
}

// Appends a closed tube through `rings` (at least two): kSides-gon rings joined by quads, a
// flat cap at each end; normals radial on the sides (the ellipse's normal) and axial on the caps.
void addTube(Primitive& p, const std::vector<Ring>& rings) {
    const Float3 axis = normalize(rings.back().centre - rings.front().centre);
    const Float3 ref = std::fabs(axis[2]) < 0.9f ? Float3{0, 0, 1} : Float3{1, 0, 0};
    const Float3 u = normalize(cross(ref, axis)), v = cross(axis, u);
    auto push = [&](Float3 pos, Float3 n, const Ring& r) {
        p.positions.push_back(pos);
        p.normals.push_back(normalize(n));
        p.joints0.push_back(jointsOf(r));
        p.weights0.push_back(weightsOf(r));
    };
    const auto sidesBase = uint32_t(p.positions.size());
    for (const Ring& r : rings)
        for (uint32_t i = 0; i < kSides; ++i) {
            const float t = 2 * kPi * float(i) / float(kSides), c = std::cos(t), s = std::sin(t);
            push(r.centre + u * (c * r.ru) + v * (s * r.rv), u * (c / r.ru) + v * (s / r.rv), r);
        }
    for (uint32_t k = 0; k + 1 < rings.size(); ++k)
        for (uint32_t i = 0; i < kSides; ++i) {
            const uint32_t a = sidesBase + k * kSides + i,
                           b = sidesBase + k * kSides + (i + 1) % kSides;
            const uint32_t c = b + kSides, d = a + kSides;
            p.indices.insert(p.indices.end(), {a, b, c, a, c, d});
        }
    // Caps: a centre vertex and the ring again with the cap's normal.
    for (bool top : {false, true}) {
        const Ring& r = top ? rings.back() : rings.front();
        const Float3 n = top ? axis : axis * -1.0f;
        const auto centre = uint32_t(p.positions.size());
        push(r.centre, n, r);
        for (uint32_t i = 0; i < kSides; ++i) {
            const float t = 2 * kPi * float(i) / float(kSides), c = std::cos(t), s = std::sin(t);
            push(r.centre + u * (c * r.ru) + v * (s * r.rv), n, r);
        }
        for (uint32_t i = 0; i < kSides; ++i) {
            const uint32_t a = centre + 1 + i, b = centre + 1 + (i + 1) % kSides;
            if (top)
                p.indices.insert(p.indices.end(), {centre, a, b});
            else
                p.indices.insert(p.indices.end(), {centre, b, a});
        }
    }
}

// The walker: one primitive of welded tubes (torso, head, arms, legs, feet), every vertex
// weighted over one or two joints, the weights smooth across each joint.
Mesh walkerMesh(uint32_t material) {
    Mesh m;
    m.name = "walker";
    m.primitives.resize(1);
    Primitive& p = m.primitives[0];
    p.material = material;
    // Torso: hips -> spine -> chest, an ellipse wider than deep; the rings' joints blend across
    // the spine (1.10) and the chest (1.30).
    std::vector<Ring> torso;
    for (float y : {0.84f, 0.92f, 1.02f, 1.10f, 1.18f, 1.26f, 1.34f, 1.42f, 1.50f}) {
        auto step = [](float x, float lo, float hi) {
            x = std::clamp((x - lo) / (hi - lo), 0.0f, 1.0f);
            return x * x * (3 - 2 * x);
        };
        const float half = 0.08f;
        const float toSpine = step(y, 1.10f - half, 1.10f + half);
        const float toChest = step(y, 1.30f - half, 1.30f + half);
        const float width = y < 1.0f ? 0.17f : y < 1.2f ? 0.15f : 0.19f;
        Ring r{{0, y, 0}, width, width * 0.62f, kHips, kSpine, toSpine};
        if (toChest > 0) r = {{0, y, 0}, width, width * 0.62f, kSpine, kChest, toChest};
        torso.push_back(r);
    }
    addTube(p, torso);
    // Head and neck: the neck blends chest into head; the skull is all head.
    addTube(p, {{{0, 1.48f, 0}, 0.05f, 0.05f, kChest, kHead, 0.3f},
                {{0, 1.55f, 0}, 0.055f, 0.055f, kChest, kHead, 0.9f},
                {{0, 1.60f, 0}, 0.085f, 0.095f, kHead, kHead, 0},
                {{0, 1.68f, 0}, 0.105f, 0.115f, kHead, kHead, 0},
                {{0, 1.77f, 0}, 0.095f, 0.105f, kHead, kHead, 0},
                {{0, 1.83f, 0}, 0.05f, 0.055f, kHead, kHead, 0}});
    for (int side : {1, -1}) {
        const float sx = float(side);
        const uint16_t upperArm = side > 0 ? kUpperArmL : kUpperArmR;
        const uint16_t forearm = side > 0 ? kForearmL : kForearmR;
        const uint16_t thigh = side > 0 ? kThighL : kThighR;
        const uint16_t shin = side > 0 ? kShinL : kShinR;
        // Arm: shoulder (blending out of the chest) -> elbow -> wrist -> hand.
        const Float3 sh{0.19f * sx, 1.47f, 0}, el{0.24f * sx, 1.17f, 0}, wr{0.27f * sx, 0.92f, 0};
        addTube(p, {{sh, 0.052f, 0.052f, kChest, upperArm, 0.5f},
                    {lerp(sh, el, 0.2f), 0.05f, 0.05f, upperArm, upperArm, 0},
                    {lerp(sh, el, 0.75f), 0.045f, 0.045f, upperArm, forearm, 0.15f},
                    {el, 0.042f, 0.042f, upperArm, forearm, 0.5f},
                    {lerp(el, wr, 0.25f), 0.04f, 0.04f, upperArm, forearm, 0.85f},
                    {lerp(el, wr, 0.7f), 0.036f, 0.036f, forearm, forearm, 0},
                    {wr, 0.03f, 0.03f, forearm, forearm, 0},
                    {{0.28f * sx, 0.80f, 0}, 0.032f, 0.032f, forearm, forearm, 0}});
        // Leg: hip (blending out of the hips) -> knee -> ankle.
        const Float3 hp{0.10f * sx, 0.94f, 0}, kn{0.10f * sx, 0.50f, 0}, an{0.10f * sx, 0.07f, 0};
        addTube(p, {{hp, 0.085f, 0.085f, kHips, thigh, 0.5f},
                    {lerp(hp, kn, 0.15f), 0.08f, 0.08f, kHips, thigh, 0.9f},
                    {lerp(hp, kn, 0.5f), 0.068f, 0.068f, thigh, thigh, 0},
                    {lerp(hp, kn, 0.85f), 0.06f, 0.06f, thigh, shin, 0.15f},
                    {kn, 0.056f, 0.056f, thigh, shin, 0.5f},
                    {lerp(kn, an, 0.15f), 0.055f, 0.055f, thigh, shin, 0.85f},
                    {lerp(kn, an, 0.5f), 0.05f, 0.05f, shin, shin, 0},
                    {an, 0.042f, 0.042f, shin, shin, 0}});
        // Foot: heel to toe along +Z, all shin.
        addTube(p, {{{0.10f * sx, 0.045f, -0.05f}, 0.045f, 0.04f, shin, shin, 0},
                    {{0.10f * sx, 0.045f, 0.06f}, 0.05f, 0.04f, shin, shin, 0},
                    {{0.10f * sx, 0.04f, 0.17f}, 0.04f, 0.03f, shin, shin, 0}});
    }
    return m;
}

// [SECTION] The walk cycle -----------------------------------------------------------------------

constexpr float kCycleSeconds = 1.0f; // one stride pair
constexpr float kClipSeconds = 24.0f; // one lap of every lane
constexpr uint32_t kCycleKeys = 8;    // joint keys per cycle (linear)
constexpr uint32_t kPathKeys = 48;    // root keys per lap (linear; 7.5 degrees of arc each)
constexpr uint32_t kPhaseBuckets = 8; // distinct walk phases (each its own joint samplers)

Float4 aroundX(float a) {
    return gltf::rotationAxis({1, 0, 0}, a);
}
Float4 aroundY(float a) {
    return gltf::rotationAxis({0, 1, 0}, a);
}
Float4 aroundZ(float a) {
    return gltf::rotationAxis({0, 0, 1}, a);
}

// Joint `j`'s local rotation at walk phase `phi` (radians, 2 pi a cycle). Legs swing in
// antiphase, arms against the legs, knees bend on the back swing, the shoulders counter-twist
// the hips.
Float4 walkRotation(uint32_t j, float phi) {
    const float s = std::sin(phi);
    auto knee = [](float ph) { return 0.12f + 0.55f * (0.5f - 0.5f * std::cos(ph + 0.6f)); };
    auto elbow = [](float ph) { return -(0.25f + 0.15f * (0.5f + 0.5f * std::sin(ph))); };
    switch (j) {
    case kHips:
        return gltf::multiply(aroundY(0.08f * s), aroundZ(0.04f * std::sin(phi + 0.5f)));
    case kSpine:
        return aroundY(-0.04f * s);
    case kChest:
        return aroundY(-0.08f * s);
    case kHead:
        return gltf::multiply(aroundY(0.1f * s), aroundX(0.03f * std::sin(2 * phi)));
    case kUpperArmL:
        return aroundX(0.35f * s);
    case kForearmL:
        return aroundX(elbow(phi));
    case kUpperArmR:
        return aroundX(-0.35f * s);
    case kForearmR:
        return aroundX(elbow(phi + kPi));
    case kThighL:
        return aroundX(-0.45f * s);
    case kShinL:
        return aroundX(knee(phi));
    case kThighR:
        return aroundX(0.45f * s);
    case kShinR:
        return aroundX(knee(phi + kPi));
    default:
        return {0, 0, 0, 1};
    }
}

void pushQuat(std::vector<float>& out, Float4 q) {
    // Keep consecutive keys on one hemisphere, so linear interpolation takes the short way.
    if (out.size() >= 4) {
        const float* prev = &out[out.size() - 4];
        if (prev[0] * q[0] + prev[1] * q[1] + prev[2] * q[2] + prev[3] * q[3] < 0)
            q = {-q[0], -q[1], -q[2], -q[3]};
    }
    out.insert(out.end(), q.begin(), q.end());
}

std::vector<float> keyTimes(uint32_t keys) {
    std::vector<float> t(keys + 1);
    for (uint32_t k = 0; k <= keys; ++k)
        t[k] = kClipSeconds * float(k) / float(keys);
    return t;
}

// [SECTION] The room ------------------------------------------------------------------------------

constexpr float kHalf = 9.0f; // the room is x, z in [-9, 9]
constexpr float kWallHeight = 3.5f;
constexpr float kFirstLane = 1.5f, kLaneStep = 0.5f;
constexpr uint32_t kLanes = 13; // radii 1.5 .. 7.5 m around the central plinth

// The room (floor, walls, pillars, plinth) and its two lamps, as children of the scene root.
void addRoomAndLamps(Document& doc, std::vector<uint32_t>& children) {
    const uint32_t floorMat =
        addMaterial(doc, makeMaterial("floor-stone", {0.58f, 0.56f, 0.52f}, 0.85f));
    const uint32_t wallMat = addMaterial(doc, makeMaterial("plaster", {0.75f, 0.73f, 0.70f}, 0.9f));
    const uint32_t stone =
        addMaterial(doc, makeMaterial("pillar-stone", {0.55f, 0.55f, 0.58f}, 0.8f));
    // Room: a floor, four 0.3 m walls (no roof: the sun comes in from above), four corner
    // pillars outside the outermost lane and a plinth in the middle that the lanes circle.
    Mesh floorMesh;
    floorMesh.name = "floor";
    floorMesh.primitives.resize(1);
    floorMesh.primitives[0].material = floorMat;
    addGrid(floorMesh.primitives[0], {-kHalf, 0, -kHalf}, {0, 0, 2 * kHalf}, {2 * kHalf, 0, 0}, 8,
            8, false);
    children.push_back(addNode(doc, meshNode("floor", addMesh(doc, std::move(floorMesh)))));
    const float t = 0.3f;
    children.push_back(addNode(
        doc,
        meshNode("walls",
                 addMesh(doc, solidBoxesMesh(
                                  "walls", wallMat,
                                  {{{-kHalf - t, 0, -kHalf - t}, {kHalf + t, kWallHeight, -kHalf}},
                                   {{-kHalf - t, 0, kHalf}, {kHalf + t, kWallHeight, kHalf + t}},
                                   {{-kHalf - t, 0, -kHalf}, {-kHalf, kWallHeight, kHalf}},
                                   {{kHalf, 0, -kHalf}, {kHalf + t, kWallHeight, kHalf}}})))));
    std::vector<Box> pillars;
    for (float x : {-7.0f, 7.0f})
        for (float z : {-7.0f, 7.0f})
            pillars.push_back({{x - 0.3f, 0, z - 0.3f}, {x + 0.3f, kWallHeight, z + 0.3f}});
    pillars.push_back({{-0.8f, 0, -0.8f}, {0.8f, 0.6f, 0.8f}}); // the plinth
    children.push_back(
        addNode(doc, meshNode("pillars", addMesh(doc, solidBoxesMesh("pillars", stone, pillars)))));

    // Two warm point lights under the open roof, either side of the plinth.
    for (int side : {-1, 1}) {
        doc.lights.push_back({.name = side < 0 ? "lamp-west" : "lamp-east",
                              .type = gltf::LightType::Point,
                              .color = {1.0f, 0.86f, 0.68f},
                              .intensity = 14.0f,
                              .range = 9.0f});
        Node n;
        n.name = doc.lights.back().name;
        n.translation = {4.5f * float(side), 3.0f, 0.0f};
        n.light = int32_t(doc.lights.size() - 1);
        children.push_back(addNode(doc, std::move(n)));
    }
}

} // namespace

gltf::Document buildCrowd(const CrowdOptions& options) {
    Document doc;
    doc.sceneName = "crowd";
    const uint32_t count = std::clamp(options.count, 1u, 1000u);
    const uint32_t cloth =
        addMaterial(doc, makeMaterial("walker-cloth", {0.35f, 0.45f, 0.68f}, 0.7f));

    Node root;
    root.name = "crowd";
    const uint32_t rootNode = addNode(doc, std::move(root));
    std::vector<uint32_t> children;

    addRoomAndLamps(doc, children);

    // The walker mesh and the bind pose every skin shares.
    const int32_t walker = addMesh(doc, walkerMesh(cloth));
    std::array<float, 16> ibm[kJointCount];
    for (uint32_t j = 0; j < kJointCount; ++j) {
        const Float3 b = kJoints[j].bindPosition;
        ibm[j] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -b[0], -b[1], -b[2], 1};
    }

    // The clip. A phase's 12 walk-cycle samplers are added when the first walker of that phase
    // is (a small crowd stores only the phases it uses).
    gltf::Animation clip;
    clip.name = "walk";
    const std::vector<float> cycleTimes =
        keyTimes(uint32_t(kClipSeconds / kCycleSeconds) * kCycleKeys);
    const std::vector<float> pathTimes = keyTimes(kPathKeys);
    std::array<int32_t, kPhaseBuckets> phaseSamplers;
    phaseSamplers.fill(-1);
    auto phaseSampler = [&](uint32_t bucket) {
        if (phaseSamplers[bucket] < 0) {
            phaseSamplers[bucket] = int32_t(clip.samplers.size());
            for (uint32_t j = 0; j < kJointCount; ++j) {
                gltf::AnimationSampler s;
                s.input = cycleTimes;
                for (float time : cycleTimes)
                    pushQuat(s.output, walkRotation(j, 2 * kPi *
                                                           (time / kCycleSeconds +
                                                            float(bucket) / float(kPhaseBuckets))));
                clip.samplers.push_back(std::move(s));
            }
        }
        return uint32_t(phaseSamplers[bucket]);
    };

    Pcg32 rng(options.seed, kStreamCrowdWalkers);
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t lane = i % kLanes, slot = i / kLanes;
        const uint32_t inLane = (count - lane + kLanes - 1) / kLanes; // walkers on this lane
        const float radius = kFirstLane + kLaneStep * float(lane);
        const float dir = lane % 2 == 0 ? 1.0f : -1.0f; // neighbouring lanes walk opposite ways
        const float start = 2 * kPi * (float(slot) + rng.uniform(-0.3f, 0.3f)) / float(inLane) +
                            0.37f * float(lane);
        const uint32_t firstJointSampler = phaseSampler(rng.below(kPhaseBuckets));
        const float height = rng.uniform(0.92f, 1.08f);
        const std::string name = "walker-" + std::to_string(i);

        Node rootN;
        rootN.name = name;
        rootN.scale = {height, height, height};
        const uint32_t walkerRoot = addNode(doc, std::move(rootN));
        children.push_back(walkerRoot);
        // Joints: parents before children, so kJoints' parent indices map directly.
        gltf::Skin skin;
        skin.name = name;
        for (uint32_t j = 0; j < kJointCount; ++j) {
            Node jn;
            jn.name = name + "/" + kJoints[j].name;
            const int parent = kJoints[j].parent;
            jn.translation = parent < 0 ? kJoints[j].bindPosition
                                        : kJoints[j].bindPosition - kJoints[parent].bindPosition;
            const uint32_t node = addNode(doc, std::move(jn));
            (parent < 0 ? doc.nodes[walkerRoot] : doc.nodes[skin.joints[size_t(parent)]])
                .children.push_back(node);
            skin.joints.push_back(node);
            skin.inverseBindMatrices.push_back(ibm[j]);
            clip.channels.push_back({firstJointSampler + j, node, gltf::AnimationPath::Rotation});
        }
        skin.skeleton = int32_t(skin.joints[kHips]);
        doc.skins.push_back(std::move(skin));
        Node body = meshNode(name + "/body", walker);
        body.skin = int32_t(doc.skins.size() - 1);
        doc.nodes[walkerRoot].children.push_back(addNode(doc, std::move(body)));

        // The root walks its lane: a circle of `radius` once per clip, facing along it.
        gltf::AnimationSampler move, turn;
        move.input = pathTimes;
        turn.input = pathTimes;
        for (uint32_t k = 0; k <= kPathKeys; ++k) {
            const float a = start + dir * 2 * kPi * float(k) / float(kPathKeys);
            const Float3 at{radius * std::cos(a), 0, radius * std::sin(a)};
            move.output.insert(move.output.end(), at.begin(), at.end());
            // Tangent dir * (-sin a, 0, cos a); the walker faces +Z at rest.
            pushQuat(turn.output, aroundY(std::atan2(-dir * std::sin(a), dir * std::cos(a))));
        }
        // At rest (anim.enabled=false: the frozen baseline) each walker stands at its start.
        doc.nodes[walkerRoot].translation = {move.output[0], move.output[1], move.output[2]};
        clip.samplers.push_back(std::move(move));
        clip.channels.push_back(
            {uint32_t(clip.samplers.size() - 1), walkerRoot, gltf::AnimationPath::Translation});
        doc.nodes[walkerRoot].rotation = {turn.output[0], turn.output[1], turn.output[2],
                                          turn.output[3]};
        clip.samplers.push_back(std::move(turn));
        clip.channels.push_back(
            {uint32_t(clip.samplers.size() - 1), walkerRoot, gltf::AnimationPath::Rotation});
    }
    doc.animations.push_back(std::move(clip));

    // Cameras: over the south wall looking down across the room (the intended view), and one
    // at eye level by the west wall, among the walkers.
    children.push_back(addCamera(doc, "overview-camera", {0.0f, 8.0f, 12.5f},
                                 Float3{0, 0.8f, 0.5f} - Float3{0.0f, 8.0f, 12.5f}, radians(60),
                                 16.0f / 9.0f, 0.1f, 80.0f));
    children.push_back(addCamera(doc, "floor-camera", {-8.5f, 1.7f, 3.0f},
                                 Float3{0, 1.0f, -1.0f} - Float3{-8.5f, 1.7f, 3.0f}, radians(65),
                                 16.0f / 9.0f, 0.05f, 60.0f));
    doc.nodes[rootNode].children = std::move(children);
    addSun(doc, sunDirection(radians(55), radians(30)), {0, 0, 0}, 30.0f, {1.0f, 0.97f, 0.9f},
           3.0f);
    return doc;
}

} // namespace pnb::assets
