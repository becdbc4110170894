// The moving scenes (crowd, moving-light) and the writer's skins, morph targets and animations:
// read back by glb_check (never by the writer), the skins must place every joint where its
// inverse bind matrix says, the weights must be a partition of one over joints of the skin, the
// clip must animate existing nodes with well-formed samplers, --count must set the walkers, and
// the same options must give the same bytes.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "glb_check.h"
#include "pnb_assets/procedural_scenes.h"

namespace {

using namespace pnb;
using assets::gltf::Document;
using nlohmann::json;
using test::Mat4;
using test::ParsedGlb;

struct Checked {
    std::vector<uint8_t> bytes;
    ParsedGlb glb;
    std::vector<Mat4> world;
};

Checked check(const Document& doc) {
    Checked c;
    EXPECT_EQ(assets::gltf::validateDocument(doc), "");
    c.bytes = assets::gltf::encodeGlb(doc);
    std::string error = test::parseGlb(c.bytes, c.glb);
    if (error.empty()) error = test::validateGltf(c.glb);
    EXPECT_EQ(error, "");
    if (error.empty()) c.world = test::worldMatrices(c.glb);
    return c;
}

Checked crowd(uint32_t count) {
    assets::SceneRequest r;
    r.count = count;
    std::optional<Document> doc = assets::buildProceduralScene("crowd", r);
    EXPECT_TRUE(doc.has_value());
    return check(doc ? *doc : Document{});
}

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 m{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            for (int k = 0; k < 4; ++k)
                m[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
    return m;
}

std::vector<double> accessorOf(const Checked& c, const json& ref) {
    return test::readAccessor(c.glb, ref.get<size_t>());
}

// --- crowd ------------------------------------------------------------------------------------

TEST(ProceduralCrowd, CountSetsTheWalkersWhoShareOneMeshAndHaveASkinEach) {
    for (uint32_t count : {1u, 100u}) {
        const Checked c = crowd(count);
        ASSERT_FALSE(c.world.empty());
        const json& j = c.glb.json;
        ASSERT_EQ(j["skins"].size(), count);
        std::set<size_t> meshes, skins;
        for (const json& n : j["nodes"])
            if (n.contains("skin")) {
                meshes.insert(n["mesh"].get<size_t>());
                skins.insert(n["skin"].get<size_t>());
            }
        EXPECT_EQ(meshes.size(), 1u) << "every walker draws the one walker mesh";
        EXPECT_EQ(skins.size(), count) << "every walker has its own skin";
        const json& walker = j["meshes"][*meshes.begin()];
        ASSERT_EQ(walker["primitives"].size(), 1u);
        const size_t triangles =
            j["accessors"][walker["primitives"][0]["indices"].get<size_t>()]["count"]
                .get<size_t>() /
            3;
        EXPECT_GE(triangles, 300u);
        EXPECT_LE(triangles, 2000u);
        EXPECT_GT(test::renderedTriangles(c.glb), triangles * count) << "walkers plus the room";
        EXPECT_EQ(j["animations"].size(), 1u) << "one clip holds every walker";
    }
    // The file stays small: shared mesh, bind pose and walk-cycle samplers.
    EXPECT_LT(crowd(100).bytes.size(), 2u << 20);
}

TEST(ProceduralCrowd, InverseBindMatricesUndoEachJointsBindPlacement) {
    const Checked c = crowd(3);
    ASSERT_FALSE(c.world.empty());
    const json& j = c.glb.json;
    for (size_t n = 0; n < j["nodes"].size(); ++n) {
        const json& node = j["nodes"][n];
        if (!node.contains("skin")) continue;
        const json& skin = j["skins"][node["skin"].get<size_t>()];
        std::vector<size_t> joints = skin["joints"];
        EXPECT_EQ(joints.size(), 12u);
        EXPECT_EQ(std::set<size_t>(joints.begin(), joints.end()).size(), joints.size());
        std::vector<double> ibm = accessorOf(c, skin["inverseBindMatrices"]);
        ASSERT_EQ(ibm.size(), 16 * joints.size());
        // The walker's root is the skeleton root's parent: at rest, world(joint) * IBM is that
        // root's world matrix for every joint (the bind pose is the rest pose).
        const size_t skeleton = skin["skeleton"];
        size_t walkerRoot = j["nodes"].size();
        for (size_t p = 0; p < j["nodes"].size(); ++p)
            for (size_t child : j["nodes"][p].value("children", std::vector<size_t>{}))
                if (child == skeleton) walkerRoot = p;
        ASSERT_LT(walkerRoot, j["nodes"].size());
        for (size_t k = 0; k < joints.size(); ++k) {
            Mat4 inv;
            std::copy(ibm.begin() + ptrdiff_t(16 * k), ibm.begin() + ptrdiff_t(16 * k + 16),
                      inv.begin());
            const Mat4 m = multiply(c.world[joints[k]], inv);
            for (int e = 0; e < 16; ++e)
                EXPECT_NEAR(m[e], c.world[walkerRoot][e], 1e-5)
                    << "joint " << k << " element " << e;
        }
    }
}

TEST(ProceduralCrowd, WeightsArePartitionsOfOneOverTheSkinsJointsAndBlendAcrossEachJoint) {
    const Checked c = crowd(1);
    const json& j = c.glb.json;
    size_t body = 0;
    while (!j["nodes"][body].contains("skin"))
        ++body;
    const size_t jointCount = j["skins"][j["nodes"][body]["skin"].get<size_t>()]["joints"].size();
    const json& attr =
        j["meshes"][j["nodes"][body]["mesh"].get<size_t>()]["primitives"][0]["attributes"];
    ASSERT_TRUE(attr.contains("NORMAL"));
    std::vector<double> joints = accessorOf(c, attr["JOINTS_0"]),
                        weights = accessorOf(c, attr["WEIGHTS_0"]);
    ASSERT_EQ(joints.size(), weights.size());
    std::set<std::pair<int, int>> blended; // joint pairs some vertex is shared between
    std::set<int> used;
    for (size_t v = 0; v < weights.size(); v += 4) {
        double sum = 0;
        std::vector<int> influences;
        for (int k = 0; k < 4; ++k) {
            EXPECT_GE(weights[v + k], 0.0);
            EXPECT_LT(joints[v + k], double(jointCount));
            sum += weights[v + k];
            if (weights[v + k] > 0) influences.push_back(int(joints[v + k]));
        }
        EXPECT_NEAR(sum, 1.0, 1e-6) << "vertex " << v / 4;
        EXPECT_EQ(std::set<int>(influences.begin(), influences.end()).size(), influences.size())
            << "a joint twice on vertex " << v / 4;
        used.insert(influences.begin(), influences.end());
        if (influences.size() == 2)
            blended.insert(
                {std::min(influences[0], influences[1]), std::max(influences[0], influences[1])});
    }
    EXPECT_EQ(used.size(), jointCount) << "every joint moves some vertex";
    // Smooth skinning: each of the 11 bones below the hips shares vertices with its parent.
    EXPECT_GE(blended.size(), 11u);
}

TEST(ProceduralCrowd, TheClipAnimatesEveryWalkersJointsAndRootAndLoops) {
    const Checked c = crowd(20);
    const json& j = c.glb.json;
    const json& clip = j["animations"][0];
    std::map<size_t, std::set<std::string>> animated;
    double start = 1e9, end = -1e9;
    std::map<size_t, std::vector<size_t>> thighSamplers;
    for (const json& ch : clip["channels"]) {
        const size_t node = ch["target"]["node"];
        ASSERT_LT(node, j["nodes"].size());
        animated[node].insert(ch["target"]["path"].get<std::string>());
        const json& smp = clip["samplers"][ch["sampler"].get<size_t>()];
        EXPECT_EQ(smp.value("interpolation", "LINEAR"), "LINEAR");
        std::vector<double> t = accessorOf(c, smp["input"]);
        start = std::min(start, t.front());
        end = std::max(end, t.back());
        if (j["nodes"][node].value("name", "").ends_with("/thigh-L"))
            thighSamplers[ch["sampler"].get<size_t>()].push_back(node);
    }
    EXPECT_EQ(start, 0.0);
    EXPECT_NEAR(end, 24.0, 1e-6);
    for (const json& skin : j["skins"])
        for (size_t joint : skin["joints"])
            EXPECT_TRUE(animated[joint].count("rotation")) << "joint node " << joint;
    size_t roots = 0;
    for (size_t n = 0; n < j["nodes"].size(); ++n) {
        const std::string name = j["nodes"][n].value("name", "");
        if (name.rfind("walker-", 0) != 0 || name.find('/') != std::string::npos) continue;
        ++roots;
        EXPECT_TRUE(animated[n].count("translation")) << name;
        // The lap closes: the last translation key is the first.
        for (const json& ch : clip["channels"])
            if (ch["target"]["node"] == n && ch["target"]["path"] == "translation") {
                std::vector<double> p =
                    accessorOf(c, clip["samplers"][ch["sampler"].get<size_t>()]["output"]);
                for (int k = 0; k < 3; ++k)
                    EXPECT_NEAR(p[k], p[p.size() - 3 + k], 1e-4) << name;
                const double x = p[0], z = p[2];
                EXPECT_GE(std::hypot(x, z), 1.4) << name << " starts off its lane";
                EXPECT_LE(std::hypot(x, z), 7.6) << name << " starts off its lane";
            }
    }
    EXPECT_EQ(roots, 20u);
    EXPECT_GE(thighSamplers.size(), 3u) << "the walkers are not all in step";
}

TEST(ProceduralCrowd, SameOptionsGiveIdenticalBytesAndTheSeedChangesThem) {
    EXPECT_TRUE(crowd(100).bytes == crowd(100).bytes);
    assets::SceneRequest r;
    r.count = 10;
    r.seed = 2;
    std::optional<Document> other = assets::buildProceduralScene("crowd", r);
    ASSERT_TRUE(other);
    EXPECT_FALSE(assets::gltf::encodeGlb(*other) == crowd(10).bytes);
}

// --- moving-light -----------------------------------------------------------------------------

TEST(ProceduralMovingLight, ALightABoxAndAMorphMoveInOneClip) {
    const Checked c = check(assets::buildMovingLight());
    ASSERT_FALSE(c.world.empty());
    const json& j = c.glb.json;
    ASSERT_EQ(j["animations"].size(), 1u);
    const json& clip = j["animations"][0];
    std::map<std::string, std::set<std::string>> animated;
    std::map<std::string, std::vector<double>> outputs;
    for (const json& ch : clip["channels"]) {
        const json& node = j["nodes"][ch["target"]["node"].get<size_t>()];
        const std::string path = ch["target"]["path"];
        animated[node.value("name", "")].insert(path);
        outputs[node.value("name", "") + "." + path] =
            accessorOf(c, clip["samplers"][ch["sampler"].get<size_t>()]["output"]);
    }
    const int lamp = test::findNode(c.glb, "moving-lamp");
    ASSERT_GE(lamp, 0);
    const size_t light = j["nodes"][lamp]["extensions"]["KHR_lights_punctual"]["light"];
    EXPECT_EQ(j["extensions"]["KHR_lights_punctual"]["lights"][light]["type"], "point");
    EXPECT_TRUE(animated["moving-lamp"].count("translation"));
    EXPECT_TRUE(animated["moving-box"].count("translation"));
    EXPECT_TRUE(animated["moving-box"].count("rotation"));
    EXPECT_TRUE(animated["morph-ball"].count("weights"));
    // The lamp travels metres, the box slides across the room, the ball squashes fully.
    const std::vector<double>& lampPath = outputs["moving-lamp.translation"];
    double reach = 0;
    for (size_t k = 0; k < lampPath.size(); k += 3)
        reach =
            std::max(reach, std::hypot(lampPath[k] - lampPath[0], lampPath[k + 2] - lampPath[2]));
    EXPECT_GT(reach, 3.0);
    const std::vector<double>& w = outputs["morph-ball.weights"];
    EXPECT_EQ(*std::min_element(w.begin(), w.end()), 0.0);
    EXPECT_GT(*std::max_element(w.begin(), w.end()), 0.95);
    const int ball = test::findNode(c.glb, "morph-ball");
    const json& mesh = j["meshes"][j["nodes"][ball]["mesh"].get<size_t>()];
    ASSERT_EQ(mesh["weights"].size(), 1u);
    ASSERT_EQ(mesh["primitives"][0]["targets"].size(), 1u);
    EXPECT_TRUE(check(assets::buildMovingLight()).bytes == c.bytes);
}

// --- the writer's validation of what it cannot write -----------------------------------------

Document skinnedTriangle() {
    Document doc;
    doc.materials.push_back({});
    assets::gltf::Primitive p;
    p.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    p.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    p.indices = {0, 1, 2};
    p.joints0 = {{0, 0, 0, 0}, {0, 1, 0, 0}, {1, 0, 0, 0}};
    p.weights0 = {{1, 0, 0, 0}, {0.5f, 0.5f, 0, 0}, {1, 0, 0, 0}};
    doc.meshes.push_back({"tri", {p}, {}});
    doc.nodes.resize(3);
    doc.nodes[0].children = {1, 2};
    doc.nodes[1].children = {};
    doc.nodes[2].mesh = 0;
    doc.nodes[2].skin = 0;
    doc.nodes[0].name = "j0";
    doc.nodes[1].name = "j1";
    const std::array<float, 16> identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    // Two skins on the same bind pose: their inverse bind matrices are stored once.
    doc.skins.push_back({"s", {0, 1}, {identity, identity}, 0});
    doc.animations.push_back({"a",
                              {{{0, 1}, {0, 0, 0, 1, 0, 0, 0, 1}, {}}},
                              {{0, 1, assets::gltf::AnimationPath::Rotation}}});
    return doc;
}

TEST(GltfWriterAnimation, WritesSkinsAndClipsThatReadBackAndStoresSharedDataOnce) {
    const Checked c = check(skinnedTriangle());
    const json& j = c.glb.json;
    EXPECT_EQ(j["nodes"][2]["skin"], 0);
    EXPECT_EQ(
        j["accessors"][j["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"].get<size_t>()]
         ["componentType"],
        5121);
    EXPECT_EQ(j["animations"][0]["channels"][0]["target"]["path"], "rotation");
    Document two = skinnedTriangle();
    two.skins.push_back(two.skins[0]);
    two.nodes.push_back(two.nodes[2]);
    two.nodes.back().skin = 1;
    two.nodes[0].children.push_back(3);
    const Checked d = check(two);
    EXPECT_EQ(d.glb.json["skins"][0]["inverseBindMatrices"],
              d.glb.json["skins"][1]["inverseBindMatrices"]);
}

TEST(GltfWriterAnimation, ValidationNamesBadSkinsWeightsAndSamplers) {
    auto why = [](auto change) {
        Document doc = skinnedTriangle();
        change(doc);
        return assets::gltf::validateDocument(doc);
    };
    EXPECT_EQ(why([](Document&) {}), "");
    EXPECT_NE(why([](Document& d) {
                  d.meshes[0].primitives[0].weights0[1] = {0.5f, 0.4f, 0, 0};
              }),
              "");
    EXPECT_NE(why([](Document& d) {
                  d.meshes[0].primitives[0].joints0[1] = {0, 2, 0, 0};
              }),
              "")
        << "joint index outside the skin";
    EXPECT_NE(why([](Document& d) { d.nodes[2].skin = assets::gltf::kNone; }), "");
    EXPECT_NE(why([](Document& d) { d.skins[0].inverseBindMatrices.pop_back(); }), "");
    EXPECT_NE(why([](Document& d) { d.animations[0].samplers[0].output.pop_back(); }), "");
    EXPECT_NE(why([](Document& d) { d.animations[0].samplers[0].input = {1, 1}; }), "");
    EXPECT_NE(why([](Document& d) { d.animations[0].channels[0].node = 7; }), "");
    EXPECT_NE(why([](Document& d) {
                  d.animations[0].channels[0].path = assets::gltf::AnimationPath::Weights;
              }),
              "")
        << "weights on a node without morph targets";
    EXPECT_NE(why([](Document& d) { d.animations[0].samplers[0].output[3] = 2; }), "")
        << "a rotation key that is not a unit quaternion";
}

} // namespace
