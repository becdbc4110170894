// Moving scenes through pnb-convert (issue 42): glTF skins, clips and morph targets into SKIN,
// ANIM and MRPH; the deformed meshes' streams; the `deform` program only where something
// deforms; and the bad inputs, each a clear error or a documented clamp. Small glTFs are
// written by the tests (a two-bone skinned strip, a morphed triangle); the Khronos models are
// used when ../shared/khronos is there (skipped otherwise).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "pnb/animation_pose.h"
#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_converter/convert.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;

// Little-endian bytes of the test's buffer, each part 4-byte aligned.
struct Bin {
    std::vector<uint8_t> bytes;
    template <class T> size_t add(const std::vector<T>& values) {
        while (bytes.size() % 4) bytes.push_back(0);
        const size_t offset = bytes.size();
        bytes.resize(offset + values.size() * sizeof(T));
        if (!values.empty()) std::memcpy(bytes.data() + offset, values.data(), values.size() * sizeof(T));
        return offset;
    }
};

// Accessors over the one buffer, written as "bufferViews" and "accessors" JSON.
struct Accessors {
    std::string views, accessors;
    int count = 0;
    int add(size_t offset, size_t bytes, int componentType, size_t n, const char* type) {
        views += std::string(count ? "," : "") + "{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) +
                 ",\"byteLength\":" + std::to_string(bytes) + "}";
        accessors += std::string(count ? "," : "") + "{\"bufferView\":" + std::to_string(count) +
                     ",\"componentType\":" + std::to_string(componentType) + ",\"count\":" + std::to_string(n) +
                     ",\"type\":\"" + type + "\"}";
        return count++;
    }
    std::string json() const { return "\"bufferViews\":[" + views + "],\"accessors\":[" + accessors + "],"; }
};

constexpr int kFloat = 5126, kU8 = 5121, kU16 = 5123;

// The two-bone strip's knobs: what the bad-input tests change.
struct StripOptions {
    std::vector<uint8_t> joints = {0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 0.5f, 0.5f, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    std::vector<float> times = {0, 0.5f, 1};
    std::vector<float> rotations; // default: joint 1 turning about z, 0 -> 90 degrees
    size_t outputKeys = 0;        // rotations in the output accessor (0: as many as times)
    int extraJoints = 0;          // joint nodes added to the skin (for the joint-count limit)
    int channelNode = 2;          // the node the clip animates (J1)
};

// A 1 x 2 strip of 6 vertices skinned to two joints (J0 at the origin, J1 at y = 1, its child),
// with one clip "Bend" rotating J1. Returns the glTF JSON; the buffer goes to `binPath`.
std::string skinnedStrip(const StripOptions& o, const std::string& binName, Bin& bin) {
    Accessors a;
    const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0, 1, 2, 0};
    const std::vector<uint16_t> indices = {0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4};
    const int jointCount = 2 + o.extraJoints;
    std::vector<float> ibm;
    for (int j = 0; j < jointCount; ++j) {
        const float y = j == 1 ? -1.0f : 0.0f;
        ibm.insert(ibm.end(), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, y, 0, 1});
    }
    std::vector<float> rotations = o.rotations;
    if (rotations.empty()) {
        for (size_t k = 0; k < o.times.size(); ++k) {
            const float angle = float(M_PI / 2) * float(k) / float(std::max<size_t>(1, o.times.size() - 1));
            rotations.insert(rotations.end(), {0, 0, std::sin(angle / 2), std::cos(angle / 2)});
        }
    }
    const size_t outputKeys = o.outputKeys ? o.outputKeys : rotations.size() / 4;
    const int pos = a.add(bin.add(positions), positions.size() * 4, kFloat, 6, "VEC3");
    const int idx = a.add(bin.add(indices), indices.size() * 2, kU16, indices.size(), "SCALAR");
    const int jnt = a.add(bin.add(o.joints), o.joints.size(), kU8, 6, "VEC4");
    const int wgt = a.add(bin.add(o.weights), o.weights.size() * 4, kFloat, 6, "VEC4");
    const int inv = a.add(bin.add(ibm), ibm.size() * 4, kFloat, size_t(jointCount), "MAT4");
    const int in = a.add(bin.add(o.times), o.times.size() * 4, kFloat, o.times.size(), "SCALAR");
    const int out = a.add(bin.add(rotations), outputKeys * 16, kFloat, outputKeys, "VEC4");
    std::string jointList = "1,2", extraNodes;
    for (int j = 0; j < o.extraJoints; ++j) {
        jointList += "," + std::to_string(4 + j);
        extraNodes += ",{\"name\":\"X" + std::to_string(j) + "\"}";
    }
    std::string rootChildren = "1,3";
    for (int j = 0; j < o.extraJoints; ++j) rootChildren += "," + std::to_string(4 + j);
    return "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":" + std::to_string(bin.bytes.size()) +
           ",\"uri\":\"" + binName + "\"}]," + a.json() +
           "\"meshes\":[{\"name\":\"Strip\",\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(pos) +
           ",\"JOINTS_0\":" + std::to_string(jnt) + ",\"WEIGHTS_0\":" + std::to_string(wgt) +
           "},\"indices\":" + std::to_string(idx) + "}]}]," +
           "\"skins\":[{\"name\":\"Rig\",\"joints\":[" + jointList + "],\"inverseBindMatrices\":" + std::to_string(inv) + "}]," +
           "\"animations\":[{\"name\":\"Bend\",\"samplers\":[{\"input\":" + std::to_string(in) + ",\"output\":" +
           std::to_string(out) + "}],\"channels\":[{\"sampler\":0,\"target\":{\"node\":" + std::to_string(o.channelNode) +
           ",\"path\":\"rotation\"}}]}]," +
           "\"nodes\":[{\"name\":\"Root\",\"children\":[" + rootChildren + "]},{\"name\":\"J0\",\"children\":[2]}," +
           "{\"name\":\"J1\",\"translation\":[0,1,0]},{\"name\":\"Body\",\"mesh\":0,\"skin\":0}" + extraNodes + "]," +
           "\"scenes\":[{\"nodes\":[0]}],\"scene\":0}";
}

// A triangle with two position morph targets, a normal, and a clip animating its weights; without
// `animated`, the same triangle with neither (a static scene).
std::string morphedTriangle(const std::string& binName, Bin& bin, bool animated = true) {
    Accessors a;
    const int pos = a.add(bin.add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}), 36, kFloat, 3, "VEC3");
    const int nrm = a.add(bin.add(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}), 36, kFloat, 3, "VEC3");
    const int t0 = a.add(bin.add(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}), 36, kFloat, 3, "VEC3");
    const int t1 = a.add(bin.add(std::vector<float>{1, 0, 0, 0, 0, 0, 0, 0, 0}), 36, kFloat, 3, "VEC3");
    const int in = a.add(bin.add(std::vector<float>{0, 1}), 8, kFloat, 2, "SCALAR");
    const int out = a.add(bin.add(std::vector<float>{0, 0, 1, 0.5f}), 16, kFloat, 4, "SCALAR");
    if (!animated)
        return "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":" + std::to_string(bin.bytes.size()) +
               ",\"uri\":\"" + binName + "\"}]," + a.json() +
               "\"meshes\":[{\"name\":\"Tri\",\"primitives\":[{\"attributes\":{\"POSITION\":" +
               std::to_string(pos) + ",\"NORMAL\":" + std::to_string(nrm) + "}}]}]," +
               "\"nodes\":[{\"name\":\"Still\",\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}],\"scene\":0}";
    return "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":" + std::to_string(bin.bytes.size()) +
           ",\"uri\":\"" + binName + "\"}]," + a.json() +
           "\"meshes\":[{\"name\":\"Tri\",\"weights\":[0.25,0],\"primitives\":[{\"attributes\":{\"POSITION\":" +
           std::to_string(pos) + ",\"NORMAL\":" + std::to_string(nrm) + "},\"targets\":[{\"POSITION\":" +
           std::to_string(t0) + "},{\"POSITION\":" + std::to_string(t1) + "}]}]}]," +
           "\"animations\":[{\"name\":\"Pulse\",\"samplers\":[{\"input\":" + std::to_string(in) + ",\"output\":" +
           std::to_string(out) + "}],\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"weights\"}}]}]," +
           "\"nodes\":[{\"name\":\"Morphed\",\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}],\"scene\":0}";
}

class AnimationConvert : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        mDir = fs::temp_directory_path() / ("pnb_anim_" + std::to_string(getpid()) + "_" + info->name());
        fs::create_directories(mDir);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(mDir, ec);
    }
    // Writes `json` and `bin` as name.gltf/name.bin.
    std::string write(const std::string& name, const std::string& json, const Bin& bin) {
        std::ofstream(mDir / (name + ".bin"), std::ios::binary)
            .write(reinterpret_cast<const char*>(bin.bytes.data()), std::streamsize(bin.bytes.size()));
        std::ofstream(mDir / (name + ".gltf"), std::ios::binary) << json;
        return (mDir / (name + ".gltf")).string();
    }
    std::string strip(const std::string& name, const StripOptions& o = {}) {
        Bin bin;
        const std::string json = skinnedStrip(o, name + ".bin", bin);
        return write(name, json, bin);
    }
    Result<ConvertSummary, ConvertError> convert(const std::string& input, bool quantize = false,
                                                 bool validateShaders = false, uint32_t lods = 0) {
        ConvertSettings s;
        s.input = input;
        s.output = (mDir / (fs::path(input).stem().string() + ".pnb")).string();
        s.noSidecar = true;
        s.jobs = 1;
        s.validateShaders = validateShaders;
        s.mesh.quantize = quantize;
        s.mesh.lodCount = lods;
        mOutput = s.output;
        return convertScene(s);
    }
    // The scene's streams may be views of the container's mapping: the container stays open
    // with the fixture.
    Scene load() {
        auto c = Container::open(mOutput);
        EXPECT_TRUE(c.ok());
        if (!c.ok()) return {};
        mContainers.push_back(std::make_unique<Container>(std::move(*c)));
        auto scene = readScene(*mContainers.back());
        EXPECT_TRUE(scene.ok()) << scene.error().describe();
        return scene.ok() ? std::move(*scene) : Scene{};
    }
    fs::path mDir;
    std::string mOutput;
    std::vector<std::unique_ptr<Container>> mContainers;
};

const VertexStream* streamOf(const Mesh& m, VertexSemantic s) {
    for (const VertexStream& v : m.streams)
        if (v.semantic == s) return &v;
    return nullptr;
}

std::vector<float> floatsOf(const VertexStream& v) {
    std::vector<float> out(v.data.size() / 4);
    std::memcpy(out.data(), v.data.data(), out.size() * 4);
    return out;
}

const Program* programNamed(const Scene& s, const std::string& name) {
    for (const Program& p : s.programs)
        if (s.str(p.name) == name) return &p;
    return nullptr;
}

std::vector<std::string> definesOf(const Scene& s, const Program& p) {
    std::vector<std::string> out;
    for (StringRef d : p.defines) out.emplace_back(s.str(d));
    return out;
}

uint32_t nodeNamed(const Scene& s, const std::string& name) {
    for (uint32_t i = 0; i < s.nodes.nodes.size(); ++i)
        if (s.str(s.nodes.nodes[i].name) == name) return i;
    return kNone;
}

// Node `node`'s vertices at time t of clip `clip` differ from the rest pose and are all finite.
void expectMovesAt(const Scene& scene, uint32_t node, uint32_t clip, double t) {
    const Pose rest = restPose(scene);
    const Pose posed = poseAt(scene, clip, t);
    const DeformedVertices a = deformVertices(scene, node, rest, nodeWorldMatrices(rest.graph));
    const DeformedVertices b = deformVertices(scene, node, posed, nodeWorldMatrices(posed.graph));
    ASSERT_EQ(a.positions.size(), b.positions.size());
    ASSERT_FALSE(b.positions.empty());
    double moved = 0;
    for (size_t i = 0; i < b.positions.size(); ++i) {
        const Vec3 p = b.positions[i], q = a.positions[i];
        ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) << "vertex " << i;
        moved = std::max(moved, double(std::abs(p.x - q.x) + std::abs(p.y - q.y) + std::abs(p.z - q.z)));
    }
    EXPECT_GT(moved, 1e-3) << "clip " << clip << " at t = " << t << " leaves the mesh at rest";
}

bool hasWarning(const ConvertSummary& s, const std::string& needle) {
    return std::any_of(s.warnings.begin(), s.warnings.end(),
                       [&](const std::string& w) { return w.find(needle) != std::string::npos; });
}

// [SECTION] the skinned strip

TEST_F(AnimationConvert, SkinnedStripWritesSkinClipAndDeformProgram) {
    // Shader validation on: the `deform` compute program must pass glslang like the others.
    auto r = convert(strip("strip"), false, true, 2);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Scene s = load();
    ASSERT_EQ(s.skins.size(), 1u);
    EXPECT_EQ(s.str(s.skins[0].name), "Rig");
    EXPECT_EQ(s.skins[0].joints.size(), 2u);
    const uint32_t body = nodeNamed(s, "Body");
    ASSERT_NE(body, kNone);
    EXPECT_EQ(s.skins[0].nodes, std::vector<uint32_t>{body});
    EXPECT_FLOAT_EQ(s.skins[0].inverseBindMatrices[1][13], -1.0f);
    ASSERT_EQ(s.animations.size(), 1u);
    EXPECT_EQ(s.str(s.animations[0].name), "Bend");
    ASSERT_EQ(s.animations[0].channels.size(), 1u);
    EXPECT_EQ(s.animations[0].channels[0].node, nodeNamed(s, "J1"));
    EXPECT_EQ(s.animations[0].channels[0].property, AnimatedProperty::Rotation);
    EXPECT_DOUBLE_EQ(clipDuration(s.animations[0]), 1.0);
    EXPECT_TRUE(s.morphTargets.empty());
    // The mesh: F32 positions, U8 joints, F32 weights; no coarse proxy even with LOD levels.
    const Mesh& m = s.meshes[s.nodes.nodes[body].mesh];
    ASSERT_NE(streamOf(m, VertexSemantic::Joints0), nullptr);
    EXPECT_EQ(streamOf(m, VertexSemantic::Joints0)->componentType, ComponentType::U8);
    EXPECT_EQ(streamOf(m, VertexSemantic::Weights0)->componentType, ComponentType::F32);
    EXPECT_TRUE(s.meshDetails.empty());
    const Program* deform = programNamed(s, "deform");
    ASSERT_NE(deform, nullptr);
    EXPECT_EQ(definesOf(s, *deform), std::vector<std::string>{"SKIN"});
    ASSERT_EQ(deform->shaders.size(), 1u);
    EXPECT_EQ(s.shaders[deform->shaders[0]].stage, ShaderStage::Compute);
    expectMovesAt(s, body, 0, 0.75);
    // The rest-pose bounds hold the strip (1 x 2 at the origin).
    EXPECT_NEAR(s.nodes.nodes[body].worldBounds.max.y, 2.0f, 1e-5f);
}

TEST_F(AnimationConvert, QuantizeLeavesDeformedStreamsF32) {
    auto r = convert(strip("strip"), true);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Scene s = load();
    const Mesh& m = s.meshes[s.nodes.nodes[nodeNamed(s, "Body")].mesh];
    for (VertexSemantic sem : {VertexSemantic::Position, VertexSemantic::Normal}) {
        const VertexStream* v = streamOf(m, sem);
        ASSERT_NE(v, nullptr);
        EXPECT_EQ(v->componentType, ComponentType::F32);
        EXPECT_EQ(v->encoding, VertexEncoding::Plain);
    }
}

// [SECTION] bad input

TEST_F(AnimationConvert, JointIndexOutOfRangeIsAnErrorNamingMeshPrimitiveAndJointCount) {
    StripOptions o;
    o.joints[8] = 7;
    auto r = convert(strip("badjoint", o));
    ASSERT_FALSE(r.ok());
    const std::string& e = r.error().message;
    EXPECT_NE(e.find("badjoint.gltf"), std::string::npos) << e;
    EXPECT_NE(e.find("mesh 'Strip' primitive 0"), std::string::npos) << e;
    EXPECT_NE(e.find("joint 7"), std::string::npos) << e;
    EXPECT_NE(e.find("2 joints"), std::string::npos) << e;
}

TEST_F(AnimationConvert, MoreJointsThanTheLimitIsAnError) {
    StripOptions o;
    o.extraJoints = int(kMaxJoints) - 1; // 1025 joints
    auto r = convert(strip("manyjoints", o));
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("skin 'Rig': 1025 joints, at most 1024"), std::string::npos)
        << r.error().message;
}

TEST_F(AnimationConvert, WeightsAreNormalisedWithOneWarning) {
    StripOptions o;
    o.weights = {2, 0, 0, 0, 1, 0, 0, 0, 0.3f, 0.3f, 0, 0, 0.5f, 0.5f, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0};
    auto r = convert(strip("weights", o));
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(hasWarning(*r, "2 skinned vertices had joint weights not summing to 1 (normalised), 1 had "
                               "weights summing to 0"));
    const Scene s = load();
    const Mesh& m = s.meshes[s.nodes.nodes[nodeNamed(s, "Body")].mesh];
    const std::vector<float> w = floatsOf(*streamOf(m, VertexSemantic::Weights0));
    ASSERT_EQ(w.size(), size_t(m.vertexCount) * 4);
    for (size_t v = 0; v < m.vertexCount; ++v)
        EXPECT_NEAR(w[v * 4] + w[v * 4 + 1] + w[v * 4 + 2] + w[v * 4 + 3], 1.0f, 1e-6f) << "vertex " << v;
}

TEST_F(AnimationConvert, NanKeyframeIsAnErrorNamingAnimationAndChannel) {
    StripOptions o;
    o.rotations = {0, 0, 0, 1, 0, 0, std::numeric_limits<float>::quiet_NaN(), 1, 0, 0, 0, 1};
    auto r = convert(strip("nankey", o));
    ASSERT_FALSE(r.ok());
    const std::string& e = r.error().message;
    EXPECT_NE(e.find("animation 'Bend' channel 0 (node 'J1' rotation)"), std::string::npos) << e;
    EXPECT_NE(e.find("key 1 holds a value that is not finite"), std::string::npos) << e;
}

TEST_F(AnimationConvert, SamplerCountMismatchIsAnErrorNamingTheAccessors) {
    StripOptions o;
    o.outputKeys = 2; // 3 times, 2 rotations
    auto r = convert(strip("mismatch", o));
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("animation 'Bend' channel 0 (node 'J1' rotation) sampler 0: input "
                                     "accessor 5 has 3 keys, output accessor 6 has 8 values, 12 needed"),
              std::string::npos)
        << r.error().message;
}

TEST_F(AnimationConvert, ChannelOfAMissingNodeIsAnError) {
    StripOptions o;
    o.channelNode = 42;
    auto r = convert(strip("missingnode", o));
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("animation 'Bend' channel 0: target node 42 does not exist (4 nodes)"),
              std::string::npos)
        << r.error().message;
}

TEST_F(AnimationConvert, ZeroLengthClipIsKeptAndPlaysItsKey) {
    StripOptions o;
    o.times = {0};
    o.rotations = {0, 0, 0.7071068f, 0.7071068f};
    auto r = convert(strip("onekey", o));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Scene s = load();
    ASSERT_EQ(s.animations.size(), 1u);
    EXPECT_EQ(clipDuration(s.animations[0]), 0.0);
    const Pose p = poseAt(s, 0, 12.5);
    EXPECT_NEAR(p.graph.nodes[nodeNamed(s, "J1")].rotation.z, 0.7071068f, 1e-6f);
    expectMovesAt(s, nodeNamed(s, "Body"), 0, 3.0);
}

TEST_F(AnimationConvert, MillionKeyClipConvertsInSeconds) {
    StripOptions o;
    const size_t n = 1000000;
    o.times.resize(n);
    o.rotations.resize(n * 4);
    for (size_t k = 0; k < n; ++k) {
        o.times[k] = float(k) / 1000.0f;
        const float a = float(k % 1000) * 0.001f;
        o.rotations[k * 4 + 2] = std::sin(a);
        o.rotations[k * 4 + 3] = std::cos(a);
    }
    const std::string input = strip("million", o);
    const auto start = std::chrono::steady_clock::now();
    auto r = convert(input);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_TRUE(r.ok()) << r.error().message;
    std::cout << "10^6-key clip converted in " << seconds << " s\n";
    EXPECT_LT(seconds, 30.0) << "a quadratic step?";
    const Scene s = load();
    ASSERT_EQ(s.animations.size(), 1u);
    EXPECT_EQ(s.animations[0].channels[0].times.size(), n);
}

TEST_F(AnimationConvert, MeshSharedBySkinnedAndStaticNodesIsCopied) {
    Bin bin;
    std::string json = skinnedStrip({}, "shared.bin", bin);
    // A fifth node draws the same mesh without a skin.
    const std::string body = "{\"name\":\"Body\",\"mesh\":0,\"skin\":0}";
    json.replace(json.find(body), body.size(), body + ",{\"name\":\"Statue\",\"mesh\":0,\"translation\":[5,0,0]}");
    json.replace(json.find("\"children\":[1,3]"), 16, "\"children\":[1,3,4]");
    auto r = convert(write("shared", json, bin));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Scene s = load();
    const uint32_t skinned = s.nodes.nodes[nodeNamed(s, "Body")].mesh;
    const uint32_t still = s.nodes.nodes[nodeNamed(s, "Statue")].mesh;
    ASSERT_NE(skinned, still);
    EXPECT_NE(streamOf(s.meshes[skinned], VertexSemantic::Joints0), nullptr);
    EXPECT_EQ(streamOf(s.meshes[still], VertexSemantic::Joints0), nullptr);
    EXPECT_FALSE(isDeformed(s, nodeNamed(s, "Statue")));
}

// [SECTION] morph targets

TEST_F(AnimationConvert, MorphedTriangleWritesMorphTargetsAndWeightsClip) {
    Bin bin;
    const std::string json = morphedTriangle("morph.bin", bin);
    auto r = convert(write("morph", json, bin));
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Scene s = load();
    ASSERT_EQ(s.morphTargets.size(), 1u);
    const MorphTargets& t = s.morphTargets[0];
    EXPECT_EQ(t.weights, (std::vector<float>{0.25f, 0}));
    ASSERT_EQ(t.targets.size(), 2u);
    ASSERT_EQ(t.targets[0].deltas.size(), 1u) << "the source moves positions only";
    EXPECT_EQ(t.targets[0].deltas[0].semantic, VertexSemantic::Position);
    EXPECT_TRUE(s.skins.empty());
    ASSERT_EQ(s.animations.size(), 1u);
    EXPECT_EQ(s.animations[0].channels[0].property, AnimatedProperty::Weights);
    const Program* deform = programNamed(s, "deform");
    ASSERT_NE(deform, nullptr);
    EXPECT_EQ(definesOf(s, *deform), std::vector<std::string>{"MORPH"});
    // Rest bounds at the default weights: z = 0.25 everywhere.
    const Node& n = s.nodes.nodes[nodeNamed(s, "Morphed")];
    EXPECT_NEAR(n.worldBounds.min.z, 0.25f, 1e-6f);
    expectMovesAt(s, nodeNamed(s, "Morphed"), 0, 0.5);
}

TEST_F(AnimationConvert, StaticSceneHasNoAnimationChunksNorDeformProgram) {
    Bin bin;
    const std::string json = morphedTriangle("static.bin", bin, false);
    auto r = convert(write("static", json, bin));
    ASSERT_TRUE(r.ok()) << r.error().message;
    auto c = Container::open(mOutput);
    ASSERT_TRUE(c.ok());
    for (const ChunkInfo& info : c->chunks())
        EXPECT_TRUE(info.header.tag != tags::kMorphTargets && info.header.tag != tags::kSkin &&
                    info.header.tag != tags::kAnimation);
    const Scene s = load();
    EXPECT_EQ(programNamed(s, "deform"), nullptr);
    EXPECT_TRUE(s.morphTargets.empty() && s.skins.empty() && s.animations.empty());
}

// [SECTION] Khronos sample models

#ifdef PNB_KHRONOS_DIR
const fs::path kKhronos = PNB_KHRONOS_DIR;
#else
const fs::path kKhronos = "../shared/khronos";
#endif

#define PNB_REQUIRE_KHRONOS(model)                                                                 \
    do {                                                                                           \
        if (!fs::exists(kKhronos / (model)))                                                       \
            GTEST_SKIP() << (kKhronos / (model)) << " not found (../shared/khronos): skipped";     \
    } while (0)

// The first deformed node.
uint32_t deformedNode(const Scene& s) {
    for (uint32_t i = 0; i < s.nodes.nodes.size(); ++i)
        if (s.nodes.nodes[i].mesh != kNone && isDeformed(s, i)) return i;
    return kNone;
}

TEST_F(AnimationConvert, CesiumManHasOneSkinOf19JointsAndOneClip) {
    const fs::path model = kKhronos / "CesiumMan/glTF-Binary/CesiumMan.glb";
    PNB_REQUIRE_KHRONOS("CesiumMan/glTF-Binary/CesiumMan.glb");
    auto r = convert(model.string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Scene s = load();
    ASSERT_EQ(s.skins.size(), 1u);
    EXPECT_EQ(s.skins[0].joints.size(), 19u);
    ASSERT_EQ(s.animations.size(), 1u);
    EXPECT_NEAR(clipDuration(s.animations[0]), 2.0, 1e-3);
    EXPECT_TRUE(s.morphTargets.empty());
    const uint32_t node = deformedNode(s);
    ASSERT_NE(node, kNone);
    expectMovesAt(s, node, 0, 0.9);
}

TEST_F(AnimationConvert, FoxHasOneSkinOf24JointsAndThreeClips) {
    const fs::path model = kKhronos / "Fox/glTF-Binary/Fox.glb";
    PNB_REQUIRE_KHRONOS("Fox/glTF-Binary/Fox.glb");
    auto r = convert(model.string(), true); // quantized: the skinned mesh stays F32
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Scene s = load();
    ASSERT_EQ(s.skins.size(), 1u);
    EXPECT_EQ(s.skins[0].joints.size(), 24u);
    ASSERT_EQ(s.animations.size(), 3u);
    const char* names[] = {"Survey", "Walk", "Run"};
    const double durations[] = {3.4166667, 0.7083333, 1.1583333};
    const uint32_t node = deformedNode(s);
    ASSERT_NE(node, kNone);
    for (uint32_t c = 0; c < 3; ++c) {
        EXPECT_EQ(s.str(s.animations[c].name), names[c]);
        EXPECT_NEAR(clipDuration(s.animations[c]), durations[c], 1e-4);
        expectMovesAt(s, node, c, durations[c] * 0.4);
    }
}

TEST_F(AnimationConvert, AnimatedMorphCubeHasTwoTargetsAndOneClip) {
    const fs::path model = kKhronos / "AnimatedMorphCube/glTF/AnimatedMorphCube.gltf";
    PNB_REQUIRE_KHRONOS("AnimatedMorphCube/glTF/AnimatedMorphCube.gltf");
    auto r = convert(model.string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Scene s = load();
    ASSERT_EQ(s.morphTargets.size(), 1u);
    EXPECT_EQ(s.morphTargets[0].targets.size(), 2u);
    EXPECT_TRUE(s.skins.empty());
    ASSERT_EQ(s.animations.size(), 1u);
    EXPECT_NEAR(clipDuration(s.animations[0]), 4.2, 1e-3);
    const uint32_t node = deformedNode(s);
    ASSERT_NE(node, kNone);
    expectMovesAt(s, node, 0, 1.0);
}

// [SECTION] assimp (Collada)

// A Collada file: the same 1 x 2 strip skinned to J0 and J1 (J1 at y = 1, its inverse bind
// matrix a translation by -1), with one clip "Bend" turning J1 by 90 degrees about z in 1 s.
const char* const kSkinnedStripDae = R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries>
    <geometry id="strip-mesh" name="Strip"><mesh>
      <source id="strip-pos">
        <float_array id="strip-pos-array" count="18">0 0 0 1 0 0 0 1 0 1 1 0 0 2 0 1 2 0</float_array>
        <technique_common><accessor source="#strip-pos-array" count="6" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="strip-vtx"><input semantic="POSITION" source="#strip-pos"/></vertices>
      <triangles count="4"><input semantic="VERTEX" source="#strip-vtx" offset="0"/>
        <p>0 1 3 0 3 2 2 3 5 2 5 4</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_controllers>
    <controller id="strip-skin"><skin source="#strip-mesh">
      <bind_shape_matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</bind_shape_matrix>
      <source id="joints"><Name_array id="joints-array" count="2">J0 J1</Name_array>
        <technique_common><accessor source="#joints-array" count="2" stride="1">
          <param name="JOINT" type="name"/></accessor></technique_common></source>
      <source id="binds"><float_array id="binds-array" count="32">1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 1 0 0 0 0 1 0 -1 0 0 1 0 0 0 0 1</float_array>
        <technique_common><accessor source="#binds-array" count="2" stride="16">
          <param name="TRANSFORM" type="float4x4"/></accessor></technique_common></source>
      <source id="weights"><float_array id="weights-array" count="3">1 0.5 0.5</float_array>
        <technique_common><accessor source="#weights-array" count="3" stride="1">
          <param name="WEIGHT" type="float"/></accessor></technique_common></source>
      <joints><input semantic="JOINT" source="#joints"/><input semantic="INV_BIND_MATRIX" source="#binds"/></joints>
      <vertex_weights count="6">
        <input semantic="JOINT" source="#joints" offset="0"/><input semantic="WEIGHT" source="#weights" offset="1"/>
        <vcount>1 1 2 2 1 1</vcount>
        <v>0 0 0 0 0 1 1 2 0 1 1 2 1 0 1 0</v>
      </vertex_weights>
    </skin></controller>
  </library_controllers>
  <library_animations>
    <animation id="Bend" name="Bend">
      <source id="bend-in"><float_array id="bend-in-array" count="2">0 1</float_array>
        <technique_common><accessor source="#bend-in-array" count="2" stride="1">
          <param name="TIME" type="float"/></accessor></technique_common></source>
      <source id="bend-out"><float_array id="bend-out-array" count="32">1 0 0 0 0 1 0 1 0 0 1 0 0 0 0 1 0 -1 0 0 1 0 0 1 0 0 1 0 0 0 0 1</float_array>
        <technique_common><accessor source="#bend-out-array" count="2" stride="16">
          <param name="TRANSFORM" type="float4x4"/></accessor></technique_common></source>
      <source id="bend-interp"><Name_array id="bend-interp-array" count="2">LINEAR LINEAR</Name_array>
        <technique_common><accessor source="#bend-interp-array" count="2" stride="1">
          <param name="INTERPOLATION" type="name"/></accessor></technique_common></source>
      <sampler id="bend-sampler"><input semantic="INPUT" source="#bend-in"/>
        <input semantic="OUTPUT" source="#bend-out"/><input semantic="INTERPOLATION" source="#bend-interp"/></sampler>
      <channel source="#bend-sampler" target="J1/transform"/>
    </animation>
  </library_animations>
  <library_visual_scenes>
    <visual_scene id="Scene">
      <node id="J0" name="J0" sid="J0" type="JOINT">
        <node id="J1" name="J1" sid="J1" type="JOINT"><matrix sid="transform">1 0 0 0 0 1 0 1 0 0 1 0 0 0 0 1</matrix></node>
      </node>
      <node id="Body" name="Body"><instance_controller url="#strip-skin"><skeleton>#J0</skeleton></instance_controller></node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
)";

TEST_F(AnimationConvert, ColladaSkinnedStripWritesSkinAndClip) {
    const fs::path dae = mDir / "strip.dae";
    std::ofstream(dae) << kSkinnedStripDae;
    auto r = convert(dae.string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Scene s = load();
    ASSERT_EQ(s.skins.size(), 1u);
    const Skin& skin = s.skins[0];
    ASSERT_EQ(skin.joints.size(), 2u);
    EXPECT_EQ(s.str(s.nodes.nodes[skin.joints[0]].name), "J0");
    EXPECT_EQ(s.str(s.nodes.nodes[skin.joints[1]].name), "J1");
    EXPECT_NEAR(skin.inverseBindMatrices[1][13], -1.0f, 1e-6f) << "J1's offset: y - 1";
    ASSERT_EQ(skin.nodes.size(), 1u);
    ASSERT_EQ(s.animations.size(), 1u);
    const Animation& clip = s.animations[0];
    bool rotatesJ1 = false;
    for (const AnimationChannel& c : clip.channels)
        rotatesJ1 |= c.node == skin.joints[1] && c.property == AnimatedProperty::Rotation;
    EXPECT_TRUE(rotatesJ1);
    EXPECT_NEAR(clipDuration(clip), 1.0, 1e-4);
    // Half way, J1 has turned 45 degrees about z: the top row's vertices moved.
    const Pose p = poseAt(s, 0, 0.5);
    EXPECT_NEAR(p.graph.nodes[skin.joints[1]].rotation.z, std::sin(M_PI / 8), 1e-3);
    expectMovesAt(s, skin.nodes[0], 0, 0.5);
}

} // namespace
