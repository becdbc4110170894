// import_gltf.cpp — glTF 2.0 (.gltf, .glb) into the scene IR through tinygltf (importers.h).
//
// Every byte taken from a buffer goes through one bounds-checked accessor reader. Every index
// the file gives is checked before it is used. Every count is checked against the bytes behind
// it before anything is allocated, and the total the importer keeps is capped (kOutputBudget*).
//
// Does NOT do: image decoding (images stay paths or encoded bytes), animation, skinning, morph
// targets (all warned about and ignored), material extensions other than emissive_strength
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
// Index: [SECTION] messages and limits, [SECTION] loading, [SECTION] accessor reader,
// [SECTION] draco, [SECTION] meshes, [SECTION] images and materials,
// [SECTION] lights and cameras, [SECTION] nodes, [SECTION] importGltf
#include "pnb_converter/importers.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <draco/compression/decode.h>
#include <draco/mesh/mesh.h>
#include <nlohmann/json.hpp>

#include "gltf_internal.h"
#include "gltf_meshopt.h"

// The tinygltf implementation is compiled here and only here. We don't need stb: images are
// never decoded here. External images are not read, because we keep their URI. The built-in
// Draco path is not used (see above).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

namespace pnb::converter {

namespace {

using namespace gltf_internal;

// [SECTION] messages and limits

// Decoded data the importer may keep, as a multiple of the input bytes (file plus buffers), with
// a floor for small inputs. Legitimate expansion is bounded: integer attributes become floats
// (at most 4x), strips and fans become lists (3x), and Draco typically achieves 10-30x. Without
// a cap, primitives that share one accessor could multiply memory use without bound.
constexpr uint64_t kOutputBudgetFactor = 64;
constexpr uint64_t kMinOutputBudgetBytes = 512ull << 20;
// tinygltf turns extensions and extras into Values recursively, so deep JSON would overflow the
// stack. No valid glTF nests anywhere near this deep.
constexpr int kMaxJsonDepth = 64;

// "mesh 'Wheel'" when named, "mesh 3" when not. Precondition: index is valid.
template <class T>
std::string label(const char* kind, int index, const std::vector<T>& items) {
    const std::string& name = items[size_t(index)].name;
    return name.empty() ? strf("%s %d", kind, index) : strf("%s '%s'", kind, name.c_str());
}

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

using Check = std::optional<ConvertError>; // empty = success

// State of one import. The *Map vectors memoise lazy imports: glTF index → IR index, -1 = not
// imported yet, -2 = dropped (a warning was already given).
struct Ctx {
    const tinygltf::Model& model;
    IrScene& scene;
    std::string file;    // the source's file name, the prefix of every message
    std::string baseDir; // the source's directory, for external images
    uint64_t budgetBytes = 0, retainedBytes = 0;
    std::vector<int> meshMap, materialMap, imageMap, lightMap, cameraMap;

    ConvertError fail(const std::string& msg,
                      ConvertErrorKind kind = ConvertErrorKind::Input) const {
        return {kind, file + ": " + msg};
    }
    void warn(const std::string& msg) { scene.warnings.push_back(file + ": " + msg); }

    // Checks that `bytes` more decoded data stay inside the output budget.
    Check fits(uint64_t bytes, const std::string& who) const {
        if (bytes <= budgetBytes - std::min(retainedBytes, budgetBytes)) return {};
        return fail(strf("%s: decoding needs %llu more bytes, past the importer's limit of %llu "
                         "bytes (%llu x the input size, at least %llu MiB)",
                         who.c_str(), (unsigned long long)bytes, (unsigned long long)budgetBytes,
                         (unsigned long long)kOutputBudgetFactor,
                         (unsigned long long)(kMinOutputBudgetBytes >> 20)));
    }
};

// [SECTION] loading

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
    "EXT_meshopt_compression",
};

// Texture extensions for image formats we do not decode (KTX2/Basis Universal, WebP). A texture
// using one may name a fallback image in its ordinary `source`, which we use; a texture without
// one is an Unsupported error when a material uses it (importTextureRef), so a file that
// requires them fails only if the scene actually needs such an image.
constexpr const char* kImageFormatExtensions[] = {"KHR_texture_basisu", "EXT_texture_webp"};

bool isSupported(const std::string& extension) {
    return std::find(std::begin(kSupportedExtensions), std::end(kSupportedExtensions),
                     extension) != std::end(kSupportedExtensions);
}

bool isImageFormatExtension(const std::string& extension) {
    return std::find(std::begin(kImageFormatExtensions), std::end(kImageFormatExtensions),
                     extension) != std::end(kImageFormatExtensions);
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
        if (!isSupported(ext)) ctx.warn("ignored extension " + ext);
    }
    return std::nullopt;
}

// Helpers over tinygltf::Value, whose Get() asserts on the wrong type.
const tinygltf::Value* member(const tinygltf::Value* v, const char* key) {
    return v && v->IsObject() && v->Has(key) ? &v->Get(key) : nullptr;
}
const tinygltf::Value* extensionObject(const tinygltf::ExtensionMap& extensions,
                                       const char* name) {
    auto it = extensions.find(name);
    return it != extensions.end() && it->second.IsObject() ? &it->second : nullptr;
}
std::optional<double> numberOf(const tinygltf::Value* v) {
    if (!v || !v->IsNumber() || !std::isfinite(v->GetNumberAsDouble())) return std::nullopt;
    return v->GetNumberAsDouble();
}
std::optional<int> intOf(const tinygltf::Value* v) {
    if (!v || !v->IsInt()) return std::nullopt;
    return v->Get<int>();
}
bool numbersOf(const tinygltf::Value* v, float* out, size_t n) {
    if (!v || !v->IsArray() || v->ArrayLen() != n) return false;
    for (size_t i = 0; i < n; ++i) {
        const std::optional<double> x = numberOf(&v->Get(int(i)));
        if (!x) return false;
        out[i] = float(*x);
    }
    return true;
}
bool finiteAll(const std::vector<double>& values) {
    return std::all_of(values.begin(), values.end(), [](double x) { return std::isfinite(x); });
}

// [SECTION] accessor reader

size_t componentSize(int componentType) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0; // INT and DOUBLE are not glTF 2.0 accessor types
    }
}

const char* typeName(int components) {
    static const char* const kNames[] = {"?", "SCALAR", "VEC2", "VEC3", "VEC4"};
    return components >= 1 && components <= 4 ? kNames[components] : "?";
}

// One component, exactly: every glTF component type fits a double without rounding. memcpy
// because glTF only promises alignment for well-formed files.
double readComponent(const uint8_t* p, int componentType) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return double(int8_t(p[0]));
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return double(p[0]);
    case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t v; std::memcpy(&v, p, 2); return v; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; std::memcpy(&v, p, 2); return v; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; std::memcpy(&v, p, 4); return v; }
    case TINYGLTF_COMPONENT_TYPE_FLOAT: { float v; std::memcpy(&v, p, 4); return v; }
    default: return 0;
    }
}

// glTF 2.0 §3.11: signed values map with max(c / MAX, -1), unsigned ones with c / MAX.
float toFloat(double raw, int componentType, bool normalized) {
    if (!normalized) return float(raw);
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return std::max(float(raw / 127.0), -1.0f);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return float(raw / 255.0);
    case TINYGLTF_COMPONENT_TYPE_SHORT: return std::max(float(raw / 32767.0), -1.0f);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return float(raw / 65535.0);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return float(raw / 4294967295.0);
    default: return float(raw);
    }
}

// What an accessor's data is and where, after validation: element i's bytes are
// base[i * stride, i * stride + elementSize), all inside a loaded buffer.
struct AccessorLayout {
    const tinygltf::Accessor* accessor = nullptr;
    size_t count = 0, componentSize = 0, elementSize = 0, stride = 0;
    int componentType = 0, components = 0;
    bool normalized = false;
    const uint8_t* base = nullptr; // null: no bufferView, so all zeros (plus sparse values)
};

std::string accessorWho(int index, const std::string& where) {
    return strf("accessor %d (%s)", index, where.c_str());
}

// The bytes of a bufferView, checked against the size of the buffer that was actually loaded.
Result<std::span<const uint8_t>, ConvertError> viewBytes(const Ctx& ctx, int view,
                                                         const std::string& who) {
    const tinygltf::Model& m = ctx.model;
    if (view < 0 || size_t(view) >= m.bufferViews.size()) {
        return ctx.fail(strf("%s: bufferView %d does not exist (%zu bufferViews)", who.c_str(),
                             view, m.bufferViews.size()));
    }
    const tinygltf::BufferView& bv = m.bufferViews[size_t(view)];
    if (bv.buffer < 0 || size_t(bv.buffer) >= m.buffers.size()) {
        return ctx.fail(strf("%s: bufferView %d refers to buffer %d, which does not exist (%zu "
                             "buffers)",
                             who.c_str(), view, bv.buffer, m.buffers.size()));
    }
    const std::vector<unsigned char>& data = m.buffers[size_t(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset) {
        return ctx.fail(strf("%s: bufferView %d (byteOffset %zu, byteLength %zu) exceeds buffer "
                             "%d (%zu bytes)",
                             who.c_str(), view, bv.byteOffset, bv.byteLength, bv.buffer,
                             data.size()));
    }
    return std::span<const uint8_t>(data.data() + bv.byteOffset, bv.byteLength);
}

// Validates accessor `index` for one use (`where` names it: "mesh 'Cube' primitive 0 POSITION").
Result<AccessorLayout, ConvertError> layoutOf(const Ctx& ctx, int index, const std::string& where,
                                              bool forIndices) {
    const tinygltf::Model& m = ctx.model;
    const std::string who = accessorWho(index, where);
    if (index < 0 || size_t(index) >= m.accessors.size()) {
        return ctx.fail(strf("%s: does not exist (%zu accessors)", who.c_str(),
                             m.accessors.size()));
    }
    const tinygltf::Accessor& a = m.accessors[size_t(index)];
    AccessorLayout l;
    l.accessor = &a;
    l.componentType = a.componentType;
    l.componentSize = componentSize(a.componentType);
    const bool allowed = forIndices
        ? (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
           a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
           a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        : (l.componentSize != 0 && a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
    if (!allowed) {
        return ctx.fail(strf("%s: componentType %d is not allowed here", who.c_str(),
                             a.componentType));
    }
    l.components = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    if (l.components < 1 || l.components > 4) {
        return ctx.fail(strf("%s: matrix types are not allowed here", who.c_str()));
    }
    if (a.count == 0) return ctx.fail(who + ": count is 0");
    if (a.count > std::numeric_limits<uint32_t>::max()) {
        return ctx.fail(strf("%s: count %zu does not fit 32-bit indices", who.c_str(), a.count));
    }
    l.count = a.count;
    l.normalized = a.normalized && !forIndices;
    l.elementSize = l.componentSize * size_t(l.components);
    l.stride = l.elementSize;
    if (a.bufferView < 0) return l; // all zeros unless sparse (glTF 2.0 §3.6.2.3)

    auto view = viewBytes(ctx, a.bufferView, who);
    if (!view) return view.error();
    const size_t declaredStride = m.bufferViews[size_t(a.bufferView)].byteStride;
    if (declaredStride != 0) {
        if (declaredStride < l.elementSize) {
            return ctx.fail(strf("%s: bufferView %d byteStride %zu is smaller than the element "
                                 "(%zu bytes)",
                                 who.c_str(), a.bufferView, declaredStride, l.elementSize));
        }
        l.stride = declaredStride;
    }
    // The last element ends at byteOffset + (count - 1) * stride + elementSize; checked without
    // overflow.
    const size_t size = view->size();
    const bool fits = a.byteOffset <= size && size - a.byteOffset >= l.elementSize &&
                      (l.count - 1) <= (size - a.byteOffset - l.elementSize) / l.stride;
    if (!fits) {
        return ctx.fail(strf("%s: byteOffset %zu + count %zu x stride %zu exceeds bufferView %d "
                             "(%zu bytes)",
                             who.c_str(), a.byteOffset, l.count, l.stride, a.bufferView, size));
    }
    l.base = view->data() + a.byteOffset;
    return l;
}

// Validates the accessor's sparse substitution and calls apply(element, valueBytes) for each
// entry. Sparse index and value arrays are tightly packed (glTF 2.0 §3.6.2.3).
template <class Apply>
Check applySparse(const Ctx& ctx, const AccessorLayout& l, const std::string& who, Apply apply) {
    const auto& s = l.accessor->sparse;
    if (!s.isSparse) return std::nullopt;
    if (s.count < 1 || size_t(s.count) > l.count) {
        return ctx.fail(strf("%s: sparse count %d is outside 1..%zu", who.c_str(), s.count,
                             l.count));
    }
    const int indexType = s.indices.componentType;
    const size_t indexSize = componentSize(indexType);
    if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        return ctx.fail(strf("%s: sparse indices componentType %d is not allowed", who.c_str(),
                             indexType));
    }
    const size_t n = size_t(s.count);
    struct Part { const char* name; int view; int offset; size_t elementSize; };
    const Part parts[2] = {{"indices", s.indices.bufferView, s.indices.byteOffset, indexSize},
                           {"values", s.values.bufferView, s.values.byteOffset, l.elementSize}};
    const uint8_t* starts[2] = {};
    for (int i = 0; i < 2; ++i) {
        const Part& p = parts[i];
        const std::string partWho = who + " sparse " + p.name;
        auto view = viewBytes(ctx, p.view, partWho);
        if (!view) return view.error();
        // n <= accessor count <= 2^32 and elementSize <= 16, so n * elementSize cannot overflow.
        const size_t bytes = n * p.elementSize;
        if (p.offset < 0 || size_t(p.offset) > view->size() ||
            bytes > view->size() - size_t(p.offset)) {
            return ctx.fail(strf("%s: byteOffset %d + %zu x %zu bytes exceeds bufferView %d "
                                 "(%zu bytes)",
                                 partWho.c_str(), p.offset, n, p.elementSize, p.view,
                                 view->size()));
        }
        starts[i] = view->data() + p.offset;
    }
    for (size_t k = 0; k < n; ++k) {
        const double index = readComponent(starts[0] + k * indexSize, indexType);
        if (index >= double(l.count)) {
            return ctx.fail(strf("%s: sparse index %.0f (entry %zu) is out of range 0..%zu",
                                 who.c_str(), index, k, l.count - 1));
        }
        apply(size_t(index), starts[1] + k * l.elementSize);
    }
    return std::nullopt;
}

// What an attribute must look like.
struct AttributeSpec {
    int minComponents = 1, maxComponents = 4;
    bool forceNormalized = false; // integer COLOR_0 is always normalized
};

Check checkComponents(const Ctx& ctx, int components, const AttributeSpec& spec,
                      const std::string& who) {
    if (components >= spec.minComponents && components <= spec.maxComponents) return {};
    const std::string expected = spec.minComponents == spec.maxComponents
        ? typeName(spec.minComponents)
        : strf("%s..%s", typeName(spec.minComponents), typeName(spec.maxComponents));
    return ctx.fail(strf("%s: type %s, expected %s", who.c_str(), typeName(components),
                         expected.c_str()));
}

// The single entry point for attribute data: returns count x components floats.
Result<std::vector<float>, ConvertError> readFloats(const Ctx& ctx, int index,
                                                    const std::string& where,
                                                    const AttributeSpec& spec, int& components) {
    auto layout = layoutOf(ctx, index, where, false);
    if (!layout) return layout.error();
    const AccessorLayout& l = *layout;
    const std::string who = accessorWho(index, where);
    if (auto e = checkComponents(ctx, l.components, spec, who)) return *e;
    if (auto e = ctx.fits(uint64_t(l.count) * uint64_t(l.components) * sizeof(float), who)) {
        return *e;
    }
    const bool normalized =
        l.normalized || (spec.forceNormalized && l.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT);
    const size_t nc = size_t(l.components);
    std::vector<float> out(l.count * nc, 0.0f);
    auto decode = [&](size_t element, const uint8_t* src) {
        for (size_t c = 0; c < nc; ++c) {
            out[element * nc + c] = toFloat(readComponent(src + c * l.componentSize,
                                                          l.componentType),
                                            l.componentType, normalized);
        }
    };
    if (l.base) {
        for (size_t i = 0; i < l.count; ++i) decode(i, l.base + i * l.stride);
    }
    if (auto e = applySparse(ctx, l, who, decode)) return *e;
    components = l.components;
    return out;
}

Result<std::vector<uint32_t>, ConvertError> readIndices(const Ctx& ctx, int index,
                                                        const std::string& where) {
    auto layout = layoutOf(ctx, index, where, true);
    if (!layout) return layout.error();
    const AccessorLayout& l = *layout;
    const std::string who = accessorWho(index, where);
    if (l.components != 1) {
        return ctx.fail(strf("%s: type %s, expected SCALAR", who.c_str(), typeName(l.components)));
    }
    if (auto e = ctx.fits(uint64_t(l.count) * sizeof(uint32_t), who)) return *e;
    std::vector<uint32_t> out(l.count, 0);
    auto decode = [&](size_t element, const uint8_t* src) {
        out[element] = uint32_t(readComponent(src, l.componentType));
    };
    if (l.base) {
        for (size_t i = 0; i < l.count; ++i) decode(i, l.base + i * l.stride);
    }
    if (auto e = applySparse(ctx, l, who, decode)) return *e;
    return out;
}

// [SECTION] draco

struct DracoMesh {
    std::unique_ptr<draco::Mesh> mesh;
    const tinygltf::Value* attributes = nullptr; // semantic → Draco unique id
};

// Decodes a primitive's KHR_draco_mesh_compression bufferView.
Result<DracoMesh, ConvertError> decodeDraco(const Ctx& ctx, const tinygltf::Value& ext,
                                            const std::string& where) {
    const std::string who = where + " KHR_draco_mesh_compression";
    const std::optional<int> view = intOf(member(&ext, "bufferView"));
    const tinygltf::Value* attributes = member(&ext, "attributes");
    if (!view || !attributes || !attributes->IsObject()) {
        return ctx.fail(who + ": needs an integer bufferView and an attributes object");
    }
    auto bytes = viewBytes(ctx, *view, who);
    if (!bytes) return bytes.error();
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes->data()), bytes->size());
    auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
    if (!type.ok() || type.value() != draco::TRIANGULAR_MESH) {
        return ctx.fail(who + ": bufferView " + std::to_string(*view) +
                        " is not a Draco triangle mesh");
    }
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) {
        return ctx.fail(who + ": Draco decoding failed: " + decoded.status().error_msg_string());
    }
    DracoMesh out;
    out.mesh = std::move(decoded).value();
    out.attributes = attributes;
    if (!out.mesh) return ctx.fail(who + ": Draco decoding failed");
    return out;
}

// A decoded Draco attribute as floats. The accessor (`index`) describes the decoded data: its
// type, component type and normalized flag. We apply that flag ourselves instead of Draco's
// own, which encoders don't always set.
Result<std::vector<float>, ConvertError> readDracoFloats(Ctx& ctx, const DracoMesh& draco,
                                                         int dracoId, int index,
                                                         const std::string& where,
                                                         const AttributeSpec& spec,
                                                         int& components) {
    const std::string who = accessorWho(index, where);
    if (index < 0 || size_t(index) >= ctx.model.accessors.size()) {
        return ctx.fail(strf("%s: does not exist (%zu accessors)", who.c_str(),
                             ctx.model.accessors.size()));
    }
    const tinygltf::Accessor& a = ctx.model.accessors[size_t(index)];
    const int nc = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    if (auto e = checkComponents(ctx, nc, spec, who)) return *e;
    if (componentSize(a.componentType) == 0 ||
        a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        return ctx.fail(strf("%s: componentType %d is not allowed here", who.c_str(),
                             a.componentType));
    }
    const draco::PointAttribute* att =
        dracoId < 0 ? nullptr : draco.mesh->GetAttributeByUniqueId(uint32_t(dracoId));
    if (!att) return ctx.fail(strf("%s: Draco attribute %d does not exist", who.c_str(), dracoId));
    if (att->num_components() != nc) {
        return ctx.fail(strf("%s: Draco attribute %d has %d components, the accessor is %s",
                             who.c_str(), dracoId, int(att->num_components()), typeName(nc)));
    }
    const size_t n = draco.mesh->num_points();
    if (n == 0) return ctx.fail(who + ": the Draco mesh has no points");
    if (!att->is_mapping_identity() && att->indices_map_size() < n) {
        return ctx.fail(strf("%s: Draco attribute %d maps fewer points than the mesh has",
                             who.c_str(), dracoId));
    }
    if (auto e = ctx.fits(uint64_t(n) * uint64_t(nc) * sizeof(float), who)) return *e;
    const bool isFloat = att->data_type() == draco::DT_FLOAT32 ||
                         att->data_type() == draco::DT_FLOAT64;
    const bool normalized =
        a.normalized || (spec.forceNormalized && a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT);
    std::vector<float> out(n * size_t(nc));
    for (size_t p = 0; p < n; ++p) {
        const draco::AttributeValueIndex value = att->mapped_index(draco::PointIndex(uint32_t(p)));
        bool ok = value.value() < att->size();
        float* dst = out.data() + p * size_t(nc);
        if (ok && isFloat) {
            ok = att->ConvertValue<float>(value, int8_t(nc), dst);
        } else if (ok) {
            int64_t raw[4] = {};
            ok = att->ConvertValue<int64_t>(value, int8_t(nc), raw);
            for (int c = 0; ok && c < nc; ++c) {
                dst[c] = toFloat(double(raw[c]), a.componentType, normalized);
            }
        }
        if (!ok) {
            return ctx.fail(strf("%s: Draco attribute %d: value of point %zu is unreadable",
                                 who.c_str(), dracoId, p));
        }
    }
    if (a.count != n) {
        // The decoded data is the truth; the accessor's count is only a declaration.
        ctx.warn(strf("%s: count %zu, Draco decoded %zu points", who.c_str(), a.count, n));
    }
    components = nc;
    return out;
}

Result<std::vector<uint32_t>, ConvertError> readDracoIndices(const Ctx& ctx, const DracoMesh& draco,
                                                             const std::string& where) {
    const draco::Mesh& mesh = *draco.mesh;
    const size_t faces = mesh.num_faces();
    if (auto e = ctx.fits(uint64_t(faces) * 3 * sizeof(uint32_t), where)) return *e;
    std::vector<uint32_t> out;
    out.reserve(faces * 3);
    for (uint32_t f = 0; f < faces; ++f) {
        for (const draco::PointIndex& p : mesh.face(draco::FaceIndex(f))) out.push_back(p.value());
    }
    return out; // range-checked by the caller, like every other index source
}

// [SECTION] meshes

// glTF 2.0 §3.7.2.1: strips and fans, in the winding the specification gives.
Result<std::vector<uint32_t>, ConvertError> triangulate(Ctx& ctx, std::vector<uint32_t> in,
                                                        int mode, const std::string& where) {
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (size_t extra = in.size() % 3) {
            ctx.warn(strf("%s: %zu indices are not a multiple of 3; the last %zu are dropped",
                          where.c_str(), in.size(), extra));
            in.resize(in.size() - extra);
        }
        return in;
    }
    std::vector<uint32_t> out;
    if (in.size() < 3) return out;
    const size_t triangles = in.size() - 2;
    if (auto e = ctx.fits(uint64_t(triangles) * 3 * sizeof(uint32_t), where)) return *e;
    out.reserve(triangles * 3);
    for (size_t i = 0; i < triangles; ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            const bool odd = i % 2 != 0;
            out.insert(out.end(), {in[i], in[i + (odd ? 2 : 1)], in[i + (odd ? 1 : 2)]});
        } else { // TRIANGLE_FAN
            out.insert(out.end(), {in[i + 1], in[i + 2], in[0]});
        }
    }
    return out;
}

// Drops the vertices no triangle uses, keeping the order of the others.
void compactVertices(IrPrimitive& p) {
    const size_t n = p.vertexCount();
    std::vector<uint32_t> remap(n, 0);
    for (uint32_t i : p.indices) remap[i] = 1;
    uint32_t used = 0;
    for (uint32_t& r : remap) r = r ? used++ : std::numeric_limits<uint32_t>::max();
    if (used == n) return;
    auto compact = [&](std::vector<float>& stream, size_t nc) {
        if (stream.empty()) return;
        for (size_t v = 0; v < n; ++v) {
            if (remap[v] != std::numeric_limits<uint32_t>::max()) {
                std::copy_n(stream.begin() + std::ptrdiff_t(v * nc), nc,
                            stream.begin() + std::ptrdiff_t(size_t(remap[v]) * nc));
            }
        }
        stream.resize(size_t(used) * nc);
        stream.shrink_to_fit();
    };
    compact(p.positions, 3);
    compact(p.normals, 3);
    compact(p.tangents, 4);
    compact(p.uv0, 2);
    compact(p.uv1, 2);
    compact(p.colors, 4);
    for (uint32_t& i : p.indices) i = remap[i];
}

uint64_t sizeBytes(const IrPrimitive& p) {
    const size_t floats = p.positions.size() + p.normals.size() + p.tangents.size() +
                          p.uv0.size() + p.uv1.size() + p.colors.size();
    return uint64_t(floats) * sizeof(float) + uint64_t(p.indices.size()) * sizeof(uint32_t);
}

Result<int, ConvertError> importMaterial(Ctx& ctx, int index, const std::string& who);

const char* modeName(int mode) {
    static const char* const kNames[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP",
                                         "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};
    return mode >= 0 && mode <= 6 ? kNames[mode] : "?";
}

// One primitive as a triangle list, or nullopt when it is dropped (with a warning).
Result<std::optional<IrPrimitive>, ConvertError> importPrimitive(Ctx& ctx, int meshIndex,
                                                                 int primIndex) {
    const tinygltf::Primitive& src =
        ctx.model.meshes[size_t(meshIndex)].primitives[size_t(primIndex)];
    const std::string where =
        strf("%s primitive %d", label("mesh", meshIndex, ctx.model.meshes).c_str(), primIndex);
    const int mode = src.mode;
    if (mode < TINYGLTF_MODE_POINTS || mode > TINYGLTF_MODE_TRIANGLE_FAN) {
        return ctx.fail(strf("%s: mode %d is not a glTF primitive mode", where.c_str(), mode));
    }
    if (mode < TINYGLTF_MODE_TRIANGLES) {
        ctx.warn(strf("%s: mode %s dropped (only triangles are imported)", where.c_str(),
                      modeName(mode)));
        return std::optional<IrPrimitive>();
    }
    if (!src.targets.empty()) {
        ctx.warn(strf("%s: %zu morph targets ignored", where.c_str(), src.targets.size()));
    }
    auto position = src.attributes.find("POSITION");
    if (position == src.attributes.end()) {
        ctx.warn(where + ": no POSITION attribute; dropped");
        return std::optional<IrPrimitive>();
    }

    std::optional<DracoMesh> draco;
    if (const tinygltf::Value* ext =
            extensionObject(src.extensions, "KHR_draco_mesh_compression")) {
        auto decoded = decodeDraco(ctx, *ext, where);
        if (!decoded) return decoded.error();
        draco = std::move(decoded).value();
    }

    struct Stream { const char* semantic; std::vector<float>* out; AttributeSpec spec; };
    IrPrimitive p;
    const Stream streams[] = {
        {"POSITION", &p.positions, {3, 3, false}},  {"NORMAL", &p.normals, {3, 3, false}},
        {"TANGENT", &p.tangents, {4, 4, false}},    {"TEXCOORD_0", &p.uv0, {2, 2, false}},
        {"TEXCOORD_1", &p.uv1, {2, 2, false}},      {"COLOR_0", &p.colors, {3, 4, true}},
    };
    for (const auto& attribute : src.attributes) {
        // A named reference, not a structured binding: clang 14 cannot capture bindings.
        const std::string& semantic = attribute.first;
        const bool known = std::any_of(std::begin(streams), std::end(streams),
                                       [&](const Stream& s) { return semantic == s.semantic; });
        // Skinning is reported once per file (importGltf), not per primitive.
        const bool skinning = semantic.rfind("JOINTS_", 0) == 0 ||
                              semantic.rfind("WEIGHTS_", 0) == 0;
        if (!known && !skinning) ctx.warn(where + ": attribute " + semantic + " ignored");
    }
    size_t vertexCount = 0;
    for (const Stream& s : streams) { // POSITION first: it sets the vertex count
        auto it = src.attributes.find(s.semantic);
        if (it == src.attributes.end()) continue;
        const std::string attrWhere = where + " " + s.semantic;
        const std::optional<int> dracoId =
            draco ? intOf(member(draco->attributes, s.semantic)) : std::nullopt;
        int components = 0;
        auto data = dracoId
            ? readDracoFloats(ctx, *draco, *dracoId, it->second, attrWhere, s.spec, components)
            : readFloats(ctx, it->second, attrWhere, s.spec, components);
        if (!data) return data.error();
        const size_t count = data->size() / size_t(components);
        if (s.out == &p.positions) {
            vertexCount = count;
        } else if (count != vertexCount) {
            return ctx.fail(strf("%s: count %zu differs from POSITION's %zu",
                                 accessorWho(it->second, attrWhere).c_str(), count,
                                 vertexCount));
        }
        *s.out = std::move(data).value();
        if (s.out == &p.colors && components == 3) { // rgb → rgba, opaque
            std::vector<float> rgba(vertexCount * 4, 1.0f);
            for (size_t v = 0; v < vertexCount; ++v) {
                std::copy_n(p.colors.begin() + std::ptrdiff_t(v * 3), 3,
                            rgba.begin() + std::ptrdiff_t(v * 4));
            }
            p.colors = std::move(rgba);
        }
    }

    // Draco's decoded faces are a triangle list whatever the mode says (the extension allows
    // TRIANGLES and TRIANGLE_STRIP and decodes both to faces).
    std::vector<uint32_t> indices;
    int indexMode = mode;
    if (draco || src.indices >= 0) {
        const std::string indicesWho = draco
            ? where + " KHR_draco_mesh_compression"
            : accessorWho(src.indices, where + " indices");
        auto read = draco ? readDracoIndices(ctx, *draco, indicesWho)
                          : readIndices(ctx, src.indices, where + " indices");
        if (!read) return read.error();
        indices = std::move(read).value();
        for (size_t i = 0; i < indices.size(); ++i) {
            if (indices[i] >= vertexCount) {
                return ctx.fail(strf("%s: index %u (element %zu) is out of range 0..%zu",
                                     indicesWho.c_str(), indices[i], i, vertexCount - 1));
            }
        }
        if (draco) indexMode = TINYGLTF_MODE_TRIANGLES;
    } else {
        if (auto e = ctx.fits(uint64_t(vertexCount) * sizeof(uint32_t), where)) return *e;
        indices.resize(vertexCount);
        for (size_t i = 0; i < vertexCount; ++i) indices[i] = uint32_t(i);
    }
    auto triangles = triangulate(ctx, std::move(indices), indexMode, where);
    if (!triangles) return triangles.error();
    p.indices = std::move(triangles).value();
    if (p.indices.empty()) {
        ctx.warn(where + ": no triangles; dropped");
        return std::optional<IrPrimitive>();
    }
    compactVertices(p);

    if (src.material >= 0) {
        auto material = importMaterial(ctx, src.material, where);
        if (!material) return material.error();
        p.material = *material;
    }
    const uint64_t bytes = sizeBytes(p);
    if (auto e = ctx.fits(bytes, where)) return *e;
    ctx.retainedBytes += bytes;
    return std::optional<IrPrimitive>(std::move(p));
}

Result<int, ConvertError> importMesh(Ctx& ctx, int index, const std::string& who) {
    if (index < 0 || size_t(index) >= ctx.model.meshes.size()) {
        return ctx.fail(strf("%s: mesh %d does not exist (%zu meshes)", who.c_str(), index,
                             ctx.model.meshes.size()));
    }
    if (ctx.meshMap[size_t(index)] != -1) return ctx.meshMap[size_t(index)];
    const tinygltf::Mesh& src = ctx.model.meshes[size_t(index)];
    IrMesh mesh;
    mesh.name = src.name;
    if (src.primitives.empty()) {
        ctx.warn(label("mesh", index, ctx.model.meshes) + ": no primitives");
    }
    for (size_t i = 0; i < src.primitives.size(); ++i) {
        auto p = importPrimitive(ctx, index, int(i));
        if (!p) return p.error();
        if (p->has_value()) mesh.primitives.push_back(std::move(**p));
    }
    // An IR mesh is kept even when empty, so a node that names it stays valid.
    ctx.scene.meshes.push_back(std::move(mesh));
    return ctx.meshMap[size_t(index)] = int(ctx.scene.meshes.size() - 1);
}

// [SECTION] images and materials

// The image format from the first bytes, for embedded images that give no mimeType.
std::string sniffMimeType(std::span<const uint8_t> b) {
    auto starts = [&](const char* magic, size_t n, size_t at = 0) {
        return b.size() >= at + n && std::memcmp(b.data() + at, magic, n) == 0;
    };
    if (starts("\x89PNG\r\n\x1a\n", 8)) return "image/png";
    if (starts("\xFF\xD8\xFF", 3)) return "image/jpeg";
    if (starts("RIFF", 4) && starts("WEBP", 4, 8)) return "image/webp";
    if (starts("\xABKTX 20\xBB", 8)) return "image/ktx2";
    return "";
}

std::string mimeTypeFromExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) {
        return char(std::tolower(c));
    });
    if (ext == ".png") return "image/png";
    if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
    if (ext == ".webp") return "image/webp";
    if (ext == ".ktx2") return "image/ktx2";
    return "";
}

// The IR index of glTF image `index`, or -1 when it cannot be used (a warning says why).
Result<int, ConvertError> importImage(Ctx& ctx, int index, const std::string& who) {
    const tinygltf::Model& m = ctx.model;
    if (index < 0 || size_t(index) >= m.images.size()) {
        return ctx.fail(strf("%s: image %d does not exist (%zu images)", who.c_str(), index,
                             m.images.size()));
    }
    int& mapped = ctx.imageMap[size_t(index)];
    if (mapped != -1) return mapped == -2 ? -1 : mapped;
    const tinygltf::Image& src = m.images[size_t(index)];
    const std::string imageWho = label("image", index, m.images);
    IrImage image;
    image.name = src.name;
    image.mimeType = src.mimeType;
    auto drop = [&](const std::string& why) {
        ctx.warn(imageWho + ": " + why + "; textures using it are dropped");
        mapped = -2;
        return -1;
    };
    if (!src.uri.empty()) { // external file (data URIs arrive as bytes, see keepEncodedImage)
        if (src.uri.find("://") != std::string::npos) {
            return drop("URI '" + src.uri + "' is remote");
        }
        const std::filesystem::path relative(percentDecode(src.uri));
        const std::filesystem::path resolved =
            ctx.baseDir.empty() ? relative : std::filesystem::path(ctx.baseDir) / relative;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(resolved, ec)) {
            return drop("file '" + resolved.string() + "' not found");
        }
        image.path = resolved.lexically_normal().string();
        if (image.name.empty()) image.name = relative.stem().string();
        if (image.mimeType.empty()) image.mimeType = mimeTypeFromExtension(relative);
    } else if (src.bufferView >= 0) {
        auto bytes = viewBytes(ctx, src.bufferView, imageWho);
        if (!bytes) return bytes.error();
        if (auto e = ctx.fits(bytes->size(), imageWho)) return *e;
        image.encoded.assign(bytes->begin(), bytes->end());
    } else if (!src.image.empty()) {
        if (auto e = ctx.fits(src.image.size(), imageWho)) return *e;
        image.encoded = src.image;
    } else {
        return drop("no data");
    }
    if (image.mimeType.empty()) image.mimeType = sniffMimeType(image.encoded);
    if (image.name.empty()) image.name = strf("image%d", index);
    ctx.retainedBytes += image.encoded.size();
    ctx.scene.images.push_back(std::move(image));
    return mapped = int(ctx.scene.images.size() - 1);
}

void applySampler(Ctx& ctx, const tinygltf::Sampler& s, IrTextureRef& ref, const std::string& who) {
    switch (s.minFilter) {
    case -1: break; // absent: keep the default
    case TINYGLTF_TEXTURE_FILTER_NEAREST: ref.minFilter = MinFilter::Nearest; break;
    case TINYGLTF_TEXTURE_FILTER_LINEAR: ref.minFilter = MinFilter::Linear; break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST:
        ref.minFilter = MinFilter::NearestMipNearest; break;
    case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST:
        ref.minFilter = MinFilter::LinearMipNearest; break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR:
        ref.minFilter = MinFilter::NearestMipLinear; break;
    case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR:
        ref.minFilter = MinFilter::LinearMipLinear; break;
    default: ctx.warn(strf("%s: minFilter %d is invalid; using the default", who.c_str(),
                           s.minFilter));
    }
    switch (s.magFilter) {
    case -1: break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST: ref.magFilter = MagFilter::Nearest; break;
    case TINYGLTF_TEXTURE_FILTER_LINEAR: ref.magFilter = MagFilter::Linear; break;
    default: ctx.warn(strf("%s: magFilter %d is invalid; using the default", who.c_str(),
                           s.magFilter));
    }
    auto wrap = [&](int value, Wrap& out, const char* name) {
        switch (value) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT: out = Wrap::Repeat; break;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: out = Wrap::ClampToEdge; break;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: out = Wrap::MirroredRepeat; break;
        default: ctx.warn(strf("%s: %s %d is invalid; using REPEAT", who.c_str(), name, value));
        }
    };
    wrap(s.wrapS, ref.wrapU, "wrapS");
    wrap(s.wrapT, ref.wrapV, "wrapT");
}

// A material's reference to a texture (tinygltf has three TextureInfo structs).
struct TexInfo {
    int index = -1, texCoord = 0;
    const tinygltf::ExtensionMap* extensions = nullptr;
};
template <class T> TexInfo texInfo(const T& info) {
    return {info.index, info.texCoord, &info.extensions};
}

Result<IrTextureRef, ConvertError> importTextureRef(Ctx& ctx, const TexInfo& info,
                                                    const std::string& who) {
    IrTextureRef ref;
    if (info.index < 0) return ref;
    const tinygltf::Model& m = ctx.model;
    if (size_t(info.index) >= m.textures.size()) {
        return ctx.fail(strf("%s: texture %d does not exist (%zu textures)", who.c_str(),
                             info.index, m.textures.size()));
    }
    const tinygltf::Texture& tex = m.textures[size_t(info.index)];
    if (tex.sampler >= 0) {
        if (size_t(tex.sampler) >= m.samplers.size()) {
            return ctx.fail(strf("%s: texture %d: sampler %d does not exist (%zu samplers)",
                                 who.c_str(), info.index, tex.sampler, m.samplers.size()));
        }
        applySampler(ctx, m.samplers[size_t(tex.sampler)], ref,
                     strf("%s: sampler %d", who.c_str(), tex.sampler));
    }
    int texCoord = info.texCoord;
    if (const tinygltf::Value* t = extensionObject(*info.extensions, "KHR_texture_transform")) {
        float v[2];
        if (numbersOf(member(t, "offset"), v, 2)) ref.offset = {v[0], v[1]};
        if (numbersOf(member(t, "scale"), v, 2)) ref.scale = {v[0], v[1]};
        if (auto r = numberOf(member(t, "rotation"))) ref.rotationRadians = float(*r);
        if (auto c = intOf(member(t, "texCoord"))) texCoord = *c;
    }
    if (texCoord < 0 || texCoord > 1) {
        ctx.warn(strf("%s: TEXCOORD_%d is not imported; using TEXCOORD_0", who.c_str(),
                      texCoord));
        texCoord = 0;
    }
    ref.texCoord = uint8_t(texCoord);
    if (tex.source < 0) {
        for (const char* name : kImageFormatExtensions) {
            const tinygltf::Value* ext = extensionObject(tex.extensions, name);
            if (!ext) continue;
            const std::optional<int> image = intOf(member(ext, "source"));
            const std::string imageWho =
                image && *image >= 0 && size_t(*image) < m.images.size()
                    ? label("image", *image, m.images)
                    : std::string("its image");
            return ctx.fail(strf("%s: texture %d: %s needs %s, which is not supported, and the "
                                 "texture has no fallback source image",
                                 who.c_str(), info.index, imageWho.c_str(), name),
                            ConvertErrorKind::Unsupported);
        }
        ctx.warn(strf("%s: texture %d has no image in a format we read; dropped", who.c_str(),
                      info.index));
        return ref;
    }
    auto image = importImage(ctx, tex.source, who);
    if (!image) return image.error();
    ref.image = *image;
    return ref;
}

float clampOr(double v, float lo, float hi, float fallback) {
    return std::isfinite(v) ? std::clamp(float(v), lo, hi) : fallback;
}

Result<int, ConvertError> importMaterial(Ctx& ctx, int index, const std::string& who) {
    const tinygltf::Model& m = ctx.model;
    if (index < 0 || size_t(index) >= m.materials.size()) {
        return ctx.fail(strf("%s: material %d does not exist (%zu materials)", who.c_str(),
                             index, m.materials.size()));
    }
    if (ctx.materialMap[size_t(index)] != -1) return ctx.materialMap[size_t(index)];
    const tinygltf::Material& src = m.materials[size_t(index)];
    const std::string matWho = label("material", index, m.materials);
    IrMaterial out;
    out.name = src.name;
    Material& pbr = out.pbr;
    const tinygltf::PbrMetallicRoughness& mr = src.pbrMetallicRoughness;

    // Factors outside their glTF ranges are clamped: later stages rely on the ranges.
    if (mr.baseColorFactor.size() == 4 && finiteAll(mr.baseColorFactor)) {
        const auto& c = mr.baseColorFactor;
        pbr.baseColorFactor = {clampOr(c[0], 0, 1, 1), clampOr(c[1], 0, 1, 1),
                               clampOr(c[2], 0, 1, 1), clampOr(c[3], 0, 1, 1)};
    } else {
        ctx.warn(matWho + ": baseColorFactor is not 4 numbers; using white");
    }
    pbr.metallicFactor = clampOr(mr.metallicFactor, 0, 1, 1);
    pbr.roughnessFactor = clampOr(mr.roughnessFactor, 0, 1, 1);
    if (src.emissiveFactor.size() == 3 && finiteAll(src.emissiveFactor)) {
        const auto& e = src.emissiveFactor;
        pbr.emissiveFactor = {clampOr(e[0], 0, 1, 0), clampOr(e[1], 0, 1, 0),
                              clampOr(e[2], 0, 1, 0)};
    }
    if (const tinygltf::Value* ext =
            extensionObject(src.extensions, "KHR_materials_emissive_strength")) {
        if (auto s = numberOf(member(ext, "emissiveStrength")); s && *s >= 0) {
            pbr.emissiveStrength = float(*s);
        }
    }
    pbr.normalScale = std::isfinite(src.normalTexture.scale) ? float(src.normalTexture.scale) : 1;
    pbr.occlusionStrength = clampOr(src.occlusionTexture.strength, 0, 1, 1);
    if (src.alphaMode == "MASK") {
        pbr.alphaMode = AlphaMode::Mask;
    } else if (src.alphaMode == "BLEND") {
        pbr.alphaMode = AlphaMode::Blend;
    } else if (src.alphaMode != "OPAQUE") {
        ctx.warn(matWho + ": alphaMode '" + src.alphaMode + "' is invalid; using OPAQUE");
    }
    pbr.alphaCutoff = clampOr(src.alphaCutoff, 0, std::numeric_limits<float>::max(), 0.5f);
    pbr.doubleSided = src.doubleSided;

    struct Slot { TextureSlotKind kind; TexInfo info; const char* name; };
    Slot slots[] = {
        {TextureSlotKind::BaseColor, texInfo(mr.baseColorTexture), "baseColorTexture"},
        {TextureSlotKind::MetallicRoughness, texInfo(mr.metallicRoughnessTexture),
         "metallicRoughnessTexture"},
        {TextureSlotKind::Normal, texInfo(src.normalTexture), "normalTexture"},
        {TextureSlotKind::Occlusion, texInfo(src.occlusionTexture), "occlusionTexture"},
        {TextureSlotKind::Emissive, texInfo(src.emissiveTexture), "emissiveTexture"},
    };

    // KHR_materials_pbrSpecularGlossiness (archived): files usually carry a metallic-roughness
    // fallback, and it is what we use when it is there. Otherwise we approximate: diffuse
    // becomes base colour, metallic is 0 and roughness is 1 - glossiness. Specular is lost.
    if (const tinygltf::Value* sg =
            extensionObject(src.extensions, "KHR_materials_pbrSpecularGlossiness")) {
        const bool hasFallback = mr.baseColorTexture.index >= 0 ||
                                 mr.metallicRoughnessTexture.index >= 0 ||
                                 mr.baseColorFactor != std::vector<double>{1, 1, 1, 1} ||
                                 mr.metallicFactor != 1 || mr.roughnessFactor != 1;
        if (hasFallback) {
            ctx.warn(matWho + ": KHR_materials_pbrSpecularGlossiness ignored; using its "
                              "metallic-roughness fallback");
        } else {
            ctx.warn(matWho + ": KHR_materials_pbrSpecularGlossiness approximated (diffuse as "
                              "base colour, metallic 0, roughness 1 - glossiness, specular "
                              "ignored)");
            float diffuse[4];
            if (numbersOf(member(sg, "diffuseFactor"), diffuse, 4)) {
                pbr.baseColorFactor = {std::clamp(diffuse[0], 0.0f, 1.0f),
                                       std::clamp(diffuse[1], 0.0f, 1.0f),
                                       std::clamp(diffuse[2], 0.0f, 1.0f),
                                       std::clamp(diffuse[3], 0.0f, 1.0f)};
            }
            pbr.metallicFactor = 0;
            pbr.roughnessFactor =
                1.0f - clampOr(numberOf(member(sg, "glossinessFactor")).value_or(1.0), 0, 1, 1);
            if (const tinygltf::Value* diffuseTexture = member(sg, "diffuseTexture")) {
                static const tinygltf::ExtensionMap kNoExtensions;
                slots[0].info = {intOf(member(diffuseTexture, "index")).value_or(-1),
                                 intOf(member(diffuseTexture, "texCoord")).value_or(0),
                                 &kNoExtensions};
            }
        }
    }

    for (const Slot& slot : slots) {
        auto ref = importTextureRef(ctx, slot.info, matWho + " " + slot.name);
        if (!ref) return ref.error();
        out.textures[size_t(slot.kind)] = *ref;
    }
    ctx.scene.materials.push_back(std::move(out));
    return ctx.materialMap[size_t(index)] = int(ctx.scene.materials.size() - 1);
}

// [SECTION] lights and cameras

// The IR index of KHR_lights_punctual light `index`, or -1 when it is dropped (warned).
Result<int, ConvertError> importLight(Ctx& ctx, int index, const std::string& who) {
    const tinygltf::Model& m = ctx.model;
    if (index < 0 || size_t(index) >= m.lights.size()) {
        return ctx.fail(strf("%s: light %d does not exist (%zu lights)", who.c_str(), index,
                             m.lights.size()));
    }
    int& mapped = ctx.lightMap[size_t(index)];
    if (mapped != -1) return mapped == -2 ? -1 : mapped;
    const tinygltf::Light& src = m.lights[size_t(index)];
    const std::string lightWho = label("light", index, m.lights);
    IrLight light;
    light.name = src.name;
    if (src.type == "directional") {
        light.type = LightType::Directional;
    } else if (src.type == "point") {
        light.type = LightType::Point;
    } else if (src.type == "spot") {
        light.type = LightType::Spot;
    } else {
        ctx.warn(lightWho + ": type '" + src.type + "' is unknown; dropped");
        mapped = -2;
        return -1;
    }
    if (src.color.size() == 3 && finiteAll(src.color)) {
        light.color = {clampOr(src.color[0], 0, 1, 1), clampOr(src.color[1], 0, 1, 1),
                       clampOr(src.color[2], 0, 1, 1)};
    } else if (!src.color.empty()) {
        ctx.warn(lightWho + ": color is not 3 numbers; using white");
    }
    light.intensity = clampOr(src.intensity, 0, std::numeric_limits<float>::max(), 1);
    if (!(src.intensity >= 0) || !std::isfinite(src.intensity))
        ctx.warn(lightWho + strf(": intensity %g is not a finite number >= 0; %g", src.intensity,
                                 double(light.intensity)));
    // range: absent (tinygltf: 0) stays 0, an invalid one (negative, or too large for a float)
    // is passed on as it is: processLights (light_processing.h) replaces both with the computed
    // range and warns, naming the light, whichever importer it came from.
    if (std::isnan(src.range)) light.range = std::numeric_limits<float>::quiet_NaN();
    else if (std::fabs(src.range) > double(std::numeric_limits<float>::max()))
        light.range = (src.range > 0 ? 1 : -1) * std::numeric_limits<float>::infinity();
    else light.range = float(src.range);
    if (light.type == LightType::Spot) {
        const double inner = src.spot.innerConeAngle, outer = src.spot.outerConeAngle;
        light.outerConeRadians = clampOr(outer, 0, kMaxSpotConeRadians, 0.7853982f);
        light.innerConeRadians = clampOr(inner, 0, light.outerConeRadians, 0.0f);
        // In double, so that pi/2 written as 1.5707963267948966 is inside.
        if (!(inner >= 0 && inner <= outer && outer <= double(kMaxSpotConeRadians))) {
            ctx.warn(lightWho + strf(": spot cone angles (inner %g, outer %g) outside 0 <= inner "
                                     "<= outer <= pi/2; clamped to inner %g, outer %g",
                                     inner, outer, double(light.innerConeRadians),
                                     double(light.outerConeRadians)));
        }
    }
    ctx.scene.lights.push_back(std::move(light));
    return mapped = int(ctx.scene.lights.size() - 1);
}

Result<int, ConvertError> importCamera(Ctx& ctx, int index, const std::string& who) {
    const tinygltf::Model& m = ctx.model;
    if (index < 0 || size_t(index) >= m.cameras.size()) {
        return ctx.fail(strf("%s: camera %d does not exist (%zu cameras)", who.c_str(), index,
                             m.cameras.size()));
    }
    if (ctx.cameraMap[size_t(index)] != -1) return ctx.cameraMap[size_t(index)];
    const tinygltf::Camera& src = m.cameras[size_t(index)];
    const float kMax = std::numeric_limits<float>::max();
    IrCamera cam;
    cam.name = src.name;
    if (src.type == "orthographic") { // tinygltf accepts only the two types
        const tinygltf::OrthographicCamera& o = src.orthographic;
        cam.projection = Projection::Orthographic;
        cam.xmag = clampOr(o.xmag, -kMax, kMax, 1);
        cam.ymag = clampOr(o.ymag, -kMax, kMax, 1);
        cam.znear = clampOr(o.znear, 0, kMax, 0);
        cam.zfar = clampOr(o.zfar, 0, kMax, 0);
    } else {
        const tinygltf::PerspectiveCamera& p = src.perspective;
        cam.projection = Projection::Perspective;
        cam.yfovRadians = p.yfov > 0 ? clampOr(p.yfov, 0, 3.1415926f, 0.8f) : 0.8f;
        cam.aspectRatio = clampOr(p.aspectRatio, 0, kMax, 0); // absent: tinygltf gives 0
        cam.znear = p.znear > 0 ? clampOr(p.znear, 0, kMax, 0.1f) : 0.1f;
        cam.zfar = clampOr(p.zfar, 0, kMax, 0); // absent (infinite): tinygltf gives 0
        if (p.yfov <= 0 || p.znear <= 0) {
            ctx.warn(label("camera", index, m.cameras) + ": yfov and znear must be > 0; "
                                                          "defaults used");
        }
    }
    ctx.scene.cameras.push_back(std::move(cam));
    return ctx.cameraMap[size_t(index)] = int(ctx.scene.cameras.size() - 1);
}

// [SECTION] nodes

struct Dvec3 { double x, y, z; };
double dot(const Dvec3& a, const Dvec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Dvec3 cross(const Dvec3& a, const Dvec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Dvec3 scaled(const Dvec3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
Dvec3 minus(const Dvec3& a, const Dvec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }

// Rotation matrix (columns c0 c1 c2, orthonormal, det +1) to a unit quaternion xyzw (Shepperd).
Vec4 quaternionFromColumns(const Dvec3& c0, const Dvec3& c1, const Dvec3& c2) {
    const double m00 = c0.x, m10 = c0.y, m20 = c0.z;
    const double m01 = c1.x, m11 = c1.y, m21 = c1.z;
    const double m02 = c2.x, m12 = c2.y, m22 = c2.z;
    double x, y, z, w;
    const double trace = m00 + m11 + m22;
    if (trace > 0) {
        const double s = std::sqrt(trace + 1.0) * 2;
        w = 0.25 * s; x = (m21 - m12) / s; y = (m02 - m20) / s; z = (m10 - m01) / s;
    } else if (m00 > m11 && m00 > m22) {
        const double s = std::sqrt(1.0 + m00 - m11 - m22) * 2;
        w = (m21 - m12) / s; x = 0.25 * s; y = (m01 + m10) / s; z = (m02 + m20) / s;
    } else if (m11 > m22) {
        const double s = std::sqrt(1.0 + m11 - m00 - m22) * 2;
        w = (m02 - m20) / s; x = (m01 + m10) / s; y = 0.25 * s; z = (m12 + m21) / s;
    } else {
        const double s = std::sqrt(1.0 + m22 - m00 - m11) * 2;
        w = (m10 - m01) / s; x = (m02 + m20) / s; y = (m12 + m21) / s; z = 0.25 * s;
    }
    const double len = std::sqrt(x * x + y * y + z * z + w * w);
    if (!(len > 0) || !std::isfinite(len)) return {0, 0, 0, 1};
    return {float(x / len), float(y / len), float(z / len), float(w / len)};
}

// Column-major 4x4 into TRS. A negative determinant becomes a negative x scale. Shear (columns
// not orthogonal) and a projective last row cannot be represented: we warn and take the
// Gram-Schmidt rotation, which keeps the x axis exact.
void decomposeMatrix(Ctx& ctx, const std::vector<double>& m, IrNode& node, const std::string& who) {
    if (!finiteAll(m)) {
        ctx.warn(who + ": matrix has non-finite values; using identity");
        return;
    }
    node.translation = {float(m[12]), float(m[13]), float(m[14])};
    Dvec3 c[3] = {{m[0], m[1], m[2]}, {m[4], m[5], m[6]}, {m[8], m[9], m[10]}};
    double s[3] = {std::sqrt(dot(c[0], c[0])), std::sqrt(dot(c[1], c[1])),
                   std::sqrt(dot(c[2], c[2]))};
    if (m[3] != 0 || m[7] != 0 || m[11] != 0 || m[15] != 1) {
        ctx.warn(who + ": matrix is projective (last row not 0 0 0 1); the row is ignored");
    }
    const double kTiny = 1e-12;
    if (s[0] < kTiny || s[1] < kTiny || s[2] < kTiny) {
        ctx.warn(who + ": matrix has a zero scale axis; rotation set to identity");
        node.scale = {float(s[0]), float(s[1]), float(s[2])};
        return;
    }
    if (dot(c[0], cross(c[1], c[2])) < 0) s[0] = -s[0]; // a mirror: flip x
    for (int i = 0; i < 3; ++i) c[i] = scaled(c[i], 1.0 / s[i]);
    const double kShear = 1e-4;
    if (std::abs(dot(c[0], c[1])) > kShear || std::abs(dot(c[0], c[2])) > kShear ||
        std::abs(dot(c[1], c[2])) > kShear) {
        ctx.warn(who + ": matrix has shear, which TRS cannot express; decomposed approximately");
    }
    const Dvec3 r0 = c[0];
    Dvec3 r1 = minus(c[1], scaled(r0, dot(c[1], r0)));
    const double len1 = std::sqrt(dot(r1, r1));
    r1 = len1 > kTiny ? scaled(r1, 1.0 / len1) : (std::abs(r0.x) < 0.9 ? Dvec3{1, 0, 0}
                                                                          : Dvec3{0, 1, 0});
    if (len1 <= kTiny) { // c1 parallel to c0: any perpendicular axis
        r1 = minus(r1, scaled(r0, dot(r1, r0)));
        r1 = scaled(r1, 1.0 / std::sqrt(dot(r1, r1)));
    }
    const Dvec3 r2 = cross(r0, r1);
    node.rotation = quaternionFromColumns(r0, r1, r2);
    node.scale = {float(s[0]), float(s[1]), float(s[2])};
}

void applyTrs(Ctx& ctx, const tinygltf::Node& src, IrNode& node, const std::string& who) {
    if (!src.matrix.empty()) {
        if (src.matrix.size() == 16) {
            decomposeMatrix(ctx, src.matrix, node, who);
        } else {
            ctx.warn(strf("%s: matrix has %zu values, not 16; using identity", who.c_str(),
                          src.matrix.size()));
        }
        return;
    }
    auto vec = [&](const std::vector<double>& v, size_t n, const char* name) {
        if (v.empty()) return false;
        if (v.size() == n && finiteAll(v)) return true;
        ctx.warn(strf("%s: %s is not %zu finite numbers; using the default", who.c_str(), name,
                      n));
        return false;
    };
    if (vec(src.translation, 3, "translation")) {
        node.translation = {float(src.translation[0]), float(src.translation[1]),
                            float(src.translation[2])};
    }
    if (vec(src.scale, 3, "scale")) {
        node.scale = {float(src.scale[0]), float(src.scale[1]), float(src.scale[2])};
    }
    if (vec(src.rotation, 4, "rotation")) {
        const auto& q = src.rotation;
        const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (len > 1e-12 && std::isfinite(len)) {
            node.rotation = {float(q[0] / len), float(q[1] / len), float(q[2] / len),
                             float(q[3] / len)};
            if (std::abs(len - 1.0) > 1e-3) ctx.warn(who + ": rotation was not unit; normalized");
        } else {
            ctx.warn(who + ": rotation is a zero quaternion; using identity");
        }
    }
}

// Fills in one IR node from glTF node `index`; imports what it references.
Check importNodeContent(Ctx& ctx, int index, IrNode& node) {
    const tinygltf::Node& src = ctx.model.nodes[size_t(index)];
    const std::string who = label("node", index, ctx.model.nodes);
    node.name = src.name;
    applyTrs(ctx, src, node, who);
    if (src.mesh >= 0) {
        auto mesh = importMesh(ctx, src.mesh, who);
        if (!mesh) return mesh.error();
        node.mesh = *mesh;
    }
    if (src.camera >= 0) {
        auto camera = importCamera(ctx, src.camera, who);
        if (!camera) return camera.error();
        node.camera = *camera;
    }
    if (const tinygltf::Value* ext = extensionObject(src.extensions, "KHR_lights_punctual")) {
        const std::optional<int> light = intOf(member(ext, "light"));
        if (!light) return ctx.fail(who + ": KHR_lights_punctual has no integer 'light'");
        auto imported = importLight(ctx, *light, who);
        if (!imported) return imported.error();
        node.light = *imported;
    }
    return std::nullopt;
}

// Flattens the trees under `roots` into ctx.scene.nodes, parents first (depth-first pre-order,
// with an explicit stack because a chain of nodes can be as long as the file allows).
Check flattenNodes(Ctx& ctx, const std::vector<int>& roots, const std::string& rootsWho) {
    const tinygltf::Model& m = ctx.model;
    std::vector<int> irIndexOf(m.nodes.size(), -1);
    struct Pending { int node, irParent, parent; }; // parent: glTF index, -1 for a root
    std::vector<Pending> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, -1, -1});
    while (!stack.empty()) {
        const Pending cur = stack.back();
        stack.pop_back();
        const std::string referrer =
            cur.parent < 0 ? rootsWho : label("node", cur.parent, m.nodes);
        if (cur.node < 0 || size_t(cur.node) >= m.nodes.size()) {
            return ctx.fail(strf("%s refers to node %d, which does not exist (%zu nodes)",
                                 referrer.c_str(), cur.node, m.nodes.size()));
        }
        const std::string who = label("node", cur.node, m.nodes);
        if (const int placed = irIndexOf[size_t(cur.node)]; placed >= 0) {
            for (int a = cur.irParent; a >= 0; a = ctx.scene.nodes[size_t(a)].parent) {
                if (a == placed) {
                    return ctx.fail(who + ": the node graph has a cycle (" + who +
                                    " is its own ancestor)");
                }
            }
            return ctx.fail(who + " is referenced more than once (again by " + referrer +
                            "); glTF nodes must form strict trees");
        }
        IrNode node;
        node.parent = cur.irParent;
        if (auto e = importNodeContent(ctx, cur.node, node)) return e;
        irIndexOf[size_t(cur.node)] = int(ctx.scene.nodes.size());
        ctx.scene.nodes.push_back(std::move(node));
        const int irIndex = int(ctx.scene.nodes.size() - 1);
        const std::vector<int>& children = m.nodes[size_t(cur.node)].children;
        for (auto it = children.rbegin(); it != children.rend(); ++it) {
            stack.push_back({*it, irIndex, cur.node});
        }
    }
    return std::nullopt;
}

// The roots to import: the default scene's (or scene 0's) nodes. A file without scenes gets
// every node that is nobody's child, since there is nothing else to convert.
Result<std::vector<int>, ConvertError> chooseRoots(Ctx& ctx, std::string& rootsWho) {
    const tinygltf::Model& m = ctx.model;
    if (m.scenes.empty()) {
        if (m.defaultScene >= 0) {
            return ctx.fail(strf("scene %d does not exist (the file has no scenes)",
                                 m.defaultScene));
        }
        std::vector<bool> isChild(m.nodes.size(), false);
        for (const tinygltf::Node& n : m.nodes) {
            for (int c : n.children) {
                if (c >= 0 && size_t(c) < m.nodes.size()) isChild[size_t(c)] = true;
            }
        }
        std::vector<int> roots;
        for (size_t i = 0; i < m.nodes.size(); ++i) {
            if (!isChild[i]) roots.push_back(int(i));
        }
        if (!m.nodes.empty()) ctx.warn("no scenes; importing every root node");
        rootsWho = "the root node list";
        return roots;
    }
    const int scene = m.defaultScene >= 0 ? m.defaultScene : 0;
    if (size_t(scene) >= m.scenes.size()) {
        return ctx.fail(strf("scene %d does not exist (%zu scenes)", scene, m.scenes.size()));
    }
    rootsWho = label("scene", scene, m.scenes);
    if (m.scenes.size() > 1) {
        ctx.warn(strf("%zu scenes; importing %s, the others are ignored", m.scenes.size(),
                      rootsWho.c_str()));
    }
    return m.scenes[size_t(scene)].nodes;
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

    if (!model.skins.empty()) ctx.warn(strf("%zu skins ignored", model.skins.size()));
    if (!model.animations.empty()) {
        ctx.warn(strf("%zu animations ignored", model.animations.size()));
    }
    std::string rootsWho;
    auto roots = chooseRoots(ctx, rootsWho);
    if (!roots) return roots.error();
    if (auto e = flattenNodes(ctx, *roots, rootsWho)) return *e;
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
