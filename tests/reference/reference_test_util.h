// reference_test_util.h — shared helpers of the pnb_reference tests: temporary directories,
// loading converted containers, and the ground + box scene whose shadow footprint is known.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "gltf_fixture.h"
#include "pnb/reader.h"
#include "pnb/scene.h"

namespace pnb::reference::test {

namespace fs = std::filesystem;
namespace gltf = pnb::assets::gltf;

// A fresh directory under the system temp dir, removed with its contents at the end of scope.
struct TempDir {
    fs::path path;
    explicit TempDir(const std::string& name) {
        static std::atomic<int> counter{0};
        path = fs::temp_directory_path() / ("pnb-reference-test-" + std::to_string(::getpid()) +
                                            "-" + std::to_string(counter++) + "-" + name);
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::string str() const { return path.string(); }
};

// A container and the scene decoded from it (the scene's blobs point into the mapping).
struct LoadedScene {
    std::unique_ptr<Container> container;
    Scene scene;
};

inline std::unique_ptr<LoadedScene> loadPnb(const std::string& path) {
    auto c = Container::open(path);
    EXPECT_TRUE(c.ok()) << path << ": " << (c.ok() ? "" : c.error().describe());
    if (!c.ok()) return nullptr;
    auto loaded = std::make_unique<LoadedScene>();
    loaded->container = std::make_unique<Container>(std::move(*c));
    auto s = readScene(*loaded->container);
    EXPECT_TRUE(s.ok()) << path << ": " << (s.ok() ? "" : s.error().describe());
    if (!s.ok()) return nullptr;
    loaded->scene = std::move(*s);
    return loaded;
}

// Quaternion turning a quad's +Z normal to +Y (-90 degrees about X): a ground plane.
inline constexpr gltf::Float4 kFaceUp{-0.70710678f, 0, 0, 0.70710678f};

inline gltf::Material material(const std::string& name,
                               gltf::AlphaMode mode = gltf::AlphaMode::Opaque) {
    gltf::Material m;
    m.name = name;
    m.alphaMode = mode;
    if (mode == gltf::AlphaMode::Blend) m.baseColorFactor = {1, 1, 1, 0.5f};
    return m;
}

// A 40 x 40 ground quad at y = 0 and a 2 x 2 x 2 box spanning y in [2, 4], x and z in [-1, 1],
// everything shifted by `offset` (world units). With the light straight up the box's shadow on
// the ground is x, z in [-1, 1]; with the light towards (1, 2, 0) it is x in [-3, 0], z in [-1, 1].
inline gltf::Document groundAndBox(gltf::Float3 offset = {0, 0, 0}) {
    gltf::Document doc;
    doc.materials.push_back(material("stone"));
    pnb::test::addObject(doc, "ground", pnb::test::quad(40, 40, 0), offset, kFaceUp);
    pnb::test::addObject(doc, "box", pnb::test::box(2, 2, 2, 0),
                    {offset[0], offset[1] + 3, offset[2]});
    return doc;
}

#ifdef PNB_REFERENCE_EXE
// pnb-reference run as a child process with `args` (already shell-quoted where needed).
struct RunResult {
    int exitCode = -1;
    std::string output; // stdout and stderr
};

inline RunResult run(const std::string& args) {
    const std::string command = std::string("'") + PNB_REFERENCE_EXE + "' " + args + " 2>&1";
    RunResult r;
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) return r;
    char buffer[4096];
    size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
    const int status = ::pclose(pipe);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}
#endif

} // namespace pnb::reference::test
