// The animation chunks (MRPH, SKIN, ANIM; docs/FORMAT.md §4.3) and the pose library
// (pnb/animation_pose.h): round trip, glTF's sampling rules, skinning and morphing against
// hand-computed poses, conservative bounds, and the rules that keep hostile files out.
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "format_test_util.h"
#include "pnb/animation_pose.h"
#include "pnb/scene_builder.h"

namespace pnb::test {

namespace {

VertexStream f32Stream(SceneBuilder& b, VertexSemantic semantic, const std::vector<float>& values, uint8_t components) {
    VertexStream s;
    s.semantic = semantic;
    s.componentType = ComponentType::F32;
    s.componentCount = components;
    s.data = b.keep(values);
    return s;
}

// A vertical strip from y = 0 to y = 2, x in {0, 1}, skinned to two joints: node 0 (the root
// joint at the origin) holds the bottom row, node 1 (a joint at y = 1) the top row. Node 2 draws
// it. Node 3 draws a triangle (mesh 1) with one morph target that lifts it by +1 in z. Clip 0:
// joint 1 turns 90 degrees about +Z from t = 0 to t = 1 (linear), node 3's weight goes 0 -> 1
// (linear), node 3 steps in x at t = 0.5.
void buildAnimatedScene(SceneBuilder& b) {
    Scene& s = b.scene;
    s.info.name = b.intern("animated");
    Mesh strip;
    strip.name = b.intern("strip");
    strip.vertexCount = 4;
    strip.streams.push_back(f32Stream(b, VertexSemantic::Position, {0, 0, 0, 1, 0, 0, 0, 2, 0, 1, 2, 0}, 3));
    strip.streams.push_back(f32Stream(b, VertexSemantic::Normal, {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, 3));
    VertexStream joints;
    joints.semantic = VertexSemantic::Joints0;
    joints.componentType = ComponentType::U8;
    joints.componentCount = 4;
    joints.data = b.keep(std::vector<uint8_t>{0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    strip.streams.push_back(joints);
    strip.streams.push_back(f32Stream(b, VertexSemantic::Weights0, {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, 4));
    strip.indices = b.keep(std::vector<uint32_t>{0, 1, 2, 2, 1, 3});
    strip.submeshes.push_back({kNone, 0, 6, 0, 0, {}});
    s.meshes.push_back(strip);

    Mesh tri;
    tri.name = b.intern("tri");
    tri.vertexCount = 3;
    tri.streams.push_back(f32Stream(b, VertexSemantic::Position, {0, 0, 0, 1, 0, 0, 0, 1, 0}, 3));
    tri.indices = b.keep(std::vector<uint32_t>{0, 1, 2});
    tri.submeshes.push_back({kNone, 0, 3, 0, 0, {}});
    s.meshes.push_back(tri);
    MorphTargets morph;
    morph.mesh = 1;
    morph.weights = {0};
    MorphTarget lift;
    lift.name = b.intern("lift");
    lift.deltas.push_back(f32Stream(b, VertexSemantic::Position, {0, 0, 1, 0, 0, 1, 0, 0, 1}, 3));
    morph.targets.push_back(lift);
    s.morphTargets.push_back(morph);

    Node root, joint, skinned, morphed;
    root.name = b.intern("root");
    joint.name = b.intern("joint");
    joint.parent = 0;
    joint.translation = {0, 1, 0};
    skinned.name = b.intern("skinned");
    skinned.mesh = 0;
    skinned.translation = {5, 0, 0}; // only its translation places the skinned mesh
    skinned.rotation = {0, 1, 0, 0};  // ignored (glTF)
    morphed.name = b.intern("morphed");
    morphed.mesh = 1;
    s.nodes.nodes = {root, joint, skinned, morphed};

    Skin skin;
    skin.name = b.intern("skin");
    skin.joints = {0, 1};
    skin.inverseBindMatrices = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1},
                                {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1}};
    skin.nodes = {2};
    s.skins.push_back(skin);

    Animation clip;
    clip.name = b.intern("clip");
    const float h = float(std::sqrt(0.5));
    clip.channels.push_back({1, AnimatedProperty::Rotation, KeyInterpolation::Linear, {0, 1}, {0, 0, 0, 1, 0, 0, h, h}});
    clip.channels.push_back({3, AnimatedProperty::Weights, KeyInterpolation::Linear, {0, 1}, {0, 1}});
    clip.channels.push_back({3, AnimatedProperty::Translation, KeyInterpolation::Step, {0, 0.5f}, {0, 0, 0, 2, 0, 0}});
    s.animations.push_back(clip);
}

Result<Scene> roundTrip(const Scene& scene) {
    static std::vector<std::vector<std::byte>> keep; // the read scene's blobs view these bytes
    keep.push_back(writeToMemory(scene));
    auto c = Container::fromMemory(keep.back());
    if (!c) return c.error();
    return readScene(*c);
}

Status validate(SceneBuilder& b) { return validateScene(b.scene); }

} // namespace

TEST(AnimationChunks, SurviveWriteAndReadInStreamOrder) {
    SceneBuilder b;
    buildAnimatedScene(b);
    ASSERT_TRUE(isOk(validate(b))) << validate(b).message;
    auto read = roundTrip(b.scene);
    ASSERT_TRUE(read) << read.error().message;
    ASSERT_EQ(read->skins.size(), 1u);
    ASSERT_EQ(read->animations.size(), 1u);
    ASSERT_EQ(read->morphTargets.size(), 1u);
    EXPECT_EQ(read->skins[0].joints, (std::vector<uint32_t>{0, 1}));
    EXPECT_EQ(read->skins[0].inverseBindMatrices[1][13], -1.0f);
    EXPECT_EQ(read->animations[0].channels[2].interpolation, KeyInterpolation::Step);
    EXPECT_EQ(read->morphTargets[0].targets[0].deltas[0].data.size(), 36u);
    EXPECT_EQ(read->str(read->morphTargets[0].targets[0].name), "lift");
}

TEST(AnimationPose, SamplesStepLinearAndSlerpAsGltfDoes) {
    SceneBuilder b;
    buildAnimatedScene(b);
    const Scene& s = b.scene;
    EXPECT_DOUBLE_EQ(clipDuration(s.animations[0]), 1.0);
    Pose p = poseAt(s, 0u, 0.25);
    EXPECT_NEAR(p.weights[3][0], 0.25, 1e-6);          // linear
    EXPECT_EQ(p.graph.nodes[3].translation.x, 0.0f);   // step: the key before
    p = poseAt(s, 0u, 0.5);
    EXPECT_EQ(p.graph.nodes[3].translation.x, 2.0f);   // step: the key at t
    // Slerp halfway: 45 degrees about +Z.
    const double half = std::sin(std::numbers::pi / 8);
    EXPECT_NEAR(p.graph.nodes[1].rotation.z, half, 1e-6);
    EXPECT_NEAR(p.graph.nodes[1].rotation.w, std::cos(std::numbers::pi / 8), 1e-6);
    // Looping: 1.25 plays 0.25; a rest pose without a clip.
    EXPECT_NEAR(poseAt(s, 0u, 1.25).weights[3][0], 0.25, 1e-6);
    EXPECT_EQ(poseAt(s, std::nullopt, 0.25).weights[3][0], 0.0f);
    EXPECT_DOUBLE_EQ(clipTime(0, 7.5), 0.0); // a zero-length clip is a constant pose
    EXPECT_DOUBLE_EQ(clipTime(2, -0.5), 1.5);
    EXPECT_DOUBLE_EQ(clipTime(2, 5, false), 2.0);
}

TEST(AnimationPose, CubicSplineFollowsTheHermiteCurveAndStaysFinite) {
    AnimationChannel c{0, AnimatedProperty::Translation, KeyInterpolation::CubicSpline, {0, 2}, {}};
    // key 0: in (0,0,0) value (0,0,0) out (1,0,0); key 1: in (1,0,0) value (2,0,0) out (0,0,0).
    c.values = {0, 0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 2, 0, 0, 0, 0, 0};
    SceneBuilder b;
    b.scene.nodes.nodes.resize(1);
    b.scene.animations.push_back({kNone, {c}});
    // Tangents 1 over an interval of 2 on a line from 0 to 2: the curve is the line itself.
    for (double t : {0.0, 0.5, 1.0, 1.5, 2.0}) {
        Pose p = restPose(b.scene);
        applyClip(b.scene, b.scene.animations[0], t, p); // at the clip's time (poseAt loops 2 to 0)
        EXPECT_NEAR(p.graph.nodes[0].translation.x, t, 1e-5) << t;
    }
    // Tangents float can hold whose curve it cannot: the nearer key's value, never infinity.
    const float big = std::numeric_limits<float>::max();
    b.scene.animations[0].channels[0].values = {0, 0, 0, 0, 0, 0, big, big, big, big, big, big, 2, 0, 0, 0, 0, 0};
    Pose extreme;
    extreme.graph = b.scene.nodes;
    extreme.weights.resize(1);
    applyClip(b.scene, b.scene.animations[0], 0.9, extreme);
    EXPECT_TRUE(std::isfinite(extreme.graph.nodes[0].translation.x));
    EXPECT_TRUE(std::isfinite(extreme.graph.nodes[0].translation.y));
}

TEST(AnimationPose, SkinsAndMorphsVerticesAsComputedByHand) {
    SceneBuilder b;
    buildAnimatedScene(b);
    const Scene& s = b.scene;
    Pose p = restPose(s);
    applyClip(s, s.animations[0], 1.0, p); // joint 1 turned 90 degrees about +Z, weight 1
    const auto world = nodeWorldMatrices(p.graph);
    const DeformedVertices strip = deformVertices(s, 2, p, world);
    ASSERT_EQ(strip.positions.size(), 4u);
    // Bottom row stays; the top row (1 above joint 1 at y = 1) turns about (0, 1): (x, 2) -> (-1, 1 + x).
    // Positions are relative to the skinned node's placement, its translation (5, 0, 0).
    EXPECT_NEAR(strip.positions[1].x + 5, 1, 1e-6);
    EXPECT_NEAR(strip.positions[2].x + 5, -1, 1e-6);
    EXPECT_NEAR(strip.positions[2].y, 1, 1e-6);
    EXPECT_NEAR(strip.positions[3].x + 5, -1, 1e-6);
    EXPECT_NEAR(strip.positions[3].y, 2, 1e-6);
    EXPECT_NEAR(strip.normals[3].z, 1, 1e-6);
    // Placed by the skinned node's translation alone (its rotation is ignored, as glTF says).
    const Matrix4d place = drawingMatrix(s, 2, world);
    EXPECT_EQ(place[12], 5.0);
    EXPECT_EQ(place[0], 1.0);
    const DeformedVertices tri = deformVertices(s, 3, p, world);
    EXPECT_NEAR(tri.positions[1].z, 1, 1e-6);
    // The rest pose is the stored mesh.
    const Pose rest = restPose(s);
    const DeformedVertices still = deformVertices(s, 2, rest, nodeWorldMatrices(rest.graph));
    EXPECT_NEAR(still.positions[3].x + 5, 1, 1e-6);
    EXPECT_NEAR(still.positions[3].y, 2, 1e-6);
}

TEST(AnimationPose, AVertexCarriedBeyondFloatStaysWhereItIsStored) {
    SceneBuilder b;
    buildAnimatedScene(b);
    const float big = std::numeric_limits<float>::max();
    b.scene.skins[0].inverseBindMatrices[1] = {big, 0, 0, 0, 0, big, 0, 0, 0, 0, big, 0, big, big, 0, 1};
    b.scene.morphTargets[0].targets[0].deltas[0] = f32Stream(b, VertexSemantic::Position, {big, big, big, 0, 0, 1, 0, 0, 1}, 3);
    ASSERT_TRUE(isOk(validate(b))) << validate(b).message; // finite, so a reader accepts it
    Pose p = restPose(b.scene);
    applyClip(b.scene, b.scene.animations[0], 1.0, p);
    p.weights[3][0] = big; // as a clip may set it
    const auto world = nodeWorldMatrices(p.graph);
    for (uint32_t node : {2u, 3u}) {
        const DeformedVertices d = deformVertices(b.scene, node, p, world);
        for (const Vec3& v : d.positions) EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) << node;
        for (const Vec3& n : d.normals) EXPECT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z)) << node;
    }
    // The top row, whose joint overflows, is where the mesh stores it; the bottom row is skinned.
    const DeformedVertices strip = deformVertices(b.scene, 2, p, world);
    EXPECT_EQ(strip.positions[3].x, 1.0f);
    EXPECT_EQ(strip.positions[3].y, 2.0f);
    EXPECT_NEAR(strip.positions[1].x + 5, 1, 1e-6);
}

TEST(AnimationPose, DeformedBoundsHoldEveryPosedVertex) {
    SceneBuilder b;
    buildAnimatedScene(b);
    const Scene& s = b.scene;
    for (uint32_t node : {2u, 3u}) {
        const DeformBounds db = deformBounds(s, node);
        for (double t = 0; t <= 1.0; t += 0.125) {
            Pose p = poseAt(s, 0u, t);
            const auto world = nodeWorldMatrices(p.graph);
            std::vector<std::array<float, 16>> joints;
            if (const Skin* skin = skinOf(s, node)) joints = jointMatrices(*skin, world, node);
            const Aabb box = deformedBounds(db, joints, p.weights[node]);
            for (const Vec3& v : deformVertices(s, node, p, world).positions) {
                EXPECT_GE(v.x, box.min.x - 1e-5f) << node << " at " << t;
                EXPECT_LE(v.x, box.max.x + 1e-5f) << node << " at " << t;
                EXPECT_GE(v.y, box.min.y - 1e-5f) << node << " at " << t;
                EXPECT_LE(v.y, box.max.y + 1e-5f) << node << " at " << t;
                EXPECT_GE(v.z, box.min.z - 1e-5f) << node << " at " << t;
                EXPECT_LE(v.z, box.max.z + 1e-5f) << node << " at " << t;
            }
        }
    }
}

TEST(AnimationChunks, ValidationRefusesWhatWouldIndexOutOfBoundsOrPoseNaN) {
    struct Case {
        const char* what;
        void (*spoil)(SceneBuilder&);
        const char* message; // a part of the error
    };
    const Case cases[] = {
        {"joint index out of range",
         [](SceneBuilder& b) {
             b.scene.meshes[0].streams[2].data = b.keep(std::vector<uint8_t>{0, 0, 0, 0, 0, 0, 0, 0, 7, 0, 0, 0, 1, 0, 0, 0});
         },
         "names joint 7"},
        {"negative weight",
         [](SceneBuilder& b) {
             b.scene.meshes[0].streams[3] = f32Stream(b, VertexSemantic::Weights0, {1, 0, 0, 0, -1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, 4);
         },
         "weight -1"},
        {"NaN key value",
         [](SceneBuilder& b) { b.scene.animations[0].channels[0].values[3] = std::nanf(""); }, "not finite"},
        {"times that do not increase",
         [](SceneBuilder& b) { b.scene.animations[0].channels[1].times = {0.5f, 0.5f}; }, "does not increase"},
        {"too few values", [](SceneBuilder& b) { b.scene.animations[0].channels[0].values.pop_back(); }, "values"},
        {"two channels on one property",
         [](SceneBuilder& b) { b.scene.animations[0].channels.push_back(b.scene.animations[0].channels[2]); },
         "same property"},
        {"weights of a mesh without targets",
         [](SceneBuilder& b) { b.scene.animations[0].channels[1].node = 1; }, "no morph targets"},
        {"joint that is no node", [](SceneBuilder& b) { b.scene.skins[0].joints[1] = 99; }, "joint node = 99"},
        {"missing bind matrix", [](SceneBuilder& b) { b.scene.skins[0].inverseBindMatrices.pop_back(); }, "inverse bind"},
        {"more joints than kMaxJoints",
         [](SceneBuilder& b) {
             b.scene.skins[0].joints.assign(kMaxJoints + 1, 0);
             b.scene.skins[0].inverseBindMatrices.resize(kMaxJoints + 1);
         },
         "joints, not 1.."},
        {"quantised position on a deformed mesh",
         [](SceneBuilder& b) { b.scene.meshes[1].streams[0].encoding = VertexEncoding::Octahedral; }, "F32 Plain"},
        {"morph delta of the wrong length",
         [](SceneBuilder& b) {
             b.scene.morphTargets[0].targets[0].deltas[0] = f32Stream(b, VertexSemantic::Position, {0, 0, 1}, 3);
         },
         "F32 x 3"},
        {"a second MRPH for one mesh", [](SceneBuilder& b) { b.scene.morphTargets.push_back(b.scene.morphTargets[0]); }, "some already"},
        {"a node in two skins", [](SceneBuilder& b) { b.scene.skins.push_back(b.scene.skins[0]); }, "another skin"},
    };
    for (const Case& c : cases) {
        SceneBuilder b;
        buildAnimatedScene(b);
        c.spoil(b);
        const Status st = validate(b);
        ASSERT_FALSE(isOk(st)) << c.what;
        EXPECT_NE(st.message.find(c.message), std::string::npos) << c.what << ": " << st.message;
    }
}

TEST(AnimationPose, AMillionKeysAreSampledByBinarySearch) {
    SceneBuilder b;
    buildAnimatedScene(b);
    AnimationChannel& c = b.scene.animations[0].channels[1];
    constexpr size_t kKeys = 1'000'000;
    c.times.resize(kKeys);
    c.values.resize(kKeys);
    for (size_t k = 0; k < kKeys; ++k) c.times[k] = float(k) * 1e-3f, c.values[k] = float(k % 2);
    ASSERT_TRUE(isOk(validate(b)));
    auto read = roundTrip(b.scene);
    ASSERT_TRUE(read) << read.error().message;
    const auto start = std::chrono::steady_clock::now();
    double sum = 0;
    for (int f = 0; f < 10000; ++f) sum += poseAt(*read, 0u, f * 0.0999).weights[3][0];
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    EXPECT_TRUE(std::isfinite(sum));
    EXPECT_LT(ms, 5000) << "10^4 samples of a 10^6-key channel took " << ms << " ms";
    EXPECT_NEAR(clipDuration(read->animations[0]), 999.999, 1e-2);
}

} // namespace pnb::test
