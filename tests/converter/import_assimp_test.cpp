// Tests of the assimp importer (import_assimp.cpp) on Debian's assimp test models
// (/usr/share/assimp/models, package assimp-testmodels) and on hand-written OBJ/MTL files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <string_view>
#include <unistd.h>
#include <vector>

#include "pnb_converter/importers.h"
#include "import_test_support.h"
#include "pnb_converter/mtl_to_pbr.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;
using namespace pnb::converter::test;

// World transform helpers, to check where lights and cameras end up.
struct Vec3d {
    double x = 0, y = 0, z = 0;
};
Vec3d rotate(const Vec4& q, Vec3d v) {
    // v' = v + 2w (q x v) + 2 q x (q x v)
    const Vec3d u{q.x, q.y, q.z};
    auto cross = [](Vec3d a, Vec3d b) {
        return Vec3d{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    };
    const Vec3d t = cross(u, v);
    const Vec3d t2{2 * t.x, 2 * t.y, 2 * t.z};
    const Vec3d c = cross(u, t2);
    return {v.x + q.w * t2.x + c.x, v.y + q.w * t2.y + c.y, v.z + q.w * t2.z + c.z};
}
Vec3d toWorld(const IrScene& scene, int node, Vec3d point, bool isDirection) {
    for (; node >= 0; node = scene.nodes[size_t(node)].parent) {
        const IrNode& n = scene.nodes[size_t(node)];
        point = {point.x * n.scale.x, point.y * n.scale.y, point.z * n.scale.z};
        point = rotate(n.rotation, point);
        if (!isDirection) point = {point.x + n.translation.x, point.y + n.translation.y,
                                   point.z + n.translation.z};
    }
    return point;
}
Vec3d normalized(Vec3d v) {
    const double len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    return {v.x / len, v.y / len, v.z / len};
}
int nodeWithCamera(const IrScene& scene, int camera) {
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        if (scene.nodes[i].camera == camera) return int(i);
    }
    return -1;
}
int nodeWithLight(const IrScene& scene, int light) {
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        if (scene.nodes[i].light == light) return int(i);
    }
    return -1;
}

TEST(AssimpImport, BoxObjHasTwelveTrianglesOverTwentyFourCorners) {
    const std::string file = (kModels / "OBJ/box.obj").string();
    auto r = importWithAssimp(file);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectConsistent(*r, file);
    ASSERT_EQ(r->meshes.size(), 1u);
    ASSERT_EQ(r->meshes[0].primitives.size(), 1u);
    const IrPrimitive& p = r->meshes[0].primitives[0];
    // 6 quads → 12 triangles; assimp's OBJ reader gives every face corner its own vertex.
    EXPECT_EQ(p.indices.size(), 36u);
    EXPECT_EQ(p.vertexCount(), 24u);
    EXPECT_TRUE(p.normals.empty()) << "the file has none; the mesh stage generates them";
    EXPECT_TRUE(p.uv0.empty());
    for (float v : p.positions) EXPECT_EQ(std::abs(v), 0.5f);
    // Root node named after the file, then object "1" holding the mesh.
    ASSERT_EQ(r->nodes.size(), 2u);
    EXPECT_EQ(r->nodes[0].name, "box.obj");
    EXPECT_EQ(r->nodes[1].name, "1");
    EXPECT_EQ(r->nodes[1].parent, 0);
    EXPECT_EQ(r->nodes[1].mesh, 0);
    EXPECT_EQ(r->sourcePath, file);
}

TEST(AssimpImport, SpiderObjResolvesWindowsTexturePathsAndMapsMtl) {
    const std::string file = (kModels / "OBJ/spider.obj").string();
    auto r = importWithAssimp(file);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectConsistent(*r, file);
    EXPECT_EQ(r->meshes.size(), 19u); // one per object ("g" group), each with one material
    // spider.mtl: "Kd 0.827451 0.792157 0.772549", "Ns 0", "map_Kd .\wal67ar_small.jpg".
    const IrMaterial* skin = findMaterial(*r, "Skin");
    ASSERT_NE(skin, nullptr);
    EXPECT_NEAR(skin->pbr.baseColorFactor.x, 0.827451f, 1e-6f);
    EXPECT_NEAR(skin->pbr.baseColorFactor.y, 0.792157f, 1e-6f);
    EXPECT_NEAR(skin->pbr.baseColorFactor.z, 0.772549f, 1e-6f);
    EXPECT_EQ(skin->pbr.baseColorFactor.w, 1.0f);
    EXPECT_EQ(skin->pbr.roughnessFactor, expectedRoughness(0.0f));
    EXPECT_EQ(skin->pbr.metallicFactor, 0.0f);
    EXPECT_EQ(skin->pbr.alphaMode, AlphaMode::Opaque);
    const fs::path texture = imagePath(*r, *skin, TextureSlotKind::BaseColor);
    EXPECT_EQ(texture.filename(), "wal67ar_small.jpg");
    EXPECT_TRUE(fs::exists(texture)) << texture;
    // Every textured material found its file: '.\name.jpg' is a relative Windows path.
    for (const auto& m : r->materials) {
        const fs::path p = imagePath(*r, m, TextureSlotKind::BaseColor);
        EXPECT_TRUE(fs::exists(p)) << m.name << ": " << p;
    }
    EXPECT_FALSE(hasWarning(*r, {"not found"})) << allWarnings(*r);
    // assimp's synthesized "DefaultMaterial" (unused here) stays out of the IR.
    EXPECT_EQ(findMaterial(*r, "DefaultMaterial"), nullptr);
    // UVs flipped to glTF's v-down: all of this model's UVs are in [0,1] either way.
    for (const auto& mesh : r->meshes) {
        for (const auto& p : mesh.primitives) EXPECT_FALSE(p.uv0.empty()) << mesh.name;
    }
}

TEST(AssimpImport, CubeUsemtlIsOneMeshWithAPrimitivePerMaterialRun) {
    const std::string file = (kModels / "OBJ/cube_usemtl.obj").string();
    auto r = importWithAssimp(file);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectConsistent(*r, file);
    // Object "cube" switches material 4 times: assimp makes 4 aiMeshes, we make one mesh with 4
    // primitives on one node.
    ASSERT_EQ(r->meshes.size(), 1u);
    EXPECT_EQ(r->meshes[0].name, "cube");
    ASSERT_EQ(r->meshes[0].primitives.size(), 4u);
    const int cube = findNode(*r, "cube");
    ASSERT_GE(cube, 0);
    EXPECT_EQ(r->nodes[size_t(cube)].mesh, 0);
    const IrMaterial* mtl = findMaterial(*r, "mtl");
    const IrMaterial* mtl2 = findMaterial(*r, "mtl2");
    ASSERT_NE(mtl, nullptr);
    ASSERT_NE(mtl2, nullptr);
    EXPECT_FLOAT_EQ(mtl->pbr.roughnessFactor, expectedRoughness(200.0f)); // "Ns 200.000"
    EXPECT_FLOAT_EQ(mtl2->pbr.roughnessFactor, expectedRoughness(16.0f)); // "Ns 16.000"
    EXPECT_LT(mtl->pbr.roughnessFactor, mtl2->pbr.roughnessFactor);
    const auto& prims = r->meshes[0].primitives;
    EXPECT_EQ(prims[1].material, prims[3].material) << "both runs use 'mtl'";
    EXPECT_EQ(r->materials[size_t(prims[1].material)].name, "mtl");
}

TEST(AssimpImport, HandWrittenObjMtlMapsEverything) {
    TempDir dir("scene");
    const std::string file = writeHandWrittenScene(dir.path);
    auto r = importWithAssimp(file);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectConsistent(*r, file);
    std::cout << "warnings:\n" << allWarnings(*r);

    // Meshes: group "front" = 2 materials → 1 mesh, 2 primitives; each quad → 2 triangles.
    const int front = findNode(*r, "front");
    const int back = findNode(*r, "back");
    ASSERT_GE(front, 0);
    ASSERT_GE(back, 0);
    const IrMesh& frontMesh = r->meshes[size_t(r->nodes[size_t(front)].mesh)];
    EXPECT_EQ(frontMesh.name, "front");
    ASSERT_EQ(frontMesh.primitives.size(), 2u);
    EXPECT_EQ(frontMesh.primitives[0].indices.size(), 6u);
    EXPECT_EQ(frontMesh.primitives[1].indices.size(), 6u);
    EXPECT_NE(frontMesh.primitives[0].material, frontMesh.primitives[1].material);
    const IrMesh& backMesh = r->meshes[size_t(r->nodes[size_t(back)].mesh)];
    ASSERT_EQ(backMesh.primitives.size(), 1u);
    EXPECT_EQ(backMesh.primitives[0].indices.size(), 3u);
    EXPECT_TRUE(hasWarning(*r, {"mesh 'back'", "line"})) << allWarnings(*r);

    // Streams: V flipped to glTF's convention (vt 0 0.25 → v 0.75), vertex colours kept.
    const IrPrimitive& quad = frontMesh.primitives[0];
    ASSERT_EQ(quad.uv0.size(), quad.vertexCount() * 2);
    EXPECT_FLOAT_EQ(quad.uv0[0], 0.0f);
    EXPECT_FLOAT_EQ(quad.uv0[1], 0.75f);
    ASSERT_EQ(quad.colors.size(), quad.vertexCount() * 4);
    EXPECT_FLOAT_EQ(quad.colors[0], 1.0f);
    EXPECT_FLOAT_EQ(quad.colors[1], 0.0f);
    EXPECT_FLOAT_EQ(quad.colors[3], 1.0f);
    ASSERT_EQ(quad.normals.size(), quad.vertexCount() * 3);
    EXPECT_FLOAT_EQ(quad.normals[2], 1.0f);

    // "painted": Kd/Ns/d/Ke through applyMtlToPbr; the mtllib was found despite its case.
    const IrMaterial* painted = findMaterial(*r, "painted");
    ASSERT_NE(painted, nullptr);
    MtlParameters expected;
    expected.kd = {0.5f, 0.25f, 1.0f};
    expected.ns = 10.0f;
    expected.d = 0.5f;
    expected.ke = {0.1f, 0.2f, 0.3f};
    Material want;
    applyMtlToPbr(expected, want);
    EXPECT_FLOAT_EQ(painted->pbr.baseColorFactor.x, 0.5f);
    EXPECT_FLOAT_EQ(painted->pbr.baseColorFactor.y, 0.25f);
    EXPECT_FLOAT_EQ(painted->pbr.baseColorFactor.w, 0.5f);
    EXPECT_FLOAT_EQ(painted->pbr.roughnessFactor, want.roughnessFactor);
    EXPECT_FLOAT_EQ(painted->pbr.emissiveFactor.z, 0.3f);
    EXPECT_EQ(painted->pbr.alphaMode, AlphaMode::Blend) << "d 0.5";
    // Windows path, wrong case → resolved; map_d is the same file → its alpha, no warning.
    EXPECT_EQ(imagePath(*r, *painted, TextureSlotKind::BaseColor),
              (dir.path / "textures/albedo.png").lexically_normal());
    EXPECT_EQ(imagePath(*r, *painted, TextureSlotKind::Normal),
              (dir.path / "textures/normal.png").lexically_normal());
    EXPECT_FLOAT_EQ(painted->pbr.normalScale, 0.5f) << "-bm 0.5";
    EXPECT_FALSE(hasWarning(*r, {"material 'painted'", "opacity"})) << allWarnings(*r);
    EXPECT_TRUE(hasWarning(*r, {"material 'painted'", "spec.png", "ignored"}))
        << allWarnings(*r);

    // "glass": Tr 0.25 → alpha 0.75; foreign absolute path → same name next to the OBJ (with a
    // warning); a separate map_d → warning; map_Ke with no Ke → emissive factor 1.
    const IrMaterial* glass = findMaterial(*r, "glass");
    ASSERT_NE(glass, nullptr);
    EXPECT_FLOAT_EQ(glass->pbr.baseColorFactor.w, 0.75f);
    EXPECT_EQ(glass->pbr.alphaMode, AlphaMode::Blend);
    EXPECT_EQ(imagePath(*r, *glass, TextureSlotKind::BaseColor),
              (dir.path / "glass.jpg").lexically_normal());
    EXPECT_TRUE(hasWarning(*r, {"material 'glass'", "Glass.jpg", "same file name"}))
        << allWarnings(*r);
    EXPECT_TRUE(hasWarning(*r, {"material 'glass'", "mask.png", "not supported"}))
        << allWarnings(*r);
    EXPECT_EQ(imagePath(*r, *glass, TextureSlotKind::Emissive),
              (dir.path / "glow.png").lexically_normal());
    EXPECT_FLOAT_EQ(glass->pbr.emissiveFactor.x, 1.0f);
    EXPECT_EQ(r->images.size(), 4u) << "albedo, normal, glass, glow (each once)";
}

TEST(AssimpImport, CutoutWhenOpacityMapIsTheBaseColourAlpha) {
    TempDir dir("cutout");
    writeFile(dir.path / "leaf.obj", "mtllib leaf.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                     "usemtl leaf\nf 1 2 3\n");
    writeFile(dir.path / "leaf.mtl", "newmtl leaf\nKd 1 1 1\nmap_Kd leaf.png\nmap_d leaf.png\n");
    writeFile(dir.path / "leaf.png", "png");
    auto r = importWithAssimp((dir.path / "leaf.obj").string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->materials.size(), 1u);
    EXPECT_EQ(r->materials[0].pbr.alphaMode, AlphaMode::Mask);
    EXPECT_EQ(r->materials[0].pbr.baseColorFactor.w, 1.0f);
}

TEST(AssimpImport, MissingTexturesAndMaterialLibrariesAreWarningsNotErrors) {
    TempDir dir("missing");
    writeFile(dir.path / "a.obj", "mtllib nowhere.mtl\nmtllib b.mtl\nv 0 0 0\nv 1 0 0\n"
                                  "v 0 1 0\nusemtl m\nf 1 2 3\n");
    writeFile(dir.path / "b.mtl", "newmtl m\nKd 1 0 0\nmap_Kd gone.png\n");
    auto r = importWithAssimp((dir.path / "a.obj").string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(hasWarning(*r, {"nowhere.mtl"})) << allWarnings(*r);
    EXPECT_TRUE(hasWarning(*r, {"material 'm'", "gone.png", "not found"})) << allWarnings(*r);
    const IrMaterial* m = findMaterial(*r, "m");
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(m->textures[size_t(TextureSlotKind::BaseColor)].image, -1);
    EXPECT_FLOAT_EQ(m->pbr.baseColorFactor.x, 1.0f);
}

TEST(AssimpImport, MalformedObjIsAnErrorNamingTheFileNeverACrash) {
    TempDir dir("malformed");
    struct Case {
        const char* name;
        std::string_view content;
        const char* expect; // part of the message
    };
    const Case cases[] = {
        {"out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n", "out of range"},
        {"negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -9 2 3\n", "out of range"},
        {"zero_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n@@ junk\nf 0 0 0\n", "face index"},
        {"empty.obj", "", "too small"},
        {"binary.obj", std::string_view("\x00\x01\x02\xff\xfe junk junk junk junk", 25),
         "mNumMeshes is 0"},
        {"points_only.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 2 3\n", "no triangle meshes"},
        {"lines_only.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n", "no triangle meshes"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const fs::path path = dir.path / c.name;
        writeFile(path, c.content);
        auto r = importWithAssimp(path.string());
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().kind, ConvertErrorKind::Input);
        EXPECT_NE(r.error().message.find(path.string()), std::string::npos) << r.error().message;
        EXPECT_NE(r.error().message.find(c.expect), std::string::npos) << r.error().message;
    }
    // Not a file at all.
    auto missing = importWithAssimp((dir.path / "does_not_exist.obj").string());
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("does_not_exist.obj"), std::string::npos);
    auto directory = importWithAssimp(dir.path.string());
    ASSERT_FALSE(directory.ok());
}

TEST(AssimpImport, MalformedObjRepairsAreDocumented) {
    TempDir dir("repairs");
    // Garbage lines are skipped by assimp's reader; an out-of-range normal index makes it drop
    // the mesh's normals (regenerated by the mesh stage); NaN positions pass through to the mesh
    // stage, which drops their triangles with a warning.
    writeFile(dir.path / "garbage.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\n"
                                        "this is not obj\n#comment\nxyz 1 2 3\n"
                                        "f 1//1 2//5 3//1\n");
    auto r = importWithAssimp((dir.path / "garbage.obj").string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->meshes.size(), 1u);
    EXPECT_EQ(r->meshes[0].primitives[0].indices.size(), 3u);
    EXPECT_TRUE(r->meshes[0].primitives[0].normals.empty());

    writeFile(dir.path / "nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    auto n = importWithAssimp((dir.path / "nan.obj").string());
    ASSERT_TRUE(n.ok()) << n.error().message;
    EXPECT_EQ(n->meshes[0].primitives[0].vertexCount(), 3u);
}

// Every OBJ of the assimp test corpus: no crash (this runs under ASan/UBSan in the sanitizer
// build), and either a consistent scene or an error that names the file.
TEST(AssimpImport, EveryObjInTheAssimpCorpus) {
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(kModels / "OBJ")) {
        if (entry.path().extension() == ".obj") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    ASSERT_GE(files.size(), 20u);
    int ok = 0, failed = 0;
    for (const auto& path : files) {
        auto r = importWithAssimp(path.string());
        if (r.ok()) {
            ++ok;
            expectConsistent(*r, path.string());
            std::cout << "ok    " << path.filename().string() << " (" << r->meshes.size()
                      << " meshes, " << r->warnings.size() << " warnings)\n";
        } else {
            ++failed;
            EXPECT_NE(r.error().message.find(path.string()), std::string::npos)
                << r.error().message;
            std::cout << "error " << r.error().message << "\n";
        }
    }
    std::cout << ok << " ok, " << failed << " errors\n";
    EXPECT_GT(ok, failed);
}

TEST(AssimpImport, FbxLightsAndCamerasKeepTheirPlacement) {
    const std::string file = (kModels / "FBX/global_settings.fbx").string();
    auto r = importWithAssimp(file);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectConsistent(*r, file);
    ASSERT_EQ(r->cameras.size(), 2u);
    ASSERT_EQ(r->lights.size(), 2u);
    // Camera "Camera": node matrix rows (-0.651558 -0.324013 0.685921 7.48113 | -0.445271
    // 0.895396 0 5.34367 | -0.614171 -0.305421 -0.727676 6.50764); assimp's camera looks down
    // local +X. The IR camera looks down its node's -Z: in world space that must be column 0.
    int camera = -1;
    for (size_t i = 0; i < r->cameras.size(); ++i) {
        if (r->cameras[i].name == "Camera") camera = int(i);
    }
    ASSERT_GE(camera, 0);
    const int node = nodeWithCamera(*r, camera);
    ASSERT_GE(node, 0);
    const Vec3d forward = normalized(toWorld(*r, node, {0, 0, -1}, true));
    EXPECT_NEAR(forward.x, -0.651558, 1e-4);
    EXPECT_NEAR(forward.y, -0.445271, 1e-4);
    EXPECT_NEAR(forward.z, -0.614171, 1e-4);
    const Vec3d position = toWorld(*r, node, {0, 0, 0}, false);
    EXPECT_NEAR(position.x, 7.48113, 1e-3);
    EXPECT_NEAR(position.y, 5.34367, 1e-3);
    EXPECT_NEAR(position.z, 6.50764, 1e-3);
    const IrCamera& cam = r->cameras[size_t(camera)];
    EXPECT_EQ(cam.projection, Projection::Perspective);
    EXPECT_NEAR(cam.aspectRatio, 1.77778f, 1e-4f);
    EXPECT_NEAR(cam.yfovRadians, 2 * std::atan(std::tan(0.857556f / 2) / 1.77778f), 1e-4f);
    EXPECT_NEAR(cam.znear, 0.1f, 1e-6f);
    EXPECT_NEAR(cam.zfar, 100.0f, 1e-3f);
    // Point light "Lamp": attenuation 1/(0.00222223 d^2) reaches 1/256 at sqrt(256/q).
    int lamp = -1;
    for (size_t i = 0; i < r->lights.size(); ++i) {
        if (r->lights[i].name == "Lamp") lamp = int(i);
    }
    ASSERT_GE(lamp, 0);
    EXPECT_EQ(r->lights[size_t(lamp)].type, LightType::Point);
    EXPECT_NEAR(r->lights[size_t(lamp)].range, std::sqrt(256.0f / 0.00222223f), 0.5f);
    EXPECT_TRUE(hasWarning(*r, {"light 'Lamp'", "range"})) << allWarnings(*r);
    const Vec3d lampPos = toWorld(*r, nodeWithLight(*r, lamp), {0, 0, 0}, false);
    EXPECT_NEAR(lampPos.x, 4.07625, 1e-3);
    EXPECT_NEAR(lampPos.y, 5.90386, 1e-3);
}

TEST(AssimpImport, BlendFileIsConvertedFromZUp) {
    const std::string file = (kModels / "BLEND/TorusLightsCams_250_compressed.blend").string();
    auto r = importWithAssimp(file);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectConsistent(*r, file);
    // Blender's default camera sits at (7.48, -6.51, 5.34) with +Z up: (7.48, 5.34, 6.51) in Y-up.
    const int node = findNode(*r, "Camera");
    ASSERT_GE(node, 0);
    const Vec3d p = toWorld(*r, node, {0, 0, 0}, false);
    EXPECT_NEAR(p.x, 7.48113, 1e-3);
    EXPECT_NEAR(p.y, 5.34367, 1e-3);
    EXPECT_NEAR(p.z, 6.50764, 1e-3);
    EXPECT_EQ(r->lights.size(), 5u);
    EXPECT_EQ(r->cameras.size(), 2u);
}

TEST(AssimpImport, ColladaDirectionalLightAndCamera) {
    const std::string file = (kModels / "Collada/duck.dae").string();
    auto r = importWithAssimp(file);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectConsistent(*r, file);
    ASSERT_EQ(r->lights.size(), 1u);
    EXPECT_EQ(r->lights[0].type, LightType::Directional);
    EXPECT_EQ(r->lights[0].range, 0.0f);
    ASSERT_EQ(r->cameras.size(), 1u);
    EXPECT_NEAR(r->cameras[0].aspectRatio, 1.5f, 1e-6f);
    // A file with lights but no mesh is an empty scene.
    auto lightsOnly = importWithAssimp((kModels / "Collada/lights.dae").string());
    ASSERT_FALSE(lightsOnly.ok());
    EXPECT_NE(lightsOnly.error().message.find("lights.dae"), std::string::npos);
}

// A spot light hanging from a rotated node, with colour > 1 and quadratic attenuation.
constexpr std::string_view kSpotDae = R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_lights>
    <light id="spot" name="spot">
      <technique_common><spot><color>2 1 0.5</color>
        <constant_attenuation>1</constant_attenuation><linear_attenuation>0</linear_attenuation>
        <quadratic_attenuation>0.25</quadratic_attenuation>
        <falloff_angle>60</falloff_angle><falloff_exponent>0</falloff_exponent>
      </spot></technique_common>
    </light>
  </library_lights>
  <library_geometries>
    <geometry id="tri" name="tri"><mesh>
      <source id="pos"><float_array id="pos-a" count="9">0 0 0 1 0 0 0 1 0</float_array>
        <technique_common><accessor source="#pos-a" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="verts"><input semantic="POSITION" source="#pos"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#verts" offset="0"/><p>0 1 2</p>
      </triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene">
      <node id="mesh" name="mesh"><instance_geometry url="#tri"/></node>
      <node id="spotnode" name="spot"><translate>0 5 0</translate><rotate>1 0 0 -90</rotate>
        <instance_light url="#spot"/></node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";

TEST(AssimpImport, SpotLightConeRangeColourAndDirection) {
    TempDir dir("spot");
    writeFile(dir.path / "spot.dae", kSpotDae);
    auto r = importWithAssimp((dir.path / "spot.dae").string());
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectConsistent(*r, "spot.dae");
    ASSERT_EQ(r->lights.size(), 1u);
    const IrLight& light = r->lights[0];
    EXPECT_EQ(light.type, LightType::Spot);
    // Colour 2 1 0.5 = colour (1, 0.5, 0.25) x intensity 2.
    EXPECT_FLOAT_EQ(light.intensity, 2.0f);
    EXPECT_FLOAT_EQ(light.color.y, 0.5f);
    EXPECT_FLOAT_EQ(light.color.z, 0.25f);
    // 1 / (1 + 0.25 d^2) = 1/256 at d = sqrt(255 / 0.25).
    EXPECT_NEAR(light.range, std::sqrt(255.0f / 0.25f), 1e-3f);
    // falloff_angle 60 (a full angle) → inner half angle 30 degrees; outer ≤ 90 degrees.
    EXPECT_NEAR(light.innerConeRadians, 0.5235988f, 1e-5f);
    EXPECT_GE(light.outerConeRadians, light.innerConeRadians);
    EXPECT_LE(light.outerConeRadians, 1.5707964f);
    // The node is at y = 5 and rotated -90 degrees about X: the light shines straight down.
    const int node = nodeWithLight(*r, 0);
    ASSERT_GE(node, 0);
    const Vec3d position = toWorld(*r, node, {0, 0, 0}, false);
    EXPECT_NEAR(position.y, 5.0, 1e-5);
    const Vec3d direction = normalized(toWorld(*r, node, {0, 0, -1}, true));
    EXPECT_NEAR(direction.x, 0.0, 1e-5);
    EXPECT_NEAR(direction.y, -1.0, 1e-5);
    EXPECT_NEAR(direction.z, 0.0, 1e-5);
}

TEST(AssimpImport, FbxZUpMetadataRotatesTheRootAndEmbeddedTextureIsUsedByName) {
    // UpAxis 2 (+Z up), FrontAxis 1 with sign -1: 3ds Max's axes.
    const std::string file = (kModels / "FBX/embedded_ascii/box.FBX").string();
    auto r = importWithAssimp(file);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectConsistent(*r, file);
    ASSERT_EQ(r->nodes[0].parent, -1);
    const Vec3d up = toWorld(*r, 0, {0, 0, 1}, true);
    EXPECT_NEAR(up.x, 0.0, 1e-6);
    EXPECT_NEAR(up.y, 1.0, 1e-6) << "file +Z is IR +Y";
    EXPECT_NEAR(up.z, 0.0, 1e-6);
    const Vec3d front = toWorld(*r, 0, {0, -1, 0}, true);
    EXPECT_NEAR(front.z, 1.0, 1e-6) << "file -Y (front) is IR +Z";
    // The material names '..\..\..\Desktop\uv_test.png', which the FBX embeds.
    ASSERT_EQ(r->materials.size(), 1u);
    const int image = r->materials[0].textures[size_t(TextureSlotKind::BaseColor)].image;
    ASSERT_GE(image, 0);
    EXPECT_TRUE(r->images[size_t(image)].path.empty());
    EXPECT_EQ(r->images[size_t(image)].mimeType, "image/png");
    EXPECT_EQ(r->images[size_t(image)].name, "uv_test.png");
    EXPECT_GT(r->images[size_t(image)].encoded.size(), 1000u);
}

TEST(AssimpImport, SharedMeshesAreInstancedNotDuplicated) {
    const std::string file = (kModels / "Collada/teapot_instancenodes.DAE").string();
    auto r = importWithAssimp(file);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectConsistent(*r, file);
    ASSERT_EQ(r->meshes.size(), 1u);
    int users = 0;
    for (const auto& n : r->nodes) users += n.mesh == 0 ? 1 : 0;
    EXPECT_EQ(users, 2);
}

TEST(AssimpImport, EmbeddedTexturesBecomeEncodedImages) {
    // glTF with a data-URI image: assimp names it "*0" (importScene would send .gltf to
    // importGltf; importWithAssimp reads it too).
    const std::string gltf =
        (kModels / "glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf").string();
    auto r = importWithAssimp(gltf);
    ASSERT_TRUE(r.ok()) << r.error().message;
    expectConsistent(*r, gltf);
    ASSERT_EQ(r->images.size(), 1u);
    EXPECT_TRUE(r->images[0].path.empty());
    EXPECT_EQ(r->images[0].mimeType, "image/png");
    ASSERT_GT(r->images[0].encoded.size(), 8u);
    EXPECT_EQ(std::memcmp(r->images[0].encoded.data(), "\x89PNG", 4), 0);

    // Half-Life MDL: uncompressed 512x512 texels, wrapped into a PNG.
    const std::string mdl = (kModels / "MDL/MDL (HL1)/alpha_test.mdl").string();
    auto m = importWithAssimp(mdl);
    ASSERT_TRUE(m.ok()) << m.error().message;
    expectConsistent(*m, mdl);
    ASSERT_EQ(m->images.size(), 1u);
    const auto& png = m->images[0].encoded;
    EXPECT_EQ(m->images[0].mimeType, "image/png");
    ASSERT_GT(png.size(), 33u);
    EXPECT_EQ(std::memcmp(png.data(), "\x89PNG\r\n\x1a\n", 8), 0);
    auto be32 = [&](size_t at) {
        return uint32_t(png[at]) << 24 | uint32_t(png[at + 1]) << 16 | uint32_t(png[at + 2]) << 8 |
               uint32_t(png[at + 3]);
    };
    EXPECT_EQ(std::memcmp(png.data() + 12, "IHDR", 4), 0);
    EXPECT_EQ(be32(16), 512u);
    EXPECT_EQ(be32(20), 512u);
    // Stored deflate: raw rows (1 filter byte + 4 bytes per texel) + 5 bytes per 64 KiB block.
    const size_t raw = 512 * (1 + 512 * 4);
    const size_t blocks = (raw + 65534) / 65535;
    EXPECT_EQ(png.size(), 8 + 25 + 12 + 2 + raw + 5 * blocks + 4 + 12);
}

} // namespace
