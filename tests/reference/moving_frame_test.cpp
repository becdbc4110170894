// Moving frames (issue 42): every truth traces the scene posed at the frame's instant
// (pnb_reference/frame_pose.h, docs/REFERENCE.md "Moving frames"). A container built here holds
// a box that one clip moves, a morphed quad and a skinned quad; the truths at an instant must be
// those of a static scene with the box put where the clip puts it, the deformed surfaces must be
// where pnb::deformVertices puts them, and the default pose must be the container as stored.
// pnb-reference reads the instant from frame.json's "anim" (and --anim-clip / --anim-time).
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include "pnb/animation_pose.h"
#include "pnb/scene_builder.h"
#include "pnb/writer.h"
#include "pnb_reference/frame_tracer.h"
#include "pnb_reference/indirect_tracer.h"
#include "pnb_reference/local_light.h"
#include "pnb_reference/shadow_tracer.h"
#include "reference_test_util.h"

namespace pnb::reference::test {

namespace {

const glm::vec3 kUp{0, 1, 0};
const FramePose kHalfway{true, 0, 0.5}; // clip 0 at t = 0.5 s: the box at x = 2

// The scene (world units, +Y up):
//   node 0  ground: 40 x 40 quad at y = 0
//   node 1  box: 2 x 2 x 2 centred at (0, 3, 0); clip 0 moves it to (4, 3, 0) over 1 s
//   node 2  a point light 2 above the box (its child)
//   node 3  the sun, shining straight down
//   node 4  morphed quad: 2 x 2 at (10, 2, 0); its target raises vertex k by 0.5 (k + 1); clip 0
//           takes the weight from 0 to 1
//   node 5  joint 0 at (-10, 2, 0); node 6 joint 1 at (1, 0, 0) from it, raised by 2 over the clip
//   node 7  skinned quad around (-10, 2, 0), turned 90 degrees about Y (a skinned node's own
//           rotation places nothing): its -x edge follows joint 0, its +x edge joint 1
struct MovingScene {
    SceneBuilder b;
    Scene& s = b.scene;
};

uint32_t addMesh(SceneBuilder& b, const std::string& name, const std::vector<float>& positions,
                 const std::vector<uint32_t>& indices, std::vector<VertexStream> extra = {}) {
    Mesh m;
    m.name = b.intern(name);
    m.vertexCount = uint32_t(positions.size() / 3);
    VertexStream p;
    p.semantic = VertexSemantic::Position;
    p.data = b.keep(positions);
    m.streams.push_back(p);
    for (VertexStream& e : extra) m.streams.push_back(e);
    m.indices = b.keep(indices);
    Submesh sm;
    sm.material = 0;
    sm.indexCount = uint32_t(indices.size());
    for (size_t v = 0; v < positions.size(); v += 3) sm.bounds.grow({positions[v], positions[v + 1], positions[v + 2]});
    m.bounds = sm.bounds;
    m.submeshes.push_back(sm);
    b.scene.meshes.push_back(m);
    return uint32_t(b.scene.meshes.size() - 1);
}

// A horizontal w x d quad centred at (cx, y, cz), vertices (-x,-z), (+x,-z), (+x,+z), (-x,+z).
std::vector<float> quad(float cx, float y, float cz, float w, float d) {
    return {cx - w / 2, y, cz - d / 2, cx + w / 2, y, cz - d / 2, cx + w / 2, y, cz + d / 2, cx - w / 2, y, cz + d / 2};
}
const std::vector<uint32_t> kQuadIndices = {0, 2, 1, 0, 3, 2};

Node node(SceneBuilder& b, const std::string& name, Vec3 t, uint32_t mesh = kNone) {
    Node n;
    n.name = b.intern(name);
    n.translation = t;
    n.mesh = mesh;
    return n;
}

AnimationChannel linear(uint32_t node, AnimatedProperty property, std::vector<float> values) {
    AnimationChannel c;
    c.node = node;
    c.property = property;
    c.interpolation = KeyInterpolation::Linear;
    c.times = {0.0f, 1.0f};
    c.values = std::move(values);
    return c;
}

// `boxAt`: the box node's rest translation (the static scene of the instant puts it there);
// `clip`: whether the clip is written; `deformers`: whether the morphed and skinned quads are (the
// box's scenes leave them out: a static scene cannot hold their instant).
void build(MovingScene& m, Vec3 boxAt = {0, 3, 0}, bool clip = true, bool deformers = true) {
    SceneBuilder& b = m.b;
    Scene& s = m.s;
    Material stone;
    stone.name = b.intern("stone");
    stone.doubleSided = true;
    stone.metallicFactor = 0;
    s.materials.push_back(stone);

    const uint32_t ground = addMesh(b, "ground", quad(0, 0, 0, 40, 40), kQuadIndices);
    std::vector<float> box;
    for (int k = 0; k < 8; ++k) box.insert(box.end(), {k & 1 ? 1.0f : -1.0f, k & 2 ? 1.0f : -1.0f, k & 4 ? 1.0f : -1.0f});
    const std::vector<uint32_t> boxIndices = {0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1,
                                              2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
    const uint32_t boxMesh = addMesh(b, "box", box, boxIndices);

    // Morphed quad, in its node's space.
    const uint32_t morphMesh = addMesh(b, "morphed", quad(0, 0, 0, 2, 2), kQuadIndices);
    MorphTargets targets;
    targets.mesh = morphMesh;
    targets.weights = {0.0f};
    MorphTarget raise;
    VertexStream delta;
    delta.semantic = VertexSemantic::Position;
    delta.data = b.keep(std::vector<float>{0, 0.5f, 0, 0, 1.0f, 0, 0, 1.5f, 0, 0, 2.0f, 0});
    raise.deltas.push_back(delta);
    targets.targets.push_back(raise);
    s.morphTargets.push_back(targets);

    // Skinned quad, in bind (world) space: -x edge on joint 0, +x edge on joint 1.
    VertexStream joints, weights;
    joints.semantic = VertexSemantic::Joints0;
    joints.componentType = ComponentType::U8;
    joints.componentCount = 4;
    joints.data = b.keep(std::vector<uint8_t>{0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0});
    weights.semantic = VertexSemantic::Weights0;
    weights.componentCount = 4;
    weights.data = b.keep(std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    const uint32_t skinMesh = addMesh(b, "skinned", quad(-10, 2, 0, 2, 2), kQuadIndices, {joints, weights});

    Light point;
    point.name = b.intern("bulb");
    point.type = LightType::Point;
    point.intensity = 10;
    point.range = 50;
    Light sun;
    sun.name = b.intern("sun");
    sun.intensity = 3;
    s.lights.lights = {point, sun};

    s.nodes.nodes.push_back(node(b, "ground", {0, 0, 0}, ground));
    s.nodes.nodes.push_back(node(b, "box", boxAt, boxMesh));
    Node bulb = node(b, "bulb", {0, 2, 0});
    bulb.parent = 1;
    bulb.light = 0;
    s.nodes.nodes.push_back(bulb);
    Node sunNode = node(b, "sun", {0, 30, 0});
    sunNode.rotation = {-0.70710678f, 0, 0, 0.70710678f}; // -Z turned to -Y: shines down
    sunNode.light = 1;
    s.nodes.nodes.push_back(sunNode);
    s.nodes.nodes.push_back(node(b, "morphed", {10, 2, 0}, morphMesh));
    s.nodes.nodes.push_back(node(b, "joint0", {-10, 2, 0}));
    Node j1 = node(b, "joint1", {1, 0, 0});
    j1.parent = 5;
    s.nodes.nodes.push_back(j1);
    Node skinned = node(b, "skinned", {-10, 2, 0}, skinMesh);
    skinned.rotation = {0, 0.70710678f, 0, 0.70710678f};
    s.nodes.nodes.push_back(skinned);

    Skin skin;
    skin.joints = {5, 6};
    auto inverseTranslation = [](float x, float y, float z) {
        return std::array<float, 16>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -x, -y, -z, 1};
    };
    skin.inverseBindMatrices = {inverseTranslation(-10, 2, 0), inverseTranslation(-9, 2, 0)};
    skin.nodes = {7};
    s.skins.push_back(skin);
    if (!deformers) { // nodes 4 and 7 draw nothing
        s.nodes.nodes[4].mesh = s.nodes.nodes[7].mesh = kNone;
        s.skins.clear();
        s.morphTargets.clear();
    }

    if (clip) {
        Animation a;
        a.name = b.intern("move");
        a.channels.push_back(linear(1, AnimatedProperty::Translation, {0, 3, 0, 4, 3, 0}));
        if (deformers) {
            a.channels.push_back(linear(4, AnimatedProperty::Weights, {0, 1}));
            a.channels.push_back(linear(6, AnimatedProperty::Translation, {1, 0, 0, 1, 2, 0}));
        }
        s.animations.push_back(a);
    }
}

// Ground points on a grid over the box's reach (never within 0.125 of x or z = k).
std::vector<glm::vec3> groundGrid() {
    std::vector<glm::vec3> points;
    for (float x = -5.875f; x < 6; x += 0.25f)
        for (float z = -2.875f; z < 3; z += 0.25f) points.emplace_back(x, 0, z);
    return points;
}

std::vector<float> sunVisibility(const Scene& scene, const FramePose& at, const std::vector<glm::vec3>& points) {
    auto tracer = ShadowTracer::build(scene, glm::dvec3(0.0), at);
    EXPECT_TRUE(tracer.ok()) << (tracer.ok() ? "" : tracer.error().message);
    std::vector<float> out(points.size(), -1.0f);
    if (tracer.ok()) (*tracer)->visibility(points, kUp, out);
    return out;
}

size_t shadowed(const std::vector<float>& v) {
    size_t n = 0;
    for (float x : v) n += x == 0.0f;
    return n;
}

// The deformed triangles' centroids in world space, as the player draws them at `at`.
std::vector<glm::vec3> deformedCentroids(const Scene& scene, uint32_t node, double t) {
    const Pose pose = poseAt(scene, 0, t);
    const std::vector<Matrix4d> world = nodeWorldMatrices(pose.graph);
    const DeformedVertices d = deformVertices(scene, node, pose, world);
    const glm::dmat4 drawing = glm::make_mat4(drawingMatrix(scene, node, world).data());
    std::vector<glm::vec3> out;
    for (size_t k = 0; k < kQuadIndices.size(); k += 3) {
        glm::dvec3 c(0.0);
        for (size_t i = 0; i < 3; ++i) {
            const Vec3 p = d.positions[kQuadIndices[k + i]];
            c += glm::dvec3(drawing * glm::dvec4(p.x, p.y, p.z, 1.0)) / 3.0;
        }
        out.push_back(glm::vec3(c));
    }
    return out;
}

FrameImage renderTopDown(const Scene& scene, const FramePose& at) {
    auto tracer = FrameTracer::build(scene, glm::dvec3(0.0), at);
    EXPECT_TRUE(tracer.ok()) << (tracer.ok() ? "" : tracer.error().message);
    if (!tracer.ok()) return {};
    FrameCamera camera;
    camera.position = {0, 20, 0};
    camera.worldFromView = glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
    camera.orthographic = true;
    camera.xmag = camera.ymag = 12;
    camera.width = camera.height = 24;
    FrameTraceSettings s;
    s.maxBounces = 1;
    s.samplesPerPass = s.minSamples = s.maxSamples = 4;
    s.noiseTarget = 0;
    s.timeLimitSeconds = 0;
    return (*tracer)->render(camera, s);
}

} // namespace

// (a) The box moved by the clip: its shadow at t = 0.5 is that of a static box at (2, 3, 0).
TEST(MovingFrame, ShadowTruthOfAMovedBoxIsTheStaticSceneWithTheBoxThere) {
    MovingScene moving, placed;
    build(moving, {0, 3, 0}, /*clip=*/true, /*deformers=*/false);
    build(placed, {2, 3, 0}, /*clip=*/false, /*deformers=*/false);
    const std::vector<glm::vec3> points = groundGrid();
    const std::vector<float> posed = sunVisibility(moving.s, kHalfway, points);
    const std::vector<float> staticThere = sunVisibility(placed.s, {}, points);
    const std::vector<float> rest = sunVisibility(moving.s, {}, points);
    EXPECT_EQ(posed, staticThere);
    EXPECT_NE(posed, rest);
    // The footprint itself: x in [1, 3] at the instant, [-1, 1] at rest.
    for (size_t i = 0; i < points.size(); ++i) {
        const glm::vec3 p = points[i];
        const bool under = std::fabs(p.z) < 1 && p.x > 1 && p.x < 3;
        EXPECT_EQ(posed[i], under ? 0.0f : 1.0f) << p.x << ", " << p.z;
    }
    EXPECT_EQ(shadowed(posed), shadowed(rest));
    // An animated pose of a scene nothing moves is the container as stored.
    EXPECT_EQ(sunVisibility(placed.s, FramePose{true, std::nullopt, 0.25}, points), staticThere);
    EXPECT_EQ(effectivePose(placed.s, FramePose{true, std::nullopt, 0.25}), FramePose{});
}

// (a) The light on the box moves with it (placeLocalLight, and the lights every tracer places).
TEST(MovingFrame, LightsArePlacedByThePosedNodes) {
    MovingScene moving;
    build(moving);
    auto rest = placeLocalLight(moving.s, 0);
    auto posed = placeLocalLight(moving.s, 0, kHalfway);
    ASSERT_TRUE(rest.ok() && posed.ok());
    EXPECT_EQ(rest->position, glm::dvec3(0, 5, 0));
    EXPECT_EQ(posed->position, glm::dvec3(2, 5, 0));
    auto bad = placeLocalLight(moving.s, 0, FramePose{true, 3, 0});
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("clip 3"), std::string::npos) << bad.error().message;
}

// (a) The whole frame: the same image as the static scene with the box (and its light) there.
TEST(MovingFrame, WholeFrameTruthOfAMovedBoxIsTheStaticSceneWithTheBoxThere) {
    MovingScene moving, placed;
    build(moving, {0, 3, 0}, /*clip=*/true, /*deformers=*/false);
    build(placed, {2, 3, 0}, /*clip=*/false, /*deformers=*/false);
    const FrameImage posed = renderTopDown(moving.s, kHalfway);
    const FrameImage staticThere = renderTopDown(placed.s, {});
    const FrameImage rest = renderTopDown(moving.s, {});
    ASSERT_EQ(posed.mean.size(), size_t(24 * 24));
    EXPECT_EQ(posed.mean, staticThere.mean);
    EXPECT_NE(posed.mean, rest.mean);
}

// (b) Morph targets and skins: the traced surfaces are where deformVertices puts them, not where
// the container stores them.
TEST(MovingFrame, DeformedSurfacesAreTracedWhereTheCpuPoseDeformsThem) {
    MovingScene moving;
    build(moving);
    for (uint32_t node : {4u, 7u}) {
        SCOPED_TRACE(node == 4 ? "morphed" : "skinned");
        const std::vector<glm::vec3> centroids = deformedCentroids(moving.s, node, 0.5);
        std::vector<glm::vec3> below, above;
        for (glm::vec3 c : centroids) {
            below.push_back(c - glm::vec3(0, 0.02f, 0));
            above.push_back(c + glm::vec3(0, 0.02f, 0));
        }
        // Looking up: just below the posed surface it hides the sky, just above it does not.
        const std::vector<float> under = sunVisibility(moving.s, kHalfway, below);
        const std::vector<float> over = sunVisibility(moving.s, kHalfway, above);
        for (size_t i = 0; i < centroids.size(); ++i) {
            EXPECT_EQ(under[i], 0.0f) << "below centroid " << i << " (" << centroids[i].x << ", " << centroids[i].y << ")";
            EXPECT_EQ(over[i], 1.0f) << "above centroid " << i;
        }
        // The container as stored holds both quads flat at y = 2: the posed ones are above it.
        for (glm::vec3 c : centroids) EXPECT_GT(c.y, 2.1f);
        EXPECT_EQ(sunVisibility(moving.s, {}, below), std::vector<float>(below.size(), 1.0f));
    }
    // The skinned node's own rotation places nothing: its surface spans x in [-11, -9].
    const std::vector<glm::vec3> skinned = deformedCentroids(moving.s, 7, 0.5);
    for (glm::vec3 c : skinned) EXPECT_TRUE(c.x > -11 && c.x < -9 && std::fabs(c.z) < 1) << c.x << ", " << c.z;
}

// (b) The Monte-Carlo tracers build from the same posed geometry (one place: posed_scene.h).
TEST(MovingFrame, IndirectTracerSeesThePosedBox) {
    MovingScene moving, placed;
    build(moving, {0, 3, 0}, /*clip=*/true, /*deformers=*/false);
    build(placed, {2, 3, 0}, /*clip=*/false, /*deformers=*/false);
    // Points under the box's height facing down: they see the sunlit ground and the box's shadow.
    const std::vector<glm::vec3> points = {{2, 1, 0}, {0, 1, 0}, {-3, 1, 1.5f}};
    const std::vector<glm::vec3> normals(points.size(), -kUp);
    auto irradiance = [&](const Scene& scene, const FramePose& at) {
        auto tracer = IndirectTracer::build(scene, glm::dvec3(0.0), at);
        EXPECT_TRUE(tracer.ok()) << (tracer.ok() ? "" : tracer.error().message);
        std::vector<glm::vec3> mean(points.size()), error(points.size());
        IndirectSettings settings;
        settings.samples = 64;
        if (tracer.ok()) (*tracer)->irradiance(points, normals, settings, mean, error);
        return mean;
    };
    EXPECT_EQ(irradiance(moving.s, kHalfway), irradiance(placed.s, {}));
    EXPECT_NE(irradiance(moving.s, kHalfway), irradiance(moving.s, {}));
}

// ---- pnb-reference: frame.json's "anim" -------------------------------------------------------

namespace {

void writeContainer(const Scene& scene, const fs::path& path) {
    std::vector<std::byte> bytes;
    Writer w = Writer::toMemory(&bytes, {});
    Status st = writeScene(w, scene);
    ASSERT_TRUE(isOk(st)) << st.describe();
    ASSERT_TRUE(isOk(w.commit()));
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// A frame of the ground grid seen by a camera at the origin: position.exr holds groundGrid().
void writeFrame(const fs::path& dir, const nlohmann::json& anim) {
    fs::create_directories(dir);
    const std::vector<glm::vec3> points = groundGrid();
    std::vector<float> pixels;
    for (glm::vec3 p : points) pixels.insert(pixels.end(), {p.x, p.y, p.z});
    auto out = OIIO::ImageOutput::create((dir / "position.exr").string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(int(points.size()), 1, 3, OIIO::TypeDesc::FLOAT);
    ASSERT_TRUE(out->open((dir / "position.exr").string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    ASSERT_TRUE(out->close());
    nlohmann::json j = {{"camera_position", {0, 0, 0}}, {"toward_light", {0, 1, 0}}, {"width", points.size()},
                        {"height", 1}};
    if (!anim.is_null()) j["anim"] = anim;
    std::ofstream(dir / "frame.json") << j.dump(2);
}

std::vector<float> readVisibility(const fs::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    EXPECT_TRUE(in) << path;
    if (!in) return {};
    std::vector<float> v(size_t(in->spec().width) * size_t(in->spec().height));
    EXPECT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, v.data()));
    return v;
}

nlohmann::json readJson(const fs::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in, nullptr, false);
}

class MovingFrameCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        sDir = new TempDir("moving");
        MovingScene moving;
        build(moving);
        writeContainer(moving.s, sDir->path / "moving.pnb");
    }
    static void TearDownTestSuite() {
        delete sDir;
        sDir = nullptr;
    }
    static std::string scene() { return "'" + (sDir->path / "moving.pnb").string() + "'"; }
    static TempDir* sDir;
};
TempDir* MovingFrameCli::sDir = nullptr;

} // namespace

// (c) frame.json's "anim" is the instant traced, and metrics.json records it.
TEST_F(MovingFrameCli, FrameJsonAnimIsTheInstantTraced) {
    MovingScene moving;
    build(moving);
    const fs::path dir = sDir->path / "halfway";
    writeFrame(dir, {{"enabled", true}, {"clip", 0}, {"clip_name", "move"}, {"time", 0.5}});
    RunResult r = run(scene() + " --frame '" + dir.string() + "' -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(readVisibility(dir / "visibility.exr"), sunVisibility(moving.s, kHalfway, groundGrid()));
    const nlohmann::json m = readJson(dir / "metrics.json");
    ASSERT_TRUE(m.contains("pose")) << m.dump();
    EXPECT_EQ(m["pose"], nlohmann::json({{"animated", true}, {"clip", 0}, {"clip_name", "move"}, {"time", 0.5}}));

    // --anim-time overrides it (looped into the clip's 1 s as the player's clock: 2.5 s is 0.5 s).
    const fs::path other = sDir->path / "override";
    writeFrame(other, {{"enabled", true}, {"clip", 0}, {"clip_name", "move"}, {"time", 0.0}});
    r = run(scene() + " --frame '" + other.string() + "' --anim-time 2.5 -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(readVisibility(other / "visibility.exr"), sunVisibility(moving.s, kHalfway, groundGrid()));
    r = run(scene() + " --frame '" + other.string() + "' --anim-clip move --anim-time 0.5 -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(readJson(other / "metrics.json")["pose"]["time"], 0.5);
}

// (d) No "anim" (every frame dumped before issue 42), or anim disabled: the container as stored.
TEST_F(MovingFrameCli, FrameJsonWithoutAnimTracesTheContainerAsStored) {
    MovingScene moving;
    build(moving);
    const std::vector<float> stored = sunVisibility(moving.s, {}, groundGrid());
    for (const nlohmann::json& anim :
         {nlohmann::json(), nlohmann::json{{"enabled", false}, {"clip", 0}, {"clip_name", "move"}, {"time", 0.5}}}) {
        SCOPED_TRACE(anim.dump());
        const fs::path dir = sDir->path / (anim.is_null() ? "none" : "disabled");
        writeFrame(dir, anim);
        RunResult r = run(scene() + " --frame '" + dir.string() + "' -q");
        ASSERT_EQ(r.exitCode, 0) << r.output;
        EXPECT_EQ(readVisibility(dir / "visibility.exr"), stored);
        EXPECT_EQ(readJson(dir / "metrics.json")["pose"], nlohmann::json({{"animated", false}}));
    }
}

// Bad "anim": a clip the container does not have, or another container's clip, is exit 2.
TEST_F(MovingFrameCli, AClipTheContainerDoesNotHaveIsAnInputError) {
    const fs::path dir = sDir->path / "bad";
    writeFrame(dir, {{"enabled", true}, {"clip", 4}, {"clip_name", ""}, {"time", 0.5}});
    RunResult r = run(scene() + " --frame '" + dir.string() + "' -q");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("clip 4"), std::string::npos) << r.output;
    writeFrame(dir, {{"enabled", true}, {"clip", 0}, {"clip_name", "walk"}, {"time", 0.5}});
    r = run(scene() + " --frame '" + dir.string() + "' -q");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("'walk'"), std::string::npos) << r.output;
    writeFrame(dir, {{"enabled", true}, {"clip", "zero"}, {"time", 0.5}});
    r = run(scene() + " --frame '" + dir.string() + "' -q");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    r = run(scene() + " --frame '" + dir.string() + "' --anim-clip run -q");
    EXPECT_EQ(r.exitCode, 2) << r.output;
}

} // namespace pnb::reference::test
