// Playback (docs/PLAYER.md "Animation"): the deform pass against the CPU pose, bounds, determinism,
// the frozen baseline, a static scene's cost, and the local-shadow cache under a moving caster.
// The scene is built here, small: a three-joint skinned column bending, a morphed plate, a
// rigidly moving block carrying a light, a static light and a floor.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>

#include <gtest/gtest.h>

#include "anim/animate_scene.h"
#include "pnb/animation_pose.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb/writer.h"
#include "pnb_converter/shader_permutations.h"
#include "pnb_player/renderer.h"
#include "posed_frame.h"
#include "render_fixture.h"

namespace pnb::player::test {
namespace {

struct MeshData {
    std::vector<float> positions, normals, tangents, weights;
    std::vector<uint8_t> joints;
    std::vector<uint32_t> indices;
};

Aabb boxOf(const std::vector<float>& p) {
    Aabb b;
    for (size_t i = 0; i + 2 < p.size(); i += 3) b.grow({p[i], p[i + 1], p[i + 2]});
    return b;
}

// A square column along +Y from 0 to `height`, `rings` rings, skinned to joints at y = 0, 0.7,
// 1.4 (linear blend between neighbours). Vertex 5's weights sum to 2 (divided by their sum),
// vertex 0's to 0 (unskinned: it stays).
MeshData column(float half, float height, uint32_t rings) {
    MeshData m;
    const float corners[4][2] = {{-half, -half}, {half, -half}, {half, half}, {-half, half}};
    for (uint32_t r = 0; r < rings; ++r) {
        const float y = height * float(r) / float(rings - 1);
        for (const auto& c : corners) {
            m.positions.insert(m.positions.end(), {c[0], y, c[1]});
            const float l = std::sqrt(c[0] * c[0] + c[1] * c[1]);
            m.normals.insert(m.normals.end(), {c[0] / l, 0, c[1] / l});
            const float s = std::clamp(y / 0.7f, 0.0f, 2.0f);
            const uint8_t j0 = uint8_t(std::min(1.0f, std::floor(s)));
            const float f = s - float(j0);
            m.joints.insert(m.joints.end(), {j0, uint8_t(j0 + 1), 0, 0});
            m.weights.insert(m.weights.end(), {1 - f, f, 0, 0});
        }
    }
    for (float& w : std::span(m.weights).subspan(5 * 4, 4)) w *= 2;
    for (float& w : std::span(m.weights).subspan(0, 4)) w = 0;
    for (uint32_t r = 0; r + 1 < rings; ++r)
        for (uint32_t k = 0; k < 4; ++k) {
            const uint32_t a = r * 4 + k, b = r * 4 + (k + 1) % 4, c = a + 4, d = b + 4;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    return m;
}

// An n x n grid in the XZ plane, facing +Y, with tangents along +X.
MeshData plate(float size, uint32_t n) {
    MeshData m;
    for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
            m.positions.insert(m.positions.end(), {size * (float(i) / float(n - 1) - 0.5f), 0, size * (float(j) / float(n - 1) - 0.5f)});
            m.normals.insert(m.normals.end(), {0, 1, 0});
            m.tangents.insert(m.tangents.end(), {1, 0, 0, 1});
        }
    for (uint32_t j = 0; j + 1 < n; ++j)
        for (uint32_t i = 0; i + 1 < n; ++i) {
            const uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    return m;
}

// An axis-aligned box of half-size h centred at the origin, faces outward.
MeshData cube(float h) {
    MeshData m;
    const float n[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const auto& f : n) {
        const glm::vec3 nn(f[0], f[1], f[2]);
        const glm::vec3 u = std::abs(nn.y) > 0.5f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
        const glm::vec3 v = glm::cross(nn, u);
        const uint32_t base = uint32_t(m.positions.size() / 3);
        for (int c = 0; c < 4; ++c) {
            const float a = (c == 1 || c == 2) ? 1.0f : -1.0f, b = c >= 2 ? 1.0f : -1.0f;
            const glm::vec3 p = h * (nn + a * u + b * v);
            m.positions.insert(m.positions.end(), {p.x, p.y, p.z});
            m.normals.insert(m.normals.end(), {nn.x, nn.y, nn.z});
        }
        // (u, v, n) is right-handed: counter-clockwise seen from outside.
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    return m;
}

template <class T> VertexStream stream(SceneBuilder& b, VertexSemantic s, ComponentType t, uint8_t count, const std::vector<T>& data) {
    VertexStream v;
    v.semantic = s;
    v.componentType = t;
    v.componentCount = count;
    v.data = b.keep(data);
    return v;
}

uint32_t addMesh(SceneBuilder& b, const std::string& name, const MeshData& d) {
    Mesh m;
    m.name = b.intern(name);
    m.vertexCount = uint32_t(d.positions.size() / 3);
    m.streams.push_back(stream(b, VertexSemantic::Position, ComponentType::F32, 3, d.positions));
    m.streams.push_back(stream(b, VertexSemantic::Normal, ComponentType::F32, 3, d.normals));
    if (!d.tangents.empty()) m.streams.push_back(stream(b, VertexSemantic::Tangent, ComponentType::F32, 4, d.tangents));
    if (!d.joints.empty()) {
        m.streams.push_back(stream(b, VertexSemantic::Joints0, ComponentType::U8, 4, d.joints));
        m.streams.push_back(stream(b, VertexSemantic::Weights0, ComponentType::F32, 4, d.weights));
    }
    m.indexType = IndexType::U32;
    m.indices = b.keep(d.indices);
    m.bounds = boxOf(d.positions);
    Submesh sm;
    sm.material = 0;
    sm.indexCount = uint32_t(d.indices.size());
    sm.bounds = m.bounds;
    m.submeshes.push_back(sm);
    const Vec3 c{0.5f * (m.bounds.min.x + m.bounds.max.x), 0.5f * (m.bounds.min.y + m.bounds.max.y),
                 0.5f * (m.bounds.min.z + m.bounds.max.z)};
    float r = 0;
    for (size_t i = 0; i < d.positions.size(); i += 3)
        r = std::max(r, std::hypot(d.positions[i] - c.x, d.positions[i + 1] - c.y, d.positions[i + 2] - c.z));
    m.boundingSphere = {c, r};
    b.scene.meshes.push_back(std::move(m));
    return uint32_t(b.scene.meshes.size() - 1);
}

uint32_t addNode(SceneBuilder& b, const std::string& name, uint32_t parent, Vec3 t, uint32_t mesh = kNone) {
    Node n;
    n.name = b.intern(name);
    n.parent = parent;
    n.translation = t;
    n.mesh = mesh;
    b.scene.nodes.nodes.push_back(n);
    return uint32_t(b.scene.nodes.nodes.size() - 1);
}

// The shader programs of one deferred material, with shadows, and the deform program.
void addPrograms(SceneBuilder& b, bool deform) {
    const converter::MaterialFeatures features{};
    converter::SceneShaderNeeds needs;
    needs.shadows = true;
    converter::ShaderPlan plan = converter::planShaders(b.scene.materials, std::span(&features, 1), needs);
    if (deform) plan.programs.push_back({"deform", {"deform.comp"}, {ShaderStage::Compute}, {"MORPH", "SKIN"}});
    auto ok = converter::appendShaderPrograms(plan, converter::builtinShaderFiles(), b);
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    b.scene.materials[0].program = plan.materialProgram[0];
}

void addMaterial(SceneBuilder& b) {
    Material m;
    m.name = b.intern("grey");
    m.baseColorFactor = {0.8f, 0.8f, 0.8f, 1};
    m.roughnessFactor = 0.8f;
    m.metallicFactor = 0;
    b.scene.materials.push_back(m);
}

void addFloor(SceneBuilder& b) {
    MeshData floor = plate(8.0f, 2);
    floor.tangents.clear();
    addNode(b, "floor", kNone, {0, 0, 0}, addMesh(b, "floor", floor));
}

AnimationChannel channel(uint32_t node, AnimatedProperty p, std::vector<float> times, std::vector<float> values) {
    AnimationChannel c;
    c.node = node;
    c.property = p;
    c.times = std::move(times);
    c.values = std::move(values);
    return c;
}

std::vector<float> zRotation(std::initializer_list<float> degrees) {
    std::vector<float> q(4 * degrees.size(), 0.0f);
    size_t k = 0;
    for (float d : degrees) {
        const float h = 0.5f * d * std::numbers::pi_v<float> / 180.0f;
        q[4 * k + 2] = std::sin(h);
        q[4 * k + 3] = std::cos(h);
        ++k;
    }
    return q;
}

// Nodes: 0-2 joints, 3 the skinned column, 4 the morphed plate, 5 the moving block, 6 a light on
// it, 7 the static spot light over the block, 8 the floor. Clip 0 "move": 2 s.
std::string writeAnimatedScene(const std::string& name) {
    SceneBuilder b;
    b.scene.info.name = b.intern(name);
    b.scene.info.bounds = {{-4, -0.1f, -4}, {4, 3.5f, 4}};
    addMaterial(b);
    const uint32_t column0 = addMesh(b, "column", column(0.15f, 2.1f, 7));
    MeshData plateData = plate(1.0f, 5);
    const uint32_t plateMesh = addMesh(b, "plate", plateData);
    const uint32_t cubeMesh = addMesh(b, "block", cube(0.25f));
    const uint32_t j0 = addNode(b, "j0", kNone, {0, 0, 0});
    const uint32_t j1 = addNode(b, "j1", j0, {0, 0.7f, 0});
    const uint32_t j2 = addNode(b, "j2", j1, {0, 0.7f, 0});
    const uint32_t skinned = addNode(b, "column", kNone, {1, 0, 0}, column0);
    const uint32_t morphed = addNode(b, "plate", kNone, {-1.5f, 0.3f, 0}, plateMesh);
    const uint32_t block = addNode(b, "block", kNone, {-0.5f, 1.2f, 1.2f}, cubeMesh);
    const uint32_t carried = addNode(b, "carried light", block, {0, -0.4f, 0});
    const uint32_t spot = addNode(b, "spot", kNone, {-0.5f, 3.2f, 1.2f});
    addFloor(b);

    Skin skin;
    skin.joints = {j0, j1, j2};
    for (float y : {0.0f, 0.7f, 1.4f}) // inverse(world(joint)) at bind: translate(0, -y, 0)
        skin.inverseBindMatrices.push_back({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -y, 0, 1});
    skin.nodes = {skinned};
    b.scene.skins.push_back(skin);

    MorphTargets targets;
    targets.mesh = plateMesh;
    targets.weights = {0};
    std::vector<float> dp, dn, dt;
    for (size_t v = 0; v < plateData.positions.size() / 3; ++v) {
        const float x = plateData.positions[3 * v], z = plateData.positions[3 * v + 2];
        dp.insert(dp.end(), {0, 0.6f * (0.5f - x * x - z * z), 0});
        dn.insert(dn.end(), {2 * x, 0, 2 * z});
        dt.insert(dt.end(), {0, -0.5f * x, 0});
    }
    MorphTarget dome;
    dome.name = b.intern("dome");
    dome.deltas = {stream(b, VertexSemantic::Position, ComponentType::F32, 3, dp),
                   stream(b, VertexSemantic::Normal, ComponentType::F32, 3, dn),
                   stream(b, VertexSemantic::Tangent, ComponentType::F32, 3, dt)};
    targets.targets.push_back(dome);
    b.scene.morphTargets.push_back(targets);

    Light point;
    point.name = b.intern("carried");
    point.type = LightType::Point;
    point.intensity = 0.5f;
    point.range = 3;
    point.castsShadows = false;
    Light lamp;
    lamp.name = b.intern("lamp");
    lamp.type = LightType::Spot;
    lamp.intensity = 30;
    lamp.range = 8;
    lamp.outerConeRadians = 1.2f;
    b.scene.lights.lights = {point, lamp};
    b.scene.nodes.nodes[carried].light = 0;
    b.scene.nodes.nodes[spot].light = 1;
    b.scene.nodes.nodes[spot].rotation = {-std::numbers::sqrt2_v<float> / 2, 0, 0, std::numbers::sqrt2_v<float> / 2};

    Animation clip;
    clip.name = b.intern("move");
    clip.channels.push_back(channel(j1, AnimatedProperty::Rotation, {0, 1, 2}, zRotation({0, 50, 0})));
    clip.channels.push_back(channel(j2, AnimatedProperty::Rotation, {0, 1, 2}, zRotation({0, 40, 0})));
    clip.channels.push_back(channel(morphed, AnimatedProperty::Weights, {0, 1, 2}, {0, 1, 0}));
    clip.channels.push_back(channel(block, AnimatedProperty::Translation, {0, 1, 2},
                                    {-0.5f, 1.2f, 1.2f, 0.5f, 1.2f, 1.2f, -0.5f, 1.2f, 1.2f}));
    b.scene.animations.push_back(clip);
    addPrograms(b, true);

    const std::string dir = ::testing::TempDir() + "/pnb_animation";
    std::filesystem::create_directories(dir);
    const std::string path = dir + "/" + name + ".pnb";
    auto w = Writer::create(path);
    EXPECT_TRUE(w.ok());
    if (!w.ok()) return path;
    const Status written = writeScene(*w, b.scene);
    EXPECT_TRUE(isOk(written)) << written.message;
    EXPECT_TRUE(isOk(w->commit()));
    return path;
}

const std::string& animatedScene() {
    static const std::string path = writeAnimatedScene("animated");
    return path;
}

CameraState overview() { return lookAt({0, 3.5, 5.5}, {0, 0.8, 0}); }

RenderSettings animSettings(double time, bool play = false) {
    RenderSettings s = settingsForCurrentDriver();
    s.animTime = float(time);
    s.animPlay = play;
    s.warmUp = false;
    return s;
}

struct Playback {
    std::unique_ptr<GpuScene> scene;
    std::unique_ptr<Renderer> renderer;
};
Playback open(const std::string& path, const RenderSettings& s) {
    Playback p;
    auto g = loadScene(path);
    EXPECT_TRUE(g.ok()) << (g.ok() ? "" : g.error().message);
    if (!g.ok()) return p;
    p.scene = std::move(*g);
    auto r = Renderer::create(*p.scene, s);
    EXPECT_TRUE(r.ok());
    if (r.ok()) p.renderer = std::move(*r);
    return p;
}

CapturedImage frame(Renderer& r, CaptureBuffer buffer = CaptureBuffer::Color, uint32_t w = 128, uint32_t h = 96) {
    EXPECT_TRUE(r.render(overview(), w, h).ok());
    auto img = r.capture(buffer);
    EXPECT_TRUE(img.ok());
    return img.ok() ? *img : CapturedImage{};
}

// (a) + (b): the posed buffers match pnb::deformVertices at several times, and the items' bounds
// hold every posed vertex.
TEST(Animation, PosedFrameMatchesTheCpuPose) {
    for (double t : {0.0, 0.4, 1.0, 1.7}) {
        const PosedFrameCheck c = checkPosedFrame(animatedScene(), t);
        ASSERT_EQ(c.error, "") << "t = " << t;
        EXPECT_EQ(c.deformedNodes, 2u);
        EXPECT_EQ(c.vertices, 28u + 25u);
        EXPECT_LT(c.positionError, 1e-5) << "t = " << t;
        EXPECT_LT(c.normalError, 1e-5) << "t = " << t;
        EXPECT_LT(c.tangentError, 1e-5) << "t = " << t;
        EXPECT_EQ(c.outsideBounds, 0u) << "t = " << t;
    }
}

// The pose really moves the vertices: at t = 1 the column bends (its top leaves x = 1) and the
// plate domes; the unskinned vertex 0 stays.
TEST(Animation, ThePoseMovesTheDeformedMeshes) {
    Playback p = open(animatedScene(), animSettings(1.0));
    ASSERT_TRUE(p.renderer);
    ASSERT_TRUE(p.renderer->render(overview(), 64, 48).ok());
    EXPECT_EQ(p.renderer->lastFrame().deformDispatches, 2u);
    const SceneAnimation& a = *p.scene->animation;
    std::vector<float> column(28 * 3);
    glGetNamedBufferSubData(p.scene->meshes[a.deformed[0].posedMesh].buffer.id(), 0, GLsizeiptr(column.size() * 4), column.data());
    // The column's joints bend it 50 + 40 degrees about +z: its top ring (x -0.15 at the bind
    // pose, drawn relative to the skinned node's x = 1) swings to world x = -1.236.
    EXPECT_NEAR(column[27 * 3], -1.236f - 1.0f, 1e-3f);
    EXPECT_FLOAT_EQ(column[0], -0.15f); // unskinned (weights sum to 0): where it is stored
    std::vector<float> plate(25 * 3);
    glGetNamedBufferSubData(p.scene->meshes[a.deformed[1].posedMesh].buffer.id(), 0, GLsizeiptr(plate.size() * 4), plate.data());
    EXPECT_NEAR(plate[12 * 3 + 1], 0.3f, 1e-5); // the centre vertex rises by 0.6 x 0.5
}

// (c): two runs give identical images at frame N; the frame at t differs from the rest pose.
TEST(Animation, PlaybackIsDeterministicAndMoves) {
    auto run = [&](uint32_t frames) {
        Playback p = open(animatedScene(), animSettings(0.0, true));
        CapturedImage last;
        for (uint32_t k = 0; k < frames; ++k) {
            p.renderer->setAnimationClock(double(k) / 8.0);
            last = frame(*p.renderer);
        }
        EXPECT_NEAR(p.renderer->animationTime(), double(frames - 1) / 8.0, 1e-9);
        return last;
    };
    const CapturedImage a = run(6), b = run(6);
    ASSERT_EQ(a.u8.size(), b.u8.size());
    EXPECT_EQ(a.u8, b.u8);
    Playback rest = open(animatedScene(), animSettings(0.0));
    const CapturedImage atRest = frame(*rest.renderer);
    EXPECT_GT(compareRgba8(a, atRest).fractionOver(8), 0.01);
}

// (d): anim.enabled = false draws the stored pose and runs no deform pass; turning it on poses,
// turning it off again restores the stored streams.
TEST(Animation, DisabledDrawsTheStoredPoseWithoutDeforming) {
    RenderSettings off = animSettings(1.0);
    off.animEnabled = false;
    Playback p = open(animatedScene(), off);
    ASSERT_TRUE(p.renderer);
    const SceneAnimation& a = *p.scene->animation;
    auto readColumn = [&] {
        std::vector<float> v(28 * 3);
        glGetNamedBufferSubData(p.scene->meshes[a.deformed[0].posedMesh].buffer.id(), 0, GLsizeiptr(v.size() * 4), v.data());
        return v;
    };
    const std::vector<float> stored = column(0.15f, 2.1f, 7).positions;
    ASSERT_TRUE(p.renderer->render(overview(), 64, 48).ok());
    EXPECT_EQ(p.renderer->lastFrame().deformDispatches, 0u);
    EXPECT_EQ(readColumn(), stored);
    // The moving block is at rest too.
    for (const DrawItem& item : p.scene->items) {
        if (item.node == 5) {
            EXPECT_DOUBLE_EQ(item.world[3].x, -0.5);
        }
    }
    RenderSettings on = off;
    on.animEnabled = true;
    p.renderer->setSettings(on);
    ASSERT_TRUE(p.renderer->render(overview(), 64, 48).ok());
    EXPECT_EQ(p.renderer->lastFrame().deformDispatches, 2u);
    EXPECT_NE(readColumn(), stored);
    for (const DrawItem& item : p.scene->items) {
        if (item.node == 5) {
            EXPECT_DOUBLE_EQ(item.world[3].x, 0.5);
        }
    }
    // The same pose again: nothing to deform.
    ASSERT_TRUE(p.renderer->render(overview(), 64, 48).ok());
    EXPECT_EQ(p.renderer->lastFrame().deformDispatches, 0u);
    p.renderer->setSettings(off);
    ASSERT_TRUE(p.renderer->render(overview(), 64, 48).ok());
    glFinish();
    EXPECT_EQ(readColumn(), stored);
}

// The rigidly animated node carries its light; a paused clock holds the pose.
TEST(Animation, LightsFollowTheirNodes) {
    Playback p = open(animatedScene(), animSettings(0.5));
    ASSERT_TRUE(p.renderer->render(overview(), 64, 48).ok());
    ASSERT_EQ(p.scene->lights.size(), 2u);
    EXPECT_NEAR(p.scene->lights[0].position.x, 0.0, 1e-6); // the block at x = -0.5 + 0.5
    EXPECT_NEAR(p.scene->lights[0].position.y, 0.8, 1e-6);
    p.renderer->setAnimationClock(3.0); // paused: anim.play = false
    ASSERT_TRUE(p.renderer->render(overview(), 64, 48).ok());
    EXPECT_NEAR(p.scene->lights[0].position.x, 0.0, 1e-6);
    EXPECT_EQ(p.renderer->lastFrame().movedItems, 0u);
}

// (e): a static scene has no animation: no posed buffer, no deform program, no pass.
TEST(Animation, AStaticSceneHasNoneOfIt) {
    SceneBuilder b;
    b.scene.info.name = b.intern("static");
    b.scene.info.bounds = {{-4, -0.1f, -4}, {4, 1, 4}};
    addMaterial(b);
    addFloor(b);
    addNode(b, "block", kNone, {0, 0.5f, 0}, addMesh(b, "block", cube(0.25f)));
    addPrograms(b, false);
    const std::string path = ::testing::TempDir() + "/pnb_animation_static.pnb";
    {
        auto w = Writer::create(path);
        ASSERT_TRUE(w.ok());
        ASSERT_TRUE(isOk(writeScene(*w, b.scene)));
        ASSERT_TRUE(isOk(w->commit()));
    }
    Playback p = open(path, animSettings(1.0, true));
    ASSERT_TRUE(p.renderer);
    EXPECT_EQ(p.scene->animation, nullptr);
    EXPECT_EQ(p.scene->meshes.size(), 2u);
    for (const std::string& label : p.scene->programLabels) EXPECT_EQ(label.find("deform"), std::string::npos);
    p.renderer->setAnimationClock(1.0);
    ASSERT_TRUE(p.renderer->render(overview(), 64, 48).ok());
    EXPECT_EQ(p.renderer->lastFrame().deformDispatches, 0u);
    EXPECT_EQ(p.renderer->lastFrame().movedItems, 0u);
}

// (f): the local-shadow cache redraws when a caster moves: after a frame at t = 0, the frame at
// t = 1 with the cache on equals the frame at t = 1 drawn without any cache, and the block's
// shadow on the floor has moved.
TEST(Animation, TheLocalShadowCacheFollowsAMovingCaster) {
    RenderSettings cached = animSettings(0.0);
    cached.shadowLocalCache = true;
    Playback p = open(animatedScene(), cached);
    ASSERT_TRUE(p.renderer);
    const CapturedImage before = frame(*p.renderer, CaptureBuffer::Hdr);
    EXPECT_GT(p.renderer->lastFrame().localShadowTiles, 0u);
    cached.animTime = 1.0f;
    p.renderer->setSettings(cached);
    const CapturedImage moved = frame(*p.renderer, CaptureBuffer::Hdr);
    EXPECT_GT(p.renderer->lastFrame().localShadowTilesDrawn, 0u);
    RenderSettings fresh = cached;
    fresh.shadowLocalCache = false;
    Playback q = open(animatedScene(), fresh);
    const CapturedImage truth = frame(*q.renderer, CaptureBuffer::Hdr);
    ASSERT_EQ(moved.f32.size(), truth.f32.size());
    double worst = 0, change = 0;
    for (size_t i = 0; i < moved.f32.size(); ++i) {
        worst = std::max(worst, double(std::abs(moved.f32[i] - truth.f32[i])));
        change = std::max(change, double(std::abs(moved.f32[i] - before.f32[i])));
    }
    EXPECT_LT(worst, 1e-4);
    EXPECT_GT(change, 0.05);
}

// Clip choice: by name, by index, none; an unknown name is reported.
TEST(Animation, ClipsResolveByIndexOrName) {
    SceneAnimation a;
    a.clipNames = {"walk", "run"};
    bool known = false;
    EXPECT_EQ(resolveClip(a, "run", &known), 1u);
    EXPECT_TRUE(known);
    EXPECT_EQ(resolveClip(a, "0", &known), 0u);
    EXPECT_EQ(resolveClip(a, "none", &known), std::nullopt);
    EXPECT_TRUE(known);
    EXPECT_EQ(resolveClip(a, "fly", &known), std::nullopt);
    EXPECT_FALSE(known);
    EXPECT_EQ(resolveClip(a, "7", &known), std::nullopt);
    EXPECT_FALSE(known);
}

} // namespace
} // namespace pnb::player::test
