// tests/converter/import_test_support.h — helpers shared by the importer tests
// (import_assimp_test.cpp, import_obj_test.cpp): temporary directories, files, lookups in an
// IrScene and its structural invariants.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <string_view>
#include <unistd.h>

#include "pnb_converter/mtl_to_pbr.h"
#include "pnb_converter/scene_ir.h"

namespace pnb::converter::test {

namespace fs = std::filesystem;

inline const fs::path kModels = "/usr/share/assimp/models";

// A fresh directory under the system temp dir, removed with the test.
struct TempDir {
    fs::path path;
    explicit TempDir(const std::string& name) {
        path = fs::temp_directory_path() /
               ("pnb_import_" + name + "_" + std::to_string(::getpid()));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

inline void writeFile(const fs::path& path, std::string_view content) {
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary).write(content.data(), std::streamsize(content.size()));
}

inline bool hasWarning(const IrScene& scene, std::initializer_list<std::string_view> parts) {
    return std::any_of(scene.warnings.begin(), scene.warnings.end(), [&](const std::string& w) {
        return std::all_of(parts.begin(), parts.end(), [&](std::string_view p) {
            return w.find(p) != std::string::npos;
        });
    });
}

inline std::string allWarnings(const IrScene& scene) {
    std::string out;
    for (const auto& w : scene.warnings) out += "  " + w + "\n";
    return out;
}

inline float expectedRoughness(float ns) {
    MtlParameters p;
    p.ns = ns;
    Material m;
    applyMtlToPbr(p, m);
    return m.roughnessFactor;
}

inline const IrMaterial* findMaterial(const IrScene& scene, std::string_view name) {
    for (const auto& m : scene.materials) {
        if (m.name == name) return &m;
    }
    return nullptr;
}

inline int findNode(const IrScene& scene, std::string_view name) {
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        if (scene.nodes[i].name == name) return int(i);
    }
    return -1;
}

inline fs::path imagePath(const IrScene& scene, const IrMaterial& m, TextureSlotKind slot) {
    const int image = m.textures[size_t(slot)].image;
    if (image < 0 || size_t(image) >= scene.images.size()) return {};
    return scene.images[size_t(image)].path;
}

// Structural invariants every successful import must hold (indices in range, parents first).
inline void expectConsistent(const IrScene& scene, const std::string& file) {
    SCOPED_TRACE(file);
    EXPECT_FALSE(scene.meshes.empty());
    for (const auto& mesh : scene.meshes) {
        EXPECT_FALSE(mesh.primitives.empty()) << mesh.name;
        for (const auto& p : mesh.primitives) {
            ASSERT_EQ(p.positions.size() % 3, 0u);
            ASSERT_EQ(p.indices.size() % 3, 0u) << "triangle lists only";
            const size_t n = p.vertexCount();
            for (uint32_t i : p.indices) ASSERT_LT(i, n) << mesh.name;
            EXPECT_TRUE(p.normals.empty() || p.normals.size() == n * 3);
            EXPECT_TRUE(p.uv0.empty() || p.uv0.size() == n * 2);
            EXPECT_TRUE(p.uv1.empty() || p.uv1.size() == n * 2);
            EXPECT_TRUE(p.colors.empty() || p.colors.size() == n * 4);
            EXPECT_TRUE(p.tangents.empty()) << "tangents are generated later, never imported";
            EXPECT_GE(p.material, -1);
            EXPECT_LT(p.material, int(scene.materials.size()));
        }
    }
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const IrNode& n = scene.nodes[i];
        EXPECT_LT(n.parent, int(i)) << "parents first: node " << i;
        EXPECT_LT(n.mesh, int(scene.meshes.size()));
        EXPECT_LT(n.light, int(scene.lights.size()));
        EXPECT_LT(n.camera, int(scene.cameras.size()));
        const Vec4& q = n.rotation;
        EXPECT_NEAR(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w, 1.0f, 1e-4f);
    }
    for (const auto& m : scene.materials) {
        for (const auto& t : m.textures) {
            EXPECT_GE(t.image, -1);
            EXPECT_LT(t.image, int(scene.images.size()));
        }
    }
    for (const auto& image : scene.images) {
        EXPECT_NE(image.path.empty(), image.encoded.empty()) << "exactly one of path/encoded";
        EXPECT_TRUE(image.path.empty() || fs::exists(image.path)) << image.path;
    }
}

// The hand-written scene both OBJ importers are tested on: groups, two materials in one group,
// quads, points and lines, MTL parameters, Windows paths in the wrong case, an mtllib in the
// wrong case, a foreign absolute path, map_d both as the base colour's alpha and as a separate
// file, map_Ks, map_Ke.
constexpr std::string_view kSceneObj = R"(# hand-written
mtllib Scene.MTL
v 0 0 0 1 0 0
v 1 0 0 0 1 0
v 1 1 0 0 0 1
v 0 1 0 1 1 1
v 0 0 1 1 0 0
v 1 0 1 0 1 0
v 1 1 1 0 0 1
v 0 1 1 1 1 1
vt 0 0.25
vt 1 0.25
vt 1 1
vt 0 1
vn 0 0 1
o Body
g front
usemtl painted
f 1/1/1 2/2/1 3/3/1 4/4/1
usemtl glass
f 5/1/1 6/2/1 7/3/1 8/4/1
this line is garbage and is ignored
g back
usemtl painted
f 1/1/1 3/3/1 2/2/1
l 1 2 3
)";

constexpr std::string_view kSceneMtl = R"(newmtl painted
Kd 0.5 0.25 1
Ns 10
d 0.5
Ke 0.1 0.2 0.3
map_Kd Textures\Albedo.PNG
map_d Textures\Albedo.PNG
map_bump -bm 0.5 textures\Normal.png
map_Ks spec.png

newmtl glass
Kd 1 1 1
Tr 0.25
map_Kd C:\Users\someone\Desktop\Glass.jpg
map_d mask.png
map_Ke glow.png
)";

// Writes that scene and the texture files it names into `dir`; returns the OBJ's path.
inline std::string writeHandWrittenScene(const fs::path& dir) {
    writeFile(dir / "scene.obj", kSceneObj);
    writeFile(dir / "scene.mtl", kSceneMtl); // referenced as Scene.MTL
    writeFile(dir / "textures/albedo.png", "png");
    writeFile(dir / "textures/normal.png", "png");
    writeFile(dir / "glass.jpg", "jpg");
    writeFile(dir / "mask.png", "png");
    writeFile(dir / "glow.png", "png");
    return (dir / "scene.obj").string();
}

} // namespace pnb::converter::test
