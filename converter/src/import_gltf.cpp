// import_gltf.cpp — glTF 2.0 (.gltf, .glb) into the scene IR through tinygltf (importers.h).
//
// Every byte taken from a buffer goes through one bounds-checked accessor reader. Every index
// the file gives is checked before it is used. Every count is checked against the bytes behind
// it before anything is allocated, and the total the importer keeps is capped (kOutputBudget*).
//
// Does NOT do: image decoding (images stay paths or encoded bytes), KHR_animation_pointer (the
// rest pose, noted), material extensions other than emissive_strength
// (warned; spec-gloss is approximated), or processing of any kind (welding, tangents, ...).
//
// Decisions, each a documented error or a documented repair:
//  - tinygltf's own Draco path (TINYGLTF_ENABLE_DRACO) is not used. In 2.7 it indexes
//    bufferViews, buffers and accessors straight from the JSON, dereferences a null attribute
//    for an unknown Draco id, and ignores decode failures. We decode KHR_draco_mesh_compression
//    here with draco's Decoder.
//  - EXT_meshopt_compression is decoded by gltf_meshopt.cpp around tinygltf's load: its
//    fallback buffers are stubbed in the JSON (tinygltf rejects them), and the compressed
//    bufferViews are decoded into the loaded buffers before any accessor is read.
//  - KHR_texture_basisu and EXT_texture_webp textures use their fallback `source` image; one
//    without it is an Unsupported error when a material uses it (even when the file requires the
//    extension, a scene that never uses such a texture converts).
//  - tinygltf 2.7 does not check two offsets: the GLB BIN chunk end, and image bufferView ranges.
//    We validate both before handing the bytes over (checkGlb, prescanJson).
//  - Only what the chosen scene uses is imported (meshes, materials, images, lights, cameras),
//    so broken data the scene does not use does not fail the import.
//  - Errors (ConvertError{Input}): bytes outside a buffer, an index out of range, attribute
//    counts that differ, references to missing objects, a node cycle, and a node reached twice.
//    glTF nodes form strict trees, so there is no right parent to pick when a node is reached
//    twice.
//  - Repairs, each with a warning: a triangle list whose length is not a multiple of 3 loses its
//    trailing indices. A missing external image drops that texture reference. Points and lines
//    are dropped. A primitive without POSITION is dropped. A matrix with shear is decomposed by
//    Gram-Schmidt. Invalid sampler or alpha enums fall back to their defaults.
//  - Vertices that no triangle uses are dropped. Primitives often share one large accessor, and
//    the IR gives every primitive its own arrays.
//
// The stages are one file each (import_gltf_internal.h lists them); this file reads the document
// and its buffers, checks what tinygltf would not, and drives the stages (importGltf).
//
// Index: [SECTION] messages and limits, [SECTION] loading, [SECTION] importGltf
#include "pnb_converter/importers.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "gltf_internal.h"
#include "gltf_meshopt.h"

// The tinygltf implementation is compiled here and only here (import_gltf_internal.h configures
// it the same way for every file of the importer).
#define TINYGLTF_IMPLEMENTATION
#include "import_gltf_internal.h"

namespace pnb::converter {

namespace gltf_internal {

// [SECTION] loading (percentDecode is also used by import_gltf_materials.cpp for image URIs)

std::string percentDecode(const std::string& uri) {
    auto hex = [](char c) -> int {
        if (c >= '0' && c <= '9') return c - '0';
        if (c >= 'a' && c <= 'f') return c - 'a' + 10;
        if (c >= 'A' && c <= 'F') return c - 'A' + 10;
        return -1;
    };
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
            out.push_back(char(hex(uri[i + 1]) * 16 + hex(uri[i + 2])));
            i += 2;
        } else {
            out.push_back(uri[i]);
        }
    }
    return out;
}

} // namespace gltf_internal

namespace {

using namespace gltf_internal;

// [SECTION] messages and limits

// tinygltf turns extensions and extras into Values recursively, so deep JSON would overflow the
// stack. No valid glTF nests anywhere near this deep.
constexpr int kMaxJsonDepth = 64;

// tinygltf reports several problems in one string, one per line.
std::vector<std::string> splitLines(const std::string& text) {
    std::vector<std::string> lines;
    size_t begin = 0;
    while (begin < text.size()) {
        size_t end = text.find('\n', begin);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(begin, end - begin);
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
        if (!line.empty()) lines.push_back(std::move(line));
        begin = end + 1;
    }
    return lines;
}

// [SECTION] loading (continued)

uint32_t readU32(const uint8_t* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

bool isGlb(std::span<const uint8_t> bytes) {
    return bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
}

// Validates the GLB framing tinygltf trusts, and returns the JSON chunk. tinygltf 2.7 checks
// that the BIN chunk's length fits the file, but it leaves out the chunk's own 8-byte header.
// A chunk that claims to reach the end of the file then makes it read up to 8 bytes past the
// end.
std::optional<std::string> checkGlb(std::span<const uint8_t> bytes, std::string_view& json,
                                    size_t& glbLength) {
    if (bytes.size() < 20) return strf("GLB header truncated (%zu bytes)", bytes.size());
    const uint32_t version = readU32(bytes.data() + 4);
    const uint32_t length = readU32(bytes.data() + 8);
    const uint32_t jsonLength = readU32(bytes.data() + 12);
    if (version != 2) return strf("GLB version %u is not supported (2 only)", version);
    if (length > bytes.size() || length < 20) {
        return strf("GLB length %u does not match the file (%zu bytes)", length, bytes.size());
    }
    if (readU32(bytes.data() + 16) != 0x4E4F534Au) return "GLB first chunk is not JSON";
    const uint64_t jsonEnd = 20ull + jsonLength;
    if (jsonLength == 0 || jsonEnd > length) {
        return strf("GLB JSON chunk (%u bytes) runs past the end of the file (%u bytes)",
                    jsonLength, length);
    }
    if (jsonEnd < length) {
        if (jsonEnd + 8 > length) return "GLB BIN chunk header truncated";
        const uint64_t binLength = readU32(bytes.data() + jsonEnd);
        if (jsonEnd + 8 + binLength > length) {
            return strf("GLB BIN chunk (%llu bytes) runs past the end of the file (%u bytes)",
                        (unsigned long long)binLength, length);
        }
    }
    json = std::string_view(reinterpret_cast<const char*>(bytes.data()) + 20, jsonLength);
    glbLength = length;
    return std::nullopt;
}

// The GLB with its JSON chunk replaced; the chunks after it are kept as they are.
std::vector<uint8_t> replaceGlbJson(std::span<const uint8_t> glb, size_t glbLength,
                                    std::string_view oldJson, std::string json) {
    while (json.size() % 4) json.push_back(' '); // chunks end on 4-byte boundaries
    const size_t rest = glbLength - 20 - oldJson.size();
    std::vector<uint8_t> out(20 + json.size() + rest);
    auto putU32 = [&](size_t at, uint64_t v) {
        for (int i = 0; i < 4; ++i) out[at + size_t(i)] = uint8_t(v >> (8 * i));
    };
    std::memcpy(out.data(), glb.data(), 8); // magic, version
    putU32(8, out.size());
    putU32(12, json.size());
    std::memcpy(out.data() + 16, glb.data() + 16, 4); // "JSON"
    std::memcpy(out.data() + 20, json.data(), json.size());
    std::memcpy(out.data() + 20 + json.size(), glb.data() + 20 + oldJson.size(), rest);
    return out;
}

// Whether arrays and objects nest deeper than kMaxJsonDepth, from the text alone. Not with
// nlohmann's parser callback: its DOM builder rescans the enclosing container at every
// end_object, which is quadratic in the length of arrays such as "nodes".
bool jsonTooDeep(std::string_view text) {
    int depth = 0;
    bool inString = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') ++i; // skip the escaped character
            else if (c == '"') inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth) return true;
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return false;
}

// Checks the parts of the JSON that tinygltf 2.7 would use unchecked. It hands image bufferView
// bytes to the image callback as &buffer[byteOffset] with byteLength, and never compares these
// with the buffer size. It also recurses over extensions and extras once per nesting level.
// JSON that does not parse is left for tinygltf to report.
//
// tinygltf 2.7 also demands that every primitive's indices accessor has a bufferView. A Draco
// primitive's indices accessor has none: its indices are the decoded faces. So without
// tinygltf's own Draco path, every Draco file would be rejected. We drop "indices" from Draco
// primitives (we take the decoded faces anyway). EXT_meshopt_compression fallback buffers are
// stubbed and the compressed bufferViews recorded in `meshopt` (gltf_meshopt.h). `patched`
// receives the rewritten JSON; it stays empty when nothing changed.
std::optional<std::string> prescanJson(std::string_view text, std::string& patched,
                                       gltf_meshopt::MeshoptPlan& meshopt) {
    if (jsonTooDeep(text)) return strf("JSON nests deeper than %d levels", kMaxJsonDepth);
    nlohmann::json doc = nlohmann::json::parse(text.begin(), text.end(), nullptr, false);
    if (doc.is_discarded()) return std::nullopt;

    bool changed = false;
    if (auto meshes = doc.find("meshes"); doc.is_object() && meshes != doc.end() &&
                                          meshes->is_array()) {
        for (nlohmann::json& mesh : *meshes) {
            auto primitives = mesh.is_object() ? mesh.find("primitives") : mesh.end();
            if (primitives == mesh.end() || !primitives->is_array()) continue;
            for (nlohmann::json& primitive : *primitives) {
                const nlohmann::json* ext = jsonMember(primitive, "extensions");
                if (ext && jsonMember(*ext, "KHR_draco_mesh_compression") &&
                    primitive.erase("indices") > 0) {
                    changed = true;
                }
            }
        }
    }
    if (auto e = gltf_meshopt::planMeshopt(doc, meshopt, changed)) return e;
    if (changed) patched = doc.dump();

    const nlohmann::json* images = jsonMember(doc, "images");
    const nlohmann::json* views = jsonMember(doc, "bufferViews");
    const nlohmann::json* buffers = jsonMember(doc, "buffers");
    if (!images || !images->is_array()) return std::nullopt;
    for (size_t i = 0; i < images->size(); ++i) {
        const std::optional<int> view = jsonInt(jsonMember((*images)[i], "bufferView"));
        if (!view || !views || !views->is_array() || *view < 0 || size_t(*view) >= views->size()) {
            continue; // tinygltf reports these itself
        }
        const nlohmann::json& bv = (*views)[size_t(*view)];
        const std::optional<int> buffer = jsonInt(jsonMember(bv, "buffer"));
        if (!buffer || !buffers || !buffers->is_array() || *buffer < 0 ||
            size_t(*buffer) >= buffers->size()) {
            continue;
        }
        const uint64_t offset = jsonUnsigned(jsonMember(bv, "byteOffset")).value_or(0);
        const std::optional<uint64_t> length = jsonUnsigned(jsonMember(bv, "byteLength"));
        const std::optional<uint64_t> bufferLength =
            jsonUnsigned(jsonMember((*buffers)[size_t(*buffer)], "byteLength"));
        if (!length || !bufferLength) continue; // tinygltf rejects the file
        if (*length == 0 || offset > *bufferLength || *length > *bufferLength - offset) {
            return strf("image %zu: bufferView %d (byteOffset %llu, byteLength %llu) exceeds "
                        "buffer %d (%llu bytes)",
                        i, *view, (unsigned long long)offset, (unsigned long long)*length,
                        *buffer, (unsigned long long)*bufferLength);
        }
    }
    return std::nullopt;
}

// tinygltf image callback. For a data URI this is the only place the decoded file bytes exist,
// so we keep them. For a bufferView image we don't use tinygltf's pointer; importImage reads the
// view again, bounds-checked.
bool keepEncodedImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
    if (image->bufferView < 0 && bytes && size > 0) image->image.assign(bytes, bytes + size);
    return true;
}

// tinygltf looks for external buffers in the source's directory and then in the working
// directory. The second lookup would make the output depend on where the tool runs, so only
// paths inside the source's directory exist for it.
bool fileExistsInBaseDir(const std::string& absPath, void* userData) {
    const std::string& prefix = *static_cast<const std::string*>(userData);
    if (!prefix.empty() && absPath.compare(0, prefix.size(), prefix) != 0) return false;
    return tinygltf::FileExists(absPath, nullptr);
}

Result<std::vector<uint8_t>, ConvertError> readFile(const std::string& path,
                                                    const std::string& file) {
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) return ConvertError{ConvertErrorKind::Input, file + ": cannot open: " + ec.message()};
    // tinygltf takes lengths as unsigned int.
    if (size >= (uintmax_t(1) << 32)) {
        return ConvertError{ConvertErrorKind::Input,
                            strf("%s: %ju bytes; glTF/GLB files of 4 GiB or more are not "
                                 "supported",
                                 file.c_str(), size)};
    }
    std::ifstream in(path, std::ios::binary);
    std::vector<uint8_t> bytes(static_cast<size_t>(size));
    if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()))) {
        return ConvertError{ConvertErrorKind::Input, file + ": cannot read the file"};
    }
    return bytes;
}

// Extensions we implement. KHR_materials_pbrSpecularGlossiness is approximated (a warning per
// material), which is better than refusing a file that requires it.
constexpr std::string_view kSupportedExtensions[] = {
    "KHR_draco_mesh_compression", "KHR_texture_transform", "KHR_materials_emissive_strength",
    "KHR_lights_punctual", "KHR_mesh_quantization", "KHR_materials_pbrSpecularGlossiness",
    "EXT_meshopt_compression", "KHR_materials_unlit", "EXT_mesh_gpu_instancing",
};

bool isSupported(const std::string& extension) {
    return std::find(std::begin(kSupportedExtensions), std::end(kSupportedExtensions),
                     extension) != std::end(kSupportedExtensions);
}

bool isImageFormatExtension(const std::string& extension) {
    return std::find(std::begin(kImageFormatExtensions), std::end(kImageFormatExtensions),
                     extension) != std::end(kImageFormatExtensions);
}

// What the player draws instead of each glTF extension it does not implement (the summary's
// "not rendered" lines). An extension not listed is named with a generic fallback.
struct ExtensionFallback { std::string_view name, fallback; };
constexpr ExtensionFallback kExtensionFallbacks[] = {
    {"KHR_materials_transmission", "opaque: no light through the surface, no refraction"},
    {"KHR_materials_volume", "no absorption inside the volume"},
    {"KHR_materials_clearcoat", "the base layer without its clear coat"},
    {"KHR_materials_sheen", "the base layer without sheen"},
    {"KHR_materials_iridescence", "no thin-film colours"},
    {"KHR_materials_specular", "the default dielectric specular (F0 0.04, white)"},
    {"KHR_materials_ior", "index of refraction 1.5 (F0 0.04)"},
    {"KHR_materials_anisotropy", "isotropic GGX"},
    {"KHR_materials_dispersion", "no dispersion"},
    {"KHR_materials_diffuse_transmission", "opaque diffuse"},
    {"KHR_materials_variants", "the default material of each primitive"},
    {"KHR_animation_pointer", "the rest pose"},
    {"KHR_xmp_json_ld", "metadata, not carried"},
    {"EXT_lights_image_based", "the default environment or none"},
};

// How many materials, textures, meshes' primitives and nodes name extension `ext`.
std::string extensionUse(const tinygltf::Model& m, const std::string& ext) {
    size_t materials = 0, textures = 0, primitives = 0, nodes = 0;
    for (const tinygltf::Material& x : m.materials) materials += x.extensions.count(ext);
    for (const tinygltf::Texture& x : m.textures) textures += x.extensions.count(ext);
    for (const tinygltf::Mesh& x : m.meshes)
        for (const tinygltf::Primitive& p : x.primitives) primitives += p.extensions.count(ext);
    for (const tinygltf::Node& x : m.nodes) nodes += x.extensions.count(ext);
    std::string use;
    auto add = [&](size_t n, const char* what) {
        if (n) use += (use.empty() ? "" : ", ") + std::to_string(n) + " " + what;
    };
    add(materials, materials == 1 ? "material" : "materials");
    add(textures, textures == 1 ? "texture" : "textures");
    add(primitives, primitives == 1 ? "primitive" : "primitives");
    add(nodes, nodes == 1 ? "node" : "nodes");
    return use.empty() ? "declared" : use;
}

Check checkExtensions(Ctx& ctx) {
    std::string missing;
    for (const std::string& ext : ctx.model.extensionsRequired) {
        if (!isSupported(ext) && !isImageFormatExtension(ext)) {
            missing += (missing.empty() ? "" : ", ") + ext;
        }
    }
    if (!missing.empty()) {
        return ctx.fail("required extension(s) not supported: " + missing,
                        ConvertErrorKind::Unsupported);
    }
    for (const std::string& ext : ctx.model.extensionsUsed) {
        if (isSupported(ext) || isImageFormatExtension(ext)) continue; // images: per texture
        std::string_view fallback = "ignored (not known to pnb-convert)";
        for (const ExtensionFallback& f : kExtensionFallbacks)
            if (f.name == ext) fallback = f.fallback;
        ctx.scene.noteNotRendered(ext, 0, extensionUse(ctx.model, ext), std::string(fallback));
    }
    return std::nullopt;
}

// [SECTION] importGltf

Result<IrScene, ConvertError> importGltfUnguarded(const std::string& path,
                                                  const std::string& file) {
    auto bytes = readFile(path, file);
    if (!bytes) return bytes.error();
    const std::span<const uint8_t> data(*bytes);
    auto fail = [&](const std::string& msg, ConvertErrorKind kind = ConvertErrorKind::Input) {
        return ConvertError{kind, file + ": " + msg};
    };

    const bool binary = isGlb(data);
    std::string_view json(reinterpret_cast<const char*>(data.data()), data.size());
    size_t glbLength = 0;
    if (binary) {
        if (auto e = checkGlb(data, json, glbLength)) return fail(*e);
    }
    std::string patched;
    gltf_meshopt::MeshoptPlan meshopt;
    if (auto e = prescanJson(json, patched, meshopt)) return fail(*e);
    std::vector<uint8_t> patchedGlb;
    if (!patched.empty() && binary) {
        patchedGlb = replaceGlbJson(data, glbLength, json, std::move(patched));
        if (patchedGlb.size() >= (size_t(1) << 32)) return fail("GLB too large after rewriting");
        glbLength = patchedGlb.size();
    } else if (!patched.empty()) {
        if (patched.size() >= (size_t(1) << 32)) return fail("JSON too large after rewriting");
        json = patched;
    }
    const uint8_t* glbBytes = patchedGlb.empty() ? data.data() : patchedGlb.data();

    // tinygltf joins the base directory and URIs with '/'; fileExistsInBaseDir needs the same
    // prefix.
    const std::string baseDir = std::filesystem::path(path).parent_path().string();
    std::string basePrefix = baseDir;
    if (!basePrefix.empty() && basePrefix.back() != '/') basePrefix += '/';

    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&keepEncodedImage, nullptr);
    loader.SetFsCallbacks({&fileExistsInBaseDir, &tinygltf::ExpandFilePath,
                           &tinygltf::ReadWholeFile, &tinygltf::WriteWholeFile, &basePrefix});
    std::string err, warn;
    const bool loaded = binary
        ? loader.LoadBinaryFromMemory(&model, &err, &warn, glbBytes, unsigned(glbLength),
                                      baseDir)
        : loader.LoadASCIIFromString(&model, &err, &warn, json.data(), unsigned(json.size()),
                                     baseDir);
    if (!loaded) {
        std::string joined;
        for (const std::string& line : splitLines(err)) {
            joined += (joined.empty() ? "" : "; ") + line;
        }
        return fail(joined.empty() ? "tinygltf failed without a message" : joined);
    }

    IrScene scene;
    scene.sourcePath = path;
    Ctx ctx{model, scene, file, baseDir};
    // tinygltf also reports some problems as errors without failing the load: warnings to us.
    for (const std::string& line : splitLines(err)) ctx.warn("tinygltf: " + line);
    for (const std::string& line : splitLines(warn)) ctx.warn("tinygltf: " + line);

    const std::string& version = model.asset.version;
    if (version.empty() || version[0] != '2' || (version.size() > 1 && version[1] != '.')) {
        return fail("glTF version '" + version + "' is not supported (2.x only)",
                    ConvertErrorKind::Unsupported);
    }
    if (auto e = checkExtensions(ctx)) return *e;

    // The budget scales with what the file stores, measured before meshopt decoding: the
    // decoded fallback buffers must fit in it too.
    uint64_t inputBytes = data.size();
    for (const tinygltf::Buffer& b : model.buffers) inputBytes += b.data.size();
    ctx.budgetBytes = std::max(kMinOutputBudgetBytes, inputBytes * kOutputBudgetFactor);
    if (!meshopt.empty()) {
        std::vector<std::vector<unsigned char>*> buffers;
        for (tinygltf::Buffer& b : model.buffers) buffers.push_back(&b.data);
        if (auto e = gltf_meshopt::decodeMeshopt(meshopt, buffers, ctx.budgetBytes)) {
            return fail(*e);
        }
    }
    for (const tinygltf::Buffer& b : model.buffers) {
        if (!b.uri.empty() && !tinygltf::IsDataURI(b.uri)) {
            // Where tinygltf found it: only the source's directory (fileExistsInBaseDir).
            const std::filesystem::path uri(percentDecode(b.uri));
            scene.dependencies.push_back(
                (baseDir.empty() ? uri : std::filesystem::path(baseDir) / uri)
                    .lexically_normal()
                    .string());
        }
    }
    ctx.meshMap.assign(model.meshes.size(), -1);
    ctx.materialMap.assign(model.materials.size(), -1);
    ctx.imageMap.assign(model.images.size(), -1);
    ctx.lightMap.assign(model.lights.size(), -1);
    ctx.cameraMap.assign(model.cameras.size(), -1);

    ctx.skinnedMeshMap.assign(model.meshes.size(), -1);
    ctx.nodeMap.assign(model.nodes.size(), -1);

    std::string rootsWho;
    auto roots = chooseRoots(ctx, rootsWho);
    if (!roots) return roots.error();
    if (auto e = flattenNodes(ctx, *roots, rootsWho)) return *e;
    if (auto e = importSkins(ctx)) return *e;
    if (auto e = importAnimations(ctx)) return *e;
    return scene;
}

} // namespace

Result<IrScene, ConvertError> importGltf(const std::string& path) {
    const std::string file = std::filesystem::path(path).filename().string();
    // tinygltf and draco may throw (std::vector::at on empty data, bad_alloc); no exception
    // leaves the converter.
    try {
        return importGltfUnguarded(path, file);
    } catch (const std::bad_alloc&) {
        return ConvertError{ConvertErrorKind::Input, file + ": out of memory while importing"};
    } catch (const std::exception& e) {
        return ConvertError{ConvertErrorKind::Input, file + ": " + e.what()};
    }
}

} // namespace pnb::converter
