// converter/src/import_gltf_internal.h — what the glTF importer's stage files share: the state
// of one import (Ctx), the accessor reader's interface and each stage's entry point. Internal:
// import_gltf.cpp (document, buffers, extensions, importGltf), import_gltf_accessors.cpp,
// import_gltf_meshes.cpp (primitives, Draco), import_gltf_materials.cpp (images, textures,
// materials) and import_gltf_nodes.cpp (node trees, lights, cameras) include it.
//
// Every file of the importer includes tinygltf through this header, so all of them see the
// same configuration (the TinyGLTF class's defaults depend on it); import_gltf.cpp alone defines
// TINYGLTF_IMPLEMENTATION before including it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gltf_internal.h"
#include "pnb_converter/importers.h"

// The tinygltf implementation is compiled in import_gltf.cpp and only there. We don't need stb:
// images are never decoded here. External images are not read, because we keep their URI. The
// built-in Draco path is not used (import_gltf.cpp says why).
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

namespace pnb::converter::gltf_internal {

// [SECTION] messages and limits

// Decoded data the importer may keep, as a multiple of the input bytes (file plus buffers), with
// a floor for small inputs. Legitimate expansion is bounded: integer attributes become floats
// (at most 4x), strips and fans become lists (3x), and Draco typically achieves 10-30x. Without
// a cap, primitives that share one accessor could multiply memory use without bound.
inline constexpr uint64_t kOutputBudgetFactor = 64;
inline constexpr uint64_t kMinOutputBudgetBytes = 512ull << 20;

// "mesh 'Wheel'" when named, "mesh 3" when not. Precondition: index is valid.
template <class T>
inline std::string label(const char* kind, int index, const std::vector<T>& items) {
    const std::string& name = items[size_t(index)].name;
    return name.empty() ? strf("%s %d", kind, index) : strf("%s '%s'", kind, name.c_str());
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
    std::vector<int> skinnedMeshMap; // a mesh as a skinned node draws it (joints, weights)
    std::vector<int> nodeMap;        // glTF node → IR node, -1 when not imported

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

// Texture extensions for image formats we do not decode (KTX2/Basis Universal, WebP). A texture
// using one may name a fallback image in its ordinary `source`, which we use; a texture without
// one is an Unsupported error when a material uses it (importTextureRef), so a file that
// requires them fails only if the scene actually needs such an image.
inline constexpr const char* kImageFormatExtensions[] = {"KHR_texture_basisu", "EXT_texture_webp"};

// A URI's %XX escapes decoded (import_gltf.cpp).
std::string percentDecode(const std::string& uri);

// Helpers over tinygltf::Value, whose Get() asserts on the wrong type.
inline const tinygltf::Value* member(const tinygltf::Value* v, const char* key) {
    return v && v->IsObject() && v->Has(key) ? &v->Get(key) : nullptr;
}
inline const tinygltf::Value* extensionObject(const tinygltf::ExtensionMap& extensions,
                                              const char* name) {
    auto it = extensions.find(name);
    return it != extensions.end() && it->second.IsObject() ? &it->second : nullptr;
}
inline std::optional<double> numberOf(const tinygltf::Value* v) {
    if (!v || !v->IsNumber() || !std::isfinite(v->GetNumberAsDouble())) return std::nullopt;
    return v->GetNumberAsDouble();
}
inline std::optional<int> intOf(const tinygltf::Value* v) {
    if (!v || !v->IsInt()) return std::nullopt;
    return v->Get<int>();
}
inline bool numbersOf(const tinygltf::Value* v, float* out, size_t n) {
    if (!v || !v->IsArray() || v->ArrayLen() != n) return false;
    for (size_t i = 0; i < n; ++i) {
        const std::optional<double> x = numberOf(&v->Get(int(i)));
        if (!x) return false;
        out[i] = float(*x);
    }
    return true;
}
inline bool finiteAll(const std::vector<double>& values) {
    return std::all_of(values.begin(), values.end(), [](double x) { return std::isfinite(x); });
}

inline float clampOr(double v, float lo, float hi, float fallback) {
    return std::isfinite(v) ? std::clamp(float(v), lo, hi) : fallback;
}

// [SECTION] accessor reader (import_gltf_accessors.cpp; the per-component helpers stay inline
// here because the Draco reader in import_gltf_meshes.cpp calls them per value too)

inline size_t componentSize(int componentType) {
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

inline const char* typeName(int components) {
    static const char* const kNames[] = {"?", "SCALAR", "VEC2", "VEC3", "VEC4"};
    if (components == 16) return "MAT4";
    return components >= 1 && components <= 4 ? kNames[components] : "?";
}

// One component, exactly: every glTF component type fits a double without rounding. memcpy
// because glTF only promises alignment for well-formed files.
inline double readComponent(const uint8_t* p, int componentType) {
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
inline float toFloat(double raw, int componentType, bool normalized) {
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

// "accessor 3 (mesh 'Cube' primitive 0 POSITION)": the prefix of an accessor's messages.
std::string accessorWho(int index, const std::string& where);

// The bytes of a bufferView, checked against the size of the buffer that was actually loaded.
Result<std::span<const uint8_t>, ConvertError> viewBytes(const Ctx& ctx, int view,
                                                         const std::string& who);

// What an attribute must look like.
struct AttributeSpec {
    int minComponents = 1, maxComponents = 4; // {16, 16}: MAT4 (inverse bind matrices)
    bool forceNormalized = false; // integer COLOR_0 is always normalized
};

// Fails unless `components` is within the spec's range (`who` prefixes the message).
Check checkComponents(const Ctx& ctx, int components, const AttributeSpec& spec,
                      const std::string& who);

// The single entry point for attribute data: returns count x components floats.
Result<std::vector<float>, ConvertError> readFloats(const Ctx& ctx, int index,
                                                    const std::string& where,
                                                    const AttributeSpec& spec, int& components);

// An indices accessor as 32-bit indices (not yet range-checked against the vertex count).
Result<std::vector<uint32_t>, ConvertError> readIndices(const Ctx& ctx, int index,
                                                        const std::string& where);

// [SECTION] stages. Each returns the IR index of glTF object `index`, importing it on first use
// (the Ctx maps memoise); `who` names the referrer in messages.

// import_gltf_meshes.cpp: the mesh with its primitives as triangle lists (Draco decoded).
// `nodeWeights`: the node's morph weights (empty: the mesh's default weights); `skinned`: a
// skinned node draws it (its primitives carry JOINTS_0/WEIGHTS_0).
Result<int, ConvertError> importMesh(Ctx& ctx, int index, const std::vector<double>& nodeWeights,
                                     bool skinned, const std::string& who);

// import_gltf_materials.cpp: the material with its textures and images.
Result<int, ConvertError> importMaterial(Ctx& ctx, int index, const std::string& who);

// import_gltf_nodes.cpp: the roots to import (the default scene's, or every root node of a file
// without scenes), and the trees under them flattened into ctx.scene.nodes, parents first, with
// the meshes, cameras and lights they reference.
Result<std::vector<int>, ConvertError> chooseRoots(Ctx& ctx, std::string& rootsWho);
Check flattenNodes(Ctx& ctx, const std::vector<int>& roots, const std::string& rootsWho);

// import_gltf_animation.cpp, after flattenNodes: the skins of the imported nodes (joint indices
// of their meshes checked against the joint count) and the clips (channels of nodes that were
// not imported are dropped with a warning; malformed samplers are errors).
Check importSkins(Ctx& ctx);
Check importAnimations(Ctx& ctx);

} // namespace pnb::converter::gltf_internal
