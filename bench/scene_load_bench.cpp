// pnb_scene_load_bench — loading a converted container against parsing its source scene.
//
// The question it answers (converter issue): how much faster is getting a .pnb into memory than
// parsing the .glb/.obj it came from? For each input pair SOURCE CONTAINER (CONTAINER is
// pnb-convert's output for SOURCE) it times, wall clock, page cache warm:
//   PnbLoad/<src>        Container::open + load() of every chunk with XXH3 checksums verified:
//                        the mesh and texel payloads the GPU takes, in memory (zero-copy views of
//                        the mapping; the small zstd chunks decompressed)
//   PnbReadScene/<src>   Container::open + readScene(): the above plus decoding every chunk into
//                        typed structs and checking every cross-reference (validateScene)
//   TinygltfParse/<src>  tinygltf LoadBinaryFromFile (.glb) / LoadASCIIFromFile (.gltf) into a
//                        tinygltf::Model. Parse only: the converter's importGltf (IR, checks,
//                        Draco) is NOT measured. Images are not decoded (the same no-op image
//                        loader idea as converter/src/import_gltf.cpp), which favours tinygltf.
//   AssimpRead/<src>     Assimp::Importer::ReadFile(aiProcess_Triangulate): the glTF2 or OBJ
//                        importer into an aiScene. One Importer is reused, so its construction
//                        (registering every loader) is not counted. Embedded images stay encoded.
// scripts/bench-convert runs it over the procedural scenes and prints the ratios
// (source parse time / container load time); the JSON keeps every repetition.
//
// Usage:
//   pnb_scene_load_bench [benchmark flags] SOURCE CONTAINER [SOURCE CONTAINER ...]
//   pnb_scene_load_bench --export-obj IN OUT.obj
// --export-obj writes IN (anything assimp reads) as OBJ + MTL with assimp's exporter. It exists
// because `assimp export` (assimp-utils 5.2.5) aborts on our .glb files: see exportObj().
//
// Does NOT do: cold-cache measurements (they would measure the disk), GPU upload, image decoding,
// or the converter's own import (pnb-convert's timing is scripts/bench-convert's first table).

#include <benchmark/benchmark.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

// The tinygltf implementation is compiled in this file only, with the defines of
// converter/src/import_gltf.cpp (this target does not link pnb_converter, which holds the other
// copy). No stb: images are never decoded here.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include "pnb/reader.h"
#include "pnb/scene.h"

namespace {

namespace fs = std::filesystem;

[[noreturn]] void fatal(const std::string& what) {
    std::fprintf(stderr, "pnb_scene_load_bench: %s\n", what.c_str());
    std::exit(1);
}

enum class SourceKind { Glb, Gltf, Other };

struct Input {
    std::string label;     // the source's file name, e.g. "street-canyon.obj"
    std::string source;    // .glb/.gltf/.obj or anything assimp reads
    std::string container; // pnb-convert's output for `source`
    SourceKind kind = SourceKind::Other;
    uint64_t sourceBytes = 0, containerBytes = 0;
};

// Reads the whole file, so the timed runs find it in the page cache.
uint64_t warm(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fatal("cannot read " + path);
    std::vector<char> buffer(1 << 20);
    uint64_t total = 0;
    while (in.read(buffer.data(), std::streamsize(buffer.size())) || in.gcount() > 0) {
        total += uint64_t(in.gcount());
    }
    return total;
}

// tinygltf calls this for every image; keeping nothing means no image is decoded or copied.
bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
    return true;
}

// [SECTION] the four measured paths. Each returns "" on success, else a message.

std::string pnbLoad(const Input& in) {
    auto c = pnb::Container::open(in.container);
    if (!c) return c.error().describe();
    for (const pnb::ChunkInfo& chunk : c->chunks()) {
        auto payload = c->load(chunk);
        if (!payload) return payload.error().describe();
        benchmark::DoNotOptimize(payload->bytes().data());
    }
    return {};
}

std::string pnbReadScene(const Input& in) {
    auto c = pnb::Container::open(in.container);
    if (!c) return c.error().describe();
    auto scene = pnb::readScene(*c);
    if (!scene) return scene.error().describe();
    benchmark::DoNotOptimize(scene->meshes.data());
    return {};
}

std::string tinygltfParse(tinygltf::TinyGLTF& loader, const Input& in) {
    tinygltf::Model model;
    std::string err, warn;
    const bool ok = in.kind == SourceKind::Glb
        ? loader.LoadBinaryFromFile(&model, &err, &warn, in.source)
        : loader.LoadASCIIFromFile(&model, &err, &warn, in.source);
    if (!ok) return "tinygltf: " + (err.empty() ? std::string("failed") : err);
    benchmark::DoNotOptimize(model.buffers.data());
    return {};
}

std::string assimpRead(Assimp::Importer& importer, const Input& in) {
    const aiScene* scene = importer.ReadFile(in.source, aiProcess_Triangulate);
    if (scene == nullptr) return std::string("assimp: ") + importer.GetErrorString();
    benchmark::DoNotOptimize(scene->mMeshes);
    return {};
}

// [SECTION] registration

template <class Body> void run(benchmark::State& state, const Input& in, Body body) {
    for (auto _ : state) {
        if (std::string e = body(); !e.empty()) {
            state.SkipWithError(e.c_str());
            break;
        }
        benchmark::ClobberMemory();
    }
    state.counters["source_bytes"] = double(in.sourceBytes);
    state.counters["container_bytes"] = double(in.containerBytes);
}

void registerInput(const Input& in) {
    // A path that fails is reported now, by name, rather than as a skipped benchmark.
    auto check = [&](const char* what, const std::string& e) {
        if (!e.empty()) fatal(in.label + ": " + what + ": " + e);
    };
    check("container", pnbReadScene(in));
    auto add = [](const std::string& name, auto fn) {
        benchmark::RegisterBenchmark(name.c_str(), fn)
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond);
    };
    add("PnbLoad/" + in.label,
        [in](benchmark::State& state) { run(state, in, [&] { return pnbLoad(in); }); });
    add("PnbReadScene/" + in.label,
        [in](benchmark::State& state) { run(state, in, [&] { return pnbReadScene(in); }); });
    if (in.kind != SourceKind::Other) {
        tinygltf::TinyGLTF probe;
        probe.SetImageLoader(&skipImage, nullptr);
        check("tinygltf", tinygltfParse(probe, in));
        add("TinygltfParse/" + in.label, [in](benchmark::State& state) {
            tinygltf::TinyGLTF loader;
            loader.SetImageLoader(&skipImage, nullptr);
            run(state, in, [&] { return tinygltfParse(loader, in); });
        });
    }
    Assimp::Importer probe;
    check("assimp", assimpRead(probe, in));
    add("AssimpRead/" + in.label, [in](benchmark::State& state) {
        Assimp::Importer importer;
        run(state, in, [&] { return assimpRead(importer, in); });
    });
}

Input makeInput(const std::string& source, const std::string& container) {
    Input in;
    in.label = fs::path(source).filename().string();
    in.source = source;
    in.container = container;
    std::string ext = fs::path(source).extension().string();
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    in.kind = ext == ".glb" ? SourceKind::Glb : ext == ".gltf" ? SourceKind::Gltf
                                                               : SourceKind::Other;
    in.sourceBytes = warm(source);
    in.containerBytes = warm(container);
    return in;
}

// [SECTION] --export-obj

// Removes node metadata before export. Why: assimp 5.2.5's glTF2 importer stores a node's
// "extensions" object (KHR_lights_punctual) as nested metadata (AI_AIMETADATA), and
// SceneCombiner::Copy(aiMetadata), which the exporter runs first, has no case for that type and
// fails `ai_assert(false)` (SceneCombiner.cpp:1353). That is also why `assimp export` aborts on
// these files. OBJ cannot carry node metadata anyway.
void dropNodeMetadata(aiNode* node) {
    delete node->mMetaData;
    node->mMetaData = nullptr;
    for (unsigned i = 0; i < node->mNumChildren; ++i) dropNodeMetadata(node->mChildren[i]);
}

int exportObj(const std::string& input, const std::string& output) {
    Assimp::Importer importer;
    if (importer.ReadFile(input, 0) == nullptr) {
        fatal("assimp could not read " + input + ": " + importer.GetErrorString());
    }
    // The importer's scene is const; take ownership to edit it.
    std::unique_ptr<aiScene> scene(importer.GetOrphanedScene());
    dropNodeMetadata(scene->mRootNode);
    Assimp::Exporter exporter;
    if (exporter.Export(scene.get(), "obj", output) != AI_SUCCESS) {
        fatal("assimp could not write " + output + ": " + exporter.GetErrorString());
    }
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    if (argc >= 2 && std::strcmp(argv[1], "--export-obj") == 0) {
        if (argc != 4) fatal("usage: pnb_scene_load_bench --export-obj IN OUT.obj");
        return exportObj(argv[2], argv[3]);
    }
    benchmark::Initialize(&argc, argv);
    // Initialize removed its own flags; what is left are the input pairs.
    if (argc < 3 || (argc - 1) % 2 != 0) {
        fatal("usage: pnb_scene_load_bench [benchmark flags] SOURCE CONTAINER "
              "[SOURCE CONTAINER ...]\n(see scripts/bench-convert)");
    }
    for (int i = 1; i + 1 < argc; i += 2) registerInput(makeInput(argv[i], argv[i + 1]));
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
