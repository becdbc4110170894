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

} // namespace pnb::converter::test
