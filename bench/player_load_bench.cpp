// pnb_player_load_bench — time to GPU-ready: a .pnb through the player's loader against the same
// scene parsed by assimp (OBJ/MTL + PNG files) and by tinygltf (.glb with its PNGs decoded).
//
// The question it answers (player issue): how long until a scene is on the GPU and drawable,
// compared with loading its source with the usual libraries? In ONE process, page cache warm
// (every file is read once first, then one untimed warm-up round), it runs `--reps` rounds; each
// round runs every measurement once, in a shuffled order (fixed seed), so load from other
// tenants of the machine spreads over all of them. Wall clock, std::chrono::steady_clock:
//   pnb:<file>     pnb::player::loadScene(): map, verify XXH3 checksums (read), decode and
//                  validate (decode), create buffers/textures and upload straight from the
//                  mapping, glFinish (upload), compile + link the scene's programs (compile).
//                  LoadStats gives the split; "without compile" is total - compile. Then, timed
//                  separately: Renderer::create + the first frame at --frame-size + glFinish
//                  (on llvmpipe the LLVM code generation of every shader variant happens at the
//                  first draw, not in glLinkProgram). The scene is freed outside the timing.
//   assimp-obj     Assimp::Importer::ReadFile(OBJ, aiProcess_Triangulate) — the existing
//                  scene-load benchmark's flags; OBJ's faces come out unindexed (no
//                  JoinIdenticalVertices), which favours assimp — then, timed on its own,
//                  stbi_load() of every texture file the MTL names (4 channels, as tinygltf
//                  asks). FreeScene() is outside the timing. Nothing reaches the GPU.
//   tinygltf-glb   tinygltf::TinyGLTF::LoadBinaryFromFile with its default image loader
//                  (stb_image, every embedded PNG decoded to RGBA8). Nothing reaches the GPU.
//                  The generated .glb's PNGs are stored-deflate (pnb_assets' png_writer does
//                  not compress), which makes them quick to decode; so, with --glb-zlib:
//   tinygltf-glb-zlib  the same on the .glb re-encoded by --recompress-glb (identical pixels,
//                  zlib-compressed PNGs as a real exporter writes them).
//   png-stored, png-zlib  stbi_load_from_memory of the .glb's PNGs alone, stored and zlib: the
//                  decode share of the two figures above (for reading them, not competitors).
// Output: a JSON document (--json) with every sample; scripts/bench-load prints the table.
//
// Usage:
//   pnb_player_load_bench [--reps N] [--json OUT] [--frame-size WxH] [--obj SCENE.obj]
//                         [--glb SCENE.glb [--glb-zlib SCENE.zlib.glb]] CONTAINER.pnb [...]
//   pnb_player_load_bench --export-obj IN.glb OUT.obj
//   pnb_player_load_bench --recompress-glb IN.glb OUT.glb
// Only the paths whose files are given run (scripts/bench-load runs the containers a second
// time, alone, with Mesa's shader cache disabled).
// --export-obj writes IN as OBJ + MTL with assimp's exporter (the approach of
// scene_load_bench.cpp) and its embedded images, unchanged, as PNG files next to OUT, named in
// the MTL. --recompress-glb rewrites IN with every embedded PNG decoded and re-encoded by
// stb_image_write (zlib level 8), everything else unchanged (through tinygltf's writer).
//
// The tinygltf implementation is compiled in this file only (this target does not link
// pnb_converter, which holds the other copy); stb_image comes from Debian's libstb.
//
// Does NOT do: cold-cache measurements (they would measure the disk), GPU upload for assimp or
// tinygltf (which favours them), Google Benchmark (the split per repetition is the point).

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <epoxy/gl.h>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <nlohmann/json.hpp>

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
// Declarations only: the implementations are in libstb (stb_image is what tinygltf includes).
#include <stb_image.h>
#include <stb_image_write.h>

#include "pnb_player/benchmark.h"
#include "pnb_player/gl_context.h"
#include "pnb_player/gpu_scene.h"
#include "pnb_player/renderer.h"
#include "pnb_player/settings.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

[[noreturn]] void fatal(const std::string& what) {
    std::fprintf(stderr, "pnb_player_load_bench: %s\n", what.c_str());
    std::exit(1);
}

std::vector<uint8_t> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fatal("cannot read " + path);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// [SECTION] --export-obj

// See scene_load_bench.cpp: assimp 5.2.5's exporter asserts on the glTF2 importer's nested node
// metadata (KHR_lights_punctual), and OBJ cannot carry it anyway.
void dropNodeMetadata(aiNode* node) {
    delete node->mMetaData;
    node->mMetaData = nullptr;
    for (unsigned i = 0; i < node->mNumChildren; ++i)
        dropNodeMetadata(node->mChildren[i]);
}

int exportObj(const std::string& input, const std::string& output) {
    Assimp::Importer importer;
    if (importer.ReadFile(input, 0) == nullptr)
        fatal("assimp could not read " + input + ": " + importer.GetErrorString());
    std::unique_ptr<aiScene> scene(importer.GetOrphanedScene());
    dropNodeMetadata(scene->mRootNode);
    // Embedded images ("*N" texture paths, which the OBJ exporter would write verbatim) become
    // files next to the OBJ, and the materials name those files instead.
    const fs::path out(output);
    std::vector<std::string> names(scene->mNumTextures);
    for (unsigned t = 0; t < scene->mNumTextures; ++t) {
        const aiTexture* tex = scene->mTextures[t];
        if (tex->mHeight != 0)
            fatal("embedded texture " + std::to_string(t) + " is not compressed");
        std::string ext = tex->achFormatHint[0] ? tex->achFormatHint : "png";
        names[t] = out.stem().string() + "-texture-" + std::to_string(t) + "." + ext;
        std::ofstream f(out.parent_path() / names[t], std::ios::binary);
        f.write(reinterpret_cast<const char*>(tex->pcData), std::streamsize(tex->mWidth));
        if (!f) fatal("cannot write " + (out.parent_path() / names[t]).string());
    }
    for (unsigned m = 0; m < scene->mNumMaterials; ++m) {
        aiMaterial* mat = scene->mMaterials[m];
        for (int type = aiTextureType_NONE; type <= AI_TEXTURE_TYPE_MAX; ++type) {
            const auto tt = aiTextureType(type);
            for (unsigned i = 0; i < mat->GetTextureCount(tt); ++i) {
                aiString path;
                if (mat->GetTexture(tt, i, &path) != AI_SUCCESS || path.data[0] != '*') continue;
                const unsigned index = unsigned(std::atoi(path.data + 1));
                if (index >= names.size())
                    fatal("texture reference " + std::string(path.C_Str()) + " out of range");
                aiString file(names[index]);
                mat->AddProperty(&file, AI_MATKEY_TEXTURE(tt, i));
            }
        }
    }
    Assimp::Exporter exporter;
    if (exporter.Export(scene.get(), "obj", output) != AI_SUCCESS)
        fatal("assimp could not write " + output + ": " + exporter.GetErrorString());
    return 0;
}

// [SECTION] --recompress-glb

bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
    return true;
}

std::vector<uint8_t> zlibPng(const uint8_t* png, size_t size) {
    int w = 0, h = 0, n = 0;
    stbi_uc* pixels = stbi_load_from_memory(png, int(size), &w, &h, &n, 0);
    if (pixels == nullptr) fatal(std::string("stb_image: ") + stbi_failure_reason());
    std::vector<uint8_t> out;
    stbi_write_png_to_func(
        [](void* ctx, void* data, int bytes) {
            auto* o = static_cast<std::vector<uint8_t>*>(ctx);
            o->insert(o->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + bytes);
        },
        &out, w, h, n, pixels, w * n);
    stbi_image_free(pixels);
    if (out.empty()) fatal("stb_image_write failed");
    return out;
}

int recompressGlb(const std::string& input, const std::string& output) {
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&skipImage, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    if (!loader.LoadBinaryFromFile(&model, &err, &warn, input)) fatal("tinygltf: " + err);
    if (model.buffers.size() != 1) fatal(input + ": expected one buffer");
    std::vector<std::vector<uint8_t>> views;
    for (const tinygltf::BufferView& v : model.bufferViews) {
        const uint8_t* p = model.buffers[0].data.data() + v.byteOffset;
        views.emplace_back(p, p + v.byteLength);
    }
    for (const tinygltf::Image& im : model.images) {
        if (im.bufferView < 0) fatal(input + ": image " + im.name + " is not embedded");
        std::vector<uint8_t>& v = views[size_t(im.bufferView)];
        v = zlibPng(v.data(), v.size());
    }
    std::vector<uint8_t> bin;
    for (size_t i = 0; i < views.size(); ++i) {
        bin.resize((bin.size() + 3) / 4 * 4, 0);
        model.bufferViews[i].byteOffset = bin.size();
        model.bufferViews[i].byteLength = views[i].size();
        bin.insert(bin.end(), views[i].begin(), views[i].end());
    }
    model.buffers[0].data = std::move(bin);
    model.buffers[0].uri.clear();
    if (!loader.WriteGltfSceneToFile(&model, output, false, true, false, true))
        fatal("tinygltf could not write " + output);
    return 0;
}

// [SECTION] the measured paths

struct PnbSample {
    pnb::player::LoadStats load;
    double firstFrameMs = 0; // Renderer::create + first frame + glFinish, after the load
};

PnbSample pnbLoad(const std::string& path, uint32_t width, uint32_t height) {
    using namespace pnb::player;
    PnbSample s;
    auto scene = loadScene(path, {}, &s.load);
    if (!scene) fatal(path + ": " + scene.error().message);
    auto start = Clock::now();
    auto settings = resolveSettings((*scene)->settings, {});
    if (!settings) fatal(path + ": " + settings.error().message);
    auto renderer = Renderer::create(**scene, *settings);
    if (!renderer) fatal(path + ": " + renderer.error().message);
    if (auto r = (*renderer)->render(initialCamera(**scene, ""), width, height); !r)
        fatal(path + ": " + r.error().message);
    glFinish();
    s.firstFrameMs = msSince(start);
    renderer->reset();
    scene->reset();
    glFinish(); // deletions done before the next measurement starts
    return s;
}

struct AssimpSample {
    double readMs = 0, pngMs = 0;
    uint64_t triangles = 0, pixels = 0;
    uint32_t images = 0;
};

AssimpSample assimpLoad(Assimp::Importer& importer, const std::string& obj) {
    AssimpSample s;
    auto start = Clock::now();
    const aiScene* scene = importer.ReadFile(obj, aiProcess_Triangulate);
    if (scene == nullptr) fatal(std::string("assimp: ") + importer.GetErrorString());
    s.readMs = msSince(start);
    for (unsigned m = 0; m < scene->mNumMeshes; ++m)
        s.triangles += scene->mMeshes[m]->mNumFaces;
    // Every texture file the materials name, once each (paths are relative to the OBJ).
    std::set<std::string> files;
    for (unsigned m = 0; m < scene->mNumMaterials; ++m)
        for (int type = aiTextureType_NONE; type <= AI_TEXTURE_TYPE_MAX; ++type)
            for (unsigned i = 0; i < scene->mMaterials[m]->GetTextureCount(aiTextureType(type));
                 ++i) {
                aiString path;
                if (scene->mMaterials[m]->GetTexture(aiTextureType(type), i, &path) == AI_SUCCESS)
                    files.insert((fs::path(obj).parent_path() / path.C_Str()).string());
            }
    start = Clock::now();
    for (const std::string& f : files) {
        int w = 0, h = 0, n = 0;
        stbi_uc* pixels = stbi_load(f.c_str(), &w, &h, &n, 4);
        if (pixels == nullptr)
            fatal("stb_image could not decode " + f + ": " + stbi_failure_reason());
        s.pixels += uint64_t(w) * uint64_t(h);
        stbi_image_free(pixels);
    }
    s.pngMs = msSince(start);
    s.images = uint32_t(files.size());
    importer.FreeScene();
    return s;
}

struct GltfSample {
    double ms = 0;
    uint64_t pixels = 0;
    uint32_t images = 0;
};

GltfSample tinygltfLoad(const std::string& glb) {
    GltfSample s;
    double ms = 0;
    {
        tinygltf::TinyGLTF loader; // default image loader: stb_image, RGBA8
        tinygltf::Model model;
        std::string err, warn;
        auto start = Clock::now();
        if (!loader.LoadBinaryFromFile(&model, &err, &warn, glb))
            fatal("tinygltf: " + (err.empty() ? std::string("failed") : err));
        ms = msSince(start);
        for (const tinygltf::Image& im : model.images) {
            if (im.image.empty()) fatal("tinygltf did not decode image " + im.name);
            s.pixels += uint64_t(im.width) * uint64_t(im.height);
        }
        s.images = uint32_t(model.images.size());
    } // the model is freed outside the timing
    s.ms = ms;
    return s;
}

double decodeAll(const std::vector<std::vector<uint8_t>>& pngs) {
    auto start = Clock::now();
    for (const std::vector<uint8_t>& png : pngs) {
        int w = 0, h = 0, n = 0;
        stbi_uc* pixels = stbi_load_from_memory(png.data(), int(png.size()), &w, &h, &n, 4);
        if (pixels == nullptr) fatal(std::string("stb_image: ") + stbi_failure_reason());
        stbi_image_free(pixels);
    }
    return msSince(start);
}

// The .glb's embedded PNGs as stored, and re-encoded with stb_image_write's zlib.
void glbPngs(const std::string& glb, std::vector<std::vector<uint8_t>>& stored,
             std::vector<std::vector<uint8_t>>& zlib) {
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&skipImage, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    if (!loader.LoadBinaryFromFile(&model, &err, &warn, glb)) fatal("tinygltf: " + err);
    for (const tinygltf::Image& im : model.images) {
        const tinygltf::BufferView& v = model.bufferViews[size_t(im.bufferView)];
        const uint8_t* p = model.buffers[size_t(v.buffer)].data.data() + v.byteOffset;
        stored.emplace_back(p, p + v.byteLength);
        zlib.push_back(zlibPng(p, v.byteLength));
    }
}

std::string cpuModel() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown";
}

uint64_t totalBytes(const std::vector<std::vector<uint8_t>>& v) {
    uint64_t n = 0;
    for (const auto& b : v)
        n += b.size();
    return n;
}

} // namespace

int main(int argc, char** argv) {
    if (argc >= 2 && std::strcmp(argv[1], "--export-obj") == 0) {
        if (argc != 4) fatal("usage: pnb_player_load_bench --export-obj IN.glb OUT.obj");
        return exportObj(argv[2], argv[3]);
    }
    if (argc >= 2 && std::strcmp(argv[1], "--recompress-glb") == 0) {
        if (argc != 4) fatal("usage: pnb_player_load_bench --recompress-glb IN.glb OUT.glb");
        return recompressGlb(argv[2], argv[3]);
    }
    uint32_t reps = 7, width = 960, height = 540;
    std::string jsonPath, obj, glb, glbZlib;
    std::vector<std::string> containers;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) fatal(a + " needs a value");
            return argv[++i];
        };
        if (a == "--reps")
            reps = uint32_t(std::max(1, std::atoi(value().c_str())));
        else if (a == "--json")
            jsonPath = value();
        else if (a == "--obj")
            obj = value();
        else if (a == "--glb")
            glb = value();
        else if (a == "--glb-zlib")
            glbZlib = value();
        else if (a == "--frame-size") {
            std::string v = value();
            if (std::sscanf(v.c_str(), "%ux%u", &width, &height) != 2 || !width || !height)
                fatal("--frame-size expects WxH");
        } else if (!a.empty() && a[0] == '-')
            fatal("unknown option " + a + " (see the file header)");
        else
            containers.push_back(a);
    }
    if (containers.empty())
        fatal("usage: pnb_player_load_bench [--reps N] [--json OUT] [--frame-size WxH] [--obj "
              "SCENE.obj] "
              "[--glb SCENE.glb] [--glb-zlib SCENE.zlib.glb] CONTAINER.pnb [...] (see "
              "scripts/bench-load)");

    auto context = pnb::player::createHeadlessContext();
    if (!context) fatal(context.error().message);
    const pnb::player::GlInfo gl = (*context)->info();

    // Warm the page cache: every input file (the OBJ's texture files are read by the warm-up
    // round below).
    std::map<std::string, uint64_t> fileBytes;
    for (const std::string& f : containers)
        fileBytes[f] = readFile(f).size();
    for (const std::string& f : {obj, glb, glbZlib})
        if (!f.empty()) fileBytes[f] = readFile(f).size();
    std::vector<std::vector<uint8_t>> storedPngs, zlibPngs;
    if (!glb.empty()) glbPngs(glb, storedPngs, zlibPngs);

    using nlohmann::json;
    // A job runs one measurement and returns its sample; samples[j] collects job j's.
    struct Job {
        std::string name;
        std::function<json()> run;
        json samples = json::array();
    };
    Assimp::Importer importer; // reused: loader registration is not timed
    std::vector<Job> jobs;
    for (const std::string& c : containers)
        jobs.push_back({"pnb:" + fs::path(c).filename().string(), [&, c] {
                            PnbSample s = pnbLoad(c, width, height);
                            return json{{"open_ms", s.load.openMs},
                                        {"read_ms", s.load.readMs},
                                        {"decode_ms", s.load.decodeMs},
                                        {"upload_ms", s.load.uploadMs},
                                        {"compile_ms", s.load.compileMs},
                                        {"total_ms", s.load.totalMs},
                                        {"first_frame_ms", s.firstFrameMs},
                                        {"file_bytes", s.load.fileBytes},
                                        {"zero_copy_bytes", s.load.zeroCopyBytes}};
                        }});
    if (!obj.empty())
        jobs.push_back({"assimp-obj", [&] {
                            AssimpSample s = assimpLoad(importer, obj);
                            return json{{"read_ms", s.readMs},
                                        {"png_ms", s.pngMs},
                                        {"triangles", s.triangles},
                                        {"images", s.images},
                                        {"pixels", s.pixels}};
                        }});
    auto gltfJob = [&](const std::string& name, const std::string& file) {
        jobs.push_back(
            {name, [&, file] {
                 GltfSample s = tinygltfLoad(file);
                 return json{{"total_ms", s.ms}, {"images", s.images}, {"pixels", s.pixels}};
             }});
    };
    if (!glb.empty()) {
        gltfJob("tinygltf-glb", glb);
        if (!glbZlib.empty()) gltfJob("tinygltf-glb-zlib", glbZlib);
        jobs.push_back({"png-stored", [&] { return json{{"total_ms", decodeAll(storedPngs)}}; }});
        jobs.push_back({"png-zlib", [&] { return json{{"total_ms", decodeAll(zlibPngs)}}; }});
    }

    std::vector<size_t> order(jobs.size());
    for (size_t j = 0; j < jobs.size(); ++j)
        order[j] = j;
    std::fprintf(stderr, "pnb_player_load_bench: warm-up round\n");
    for (size_t j : order)
        (void)jobs[j].run();
    std::mt19937 rng(2024); // a fixed seed: the same orders every run
    json orders = json::array();
    for (uint32_t r = 0; r < reps; ++r) {
        std::shuffle(order.begin(), order.end(), rng);
        json names = json::array();
        for (size_t j : order) {
            jobs[j].samples.push_back(jobs[j].run());
            names.push_back(jobs[j].name);
        }
        orders.push_back(names);
        std::fprintf(stderr, "pnb_player_load_bench: round %u/%u done\n", r + 1, reps);
    }

    json out;
    out["machine"] = {{"cpu", cpuModel()}, {"cores", std::thread::hardware_concurrency()}};
    out["gl"] = {{"vendor", gl.vendor}, {"renderer", gl.renderer}, {"version", gl.version}};
    out["repetitions"] = reps;
    out["frame_size"] = {width, height};
    json files = json::object();
    for (const auto& [f, n] : fileBytes)
        files[f] = n;
    out["file_bytes"] = files;
    out["files"] = {{"obj", obj}, {"glb", glb}, {"glb_zlib", glbZlib}, {"containers", containers}};
    out["png"] = {{"images", storedPngs.size()},
                  {"stored_bytes", totalBytes(storedPngs)},
                  {"zlib_bytes", totalBytes(zlibPngs)}};
    out["orders"] = orders;
    json jj = json::object();
    for (const Job& j : jobs)
        jj[j.name] = j.samples;
    out["jobs"] = jj;
    const std::string text = out.dump(1) + "\n";
    if (jsonPath.empty()) {
        std::fputs(text.c_str(), stdout);
    } else {
        std::ofstream f(jsonPath);
        f << text;
        if (!f) fatal("cannot write " + jsonPath);
    }
    return 0;
}
