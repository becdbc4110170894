// pnb_load_inputs — turns pnb-make-scene's load-test .glb into the sources the peers of
// scripts/bench-load read, so that those are what real assets are:
//
//   pnb_load_inputs --reencode-glb IN.glb OUT.glb png|jpeg
//       every embedded image decoded and re-encoded by stb_image_write: "png" with its own
//       deflate at level 8 (what a tool built on stb writes; pnb-make-scene's PNGs use zlib
//       level 6), "jpeg" at quality 90 (and image/jpeg as its mimeType).
//       Everything else is unchanged (written back through tinygltf).
//   pnb_load_inputs --export-obj IN.glb OUT.obj
//       IN as OBJ + MTL through assimp's exporter, its embedded images written unchanged as
//       files next to OUT and named in the MTL.
//
// Exit codes: 0 ok, 1 usage, 2 input or output error (the message names the file). The command
// line is one pnb_cli option table, which also prints --help.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
// Declarations only: the implementations are in Debian's libstb.
#include <stb_image.h>
#include <stb_image_write.h>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "pnb_cli/options.h"

namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "pnb_load_inputs: %s\n", what.c_str());
    std::exit(2);
}

// [SECTION] --reencode-glb

bool keepEncoded(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                 const unsigned char*, int, void*) {
    return true; // the images stay encoded: this tool decodes them itself
}

void append(void* ctx, void* data, int bytes) {
    auto* out = static_cast<std::vector<uint8_t>*>(ctx);
    out->insert(out->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + bytes);
}

std::vector<uint8_t> reencode(const uint8_t* encoded, size_t size, bool jpeg,
                              const std::string& what) {
    int w = 0, h = 0, n = 0;
    stbi_uc* pixels = stbi_load_from_memory(encoded, int(size), &w, &h, &n, 0);
    if (pixels == nullptr) fail(what + ": stb_image cannot decode it: " + stbi_failure_reason());
    std::vector<uint8_t> out;
    stbi_write_png_compression_level = 8;
    const int ok = jpeg ? stbi_write_jpg_to_func(&append, &out, w, h, n, pixels, 90)
                        : stbi_write_png_to_func(&append, &out, w, h, n, pixels, w * n);
    stbi_image_free(pixels);
    if (!ok || out.empty()) fail(what + ": stb_image_write failed");
    return out;
}

int reencodeGlb(const std::string& input, const std::string& output, const std::string& codec) {
    if (codec != "png" && codec != "jpeg") fail("codec must be png or jpeg, not " + codec);
    const bool jpeg = codec == "jpeg";
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&keepEncoded, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    if (!loader.LoadBinaryFromFile(&model, &err, &warn, input)) fail(input + ": " + err);
    if (model.buffers.size() != 1) fail(input + ": expected exactly one buffer");
    std::vector<std::vector<uint8_t>> views;
    for (const tinygltf::BufferView& v : model.bufferViews) {
        const uint8_t* p = model.buffers[0].data.data() + v.byteOffset;
        views.emplace_back(p, p + v.byteLength);
    }
    for (tinygltf::Image& im : model.images) {
        if (im.bufferView < 0 || size_t(im.bufferView) >= views.size())
            fail(input + ": image " + im.name + " is not embedded in a buffer view");
        std::vector<uint8_t>& v = views[size_t(im.bufferView)];
        v = reencode(v.data(), v.size(), jpeg, input + ": image " + im.name);
        im.mimeType = jpeg ? "image/jpeg" : "image/png";
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
    // Written next to the output, then renamed: a reader never sees half a file.
    const std::string temporary = output + ".tmp";
    if (!loader.WriteGltfSceneToFile(&model, temporary, false, true, false, true))
        fail("tinygltf cannot write " + temporary);
    std::error_code ec;
    fs::rename(temporary, output, ec);
    if (ec) fail("cannot rename " + temporary + " to " + output + ": " + ec.message());
    return 0;
}

// [SECTION] --export-obj

// assimp 5.2.5's exporter asserts on the glTF2 importer's nested node metadata
// (KHR_lights_punctual), and OBJ cannot carry it anyway.
void dropNodeMetadata(aiNode* node) {
    delete node->mMetaData;
    node->mMetaData = nullptr;
    for (unsigned i = 0; i < node->mNumChildren; ++i)
        dropNodeMetadata(node->mChildren[i]);
}

int exportObj(const std::string& input, const std::string& output) {
    Assimp::Importer importer;
    if (importer.ReadFile(input, 0) == nullptr)
        fail("assimp cannot read " + input + ": " + importer.GetErrorString());
    std::unique_ptr<aiScene> scene(importer.GetOrphanedScene());
    dropNodeMetadata(scene->mRootNode);
    // Embedded images ("*N" paths, which the OBJ exporter would write verbatim) become files
    // next to the OBJ, and the materials name those files instead.
    const fs::path out(output);
    std::vector<std::string> names(scene->mNumTextures);
    for (unsigned t = 0; t < scene->mNumTextures; ++t) {
        const aiTexture* tex = scene->mTextures[t];
        if (tex->mHeight != 0)
            fail(input + ": embedded texture " + std::to_string(t) + " is not an encoded image");
        const std::string ext = tex->achFormatHint[0] ? tex->achFormatHint : "png";
        names[t] = out.stem().string() + "-texture-" + std::to_string(t) + "." + ext;
        std::ofstream f(out.parent_path() / names[t], std::ios::binary);
        f.write(reinterpret_cast<const char*>(tex->pcData), std::streamsize(tex->mWidth));
        if (!f) fail("cannot write " + (out.parent_path() / names[t]).string());
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
                    fail(input + ": texture reference " + path.C_Str() + " out of range");
                aiString file(names[index]);
                mat->AddProperty(&file, AI_MATKEY_TEXTURE(tt, i));
            }
        }
    }
    Assimp::Exporter exporter;
    if (exporter.Export(scene.get(), "obj", output) != AI_SUCCESS)
        fail("assimp cannot write " + output + ": " + exporter.GetErrorString());
    return 0;
}

// [SECTION] command line

enum class Mode { None, ReencodeGlb, ExportObj };

struct Request {
    Mode mode = Mode::None;
    std::vector<std::string> files; // the mode's arguments, in order
    bool help = false;
};

// The mode must come first (its arguments follow it), as this tool has always read its command
// line: a second mode or a mode after an argument is a usage error.
pnb::cli::Handler choose(Request& r, Mode mode) {
    return [&r, mode](const char*) {
        if (r.mode != Mode::None || !r.files.empty()) return false;
        r.mode = mode;
        return true;
    };
}

std::vector<pnb::cli::Option> options(Request& r) {
    // A mode's row names its arguments in --help; the parser takes them as positional ones.
    auto mode = [&r](std::string_view names, std::string_view arguments, std::string_view help,
                     Mode m) {
        return pnb::cli::Option{"",   names,        arguments,
                                help, choose(r, m), pnb::cli::ValueKind::None};
    };
    return {
        mode(
            "--reencode-glb", "IN.glb OUT.glb png|jpeg",
            "every embedded image decoded and re-encoded by stb_image_write: \"png\" at deflate "
            "level "
            "8, \"jpeg\" at quality 90 (and image/jpeg as its mimeType); everything else unchanged",
            Mode::ReencodeGlb),
        mode("--export-obj", "IN.glb OUT.obj",
             "IN as OBJ + MTL through assimp's exporter, its embedded images written unchanged as "
             "files next to OUT and named in the MTL",
             Mode::ExportObj),
        pnb::cli::flag("", "-h, --help", "print this help and exit",
                       [&r](const char*) {
                           r.help = true;
                           return pnb::cli::Verdict::stopHere();
                       }),
    };
}

constexpr const char* kUsage = "usage: pnb_load_inputs --reencode-glb IN.glb OUT.glb png|jpeg\n"
                               "       pnb_load_inputs --export-obj IN.glb OUT.obj\n";

} // namespace

int main(int argc, char** argv) {
    Request r;
    const std::vector<pnb::cli::Option> table = options(r);
    auto file = [&r](const char* arg) {
        if (r.mode == Mode::None) return false;
        r.files.emplace_back(arg);
        return true;
    };
    const bool parsed = !pnb::cli::parse(table, file, argc, argv);
    if (parsed && r.help) {
        std::printf(
            "%s\n%s", kUsage,
            pnb::cli::helpText(table, {.column = 16, .wrapAt = 100, .longNameOwnLine = true})
                .c_str());
        return 0;
    }
    if (parsed && r.mode == Mode::ReencodeGlb && r.files.size() == 3)
        return reencodeGlb(r.files[0], r.files[1], r.files[2]);
    if (parsed && r.mode == Mode::ExportObj && r.files.size() == 2)
        return exportObj(r.files[0], r.files[1]);
    // Every usage error gets the same two lines, as it always has.
    std::fputs(kUsage, stderr);
    return 1;
}
