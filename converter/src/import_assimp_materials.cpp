// converter/src/import_assimp_materials.cpp — assimp materials into IR materials: MTL-style
// parameters through mtl_to_pbr, one texture per slot (file references resolved, embedded
// textures kept or re-encoded as PNG). A step of the assimp importer of its own because it is
// the largest and the only one that touches images (import_assimp_internal.h).
//
// Index: [SECTION] images, [SECTION] materials
#include <assimp/ObjMaterial.h>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "import_assimp_internal.h"
#include "import_paths.h"
#include "pnb_converter/mtl_to_pbr.h"

namespace pnb::converter::assimp_detail {

using namespace import_detail;

namespace {

// [SECTION] images

uint32_t crc32(const uint8_t* data, size_t size, uint32_t crc = 0) {
    static const std::array<uint32_t, 256> table = [] {
        std::array<uint32_t, 256> t{};
        for (uint32_t i = 0; i < 256; ++i) {
            uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    crc = ~crc;
    for (size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xFF] ^ (crc >> 8);
    return ~crc;
}

void putBe32(std::vector<uint8_t>& out, uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(uint8_t(v >> shift));
}

// A PNG of an uncompressed embedded texture (MDL, HMP, ...), since IrImage carries image
// *files*. The loaders fill aiTexel's named r/g/b/a members, so its achFormatHint ("rgba8888")
// needs no interpretation. Deflate "stored" blocks: no compressor needed, and the texture stage
// re-encodes anyway.
std::vector<uint8_t> encodePngRgba8(uint32_t width, uint32_t height, const aiTexel* texels) {
    std::vector<uint8_t> raw;
    raw.reserve((size_t(width) * 4 + 1) * height);
    for (uint32_t y = 0; y < height; ++y) {
        raw.push_back(0); // filter: none
        for (uint32_t x = 0; x < width; ++x) {
            const aiTexel& t = texels[size_t(y) * width + x];
            raw.insert(raw.end(), {t.r, t.g, t.b, t.a});
        }
    }
    std::vector<uint8_t> zlib = {0x78, 0x01};
    uint32_t adlerA = 1, adlerB = 0;
    for (uint8_t byte : raw) {
        adlerA = (adlerA + byte) % 65521;
        adlerB = (adlerB + adlerA) % 65521;
    }
    for (size_t offset = 0; offset < raw.size() || offset == 0;) {
        const size_t size = std::min<size_t>(raw.size() - offset, 65535);
        const bool last = offset + size == raw.size();
        zlib.push_back(last ? 1 : 0);
        zlib.insert(zlib.end(), {uint8_t(size), uint8_t(size >> 8), uint8_t(~size),
                                 uint8_t(~size >> 8)});
        zlib.insert(zlib.end(), raw.begin() + offset, raw.begin() + offset + size);
        offset += size;
        if (last) break;
    }
    putBe32(zlib, (adlerB << 16) | adlerA);

    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    auto chunk = [&](const char* type, const std::vector<uint8_t>& data) {
        putBe32(png, uint32_t(data.size()));
        const size_t typeAt = png.size();
        png.insert(png.end(), type, type + 4);
        png.insert(png.end(), data.begin(), data.end());
        putBe32(png, crc32(png.data() + typeAt, data.size() + 4));
    };
    std::vector<uint8_t> header;
    putBe32(header, width);
    putBe32(header, height);
    header.insert(header.end(), {8, 6, 0, 0, 0}); // 8-bit RGBA, deflate, no filter, no interlace
    chunk("IHDR", header);
    chunk("IDAT", zlib);
    chunk("IEND", {});
    return png;
}

// The file's signature first (loaders' hints are sometimes wrong), then assimp's hint.
std::string mimeTypeOf(const uint8_t* data, size_t size, const char (&hint)[HINTMAXTEXTURELEN]) {
    if (size >= 8 && std::memcmp(data, "\x89PNG\r\n\x1a\n", 8) == 0) return "image/png";
    if (size >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF) return "image/jpeg";
    const std::string h(hint, strnlen(hint, HINTMAXTEXTURELEN));
    if (h == "png") return "image/png";
    if (h == "jpg" || h == "jpeg") return "image/jpeg";
    if (h == "tga") return "image/x-tga";
    if (h == "bmp") return "image/bmp";
    if (h == "dds") return "image/vnd-ms.dds";
    if (h == "ktx2") return "image/ktx2";
    return {};
}

// [SECTION] materials

// Largest embedded texture we turn into an image: 16k x 16k texels.
constexpr uint64_t kMaxEmbeddedTexels = uint64_t(16384) * 16384;

// Index of the IrImage for a texture reference, or -1 (with a warning) when nothing usable is
// found. Embedded textures win over files of the same name: they are what the source carries.
int imageFor(Context& ctx, const std::string& ref, const std::string& what) {
    const auto [embedded, embeddedIndex] = ctx.scene->GetEmbeddedTextureAndIndex(ref.c_str());
    if (embedded != nullptr) {
        const std::string key = "*" + std::to_string(embeddedIndex);
        if (auto it = ctx.imageByKey.find(key); it != ctx.imageByKey.end()) return it->second;
        IrImage image;
        std::string embeddedName = str(embedded->mFilename);
        std::replace(embeddedName.begin(), embeddedName.end(), '\\', '/');
        const std::string fileName = fs::path(embeddedName).filename().string();
        image.name = fileName.empty() ? format("embedded%d", embeddedIndex) : fileName;
        if (embedded->mHeight == 0) {
            // Compressed: mWidth is the size in bytes of an image file.
            if (embedded->pcData == nullptr || embedded->mWidth == 0) {
                ctx.warn(format("%s: embedded texture %d is empty; ignored", what.c_str(),
                                embeddedIndex));
                return -1;
            }
            const auto* bytes = reinterpret_cast<const uint8_t*>(embedded->pcData);
            image.encoded.assign(bytes, bytes + embedded->mWidth);
            image.mimeType = mimeTypeOf(bytes, embedded->mWidth, embedded->achFormatHint);
        } else {
            const uint64_t texels = uint64_t(embedded->mWidth) * embedded->mHeight;
            if (embedded->pcData == nullptr || embedded->mWidth == 0 ||
                texels > kMaxEmbeddedTexels) {
                ctx.warn(format("%s: embedded texture %d (%ux%u texels) is empty or too large; "
                                "ignored", what.c_str(), embeddedIndex, embedded->mWidth,
                                embedded->mHeight));
                return -1;
            }
            image.encoded = encodePngRgba8(embedded->mWidth, embedded->mHeight, embedded->pcData);
            image.mimeType = "image/png";
        }
        ctx.out->images.push_back(std::move(image));
        const int index = int(ctx.out->images.size() - 1);
        ctx.imageByKey.emplace(key, index);
        return index;
    }
    if (!ref.empty() && ref[0] == '*') {
        ctx.warn(format("%s: embedded texture '%s' does not exist; ignored", what.c_str(),
                        ref.c_str()));
        return -1;
    }
    return imageForReference(ctx.sourceDir, ref, what, *ctx.out, ctx.imageByKey);
}

Wrap wrapOf(aiTextureMapMode mode) {
    switch (mode) {
    case aiTextureMapMode_Clamp:
    case aiTextureMapMode_Decal: return Wrap::ClampToEdge;
    case aiTextureMapMode_Mirror: return Wrap::MirroredRepeat;
    default: return Wrap::Repeat;
    }
}

// What a texture reference resolves to, without adding an image: "*<index>" for an embedded
// texture, the resolved path for a file, "" when nothing is found.
std::string textureKey(const Context& ctx, const std::string& ref) {
    const auto [embedded, embeddedIndex] = ctx.scene->GetEmbeddedTextureAndIndex(ref.c_str());
    if (embedded != nullptr) return "*" + std::to_string(embeddedIndex);
    if (!ref.empty() && ref[0] == '*') return {};
    const auto resolved = resolveReference(ctx.sourceDir, ref);
    return resolved ? resolved->path.string() : std::string();
}

struct TextureLookup {
    std::string ref; // as written in the source
    std::string key; // textureKey()
    IrTextureRef texture;
};

// The first texture of `type`, if any. Further layers of the same type are reported: the IR has
// one texture per slot.
// `place` = false only looks the texture up (no image is added, no warnings about its file).
std::optional<TextureLookup> textureOf(Context& ctx, const aiMaterial& mat, aiTextureType type,
                                       const std::string& what, bool place = true) {
    const unsigned count = mat.GetTextureCount(type);
    if (count == 0) return std::nullopt;
    aiString path;
    aiTextureMapping mapping = aiTextureMapping_UV;
    unsigned uvIndex = 0;
    std::array<aiTextureMapMode, 2> modes{aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
    if (mat.GetTexture(type, 0, &path, &mapping, &uvIndex, nullptr, nullptr, modes.data()) !=
        aiReturn_SUCCESS) {
        return std::nullopt;
    }
    const char* typeName = aiTextureTypeToString(type);
    auto warn = [&](std::string message) {
        if (place) ctx.warn(format("%s: %s texture %s", what.c_str(), typeName, message.c_str()));
    };
    if (count > 1) warn(format("has %u layers; only the first is used", count));
    if (mapping != aiTextureMapping_UV) {
        warn("uses a projection mapping; imported with UV set 0");
        uvIndex = 0;
    }
    if (uvIndex > 1) {
        warn(format("uses UV set %u; only sets 0 and 1 are imported, using 0", uvIndex));
        uvIndex = 0;
    }
    aiUVTransform transform;
    if (mat.Get(AI_MATKEY_UVTRANSFORM(type, 0), transform) == aiReturn_SUCCESS &&
        (transform.mTranslation != aiVector2D(0, 0) || transform.mScaling != aiVector2D(1, 1) ||
         transform.mRotation != 0)) {
        warn("UV transform ignored");
    }
    TextureLookup out;
    out.ref = str(path);
    out.key = textureKey(ctx, out.ref);
    if (place) out.texture.image = imageFor(ctx, out.ref, what);
    out.texture.texCoord = uint8_t(uvIndex);
    out.texture.wrapU = wrapOf(modes[0]);
    out.texture.wrapV = wrapOf(modes[1]);
    return out;
}

std::optional<float> getFloat(const aiMaterial& mat, const char* key, unsigned type, unsigned idx) {
    ai_real v = 0;
    if (mat.Get(key, type, idx, v) == aiReturn_SUCCESS) return float(v);
    return std::nullopt;
}

std::optional<Vec3> getColor(const aiMaterial& mat, const char* key, unsigned type, unsigned idx) {
    aiColor3D c;
    if (mat.Get(key, type, idx, c) == aiReturn_SUCCESS) return Vec3{c.r, c.g, c.b};
    return std::nullopt;
}

// Same file or embedded texture, or (both unresolved) the same reference once slashes and case
// are normalised.
bool sameTexture(const TextureLookup& a, const TextureLookup& b) {
    if (!a.key.empty() || !b.key.empty()) return a.key == b.key;
    std::string x = a.ref, y = b.ref;
    std::replace(x.begin(), x.end(), '\\', '/');
    std::replace(y.begin(), y.end(), '\\', '/');
    return iequals(x, y);
}

IrMaterial convertMaterial(Context& ctx, const aiMaterial& mat) {
    IrMaterial out;
    out.name = str(mat.GetName());
    const std::string what = format("material '%s'", out.name.c_str());

    // MTL's parameters (assimp folds Tr into opacity for OBJ); the same Phong-style mapping
    // serves the other formats, whose PBR factors (Pr/Pm) win when present.
    MtlParameters mtl;
    if (auto base = getColor(mat, AI_MATKEY_BASE_COLOR)) mtl.kd = *base;
    else if (auto kd = getColor(mat, AI_MATKEY_COLOR_DIFFUSE)) mtl.kd = *kd;
    mtl.ns = getFloat(mat, AI_MATKEY_SHININESS);
    mtl.d = getFloat(mat, AI_MATKEY_OPACITY);
    mtl.tr = getFloat(mat, AI_MATKEY_TRANSPARENCYFACTOR);
    if (auto ke = getColor(mat, AI_MATKEY_COLOR_EMISSIVE)) mtl.ke = *ke;
    mtl.pr = getFloat(mat, AI_MATKEY_ROUGHNESS_FACTOR);
    mtl.pm = getFloat(mat, AI_MATKEY_METALLIC_FACTOR);
    applyMtlToPbr(mtl, out.pbr);
    int twoSided = 0;
    if (mat.Get(AI_MATKEY_TWOSIDED, twoSided) == aiReturn_SUCCESS) out.pbr.doubleSided = twoSided;

    auto& slots = out.textures;
    auto slot = [&](TextureSlotKind kind) -> IrTextureRef& { return slots[size_t(kind)]; };

    auto baseColor = textureOf(ctx, mat, aiTextureType_DIFFUSE, what);
    if (!baseColor) {
        baseColor = textureOf(ctx, mat, aiTextureType_BASE_COLOR, what);
    } else if (auto other = textureOf(ctx, mat, aiTextureType_BASE_COLOR, what, false);
               other && !sameTexture(*other, *baseColor)) {
        ctx.warn(format("%s: base colour texture '%s' ignored (the diffuse texture is used)",
                        what.c_str(), other->ref.c_str()));
    }
    if (baseColor) slot(TextureSlotKind::BaseColor) = baseColor->texture;

    if (auto opacity = textureOf(ctx, mat, aiTextureType_OPACITY, what, false)) {
        if (baseColor && sameTexture(*opacity, *baseColor)) {
            // The base colour texture's alpha is the opacity: a cut-out unless d asked for
            // translucency. (A missing base colour file was reported above.)
            const bool found = baseColor->texture.image >= 0;
            if (found && out.pbr.alphaMode == AlphaMode::Opaque) {
                out.pbr.alphaMode = AlphaMode::Mask;
            }
        } else {
            ctx.warn(format("%s: opacity map '%s' is not the base colour texture; separate "
                            "opacity maps are not supported yet (alpha mode from d only)",
                            what.c_str(), opacity->ref.c_str()));
        }
    }

    // OBJ: norm → NORMALS, map_bump/bump → HEIGHT (assimp 5.2's MTL reader). Bump maps in OBJ
    // exports are nearly always tangent-space normal maps, so HEIGHT is the fallback.
    aiTextureType normalType = aiTextureType_NORMALS;
    auto normal = textureOf(ctx, mat, aiTextureType_NORMALS, what);
    if (!normal) {
        normalType = aiTextureType_HEIGHT;
        normal = textureOf(ctx, mat, aiTextureType_HEIGHT, what);
    } else if (mat.GetTextureCount(aiTextureType_HEIGHT) > 0) {
        ctx.warn(what + ": both a normal map and a bump map; the bump map is ignored");
    }
    if (normal) {
        slot(TextureSlotKind::Normal) = normal->texture;
        // MTL's -bm multiplier scales the bump like glTF's normalTexture.scale.
        const auto bumpMultiplier = getFloat(mat, AI_MATKEY_OBJ_BUMPMULT(normalType, 0));
        if (bumpMultiplier && std::isfinite(*bumpMultiplier)) out.pbr.normalScale = *bumpMultiplier;
    }

    auto emissive = textureOf(ctx, mat, aiTextureType_EMISSIVE, what);
    if (!emissive) emissive = textureOf(ctx, mat, aiTextureType_EMISSION_COLOR, what);
    if (emissive) {
        slot(TextureSlotKind::Emissive) = emissive->texture;
        // glTF multiplies the texture by the factor; a map_Ke with no (or black) Ke means the
        // texture itself is the emission.
        const Vec3& e = out.pbr.emissiveFactor;
        if (e.x == 0 && e.y == 0 && e.z == 0) out.pbr.emissiveFactor = {1, 1, 1};
    }

    if (auto occlusion = textureOf(ctx, mat, aiTextureType_AMBIENT_OCCLUSION, what)) {
        slot(TextureSlotKind::Occlusion) = occlusion->texture;
    }

    // Everything else has no slot (glTF packs roughness and metallic into one texture, which a
    // separate map_Pr / map_Pm is not).
    static constexpr aiTextureType kIgnored[] = {
        aiTextureType_SPECULAR, aiTextureType_AMBIENT, aiTextureType_SHININESS,
        aiTextureType_DISPLACEMENT, aiTextureType_LIGHTMAP, aiTextureType_REFLECTION,
        aiTextureType_NORMAL_CAMERA, aiTextureType_METALNESS, aiTextureType_DIFFUSE_ROUGHNESS,
        aiTextureType_SHEEN, aiTextureType_CLEARCOAT, aiTextureType_TRANSMISSION,
        aiTextureType_UNKNOWN};
    for (aiTextureType type : kIgnored) {
        if (mat.GetTextureCount(type) == 0) continue;
        aiString path;
        mat.GetTexture(type, 0, &path);
        ctx.warn(format("%s: %s texture '%s' ignored (no PBR slot)", what.c_str(),
                        aiTextureTypeToString(type), path.C_Str()));
    }
    return out;
}

// True for the material assimp makes up for faces without one (OBJ: no usemtl): its name, its
// 0.6 grey, no textures. A source material that happens to share the name keeps its own values.
bool isAssimpDefaultMaterial(const aiMaterial& mat) {
    if (str(mat.GetName()) != AI_DEFAULT_MATERIAL_NAME) return false;
    for (int type = aiTextureType_NONE; type <= AI_TEXTURE_TYPE_MAX; ++type) {
        if (mat.GetTextureCount(aiTextureType(type)) > 0) return false;
    }
    const auto kd = getColor(mat, AI_MATKEY_COLOR_DIFFUSE);
    return !kd || (kd->x == 0.6f && kd->y == 0.6f && kd->z == 0.6f);
}

} // namespace

// IrScene::materials index of an aiMaterial, converting it on first use so materials no mesh
// uses (OBJ always has assimp's "DefaultMaterial") stay out of the IR. Assimp's made-up default
// maps to -1, the IR's default material.
int materialFor(Context& ctx, unsigned index) {
    if (index >= ctx.scene->mNumMaterials || ctx.scene->mMaterials[index] == nullptr) return -1;
    int& cached = ctx.materialOf[index];
    if (cached != -2) return cached;
    const aiMaterial& mat = *ctx.scene->mMaterials[index];
    if (isAssimpDefaultMaterial(mat)) {
        cached = -1;
        return cached;
    }
    ctx.out->materials.push_back(convertMaterial(ctx, mat));
    cached = int(ctx.out->materials.size() - 1);
    return cached;
}

} // namespace pnb::converter::assimp_detail
