// moving-light: a room whose light, one box and one ball move (see procedural_scenes.h), the
// scene of the moving-lights benchmark (scripts/bench-anim): GI and shadows judged along an
// animated clip against the same frames frozen.

#include <cmath>
#include <string>
#include <vector>

#include "procedural_scenes_internal.h"

namespace pnb::assets {

using namespace procedural_detail;

namespace {

constexpr float kClipSeconds = 4.0f;

// A UV sphere of `radius` (rings x segments), with one morph target that squashes it into an
// ellipsoid half as tall and 1.3 times as wide, resting on the same floor point (the deltas
// move every vertex to (1.3 x, 0.5 (y + r) - r, 1.3 z) from the centre, normals to the
// ellipsoid's).
Mesh squashBall(uint32_t material, float radius, uint32_t rings, uint32_t segments) {
    Mesh m;
    m.name = "morph-ball";
    m.weights = {0.0f};
    m.primitives.resize(1);
    Primitive& p = m.primitives[0];
    p.material = material;
    gltf::MorphTarget squash;
    const float sx = 1.3f, sy = 0.5f;
    for (uint32_t r = 0; r <= rings; ++r) {
        const float theta = kPi * float(r) / float(rings); // from the top
        for (uint32_t s = 0; s <= segments; ++s) {
            const float phi = 2 * kPi * float(s) / float(segments);
            const Float3 n{std::sin(theta) * std::cos(phi), std::cos(theta),
                           -std::sin(theta) * std::sin(phi)};
            const Float3 pos = n * radius;
            p.positions.push_back(pos);
            p.normals.push_back(n);
            const Float3 squashed{pos[0] * sx, sy * (pos[1] + radius) - radius, pos[2] * sx};
            squash.positionDeltas.push_back(squashed - pos);
            // The ellipsoid's normal: the gradient (x / sx^2, y / sy^2, z / sx^2), normalised.
            const Float3 en = normalize({n[0] / sx, n[1] / sy, n[2] / sx});
            squash.normalDeltas.push_back(en - n);
        }
    }
    for (uint32_t r = 0; r < rings; ++r)
        for (uint32_t s = 0; s < segments; ++s) {
            const uint32_t a = r * (segments + 1) + s, b = a + 1, c = a + segments + 1, d = c + 1;
            // Counter-clockwise seen from outside: down the ring (c) then along it (d).
            if (r != 0) p.indices.insert(p.indices.end(), {a, c, b});
            if (r + 1 != rings) p.indices.insert(p.indices.end(), {b, c, d});
        }
    p.targets.push_back(std::move(squash));
    return m;
}

} // namespace

gltf::Document buildMovingLight() {
    Document doc;
    doc.sceneName = "moving-light";
    const uint32_t white =
        addMaterial(doc, makeMaterial("white-wall", {0.73f, 0.73f, 0.73f}, 0.8f));
    const uint32_t red = addMaterial(doc, makeMaterial("red-wall", {0.63f, 0.065f, 0.05f}, 0.8f));
    const uint32_t green =
        addMaterial(doc, makeMaterial("green-wall", {0.14f, 0.45f, 0.091f}, 0.8f));
    const uint32_t orange =
        addMaterial(doc, makeMaterial("moving-box", {0.80f, 0.45f, 0.15f}, 0.6f));
    const uint32_t blue = addMaterial(doc, makeMaterial("morph-ball", {0.25f, 0.40f, 0.80f}, 0.5f));

    // An 8 x 4 x 8 m room (x, z in [-4, 4], y in [0, 4]) open towards +Z (the camera side),
    // with a ceiling, a red left and a green right wall: the sun comes in low through the open
    // side, the lamp moves under the ceiling.
    Mesh room;
    room.name = "room";
    const Float3 X{8, 0, 0}, Y{0, 4, 0}, Z{0, 0, 8}, lo{-4, 0, -4};
    struct Wall {
        uint32_t material;
        Float3 origin, u, v; // inward normal u x v
    };
    const Wall walls[] = {
        {white, lo, Z, X},     // floor, +Y
        {white, lo + Y, X, Z}, // ceiling, -Y
        {white, lo, X, Y},     // back, +Z
        {red, lo, Y, Z},       // left, +X
        {green, lo + X, Z, Y}, // right, -X
    };
    for (const Wall& w : walls) {
        Primitive p;
        p.material = w.material;
        addGrid(p, w.origin, w.u, w.v, 4, 4, false);
        room.primitives.push_back(std::move(p));
    }

    Node root;
    root.name = "moving-light";
    const uint32_t rootNode = addNode(doc, std::move(root));
    std::vector<uint32_t> children = {
        addNode(doc, meshNode("room", addMesh(doc, std::move(room))))};
    // A static block so that the moving light has a fixed caster too.
    children.push_back(addNode(
        doc, meshNode("block",
                      addMesh(doc, solidBoxesMesh("block", white,
                                                  {{{-2.6f, 0, -3.0f}, {-1.6f, 1.6f, -2.0f}}})))));

    gltf::Animation clip;
    clip.name = "motion";
    auto times = [](uint32_t keys) {
        std::vector<float> t(keys + 1);
        for (uint32_t k = 0; k <= keys; ++k)
            t[k] = kClipSeconds * float(k) / float(keys);
        return t;
    };

    // The lamp: a point light circling under the ceiling once per clip (32 linear keys).
    doc.lights.push_back({.name = "moving-lamp",
                          .type = gltf::LightType::Point,
                          .color = {1.0f, 0.88f, 0.72f},
                          .intensity = 20.0f,
                          .range = 10.0f});
    Node lamp;
    lamp.name = "moving-lamp";
    lamp.light = int32_t(doc.lights.size() - 1);
    gltf::AnimationSampler lampPath;
    lampPath.input = times(32);
    for (float t : lampPath.input) {
        const float a = 2 * kPi * t / kClipSeconds;
        const Float3 at{2.2f * std::cos(a), 3.2f, -0.5f + 2.2f * std::sin(a)};
        lampPath.output.insert(lampPath.output.end(), at.begin(), at.end());
    }
    lamp.translation = {lampPath.output[0], lampPath.output[1], lampPath.output[2]};
    const uint32_t lampNode = addNode(doc, std::move(lamp));
    children.push_back(lampNode);
    clip.samplers.push_back(std::move(lampPath));
    clip.channels.push_back({0, lampNode, gltf::AnimationPath::Translation});

    // The box: a 0.8 m cube sliding across the sunlit floor and back, turning a full turn about
    // its vertical axis (its node's origin is its base centre), so its shadow sweeps the floor.
    Node box = meshNode("moving-box",
                        addMesh(doc, solidBoxesMesh("moving-box", orange,
                                                    {{{-0.4f, 0, -0.4f}, {0.4f, 0.8f, 0.4f}}})));
    gltf::AnimationSampler slide, turn;
    slide.input = times(16);
    turn.input = slide.input;
    for (float t : slide.input) {
        const float u = t / kClipSeconds;
        const Float3 at{-2.0f * std::cos(2 * kPi * u), 0.0f, 1.0f};
        slide.output.insert(slide.output.end(), at.begin(), at.end());
        // A full turn: keys 22.5 degrees apart, consecutive quaternions on one hemisphere.
        Float4 q = gltf::rotationY(2 * kPi * u);
        if (!turn.output.empty() && turn.output[turn.output.size() - 1] * q[3] +
                                            turn.output[turn.output.size() - 3] * q[1] <
                                        0)
            q = {-q[0], -q[1], -q[2], -q[3]};
        turn.output.insert(turn.output.end(), q.begin(), q.end());
    }
    box.translation = {slide.output[0], slide.output[1], slide.output[2]};
    const uint32_t boxNode = addNode(doc, std::move(box));
    children.push_back(boxNode);
    clip.samplers.push_back(std::move(slide));
    clip.channels.push_back({1, boxNode, gltf::AnimationPath::Translation});
    clip.samplers.push_back(std::move(turn));
    clip.channels.push_back({2, boxNode, gltf::AnimationPath::Rotation});

    // The ball: squashed and restored twice per clip (weight 0 -> 1 -> 0, 16 linear keys).
    const uint32_t ballNode =
        addNode(doc, meshNode("morph-ball", addMesh(doc, squashBall(blue, 0.6f, 12, 24)),
                              {2.2f, 0.6f, -1.8f}));
    children.push_back(ballNode);
    gltf::AnimationSampler squash;
    squash.input = times(16);
    for (float t : squash.input)
        squash.output.push_back(0.5f - 0.5f * std::cos(4 * kPi * t / kClipSeconds));
    clip.samplers.push_back(std::move(squash));
    clip.channels.push_back({3, ballNode, gltf::AnimationPath::Weights});
    doc.animations.push_back(std::move(clip));

    // Outside the open side, looking in at the floor where the shadows move.
    children.push_back(addCamera(doc, "room-camera", {0.0f, 2.4f, 8.5f},
                                 Float3{0.0f, 1.0f, -1.0f} - Float3{0.0f, 2.4f, 8.5f}, radians(60),
                                 16.0f / 9.0f, 0.05f, 60.0f));
    doc.nodes[rootNode].children = std::move(children);
    // Low through the open side (towards -Z), a little from the right, onto the floor and back.
    addSun(doc, sunDirection(radians(35), radians(110)), {0, 0, 0}, 30.0f, {1.0f, 0.97f, 0.9f},
           3.0f);
    return doc;
}

} // namespace pnb::assets
