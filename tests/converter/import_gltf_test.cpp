// Tests of importGltf (converter/src/import_gltf.cpp). Models from Debian's assimp-testmodels
// (/usr/share/assimp/models/glTF2) for real files, and small glTF files written by the tests for
// the malformed cases: every error must name the file and the accessor or object at fault.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <unistd.h>

#include "pnb_converter/importers.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;

const fs::path kModels = "/usr/share/assimp/models/glTF2";

#define PNB_REQUIRE_MODELS()                                                                       \
    do {                                                                                           \
        if (!fs::exists(kModels)) GTEST_SKIP() << kModels << " missing (assimp test models)";      \
    } while (0)

Result<IrScene, ConvertError> load(const std::string& relative) {
    return importGltf((kModels / relative).string());
}

size_t triangleCount(const IrScene& s) {
    size_t n = 0;
    for (const IrMesh& m : s.meshes) {
        for (const IrPrimitive& p : m.primitives) n += p.indices.size() / 3;
    }
    return n;
}

bool hasWarning(const IrScene& s, const std::string& needle) {
    return std::any_of(s.warnings.begin(), s.warnings.end(),
                       [&](const std::string& w) { return w.find(needle) != std::string::npos; });
}

// The scene's "not rendered" entry for `feature`, or nullptr.
const IrNotRendered* notRendered(const IrScene& s, const std::string& feature) {
    for (const IrNotRendered& n : s.notRendered)
        if (n.feature == feature) return &n;
    return nullptr;
}

std::string allWarnings(const IrScene& s) {
    std::string out;
    for (const std::string& w : s.warnings) out += w + "\n";
    return out;
}

bool contains(const std::string& haystack, const std::string& needle) {
    return haystack.find(needle) != std::string::npos;
}

// Every index in range and a whole number of triangles: what the IR promises.
void expectValidPrimitives(const IrScene& s) {
    for (const IrMesh& m : s.meshes) {
        for (const IrPrimitive& p : m.primitives) {
            ASSERT_EQ(p.positions.size() % 3, 0u);
            ASSERT_EQ(p.indices.size() % 3, 0u);
            for (uint32_t i : p.indices) ASSERT_LT(i, p.vertexCount()) << m.name;
            EXPECT_TRUE(p.normals.empty() || p.normals.size() == p.vertexCount() * 3);
            EXPECT_TRUE(p.tangents.empty() || p.tangents.size() == p.vertexCount() * 4);
            EXPECT_TRUE(p.uv0.empty() || p.uv0.size() == p.vertexCount() * 2);
            EXPECT_TRUE(p.uv1.empty() || p.uv1.size() == p.vertexCount() * 2);
            EXPECT_TRUE(p.colors.empty() || p.colors.size() == p.vertexCount() * 4);
        }
    }
}

const uint8_t kPngMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

// [SECTION] real files

TEST(GltfImport, BoxTexturedWithExternalFiles) {
    PNB_REQUIRE_MODELS();
    auto r = load("BoxTextured-glTF/BoxTextured.gltf");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const IrScene& s = *r;
    EXPECT_TRUE(s.warnings.empty()) << allWarnings(s);
    ASSERT_EQ(s.dependencies.size(), 1u);
    EXPECT_TRUE(fs::equivalent(s.dependencies[0], kModels / "BoxTextured-glTF/BoxTextured0.bin"));
    ASSERT_EQ(s.meshes.size(), 1u);
    ASSERT_EQ(s.meshes[0].primitives.size(), 1u);
    const IrPrimitive& p = s.meshes[0].primitives[0];
    EXPECT_EQ(p.vertexCount(), 24u);
    EXPECT_EQ(p.indices.size(), 36u);
    EXPECT_EQ(p.normals.size(), 24u * 3);
    EXPECT_EQ(p.uv0.size(), 24u * 2);
    EXPECT_TRUE(p.uv1.empty());
    expectValidPrimitives(s);

    ASSERT_EQ(p.material, 0);
    ASSERT_EQ(s.materials.size(), 1u);
    const IrMaterial& m = s.materials[0];
    EXPECT_FLOAT_EQ(m.pbr.metallicFactor, 0.0f);
    EXPECT_FLOAT_EQ(m.pbr.roughnessFactor, 1.0f);
    const IrTextureRef& base = m.textures[size_t(TextureSlotKind::BaseColor)];
    ASSERT_EQ(base.image, 0);
    EXPECT_EQ(base.minFilter, MinFilter::NearestMipLinear); // 9986 in the file
    EXPECT_EQ(base.magFilter, MagFilter::Linear);
    EXPECT_EQ(base.wrapU, Wrap::MirroredRepeat); // 33648
    EXPECT_EQ(base.wrapV, Wrap::ClampToEdge);    // 33071
    EXPECT_EQ(m.textures[size_t(TextureSlotKind::Normal)].image, -1);
    ASSERT_EQ(s.images.size(), 1u);
    EXPECT_TRUE(s.images[0].encoded.empty());
    EXPECT_TRUE(fs::is_regular_file(s.images[0].path)) << s.images[0].path;
    EXPECT_EQ(fs::path(s.images[0].path).filename(), "CesiumLogoFlat.png");
    EXPECT_EQ(s.images[0].mimeType, "image/png");

    // Root with a matrix (-90 degrees about X), child with the mesh: parents first.
    ASSERT_EQ(s.nodes.size(), 2u);
    EXPECT_EQ(s.nodes[0].parent, -1);
    EXPECT_EQ(s.nodes[1].parent, 0);
    EXPECT_EQ(s.nodes[1].mesh, 0);
    const Vec4 q = s.nodes[0].rotation;
    EXPECT_NEAR(q.x, -std::sqrt(0.5f), 1e-6);
    EXPECT_NEAR(q.y, 0, 1e-6);
    EXPECT_NEAR(q.z, 0, 1e-6);
    EXPECT_NEAR(q.w, std::sqrt(0.5f), 1e-6);
    EXPECT_NEAR(s.nodes[0].scale.x, 1, 1e-6);
    EXPECT_NEAR(s.nodes[0].scale.y, 1, 1e-6);
}

TEST(GltfImport, BoxTexturedEmbeddedAndBinaryCarryEncodedPng) {
    PNB_REQUIRE_MODELS();
    for (const char* file : {"BoxTextured-glTF-Embedded/BoxTextured.gltf",
                             "BoxTextured-glTF-Binary/BoxTextured.glb"}) {
        SCOPED_TRACE(file);
        auto r = load(file);
        ASSERT_TRUE(r.ok()) << r.error().message;
        const IrScene& s = *r;
        ASSERT_EQ(s.meshes.size(), 1u);
        ASSERT_EQ(s.meshes[0].primitives.size(), 1u);
        EXPECT_EQ(s.meshes[0].primitives[0].vertexCount(), 24u);
        EXPECT_EQ(triangleCount(s), 12u);
        ASSERT_EQ(s.images.size(), 1u);
        const IrImage& img = s.images[0];
        EXPECT_TRUE(img.path.empty());
        ASSERT_GT(img.encoded.size(), 8u);
        EXPECT_EQ(std::memcmp(img.encoded.data(), kPngMagic, 8), 0);
        EXPECT_EQ(img.mimeType, "image/png");
        EXPECT_EQ(s.materials[0].textures[size_t(TextureSlotKind::BaseColor)].image, 0);
    }
}

// The Draco file was encoded from the same engine with degenerate triangles removed: 75730
// triangles uncompressed, of which 10413 repeat an index and 6 repeat a position.
TEST(GltfImport, DracoDecodesToTheUncompressedTriangles) {
    PNB_REQUIRE_MODELS();
    auto draco = load("draco/2CylinderEngine.gltf");
    ASSERT_TRUE(draco.ok()) << draco.error().message;
    auto plain = load("2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    expectValidPrimitives(*draco);
    expectValidPrimitives(*plain);
    EXPECT_TRUE(draco->warnings.empty()) << allWarnings(*draco);

    // Mesh by mesh (both files place the same meshes in the same node order).
    ASSERT_EQ(draco->meshes.size(), plain->meshes.size());
    size_t nonDegenerate = 0;
    for (size_t m = 0; m < plain->meshes.size(); ++m) {
        SCOPED_TRACE(plain->meshes[m].name);
        EXPECT_EQ(draco->meshes[m].name, plain->meshes[m].name);
        size_t meshNonDegenerate = 0, meshDraco = 0;
        for (const IrPrimitive& p : plain->meshes[m].primitives) {
            auto pos = [&](uint32_t i) {
                return std::vector<float>(p.positions.begin() + i * 3,
                                          p.positions.begin() + i * 3 + 3);
            };
            for (size_t t = 0; t < p.indices.size(); t += 3) {
                const uint32_t a = p.indices[t], b = p.indices[t + 1], c = p.indices[t + 2];
                if (a == b || b == c || a == c) continue;
                if (pos(a) == pos(b) || pos(b) == pos(c) || pos(a) == pos(c)) continue;
                ++meshNonDegenerate;
            }
        }
        for (const IrPrimitive& p : draco->meshes[m].primitives) meshDraco += p.indices.size() / 3;
        EXPECT_EQ(meshDraco, meshNonDegenerate);
        nonDegenerate += meshNonDegenerate;
    }
    EXPECT_EQ(nonDegenerate, 65311u);
    EXPECT_EQ(triangleCount(*draco), nonDegenerate);
    EXPECT_EQ(triangleCount(*plain), 75730u);
    ASSERT_FALSE(draco->meshes[0].primitives.empty());
    EXPECT_FALSE(draco->meshes[0].primitives[0].normals.empty());
}

TEST(GltfImport, TextureTransformsAndSamplers) {
    PNB_REQUIRE_MODELS();
    auto r = load("textureTransform/TextureTransformTest.gltf");
    ASSERT_TRUE(r.ok()) << r.error().message;
    std::map<std::string, IrTextureRef> byName;
    for (const IrMaterial& m : r->materials) {
        byName[m.name] = m.textures[size_t(TextureSlotKind::BaseColor)];
    }
    ASSERT_TRUE(byName.count("Offset U") && byName.count("Rotation") && byName.count("All"));
    EXPECT_FLOAT_EQ(byName["Offset U"].offset.x, 0.5f);
    EXPECT_FLOAT_EQ(byName["Offset U"].offset.y, 0.0f);
    EXPECT_FLOAT_EQ(byName["Rotation"].rotationRadians, 0.39269908f);
    EXPECT_FLOAT_EQ(byName["Scale"].scale.x, 1.5f);
    const IrTextureRef& all = byName["All"];
    EXPECT_FLOAT_EQ(all.offset.x, -0.2f);
    EXPECT_FLOAT_EQ(all.offset.y, -0.1f);
    EXPECT_FLOAT_EQ(all.rotationRadians, 0.3f);
    EXPECT_FLOAT_EQ(all.scale.y, 1.5f);
    EXPECT_EQ(all.wrapU, Wrap::ClampToEdge);
    EXPECT_EQ(all.minFilter, MinFilter::Linear);
    // "Correct" uses a texture without a sampler: defaults, identity transform.
    const IrTextureRef& plain = byName["Correct"];
    EXPECT_EQ(plain.wrapU, Wrap::Repeat);
    EXPECT_EQ(plain.minFilter, MinFilter::LinearMipLinear);
    EXPECT_FLOAT_EQ(plain.scale.x, 1.0f);
    EXPECT_FLOAT_EQ(plain.rotationRadians, 0.0f);
    // Meshes shared by several nodes are imported once.
    EXPECT_EQ(r->nodes.size(), 12u);
    EXPECT_LT(r->meshes.size(), r->nodes.size());
}

TEST(GltfImport, Cameras) {
    PNB_REQUIRE_MODELS();
    auto r = load("cameras/Cameras.gltf");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->cameras.size(), 2u);
    const IrCamera& persp = r->cameras[0];
    EXPECT_EQ(persp.projection, Projection::Perspective);
    EXPECT_FLOAT_EQ(persp.yfovRadians, 0.7f);
    EXPECT_FLOAT_EQ(persp.aspectRatio, 1.0f);
    EXPECT_FLOAT_EQ(persp.znear, 0.01f);
    EXPECT_FLOAT_EQ(persp.zfar, 100.0f);
    const IrCamera& ortho = r->cameras[1];
    EXPECT_EQ(ortho.projection, Projection::Orthographic);
    EXPECT_FLOAT_EQ(ortho.xmag, 1.0f);
    EXPECT_FLOAT_EQ(ortho.ymag, 1.0f);
    EXPECT_FLOAT_EQ(ortho.zfar, 100.0f);
    ASSERT_EQ(r->nodes.size(), 3u);
    EXPECT_EQ(r->nodes[1].camera, 0);
    EXPECT_EQ(r->nodes[2].camera, 1);
    EXPECT_FLOAT_EQ(r->nodes[1].translation.z, 3.0f);
}

// Asset generator Mesh_PrimitiveMode: 00-03 and 07-10 are points and lines (dropped), the rest
// are the same quad (two triangles) as lists, strips and fans, indexed or not.
TEST(GltfImport, PrimitiveModesBecomeTriangleLists) {
    PNB_REQUIRE_MODELS();
    const std::string dir = "glTF-Asset-Generator/Mesh_PrimitiveMode/";
    for (int i = 0; i <= 15; ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "Mesh_PrimitiveMode_%02d.gltf", i);
        SCOPED_TRACE(name);
        auto r = load(dir + name);
        ASSERT_TRUE(r.ok()) << r.error().message;
        expectValidPrimitives(*r);
        const bool pointsOrLines = (i <= 3) || (i >= 7 && i <= 10);
        if (pointsOrLines) {
            EXPECT_EQ(triangleCount(*r), 0u);
            // Named once among what is not rendered, with its fallback (not a warning).
            const IrNotRendered* n = notRendered(*r, i == 0 || i == 7 ? "points" : "lines");
            ASSERT_NE(n, nullptr) << allWarnings(*r);
            EXPECT_EQ(n->count, 1u);
            EXPECT_EQ(n->unit, "primitives");
            EXPECT_TRUE(contains(n->fallback, "dropped"));
            continue;
        }
        ASSERT_EQ(triangleCount(*r), 2u);
        // Both triangles face the same way as the plain triangle list (model 13): +Z.
        const IrPrimitive& p = r->meshes[0].primitives[0];
        for (size_t t = 0; t < p.indices.size(); t += 3) {
            auto at = [&](size_t k, int c) { return p.positions[p.indices[t + k] * 3 + c]; };
            const float ux = at(1, 0) - at(0, 0), uy = at(1, 1) - at(0, 1);
            const float vx = at(2, 0) - at(0, 0), vy = at(2, 1) - at(0, 1);
            EXPECT_GT(ux * vy - uy * vx, 0.0f) << "triangle " << t / 3 << " winds clockwise";
        }
        if (i == 4 || i == 5 || i == 6) { // unindexed: 0..n-1 before triangulation
            EXPECT_EQ(p.vertexCount(), i == 6 ? 6u : 4u);
        }
    }
}

// [SECTION] malformed files in the corpus

TEST(GltfImport, IndexOutOfRangeIsAnErrorNamingTheAccessor) {
    PNB_REQUIRE_MODELS();
    for (const char* file : {"IndexOutOfRange/IndexOutOfRange.gltf",
                             "IndexOutOfRange/AllIndicesOutOfRange.gltf"}) {
        auto r = load(file);
        ASSERT_FALSE(r.ok()) << file;
        const std::string& msg = r.error().message;
        EXPECT_EQ(r.error().kind, ConvertErrorKind::Input);
        EXPECT_TRUE(contains(msg, fs::path(file).filename().string())) << msg;
        EXPECT_TRUE(contains(msg, "accessor 0 (mesh 'Mesh' primitive 0 indices)")) << msg;
        EXPECT_TRUE(contains(msg, "out of range 0..23")) << msg;
    }
}

TEST(GltfImport, MissingBinIsAnErrorNamingTheBuffer) {
    PNB_REQUIRE_MODELS();
    auto r = load("MissingBin/BoxTextured.gltf");
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "BoxTextured.gltf: ")) << r.error().message;
    EXPECT_TRUE(contains(r.error().message, "BoxTextured0.bin")) << r.error().message;
}

TEST(GltfImport, RecursiveNodesIsAnError) {
    PNB_REQUIRE_MODELS();
    auto r = load("RecursiveNodes/RecursiveNodes.gltf");
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "RecursiveNodes.gltf: node 0")) << r.error().message;
    EXPECT_TRUE(contains(r.error().message, "cycle")) << r.error().message;
}

TEST(GltfImport, WrongTypesAreRepairedWithWarnings) {
    PNB_REQUIRE_MODELS();
    {
        auto r = load("wrongTypes/badArray.gltf"); // "primitives" is an object
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_EQ(triangleCount(*r), 0u);
        EXPECT_TRUE(hasWarning(*r, "mesh 'Mesh': no primitives")) << allWarnings(*r);
    }
    {
        auto r = load("wrongTypes/badExtension.gltf"); // KHR_texture_transform: "Not an object"
        ASSERT_TRUE(r.ok()) << r.error().message;
        const IrTextureRef& t = r->materials[0].textures[size_t(TextureSlotKind::BaseColor)];
        EXPECT_EQ(t.image, 0);
        EXPECT_FLOAT_EQ(t.scale.x, 1.0f);
        EXPECT_FLOAT_EQ(t.offset.x, 0.0f);
    }
    {
        auto r = load("wrongTypes/badNumber.gltf"); // normalTexture without index
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_TRUE(hasWarning(*r, "badNumber.gltf: tinygltf: 'index' property is missing"))
            << allWarnings(*r);
        EXPECT_EQ(r->materials[0].textures[size_t(TextureSlotKind::Normal)].image, -1);
    }
    {
        auto r = load("wrongTypes/badObject.gltf"); // pbrMetallicRoughness is an array
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_FLOAT_EQ(r->materials[0].pbr.metallicFactor, 1.0f);
        EXPECT_EQ(r->materials[0].textures[size_t(TextureSlotKind::BaseColor)].image, -1);
    }
    {
        auto r = load("wrongTypes/badUint.gltf"); // baseColorTexture index -1
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_EQ(r->materials[0].textures[size_t(TextureSlotKind::BaseColor)].image, -1);
        EXPECT_EQ(triangleCount(*r), 12u);
    }
    {
        auto r = load("wrongTypes/badString.gltf"); // a name that is a number
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_EQ(triangleCount(*r), 12u);
    }
}

TEST(GltfImport, InfinitePositionsPassThrough) {
    PNB_REQUIRE_MODELS();
    auto r = load("BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->meshes.size(), 1u);
    const std::vector<float>& pos = r->meshes[0].primitives[0].positions;
    EXPECT_TRUE(std::any_of(pos.begin(), pos.end(), [](float v) { return std::isinf(v); }));
    EXPECT_EQ(triangleCount(*r), 12u);
}

TEST(GltfImport, SchemaFailuresAndMissingScenes) {
    PNB_REQUIRE_MODELS();
    auto schema = load("SchemaFailures/sceneWrongType.gltf"); // "scene": "hello", no .bin
    ASSERT_FALSE(schema.ok());
    EXPECT_TRUE(contains(schema.error().message, "sceneWrongType.gltf: "));
    auto noScene = load("TestNoRootNode/NoScene.gltf"); // "scene": 0 and no scenes
    ASSERT_FALSE(noScene.ok());
    EXPECT_TRUE(contains(noScene.error().message, "NoScene.gltf: scene 0 does not exist"))
        << noScene.error().message;
    auto empty = load("TestNoRootNode/SceneWithoutNodes.gltf");
    ASSERT_TRUE(empty.ok()) << empty.error().message;
    EXPECT_TRUE(empty->nodes.empty());
}

TEST(GltfImport, RequiredUnsupportedExtensionIsUnsupported) {
    PNB_REQUIRE_MODELS();
    auto r = load("BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().kind, ConvertErrorKind::Unsupported);
    EXPECT_TRUE(contains(r.error().message, "KHR_technique_webgl")) << r.error().message;
    // Used but not required: named once among what is not rendered, with its fallback and how
    // much of the file uses it.
    auto clearcoat = load("ClearCoat-glTF/ClearCoatTest.gltf");
    ASSERT_TRUE(clearcoat.ok()) << clearcoat.error().message;
    const IrNotRendered* n = notRendered(*clearcoat, "KHR_materials_clearcoat");
    ASSERT_NE(n, nullptr);
    EXPECT_TRUE(contains(n->fallback, "base layer")) << n->fallback;
    EXPECT_TRUE(contains(n->unit, "materials")) << n->unit;
}

TEST(GltfImport, IncorrectVertexArraysAreTruncatedOrDropped) {
    PNB_REQUIRE_MODELS();
    auto r = load("IncorrectVertexArrays/Cube.gltf");
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectValidPrimitives(*r);
    // Cube and IndexedCube: 12 each; the truncated ones: 35 indices -> 11 triangles each.
    EXPECT_EQ(triangleCount(*r), 12u + 12u + 11u + 11u);
    EXPECT_TRUE(hasWarning(*r, "mesh 'TruncatedCube' primitive 0: 35 indices are not a multiple"))
        << allWarnings(*r);
    const IrNotRendered* lines = notRendered(*r, "lines"); // every LINES primitive of the file
    ASSERT_NE(lines, nullptr);
    EXPECT_GE(lines->count, 1u);
    EXPECT_TRUE(contains(lines->fallback, "dropped"));
}

TEST(GltfImport, SpecularGlossinessUsesTheFallback) {
    PNB_REQUIRE_MODELS();
    auto r = load("BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(hasWarning(*r, "KHR_materials_pbrSpecularGlossiness")) << allWarnings(*r);
    EXPECT_EQ(r->materials[0].textures[size_t(TextureSlotKind::BaseColor)].image, 0);
    EXPECT_FLOAT_EQ(r->materials[0].pbr.metallicFactor, 0.0f);
}

TEST(GltfImport, SkinsAndAnimationsAreImported) {
    PNB_REQUIRE_MODELS();
    auto skin = load("simple_skin/simple_skin.gltf");
    ASSERT_TRUE(skin.ok()) << skin.error().message;
    EXPECT_EQ(notRendered(*skin, "skins"), nullptr);
    ASSERT_EQ(skin->skins.size(), 1u);
    EXPECT_EQ(skin->skins[0].joints.size(), 2u);
    EXPECT_EQ(skin->animations.size(), 1u);
    EXPECT_GT(triangleCount(*skin), 0u);
    const IrNode* skinned = nullptr;
    for (const IrNode& n : skin->nodes)
        if (n.skin == 0) skinned = &n;
    ASSERT_NE(skinned, nullptr);
    ASSERT_GE(skinned->mesh, 0);
    const IrMesh& mesh = skin->meshes[size_t(skinned->mesh)];
    EXPECT_TRUE(mesh.skinned);
    EXPECT_EQ(mesh.primitives[0].joints.size(), mesh.primitives[0].vertexCount() * 4);
    auto morph = load("glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf");
    ASSERT_TRUE(morph.ok()) << morph.error().message;
    EXPECT_EQ(notRendered(*morph, "animations"), nullptr);
    ASSERT_EQ(morph->animations.size(), 1u);
    EXPECT_EQ(morph->animations[0].channels[0].property, AnimatedProperty::Weights);
    ASSERT_EQ(morph->meshes.size(), 1u);
    EXPECT_EQ(morph->meshes[0].morphWeights.size(), 2u);
}

// Every file in the corpus: no crash (the suite runs under ASan/UBSan), and either a scene whose
// primitives are valid, or an error with a message naming the file.
TEST(GltfImport, WholeCorpusImportsOrFailsCleanly) {
    PNB_REQUIRE_MODELS();
    size_t files = 0;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(kModels)) {
        const std::string ext = e.path().extension().string();
        if (ext != ".gltf" && ext != ".glb") continue;
        ++files;
        auto r = importGltf(e.path().string());
        const std::string rel = fs::relative(e.path(), kModels).string();
        if (r.ok()) {
            expectValidPrimitives(*r);
            std::cout << "[ ok    ] " << rel << " (" << triangleCount(*r) << " triangles, "
                      << r->warnings.size() << " warnings)\n";
        } else {
            const std::string& msg = r.error().message;
            EXPECT_FALSE(msg.empty()) << rel;
            EXPECT_TRUE(contains(msg, e.path().filename().string())) << rel << ": " << msg;
            std::cout << "[ error ] " << rel << ": " << msg << "\n";
        }
    }
    EXPECT_GE(files, 40u);
}

// [SECTION] crafted files

std::string base64(const std::vector<uint8_t>& in) {
    static const char* const kAlphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < in.size(); i += 3) {
        const uint32_t n = uint32_t(in[i]) << 16 |
                           (i + 1 < in.size() ? uint32_t(in[i + 1]) << 8 : 0) |
                           (i + 2 < in.size() ? uint32_t(in[i + 2]) : 0);
        out += kAlphabet[n >> 18 & 63];
        out += kAlphabet[n >> 12 & 63];
        out += i + 1 < in.size() ? kAlphabet[n >> 6 & 63] : '=';
        out += i + 2 < in.size() ? kAlphabet[n & 63] : '=';
    }
    return out;
}

// Little-endian bytes of a buffer under construction.
struct Bin {
    std::vector<uint8_t> bytes;
    template <class T> size_t add(std::initializer_list<T> values) {
        while (bytes.size() % 4) bytes.push_back(0);
        const size_t offset = bytes.size();
        for (T v : values) {
            uint8_t raw[sizeof(T)];
            std::memcpy(raw, &v, sizeof(T));
            bytes.insert(bytes.end(), raw, raw + sizeof(T));
        }
        return offset;
    }
    std::string buffer() const {
        return "{\"byteLength\":" + std::to_string(bytes.size()) +
               ",\"uri\":\"data:application/octet-stream;base64," + base64(bytes) + "\"}";
    }
};

class GltfCrafted : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        mDir = fs::temp_directory_path() /
               ("pnb_gltf_" + std::to_string(getpid()) + "_" + info->name());
        fs::create_directories(mDir);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(mDir, ec);
    }
    std::string write(const std::string& name, const std::string& text) {
        const fs::path path = mDir / name;
        std::ofstream(path, std::ios::binary) << text;
        return path.string();
    }
    // A file with one buffer (`bin`) and the given top-level members (JSON without braces).
    Result<IrScene, ConvertError> import(const Bin& bin, const std::string& members,
                                         const std::string& name = "t.gltf") {
        const std::string json = "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[" + bin.buffer() +
                                 "]," + members + "}";
        return importGltf(write(name, json));
    }

    fs::path mDir;
};

// One triangle: positions at byte 0 (36 bytes), mesh 'Tri' on node 0 of scene 0.
const char* const kTriangleScene =
    R"("meshes":[{"name":"Tri","primitives":[{"attributes":{"POSITION":0}}]}],)"
    R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0)";

// "accessors":[...], with accessor 0 = `count` float VEC3 in bufferView 0.
const std::string kPositionView = R"("bufferViews":[{"buffer":0,"byteLength":36}],)";

std::string positionAccessor(int count) {
    return R"("accessors":[{"bufferView":0,"componentType":5126,"count":)" +
           std::to_string(count) + R"(,"type":"VEC3"}],)";
}

Bin trianglePositions() {
    Bin bin;
    bin.add<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
    return bin;
}

TEST_F(GltfCrafted, ValidTriangleIsGeneratedIndices) {
    auto r = import(trianglePositions(),
                    kPositionView + positionAccessor(3) +
                    std::string(kTriangleScene));
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->meshes.size(), 1u);
    EXPECT_EQ(r->meshes[0].primitives[0].indices, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(r->meshes[0].primitives[0].material, -1);
}

TEST_F(GltfCrafted, AccessorCountLargerThanBufferViewNamesTheAccessor) {
    auto r = import(trianglePositions(),
                    kPositionView + positionAccessor(4) +
                    std::string(kTriangleScene));
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().kind, ConvertErrorKind::Input);
    EXPECT_EQ(r.error().message,
              "t.gltf: accessor 0 (mesh 'Tri' primitive 0 POSITION): byteOffset 0 + count 4 x "
              "stride 12 exceeds bufferView 0 (36 bytes)");
}

TEST_F(GltfCrafted, HugeCountIsRejectedBeforeAllocating) {
    auto r = import(trianglePositions(),
                    R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
                    R"("accessors":[{"bufferView":0,"componentType":5126,"count":4000000000,)"
                    R"("type":"VEC3"}],)" + std::string(kTriangleScene));
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "accessor 0 (mesh 'Tri' primitive 0 POSITION)"))
        << r.error().message;
    // No bufferView: zeros, but still bounded by the output budget.
    auto zeros = import(trianglePositions(),
                        R"("accessors":[{"componentType":5126,"count":4000000000,)"
                        R"("type":"VEC3"}],)" +
                            std::string(kTriangleScene));
    ASSERT_FALSE(zeros.ok());
    EXPECT_TRUE(contains(zeros.error().message, "accessor 0")) << zeros.error().message;
    EXPECT_TRUE(contains(zeros.error().message, "limit")) << zeros.error().message;
}

TEST_F(GltfCrafted, BufferViewOutsideBufferNamesBoth) {
    auto r = import(trianglePositions(),
                    std::string(R"("bufferViews":[{"buffer":0,"byteOffset":12,"byteLength":36}],)") +
                    positionAccessor(2) +
                        std::string(kTriangleScene));
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "accessor 0 (mesh 'Tri' primitive 0 POSITION): "
                                            "bufferView 0 (byteOffset 12, byteLength 36) exceeds "
                                            "buffer 0 (36 bytes)"))
        << r.error().message;
}

TEST_F(GltfCrafted, ByteStrideSmallerThanElementNamesTheAccessor) {
    auto r = import(trianglePositions(),
                    std::string(R"("bufferViews":[{"buffer":0,"byteLength":36,"byteStride":8}],)") +
                    positionAccessor(3) +
                        std::string(kTriangleScene));
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "accessor 0 (mesh 'Tri' primitive 0 POSITION): "
                                            "bufferView 0 byteStride 8 is smaller than the "
                                            "element (12 bytes)"))
        << r.error().message;
}

TEST_F(GltfCrafted, SparseIndexOutOfRangeNamesTheAccessor) {
    Bin bin = trianglePositions();
    const size_t idx = bin.add<uint16_t>({7, 0});
    const size_t val = bin.add<float>({5, 5, 5});
    auto r = import(bin,
                    "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},"
                    "{\"buffer\":0,\"byteOffset\":" + std::to_string(idx) + ",\"byteLength\":2},"
                    "{\"buffer\":0,\"byteOffset\":" + std::to_string(val) + ",\"byteLength\":12}],"
                    R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",)"
                    R"("sparse":{"count":1,"indices":{"bufferView":1,"componentType":5123},)"
                    R"("values":{"bufferView":2}}}],)" + std::string(kTriangleScene));
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "t.gltf: accessor 0 (mesh 'Tri' primitive 0 "
                                            "POSITION): sparse index 7 (entry 0) is out of "
                                            "range 0..2"))
        << r.error().message;
}

TEST_F(GltfCrafted, SparseValuesPastTheirBufferViewNameTheAccessor) {
    Bin bin = trianglePositions();
    const size_t idx = bin.add<uint16_t>({0, 2});
    auto r = import(bin,
                    "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},"
                    "{\"buffer\":0,\"byteOffset\":" + std::to_string(idx) + ",\"byteLength\":4}],"
                    R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",)"
                    R"("sparse":{"count":2,"indices":{"bufferView":1,"componentType":5123},)"
                    R"("values":{"bufferView":1}}}],)" + std::string(kTriangleScene));
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "accessor 0 (mesh 'Tri' primitive 0 POSITION) "
                                            "sparse values: byteOffset 0 + 2 x 12 bytes exceeds "
                                            "bufferView 1 (4 bytes)"))
        << r.error().message;
}

TEST_F(GltfCrafted, SparseValuesReplaceElements) {
    Bin bin = trianglePositions();
    const size_t idx = bin.add<uint8_t>({0, 2});
    const size_t val = bin.add<float>({-1, -2, -3, 7, 8, 9});
    // Base data from bufferView 0, plus a second accessor with no bufferView (zeros + sparse).
    const std::string sparse = ",\"sparse\":{\"count\":2,\"indices\":{\"bufferView\":1,"
                               "\"componentType\":5121},\"values\":{\"bufferView\":2}}}";
    auto r = import(bin,
                    "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},"
                    "{\"buffer\":0,\"byteOffset\":" + std::to_string(idx) + ",\"byteLength\":2},"
                    "{\"buffer\":0,\"byteOffset\":" + std::to_string(val) + ",\"byteLength\":24}],"
                    R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3")" +
                        sparse + R"(,{"componentType":5126,"count":3,"type":"VEC3")" + sparse +
                        "]," +
                        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1}}]}],)"
                        R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const IrPrimitive& p = r->meshes[0].primitives[0];
    EXPECT_EQ(p.positions, (std::vector<float>{-1, -2, -3, 1, 0, 0, 7, 8, 9}));
    EXPECT_EQ(p.normals, (std::vector<float>{-1, -2, -3, 0, 0, 0, 7, 8, 9}));
}

// KHR_mesh_quantization: short positions (raw), normalized byte normals, normalized ubyte
// texcoords, normalized ubyte rgb colours (alpha added), with explicit strides.
TEST_F(GltfCrafted, QuantizedAndNormalizedAttributes) {
    Bin bin;
    const size_t pos = bin.add<int16_t>({0, 0, 0, 0, 100, 0, 0, 0, 0, 100, 0, 0});
    const size_t nrm = bin.add<int8_t>({0, 0, 127, 0, 0, 0, -128, 0, 127, 0, 0, 0});
    const size_t uv = bin.add<uint8_t>({0, 255, 0, 0, 255, 0, 0, 0, 51, 102, 0, 0});
    const size_t col = bin.add<uint8_t>({255, 0, 0, 0, 0, 255, 0, 0, 0, 0, 255, 0});
    auto view = [](size_t offset, size_t length, int stride) {
        return "{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) + ",\"byteLength\":" +
               std::to_string(length) + ",\"byteStride\":" + std::to_string(stride) + "}";
    };
    auto r = import(bin,
                    "\"extensionsUsed\":[\"KHR_mesh_quantization\"],"
                    "\"extensionsRequired\":[\"KHR_mesh_quantization\"],"
                    "\"bufferViews\":[" + view(pos, 24, 8) + "," + view(nrm, 12, 4) + "," +
                        view(uv, 12, 4) + "," + view(col, 12, 4) + "],"
                    R"("accessors":[{"bufferView":0,"componentType":5122,"count":3,"type":"VEC3"},)"
                    R"({"bufferView":1,"componentType":5120,"normalized":true,"count":3,)"
                    R"("type":"VEC3"},{"bufferView":2,"componentType":5121,"normalized":true,)"
                    R"("count":3,"type":"VEC2"},{"bufferView":3,"componentType":5121,)"
                    R"("normalized":true,"count":3,"type":"VEC3"}],)"
                    R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,)"
                    R"("TEXCOORD_0":2,"COLOR_0":3}}]}],)"
                    R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->warnings.empty()) << allWarnings(*r);
    const IrPrimitive& p = r->meshes[0].primitives[0];
    EXPECT_EQ(p.positions, (std::vector<float>{0, 0, 0, 100, 0, 0, 0, 100, 0}));
    EXPECT_EQ(p.normals, (std::vector<float>{0, 0, 1, 0, 0, -1, 1, 0, 0})); // -128 -> -1
    ASSERT_EQ(p.uv0.size(), 6u);
    EXPECT_FLOAT_EQ(p.uv0[0], 0.0f);
    EXPECT_FLOAT_EQ(p.uv0[1], 1.0f);
    EXPECT_FLOAT_EQ(p.uv0[4], 0.2f);
    EXPECT_FLOAT_EQ(p.uv0[5], 0.4f);
    EXPECT_EQ(p.colors, (std::vector<float>{1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1}));
}

TEST_F(GltfCrafted, AttributeCountMismatchNamesTheAccessor) {
    Bin bin = trianglePositions();
    const size_t uv = bin.add<float>({0, 0, 1, 0});
    auto r = import(bin,
                    "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},{\"buffer\":0,"
                    "\"byteOffset\":" + std::to_string(uv) + ",\"byteLength\":16}],"
                    R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
                    R"({"bufferView":1,"componentType":5126,"count":2,"type":"VEC2"}],)"
                    R"("meshes":[{"name":"Tri","primitives":[{"attributes":{"POSITION":0,)"
                    R"("TEXCOORD_0":1}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "t.gltf: accessor 1 (mesh 'Tri' primitive 0 TEXCOORD_0): count 2 "
                                 "differs from POSITION's 3");
}

TEST_F(GltfCrafted, WrongAccessorTypeAndMissingAccessorNameTheAccessor) {
    auto r = import(trianglePositions(),
                    kPositionView + positionAccessor(3) +
                    R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"TANGENT":0}}]}],)"
                    R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])");
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "accessor 0 (mesh 0 primitive 0 TANGENT): type VEC3, "
                                            "expected VEC4"))
        << r.error().message;
    auto missing = import(trianglePositions(),
                          R"("meshes":[{"primitives":[{"attributes":{"POSITION":5}}]}],)"
                          R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])");
    ASSERT_FALSE(missing.ok());
    EXPECT_TRUE(contains(missing.error().message, "accessor 5 (mesh 0 primitive 0 POSITION): does "
                                                  "not exist (0 accessors)"))
        << missing.error().message;
}

TEST_F(GltfCrafted, NodeWithTwoParentsIsAnError) {
    auto r = import(trianglePositions(),
                    R"("nodes":[{"name":"A","children":[2]},{"name":"B","children":[2]},)"
                    R"({"name":"C"}],"scenes":[{"nodes":[0,1]}])");
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "t.gltf: node 'C' is referenced more than once (again "
                                            "by node 'B')"))
        << r.error().message;
    auto self = import(trianglePositions(),
                       R"("nodes":[{"children":[0]}],"scenes":[{"nodes":[0]}])");
    ASSERT_FALSE(self.ok());
    EXPECT_TRUE(contains(self.error().message, "cycle")) << self.error().message;
    auto dangling = import(trianglePositions(),
                           R"("nodes":[{"children":[9]}],"scenes":[{"nodes":[0]}])");
    ASSERT_FALSE(dangling.ok());
    EXPECT_TRUE(contains(dangling.error().message, "node 0 refers to node 9, which does not "
                                                   "exist"))
        << dangling.error().message;
}

TEST_F(GltfCrafted, DeepChainIsFlattenedParentsFirst) {
    std::string nodes = "\"nodes\":[";
    const int n = 5000; // deeper than any recursion would like
    for (int i = 0; i < n; ++i) {
        nodes += i + 1 < n ? "{\"children\":[" + std::to_string(i + 1) + "]}," : "{}";
    }
    auto r = import(trianglePositions(), nodes + "],\"scenes\":[{\"nodes\":[0]}]");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->nodes.size(), size_t(n));
    for (int i = 0; i < n; ++i) EXPECT_EQ(r->nodes[size_t(i)].parent, i - 1);
}

TEST_F(GltfCrafted, MatricesDecomposeWithMirrorAndShearWarnings) {
    auto r = import(trianglePositions(),
                    // 0: translate (1,2,3), scale (2,3,4). 1: mirror in x. 2: shear.
                    R"("nodes":[{"name":"S","matrix":[2,0,0,0, 0,3,0,0, 0,0,4,0, 1,2,3,1]},)"
                    R"({"name":"M","matrix":[-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]},)"
                    R"({"name":"H","matrix":[1,0,0,0, 0.5,1,0,0, 0,0,1,0, 0,0,0,1]}],)"
                    R"("scenes":[{"nodes":[0,1,2]}])");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->nodes.size(), 3u);
    const IrNode& s = r->nodes[0];
    EXPECT_FLOAT_EQ(s.translation.x, 1);
    EXPECT_FLOAT_EQ(s.translation.z, 3);
    EXPECT_FLOAT_EQ(s.scale.x, 2);
    EXPECT_FLOAT_EQ(s.scale.y, 3);
    EXPECT_FLOAT_EQ(s.scale.z, 4);
    EXPECT_FLOAT_EQ(s.rotation.w, 1);
    EXPECT_FLOAT_EQ(r->nodes[1].scale.x, -1);
    EXPECT_FLOAT_EQ(r->nodes[1].rotation.w, 1);
    EXPECT_TRUE(hasWarning(*r, "node 'H': matrix has shear")) << allWarnings(*r);
    EXPECT_FALSE(hasWarning(*r, "node 'S'")) << allWarnings(*r);
}

// Morph targets are carried as deltas with the mesh's default weights (glTF §3.7.2.2); a node's
// own weights override the mesh's and give that node a mesh of its own, with its weights.
TEST_F(GltfCrafted, MorphTargetsKeepTheirDeltasAndDefaultWeights) {
    Bin bin;
    bin.add<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});    // base triangle
    bin.add<float>({0, 0, 2, 0, 0, 2, 0, 0, 2});    // target 0: +2 z everywhere
    bin.add<float>({1, 0, 0, 0, 0, 0, 0, 0, 0});    // target 1: vertex 0 +1 x
    const std::string members =
        R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},)"
        R"({"buffer":0,"byteOffset":36,"byteLength":36},{"buffer":0,"byteOffset":72,"byteLength":36}],)"
        R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
        R"({"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"},)"
        R"({"bufferView":2,"componentType":5126,"count":3,"type":"VEC3"}],)"
        R"("meshes":[{"name":"M","weights":[0.5,0.25],"primitives":[{"attributes":{"POSITION":0},)"
        R"("targets":[{"POSITION":1},{"POSITION":2}]}]}],)"
        R"("nodes":[{"mesh":0},{"mesh":0},{"mesh":0,"weights":[1,0]}],"scenes":[{"nodes":[0,1,2]}],"scene":0)";
    auto r = import(bin, members);
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->nodes.size(), 3u);
    EXPECT_EQ(r->nodes[0].mesh, r->nodes[1].mesh) << "nodes at the default weights share the mesh";
    ASSERT_NE(r->nodes[2].mesh, r->nodes[0].mesh) << "a node with its own weights gets its own";
    const IrMesh& shared = r->meshes[size_t(r->nodes[0].mesh)];
    EXPECT_EQ(shared.primitives[0].positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}));
    EXPECT_EQ(shared.morphWeights, (std::vector<float>{0.5f, 0.25f}));
    ASSERT_EQ(shared.primitives[0].targets.size(), 2u);
    EXPECT_EQ(shared.primitives[0].targets[1].positions, (std::vector<float>{1, 0, 0, 0, 0, 0, 0, 0, 0}));
    EXPECT_TRUE(shared.primitives[0].targets[0].normals.empty()) << "the mesh has no normals to move";
    const IrMesh& own = r->meshes[size_t(r->nodes[2].mesh)];
    EXPECT_EQ(own.morphWeights, (std::vector<float>{1, 0}));
}

TEST_F(GltfCrafted, LightsEmissiveStrengthAndCameraDefaults) {
    auto r = import(trianglePositions(),
                    R"("extensionsUsed":["KHR_lights_punctual","KHR_materials_emissive_strength"],)"
                    R"("extensions":{"KHR_lights_punctual":{"lights":[)"
                    R"({"type":"directional","color":[1,0.5,0.25],"intensity":3},)"
                    R"({"type":"point","range":5,"intensity":20},)"
                    R"({"type":"spot","spot":{"innerConeAngle":0.1,"outerConeAngle":0.5}}]}},)"
                    R"("cameras":[{"type":"perspective","perspective":{"yfov":1.0,"znear":0.5}}],)"
                    R"("nodes":[{"extensions":{"KHR_lights_punctual":{"light":0}}},)"
                    R"({"extensions":{"KHR_lights_punctual":{"light":2}}},)"
                    R"({"extensions":{"KHR_lights_punctual":{"light":1}}},{"camera":0}],)"
                    R"("scenes":[{"nodes":[0,1,2,3]}])");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->warnings.empty()) << allWarnings(*r);
    ASSERT_EQ(r->lights.size(), 3u);
    EXPECT_EQ(r->lights[0].type, LightType::Directional);
    EXPECT_FLOAT_EQ(r->lights[0].color.y, 0.5f);
    EXPECT_FLOAT_EQ(r->lights[0].intensity, 3);
    EXPECT_EQ(r->lights[1].type, LightType::Spot); // imported in node order
    EXPECT_FLOAT_EQ(r->lights[1].innerConeRadians, 0.1f);
    EXPECT_FLOAT_EQ(r->lights[1].outerConeRadians, 0.5f);
    EXPECT_EQ(r->lights[2].type, LightType::Point);
    EXPECT_FLOAT_EQ(r->lights[2].range, 5);
    EXPECT_EQ(r->nodes[1].light, 1);
    ASSERT_EQ(r->cameras.size(), 1u);
    EXPECT_FLOAT_EQ(r->cameras[0].aspectRatio, 0); // absent
    EXPECT_FLOAT_EQ(r->cameras[0].zfar, 0);        // absent: infinite
    EXPECT_FLOAT_EQ(r->cameras[0].znear, 0.5f);

    auto badLight = import(trianglePositions(),
                           R"("nodes":[{"extensions":{"KHR_lights_punctual":{"light":4}}}],)"
                           R"("scenes":[{"nodes":[0]}])");
    ASSERT_FALSE(badLight.ok());
    EXPECT_TRUE(contains(badLight.error().message, "node 0: light 4 does not exist"))
        << badLight.error().message;
}

TEST_F(GltfCrafted, MaterialFactorsAlphaAndEmissiveStrength) {
    auto r = import(trianglePositions(),
                    kPositionView + positionAccessor(3) +
                    R"("materials":[{"name":"Glow","emissiveFactor":[1,0.5,0],"alphaMode":"MASK",)"
                    R"("alphaCutoff":0.25,"doubleSided":true,"pbrMetallicRoughness":{)"
                    R"("baseColorFactor":[0.5,0.25,1,0.75],"metallicFactor":0.1,)"
                    R"("roughnessFactor":0.2},"extensions":{"KHR_materials_emissive_strength":)"
                    R"({"emissiveStrength":4}}}],)"
                    R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],)"
                    R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->materials.size(), 1u);
    const Material& m = r->materials[0].pbr;
    EXPECT_EQ(r->materials[0].name, "Glow");
    EXPECT_FLOAT_EQ(m.baseColorFactor.y, 0.25f);
    EXPECT_FLOAT_EQ(m.baseColorFactor.w, 0.75f);
    EXPECT_FLOAT_EQ(m.metallicFactor, 0.1f);
    EXPECT_FLOAT_EQ(m.roughnessFactor, 0.2f);
    EXPECT_FLOAT_EQ(m.emissiveFactor.y, 0.5f);
    EXPECT_FLOAT_EQ(m.emissiveStrength, 4);
    EXPECT_EQ(m.alphaMode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(m.alphaCutoff, 0.25f);
    EXPECT_TRUE(m.doubleSided);
    EXPECT_EQ(r->meshes[0].primitives[0].material, 0);
}

TEST_F(GltfCrafted, UnusedVerticesOfASharedAccessorAreDropped) {
    Bin bin;
    bin.add<float>({9, 9, 9, 0, 0, 0, 1, 0, 0, 9, 9, 9, 0, 1, 0});
    const size_t idx = bin.add<uint16_t>({1, 2, 4, 0});
    auto r = import(bin,
                    "\"bufferViews\":[{\"buffer\":0,\"byteLength\":60},{\"buffer\":0,"
                    "\"byteOffset\":" + std::to_string(idx) + ",\"byteLength\":6}],"
                    R"("accessors":[{"bufferView":0,"componentType":5126,"count":5,"type":"VEC3"},)"
                    R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],)"
                    R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
                    R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const IrPrimitive& p = r->meshes[0].primitives[0];
    EXPECT_EQ(p.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}));
    EXPECT_EQ(p.indices, (std::vector<uint32_t>{0, 1, 2}));
}

TEST_F(GltfCrafted, UnsupportedExtensionsWarnOrFail) {
    auto used = import(trianglePositions(), R"("extensionsUsed":["KHR_materials_sheen"])");
    ASSERT_TRUE(used.ok()) << used.error().message;
    ASSERT_EQ(used->notRendered.size(), 1u);
    EXPECT_EQ(used->notRendered[0].feature, "KHR_materials_sheen");
    EXPECT_EQ(used->notRendered[0].unit, "declared"); // used by no material of this file
    EXPECT_TRUE(used->warnings.empty()) << allWarnings(*used);
    auto required = import(trianglePositions(),
                           R"("extensionsUsed":["KHR_materials_sheen","KHR_materials_volume"],)"
                           R"("extensionsRequired":["KHR_materials_volume"])");
    ASSERT_FALSE(required.ok());
    EXPECT_EQ(required.error().kind, ConvertErrorKind::Unsupported);
    EXPECT_TRUE(contains(required.error().message, "KHR_materials_volume"));
}

TEST_F(GltfCrafted, MissingImageFileDropsTheTextureWithAWarning) {
    auto r = import(trianglePositions(),
                    kPositionView + positionAccessor(3) +
                    R"("images":[{"uri":"no%20such.png"}],"textures":[{"source":0}],)"
                    R"("materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],)"
                    R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],)"
                    R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->images.empty());
    EXPECT_EQ(r->materials[0].textures[size_t(TextureSlotKind::BaseColor)].image, -1);
    EXPECT_TRUE(hasWarning(*r, "no such.png' not found")) << allWarnings(*r);
    // With the file present (percent-decoded name), the path resolves next to the .gltf.
    write("no such.png", "\x89PNG\r\n\x1a\n");
    auto found = importGltf((mDir / "t.gltf").string());
    ASSERT_TRUE(found.ok()) << found.error().message;
    ASSERT_EQ(found->images.size(), 1u);
    EXPECT_EQ(found->images[0].path, (mDir / "no such.png").string());
    EXPECT_EQ(found->images[0].mimeType, "image/png");
}

TEST_F(GltfCrafted, ImageBufferViewOutsideItsBufferIsAnError) {
    // tinygltf 2.7 would hand the image callback a pointer past the buffer: caught before.
    auto r = import(trianglePositions(),
                    R"("bufferViews":[{"buffer":0,"byteOffset":30,"byteLength":100}],)"
                    R"("images":[{"bufferView":0,"mimeType":"image/png"}])");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "t.gltf: image 0: bufferView 0 (byteOffset 30, byteLength 100) "
                                 "exceeds buffer 0 (36 bytes)");
}

TEST_F(GltfCrafted, DeeplyNestedJsonIsRejected) {
    std::string deep = "\"extras\":";
    for (int i = 0; i < 100000; ++i) deep += "[";
    for (int i = 0; i < 100000; ++i) deep += "]";
    auto r = import(trianglePositions(), deep);
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "t.gltf: JSON nests deeper")) << r.error().message;
}

TEST_F(GltfCrafted, DracoErrorsAreClean) {
    // The KHR_draco_mesh_compression edits that crash tinygltf's built-in decoder.
    Bin bin = trianglePositions();
    const std::string mesh = [](const std::string& ext) {
        return R"("extensionsUsed":["KHR_draco_mesh_compression"],)"
               R"("bufferViews":[{"buffer":0,"byteLength":36}],)"
               R"("accessors":[{"componentType":5126,"count":3,"type":"VEC3"}],)"
               R"("meshes":[{"name":"D","primitives":[{"attributes":{"POSITION":0},)"
               R"("extensions":{"KHR_draco_mesh_compression":)" + ext + "}}]}],"
               R"("nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])";
    }(R"({"bufferView":99,"attributes":{"POSITION":0}})");
    auto outOfRange = import(bin, mesh);
    ASSERT_FALSE(outOfRange.ok());
    EXPECT_TRUE(contains(outOfRange.error().message, "t.gltf: mesh 'D' primitive 0 "
                                                     "KHR_draco_mesh_compression: bufferView 99 "
                                                     "does not exist"))
        << outOfRange.error().message;
    std::string garbage = mesh;
    garbage.replace(garbage.find("99"), 2, "0");
    auto notDraco = import(bin, garbage);
    ASSERT_FALSE(notDraco.ok());
    EXPECT_TRUE(contains(notDraco.error().message, "is not a Draco triangle mesh"))
        << notDraco.error().message;
}

TEST_F(GltfCrafted, DracoUnknownAttributeIdIsAnError) {
    PNB_REQUIRE_MODELS();
    std::ifstream in(kModels / "draco/2CylinderEngine.gltf");
    std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // The first primitive's Draco POSITION id (1) becomes an id the Draco mesh does not have.
    const size_t at = json.find("\"POSITION\": 1");
    ASSERT_NE(at, std::string::npos);
    json.replace(at, 13, "\"POSITION\": 7");
    fs::copy_file(kModels / "draco/2CylinderEngine.bin", mDir / "2CylinderEngine.bin");
    auto r = importGltf(write("engine.gltf", json));
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "engine.gltf: accessor 2 (mesh "
                                            "'Piston_123-844_0_Parts_1' primitive 0 POSITION): "
                                            "Draco attribute 7 does not exist"))
        << r.error().message;
}

// Every prefix of a GLB, with the header's length as in the original and patched to the prefix
// size (so the chunk checks, not just the length check, are exercised): an error, never a crash.
TEST_F(GltfCrafted, TruncatedGlbIsAnError) {
    PNB_REQUIRE_MODELS();
    std::ifstream in(kModels / "BoxTextured-glTF-Binary/BoxTextured.glb", std::ios::binary);
    const std::string glb((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(glb.size(), 1000u);
    std::vector<size_t> sizes;
    for (size_t n = 0; n < 64; ++n) sizes.push_back(n);
    for (size_t n = 64; n < glb.size(); n += 97) sizes.push_back(n);
    for (size_t n = glb.size() - 16; n < glb.size(); ++n) sizes.push_back(n);
    for (size_t n : sizes) {
        for (bool patch : {false, true}) {
            std::string prefix = glb.substr(0, n);
            if (patch && n >= 12) {
                const uint32_t len = uint32_t(n);
                std::memcpy(prefix.data() + 8, &len, 4);
            }
            auto r = importGltf(write("box.glb", prefix));
            ASSERT_FALSE(r.ok()) << n << (patch ? " patched" : "");
            EXPECT_TRUE(contains(r.error().message, "box.glb: ")) << r.error().message;
        }
    }
    // A GLB whose BIN chunk claims to reach exactly the end of the file (tinygltf would read
    // 8 bytes past it).
    std::string lying = glb;
    uint32_t jsonLength;
    std::memcpy(&jsonLength, lying.data() + 12, 4);
    const uint32_t binLength = uint32_t(lying.size() - 20 - jsonLength);
    std::memcpy(lying.data() + 20 + jsonLength, &binLength, 4);
    auto r = importGltf(write("box.glb", lying));
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "BIN chunk")) << r.error().message;
}

TEST(GltfImport, MissingFileIsAnError) {
    auto r = importGltf("/nonexistent/dir/scene.gltf");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().kind, ConvertErrorKind::Input);
    EXPECT_TRUE(contains(r.error().message, "scene.gltf: cannot open")) << r.error().message;
}

} // namespace
