// Helpers for the material editor tests: per-test temporary directories, the build-time
// converted procedural scenes (${PNB_SCENE_DIR}), small glTF scenes built in code and converted
// with the real converter, chunk-by-chunk comparison of containers, and running the CLIs.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "pnb/reader.h"
#include "pnb/scene.h"
#include "pnb_assets/gltf_writer.h"
#include "pnb_assets/png_writer.h"
#include "pnb_converter/convert.h"
#include "gltf_fixture.h"
#include "pnb_editor/document.h"

namespace pnb::editor::test {

namespace gltf = pnb::assets::gltf;
namespace fs = std::filesystem;

// A fresh directory under the test temp dir, removed with everything in it on destruction.
class TempDir {
public:
    TempDir() {
        std::string tmpl = ::testing::TempDir() + "pnb-editor-XXXXXX";
        if (::mkdtemp(tmpl.data()) == nullptr) ADD_FAILURE() << "mkdtemp: " << std::strerror(errno);
        mPath = tmpl;
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(mPath, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::string& path() const { return mPath; }
    std::string file(const std::string& name) const { return mPath + "/" + name; }
    std::vector<std::string> list() const {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(mPath)) names.push_back(e.path().filename());
        std::sort(names.begin(), names.end());
        return names;
    }

private:
    std::string mPath;
};

inline std::vector<std::byte> readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<std::byte> bytes(chars.size());
    if (!chars.empty()) std::memcpy(bytes.data(), chars.data(), chars.size());
    return bytes;
}

inline void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// A converted procedural scene copied into `dir` (tests never modify the shared build output).
inline std::string copyScene(const TempDir& dir, const std::string& name) {
    std::string target = dir.file(name + ".pnb");
    fs::copy_file(std::string(PNB_SCENE_DIR) + "/" + name + ".pnb", target,
                  fs::copy_options::overwrite_existing);
    return target;
}

using pnb::test::checkerPng;
using pnb::test::addObject;
using pnb::test::box;
using pnb::test::quad;

// Materials: "textured" (base colour + normal map on a quad with UVs, so the mesh keeps UVs and
// tangents), "plain" (a box without UVs), "glass" (BLEND, so forward), "leaf" (MASK). Images:
// "bricks" (colour) and "bumps" (normal map). A sun and a camera.
inline gltf::Document editorScene() {
    gltf::Document doc;
    doc.sceneName = "editor-test";
    doc.images.push_back({"bricks", checkerPng(32, {200, 80, 60}, {90, 90, 90})});
    doc.images.push_back({"bumps", checkerPng(32, {128, 128, 255}, {150, 110, 240})});
    gltf::Material textured;
    textured.name = "textured";
    textured.baseColorImage = 0;
    textured.normalImage = 1;
    gltf::Material plain;
    plain.name = "plain";
    plain.baseColorFactor = {0.6f, 0.6f, 0.6f, 1};
    gltf::Material glass;
    glass.name = "glass";
    glass.baseColorFactor = {0.5f, 0.7f, 1.0f, 0.3f};
    glass.alphaMode = gltf::AlphaMode::Blend;
    glass.doubleSided = true;
    gltf::Material leaf;
    leaf.name = "leaf";
    leaf.alphaMode = gltf::AlphaMode::Mask;
    leaf.baseColorImage = 0;
    doc.materials = {textured, plain, glass, leaf};
    addObject(doc, "wall", quad(4, 4, 0, true), {0, 0, -2});
    addObject(doc, "block", box(1, 1, 1, 1), {1, 0.5f, 0});
    addObject(doc, "pane", quad(2, 2, 2, true), {-1, 1, 0.5f});
    addObject(doc, "foliage", quad(1, 1, 3, true), {0, 2, 0});
    doc.lights.push_back({"sun", gltf::LightType::Directional, {1, 1, 1}, 3.0f, 0});
    gltf::Node sun;
    sun.name = "sun";
    sun.light = 0;
    sun.rotation = gltf::lookRotation({0.3f, -1.0f, -0.5f});
    doc.nodes.push_back(sun);
    doc.cameras.push_back({"camera", 0.9f, 0, 0.1f, 0});
    gltf::Node cam;
    cam.name = "camera";
    cam.camera = 0;
    cam.translation = {0, 1, 6};
    doc.nodes.push_back(cam);
    return doc;
}

// Converts `doc` (with a sidecar if given) into dir/name.pnb with the real converter.
inline std::string convert(const TempDir& dir, const gltf::Document& doc, const std::string& name,
                           const std::string& sidecarJson = "", bool sky = false) {
    converter::EnvironmentSettings environment;
    environment.sky = sky;
    environment.skyWidth = 64; // small: only the programs matter here
    return pnb::test::convertDocument(dir.path(), doc, name, sidecarJson, true, environment);
}

// A container opened and decoded, kept together (the scene points into the container).
struct Opened {
    std::unique_ptr<Container> container;
    Scene scene;
};
inline Opened openScene(const std::string& path) {
    Opened o;
    auto c = Container::open(path);
    EXPECT_TRUE(c.ok()) << (c.ok() ? "" : c.error().describe());
    if (!c.ok()) return o;
    o.container = std::make_unique<Container>(std::move(*c));
    EXPECT_TRUE(isOk(o.container->verifyAll()));
    auto s = readScene(*o.container);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().describe());
    if (s.ok()) o.scene = std::move(*s);
    return o;
}

inline uint32_t materialIndex(const Scene& scene, std::string_view name) {
    for (uint32_t i = 0; i < scene.materials.size(); ++i)
        if (scene.str(scene.materials[i].name) == name) return i;
    ADD_FAILURE() << "no material '" << name << "'";
    return 0;
}

// "gbuffer[HAS_UV0 ...] surface.vert+gbuffer.frag": a program by name, sorted defines and stages.
inline std::string describeProgram(const Scene& s, uint32_t program) {
    if (program == kNone) return "none";
    const Program& p = s.programs[program];
    std::vector<std::string> defines;
    for (StringRef d : p.defines) defines.emplace_back(s.str(d));
    std::sort(defines.begin(), defines.end());
    std::string out = std::string(s.str(p.name)) + "[";
    for (size_t i = 0; i < defines.size(); ++i) out += (i ? " " : "") + defines[i];
    out += "]";
    for (size_t i = 0; i < p.shaders.size(); ++i)
        out += (i ? "+" : " ") + std::string(s.str(s.shaders[p.shaders[i]].name));
    return out;
}

// The whole bytes of chunk `c` (header, payload and padding).
inline std::span<const std::byte> chunkBytes(const Container& c, const ChunkInfo& info) {
    return c.bytes().subspan(info.headerOffset,
                             alignUp(info.payloadOffset + info.header.storedSize) - info.headerOffset);
}

// Runs a command line through the shell; returns its exit code, stdout (and stderr, with
// `mergeStderr`) in `output`.
inline int run(const std::string& command, std::string* output = nullptr, bool mergeStderr = true) {
    std::string full = command + (mergeStderr ? " 2>&1" : "");
    FILE* p = ::popen(full.c_str(), "r");
    if (!p) return -1;
    std::string text;
    char buf[4096];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof(buf), p)) > 0) text.append(buf, n);
    int status = ::pclose(p);
    if (output) *output = text;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Single-quoted for the shell.
inline std::string quote(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

inline std::unique_ptr<Document> openDoc(const std::string& path) {
    auto d = Document::open(path);
    EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error().describe());
    return d.ok() ? std::move(*d) : nullptr;
}

} // namespace pnb::editor::test
