// import_assimp.cpp — the formats assimp 5.2 reads (FBX, Collada, 3DS, PLY, STL, .blend, ...)
// into the scene IR. OBJ/MTL has its own importer (import_obj.cpp, tinyobjloader), which
// importScene picks for .obj; this file still reads OBJ when called directly, and its OBJ
// behaviour below is what import_obj.cpp reproduces.
//
// A translation, not a processing step: assimp runs only Triangulate, SortByPType and
// ValidateDataStructure; welding, normals, tangents and every optimisation are the mesh stage's
// (mesh_processing.h), written once for both importers.
//
// Decisions (also in the report that introduced this file):
// - Post-processing: NO aiProcess_FindInvalidData. It silently deletes whole streams it judges
//   invalid (a UV channel whose coordinates are all equal, zero normals, ...) and we could not
//   warn about it. Instead this file drops a normal/UV/colour stream holding NaN/Inf with a
//   warning naming the mesh; non-finite positions pass through because the mesh stage already
//   drops their triangles with a warning. NO JoinIdenticalVertices/GenNormals/CalcTangentSpace/
//   optimisations (the mesh stage does them), NO MakeLeftHanded/FlipWindingOrder (the IR is
//   right-handed like assimp's output), NO FlipUVs (see the V flip below).
// - Points and lines: SortByPType splits them into their own aiMeshes, which are dropped here
//   with a warning naming the mesh (the IR is triangles only).
// - V flip: IR UVs follow glTF (v = 0 is the top row of the image); assimp keeps OBJ's
//   convention (v = 0 is the bottom row), so every UV becomes (u, 1 - v). Done here rather than
//   with aiProcess_FlipUVs so the one place that knows the convention is this file.
// - Up axis: OBJ is +Y-up right-handed and taken as is. For other formats the file's "UpAxis",
//   "FrontAxis" and "CoordAxis" metadata (+ signs), which assimp 5.2 reports for FBX, become a
//   basis change on the root node. Collada and 3DS need nothing: assimp already converts them
//   in their root node. .blend is Z-up and assimp neither converts it nor reports metadata, so
//   it gets the Z-up → Y-up rotation. Units are NOT converted (FBX UnitScaleFactor is ignored).
// - Meshes: one IrMesh per distinct list of aiMeshes a node references, one IrPrimitive per
//   aiMesh. Assimp splits an OBJ object per material, so an object with two materials is one
//   IrMesh with two primitives (one submesh each) on one node, as glTF would model it; nodes
//   referencing the same list share the IrMesh (instancing).
// - map_d: the same file as map_Kd → alpha of the base colour texture (alphaMode Mask when d is
//   1, the common cut-out case; Blend when d < 1). Another file → a warning (separate opacity
//   maps are not supported yet) and the alpha mode comes from d alone.
// - Texture paths: relative to the source file's directory, '\' → '/', then a
//   case-insensitive, component-by-component lookup, then (with a warning) the file name alone
//   next to the source file (absolute paths from another machine): import_paths.h, shared with
//   import_obj.cpp. Files assimp itself opens (mtllib) go through the same resolver via an
//   IOSystem. Missing textures are dropped with a
//   warning; the material is kept.
//
// Does NOT do: processing of any kind, image decoding, animation, skinning, morph targets
// (each dropped with a warning), unit conversion.
//
// Index: [SECTION] io system, [SECTION] math, [SECTION] images,
// [SECTION] materials, [SECTION] meshes, [SECTION] axes, [SECTION] lights and cameras,
// [SECTION] scene and entry point.
#include "pnb_converter/importers.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/ObjMaterial.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "import_paths.h"
#include "pnb_converter/mtl_to_pbr.h"

namespace pnb::converter {

namespace {

namespace fs = std::filesystem;
using namespace import_detail;

std::string str(const aiString& s) { return std::string(s.C_Str(), s.length); }

// [SECTION] io system

// The files assimp opens itself (OBJ's mtllib, other formats' companion files) get the same
// backslash and case fix-ups as textures, and the ones that stay missing become warnings:
// assimp only logs them, and its logger is a process-wide singleton we cannot use per import.
class ResolvingIOSystem : public Assimp::DefaultIOSystem {
public:
    explicit ResolvingIOSystem(fs::path sourceDir) : mSourceDir(std::move(sourceDir)) {}

    bool Exists(const char* file) const override {
        return Assimp::DefaultIOSystem::Exists(file) || resolve(file).has_value();
    }

    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (Assimp::IOStream* stream = Assimp::DefaultIOSystem::Open(file, mode)) return stream;
        const bool readOnly = std::strpbrk(mode, "wa+") == nullptr;
        if (readOnly) {
            if (auto resolved = resolve(file)) {
                const std::string path = resolved->path.string();
                if (Assimp::IOStream* s = Assimp::DefaultIOSystem::Open(path.c_str(), mode)) {
                    if (resolved->byNameOnly) {
                        note(format("'%s' not found; using '%s' (same file name, next to the "
                                    "source file)", file, path.c_str()));
                    }
                    return s;
                }
            }
        }
        note(format("could not open '%s' (referenced by the source file)", file));
        return nullptr;
    }

    // Warnings collected while assimp read the file, in the order they happened.
    const std::vector<std::string>& notes() const { return mNotes; }

private:
    // Loaders retry the same name; one warning per file is enough.
    void note(std::string message) {
        if (std::find(mNotes.begin(), mNotes.end(), message) == mNotes.end()) {
            mNotes.push_back(std::move(message));
        }
    }

    // Assimp hands over paths it has already joined with the source directory (or absolute
    // ones), so they resolve from the working directory; the bare-name fallback uses the
    // source directory.
    std::optional<ResolvedPath> resolve(const char* file) const {
        if (file == nullptr || *file == '\0') return std::nullopt;
        std::string ref(file);
        std::replace(ref.begin(), ref.end(), '\\', '/');
        const fs::path p(ref);
        if (isRegularFile(p)) return ResolvedPath{p};
        if (p.is_absolute()) {
            if (auto found = findIgnoringCase(p.root_path(), p.relative_path())) {
                return ResolvedPath{*found};
            }
        } else {
            // Some loaders (LWS) open companion files by their bare relative name.
            if (auto found = findIgnoringCase(fs::path("."), p)) return ResolvedPath{*found};
            if (auto found = findIgnoringCase(mSourceDir, p)) return ResolvedPath{*found};
        }
        if (p.has_filename()) {
            if (auto byName = findIgnoringCase(mSourceDir, p.filename())) {
                return ResolvedPath{*byName, true};
            }
        }
        return std::nullopt;
    }

    fs::path mSourceDir;
    std::vector<std::string> mNotes;
};

// [SECTION] math

bool finite(const aiMatrix4x4& m) {
    for (unsigned row = 0; row < 4; ++row) {
        for (unsigned col = 0; col < 4; ++col) {
            if (!std::isfinite(m[row][col])) return false;
        }
    }
    return true;
}

aiVector3D normalizedOr(aiVector3D v, aiVector3D fallback) {
    const float len = v.Length();
    return len > 1e-12f && std::isfinite(len) ? v / len : fallback;
}

// Unit quaternion (xyzw) of a rotation matrix given by its columns. Shepperd's method: divide by
// the largest of the four candidates, so near-180-degree rotations stay accurate.
Vec4 quaternionFromColumns(const aiVector3D& x, const aiVector3D& y, const aiVector3D& z) {
    const float m00 = x.x, m10 = x.y, m20 = x.z;
    const float m01 = y.x, m11 = y.y, m21 = y.z;
    const float m02 = z.x, m12 = z.y, m22 = z.z;
    const float trace = m00 + m11 + m22;
    Vec4 q;
    if (trace > 0) {
        const float s = std::sqrt(trace + 1.0f) * 2.0f;
        q = {(m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25f * s};
    } else if (m00 > m11 && m00 > m22) {
        const float s = std::sqrt(1.0f + m00 - m11 - m22) * 2.0f;
        q = {0.25f * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s};
    } else if (m11 > m22) {
        const float s = std::sqrt(1.0f + m11 - m00 - m22) * 2.0f;
        q = {(m01 + m10) / s, 0.25f * s, (m12 + m21) / s, (m02 - m20) / s};
    } else {
        const float s = std::sqrt(1.0f + m22 - m00 - m11) * 2.0f;
        q = {(m02 + m20) / s, (m12 + m21) / s, 0.25f * s, (m10 - m01) / s};
    }
    const float len = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    if (!(len > 0) || !std::isfinite(len)) return {0, 0, 0, 1};
    // One sign for equal rotations keeps the output deterministic for equal inputs.
    const float sign = q.w < 0 ? -1.0f : 1.0f;
    return {sign * q.x / len, sign * q.y / len, sign * q.z / len, sign * q.w / len};
}

struct Trs {
    Vec3 translation{0, 0, 0};
    Vec4 rotation{0, 0, 0, 1};
    Vec3 scale{1, 1, 1};
    bool exact = true; // false: shear or a projective row, which TRS cannot hold
};

// Column lengths are the scale; a negative determinant (mirroring) goes into scale.x so the
// rotation stays proper. assimp's matrices are row-major with column vectors (a4,b4,c4 =
// translation).
Trs decompose(aiMatrix4x4 m) {
    Trs out;
    // Loaders that invert or multiply matrices (ASE) leave a bottom row like (0 0 0 0.99999994):
    // a homogeneous factor, divided out exactly. Only a non-zero d1..d3 is a real projection.
    const float w = m.d4;
    out.exact = w != 0 && std::abs(m.d1) + std::abs(m.d2) + std::abs(m.d3) <= 1e-6f * std::abs(w);
    if (w != 0 && std::isfinite(1.0f / w) && w != 1.0f) {
        for (unsigned row = 0; row < 3; ++row) {
            for (unsigned col = 0; col < 4; ++col) m[row][col] /= w;
        }
    }
    out.translation = {m.a4, m.b4, m.c4};
    aiVector3D cx(m.a1, m.b1, m.c1), cy(m.a2, m.b2, m.c2), cz(m.a3, m.b3, m.c3);
    float sx = cx.Length(), sy = cy.Length(), sz = cz.Length();
    const float det = cx * (cy ^ cz); // triple product
    if (det < 0) sx = -sx;
    out.scale = {sx, sy, sz};
    if (std::abs(sx) < 1e-20f || sy < 1e-20f || sz < 1e-20f) return out; // no rotation to find
    cx /= sx;
    cy /= sy;
    cz /= sz;
    const float kOrthoTolerance = 1e-3f;
    if (std::abs(cx * cy) > kOrthoTolerance || std::abs(cy * cz) > kOrthoTolerance ||
        std::abs(cz * cx) > kOrthoTolerance) {
        out.exact = false;
    }
    out.rotation = quaternionFromColumns(cx, cy, cz);
    return out;
}

// Rotation taking the IR's local -Z (where lights shine and cameras look) to `forward` and +Y
// towards `up`. A zero forward means -Z; an up parallel to forward is replaced.
Vec4 lookRotation(aiVector3D forward, aiVector3D up) {
    const aiVector3D f = normalizedOr(forward, aiVector3D(0, 0, -1));
    const aiVector3D z = -f;
    aiVector3D u = normalizedOr(up, aiVector3D(0, 1, 0));
    if (std::abs(u * f) > 0.999f) {
        u = std::abs(f.y) < 0.9f ? aiVector3D(0, 1, 0) : aiVector3D(1, 0, 0);
    }
    const aiVector3D x = normalizedOr(u ^ z, aiVector3D(1, 0, 0));
    const aiVector3D y = z ^ x;
    return quaternionFromColumns(x, y, z);
}

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

// State shared by the translation steps of one import.
struct Context {
    const aiScene* scene = nullptr;
    std::string path;  // as given, for messages
    fs::path sourceDir;
    IrScene* out = nullptr;
    std::map<std::string, int> imageByKey;  // resolved path or "*<embedded index>" → image
    std::vector<int> materialOf;             // aiMaterial → IrScene::materials, -2 = not yet

    void warn(std::string message) { out->warnings.push_back(std::move(message)); }
};

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

// [SECTION] meshes

std::string meshLabel(const aiMesh& mesh, unsigned index) {
    return mesh.mName.length > 0 ? format("mesh '%s'", mesh.mName.C_Str())
                                 : format("mesh %u", index);
}

// Copies a 3-component stream, reporting whether every value is finite.
bool copyVec3(const aiVector3D* src, unsigned count, std::vector<float>& dst) {
    dst.resize(size_t(count) * 3);
    bool allFinite = true;
    for (unsigned i = 0; i < count; ++i) {
        dst[i * 3 + 0] = src[i].x;
        dst[i * 3 + 1] = src[i].y;
        dst[i * 3 + 2] = src[i].z;
        allFinite = allFinite && std::isfinite(src[i].x) && std::isfinite(src[i].y) &&
                    std::isfinite(src[i].z);
    }
    return allFinite;
}

bool copyUv(const aiVector3D* src, unsigned count, std::vector<float>& dst) {
    dst.resize(size_t(count) * 2);
    bool allFinite = true;
    for (unsigned i = 0; i < count; ++i) {
        dst[i * 2 + 0] = src[i].x;
        dst[i * 2 + 1] = 1.0f - src[i].y; // assimp/OBJ v-up → glTF v-down (header block)
        allFinite = allFinite && std::isfinite(src[i].x) && std::isfinite(src[i].y);
    }
    return allFinite;
}

// The triangles of one aiMesh as an IrPrimitive; nullopt (with a warning) when it has none.
// Errors: an index outside the mesh's vertices.
Result<std::optional<IrPrimitive>, ConvertError> convertMesh(Context& ctx, unsigned meshIndex) {
    const aiMesh* mesh = ctx.scene->mMeshes[meshIndex];
    if (mesh == nullptr) return std::optional<IrPrimitive>{};
    const std::string label = meshLabel(*mesh, meshIndex);
    if (mesh->mNumVertices == 0 || mesh->mVertices == nullptr) {
        ctx.warn(label + ": no vertices; dropped");
        return std::optional<IrPrimitive>{};
    }

    if (mesh->mNumFaces > 0 && mesh->mFaces == nullptr) {
        return ConvertError{ConvertErrorKind::Input,
                            format("%s: %s has %u faces but no face array", ctx.path.c_str(),
                                   label.c_str(), mesh->mNumFaces)};
    }

    IrPrimitive prim;
    uint64_t points = 0, lines = 0, polygons = 0;
    prim.indices.reserve(size_t(mesh->mNumFaces) * 3);
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices > 0 && face.mIndices == nullptr) {
            return ConvertError{ConvertErrorKind::Input,
                                format("%s: %s face %u has no index array", ctx.path.c_str(),
                                       label.c_str(), f)};
        }
        for (unsigned k = 0; k < face.mNumIndices; ++k) {
            if (face.mIndices[k] >= mesh->mNumVertices) {
                return ConvertError{ConvertErrorKind::Input,
                                    format("%s: %s face %u: index %u out of range 0..%u",
                                           ctx.path.c_str(), label.c_str(), f, face.mIndices[k],
                                           mesh->mNumVertices - 1)};
            }
        }
        switch (face.mNumIndices) {
        case 1: ++points; break;
        case 2: ++lines; break;
        case 3: prim.indices.insert(prim.indices.end(), face.mIndices, face.mIndices + 3); break;
        default: ++polygons; break; // Triangulate leaves none; counted in case a loader does
        }
    }
    if (points + lines + polygons > 0) {
        std::string dropped;
        for (auto [count, kind] : {std::pair{points, "point"}, std::pair{lines, "line"},
                                   std::pair{polygons, "polygon"}}) {
            if (count == 0) continue;
            dropped += format("%s%llu %s(s)", dropped.empty() ? "" : ", ",
                              (unsigned long long)count, kind);
        }
        ctx.warn(format("%s: dropped %s; only triangles are imported", label.c_str(),
                        dropped.c_str()));
    }
    if (prim.indices.empty()) return std::optional<IrPrimitive>{};

    const unsigned n = mesh->mNumVertices;
    // Non-finite positions pass through: the mesh stage drops their triangles with a warning.
    copyVec3(mesh->mVertices, n, prim.positions);
    if (mesh->mNormals != nullptr && !copyVec3(mesh->mNormals, n, prim.normals)) {
        prim.normals.clear();
        ctx.warn(label + ": non-finite normals; dropped (they will be generated)");
    }
    for (unsigned set = 0; set < AI_MAX_NUMBER_OF_TEXTURECOORDS; ++set) {
        if (mesh->mTextureCoords[set] == nullptr) continue;
        if (set > 1) {
            ctx.warn(format("%s: UV set %u ignored (only sets 0 and 1 are imported)",
                            label.c_str(), set));
            continue;
        }
        std::vector<float>& uv = set == 0 ? prim.uv0 : prim.uv1;
        if (!copyUv(mesh->mTextureCoords[set], n, uv)) {
            uv.clear();
            ctx.warn(format("%s: non-finite UV set %u; dropped", label.c_str(), set));
        }
    }
    if (mesh->mColors[0] != nullptr) {
        prim.colors.resize(size_t(n) * 4);
        bool allFinite = true;
        for (unsigned i = 0; i < n; ++i) {
            const aiColor4D& c = mesh->mColors[0][i];
            prim.colors[i * 4 + 0] = c.r;
            prim.colors[i * 4 + 1] = c.g;
            prim.colors[i * 4 + 2] = c.b;
            prim.colors[i * 4 + 3] = c.a;
            allFinite = allFinite && std::isfinite(c.r) && std::isfinite(c.g) &&
                        std::isfinite(c.b) && std::isfinite(c.a);
        }
        if (!allFinite) {
            prim.colors.clear();
            ctx.warn(label + ": non-finite vertex colours; dropped");
        }
    }
    for (unsigned set = 1; set < AI_MAX_NUMBER_OF_COLOR_SETS; ++set) {
        if (mesh->mColors[set] != nullptr) {
            ctx.warn(format("%s: vertex colour set %u ignored", label.c_str(), set));
        }
    }
    if (mesh->mNumBones > 0) {
        ctx.warn(format("%s: %u bone(s) ignored (no skinning)", label.c_str(), mesh->mNumBones));
    }
    if (mesh->mNumAnimMeshes > 0) {
        ctx.warn(format("%s: %u morph target(s) ignored", label.c_str(), mesh->mNumAnimMeshes));
    }
    prim.material = materialFor(ctx, mesh->mMaterialIndex);
    return std::optional<IrPrimitive>(std::move(prim));
}

// [SECTION] axes

// Basis change from the file's axes to +Y-up right-handed (header block), or nullopt when the
// file says nothing or already is +Y-up.
std::optional<aiMatrix4x4> axisConversion(Context& ctx) {
    const aiMetadata* meta = ctx.scene->mMetaData;
    auto getInt = [&](const char* key) -> std::optional<int32_t> {
        int32_t v = 0;
        if (meta != nullptr && meta->Get(std::string(key), v)) return v;
        return std::nullopt;
    };
    const auto up = getInt("UpAxis"), upSign = getInt("UpAxisSign");
    const auto front = getInt("FrontAxis"), frontSign = getInt("FrontAxisSign");
    const auto coord = getInt("CoordAxis"), coordSign = getInt("CoordAxisSign");
    aiMatrix4x4 m;
    if (up && upSign && front && frontSign && coord && coordSign) {
        const int32_t axes[3] = {*coord, *up, *front};
        const int32_t signs[3] = {*coordSign, *upSign, *frontSign};
        bool valid = true, used[3] = {false, false, false};
        for (int i = 0; i < 3; ++i) {
            valid = valid && axes[i] >= 0 && axes[i] <= 2 && !used[axes[i]] &&
                    (signs[i] == 1 || signs[i] == -1);
            if (valid) used[axes[i]] = true;
        }
        if (!valid) {
            ctx.warn(format("axis metadata (up %d%+d, front %d%+d, coord %d%+d) is not a basis; "
                            "ignored", *up, *upSign, *front, *frontSign, *coord, *coordSign));
            return std::nullopt;
        }
        // Row i of the basis change picks the file axis that becomes IR axis i (x = coord/right,
        // y = up, z = front).
        m = aiMatrix4x4(0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);
        for (int row = 0; row < 3; ++row) m[row][axes[row]] = float(signs[row]);
        m.d4 = 1;
    } else {
        aiString sourceFormat;
        const bool blender = meta != nullptr &&
                             meta->Get(std::string("SourceAsset_Format"), sourceFormat) &&
                             std::strncmp(sourceFormat.C_Str(), "Blender 3D", 10) == 0;
        if (!blender) return std::nullopt;
        // Blender: +Z up, -Y front → IR y = z, z = -y.
        m = aiMatrix4x4(1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1);
    }
    if (m.IsIdentity()) return std::nullopt;
    if (m.Determinant() < 0) {
        ctx.warn("the file's axes are left-handed; the root node mirrors them (negative scale)");
    }
    return m;
}

// [SECTION] lights and cameras

// The node a light or camera hangs from: assimp names it after the light/camera. When the
// source also gives a local position/orientation, a child node carries it, because the IR's
// lights and cameras sit at their node's origin looking down -Z.
int attachmentNode(Context& ctx, const std::map<std::string, int>& nodeByName,
                   const std::string& name, const aiVector3D& position, const Vec4& rotation,
                   bool isLight) {
    int parent = -1;
    if (auto it = nodeByName.find(name); it != nodeByName.end()) {
        parent = it->second;
    } else {
        ctx.warn(format("%s '%s' has no node; placed at the origin", isLight ? "light" : "camera",
                        name.c_str()));
    }
    const bool identity = position == aiVector3D(0, 0, 0) &&
                          std::abs(rotation.w) > 1.0f - 1e-6f;
    if (parent >= 0 && identity) {
        IrNode& node = ctx.out->nodes[size_t(parent)];
        if ((isLight ? node.light : node.camera) < 0) return parent;
    }
    IrNode child;
    child.name = name;
    child.parent = parent;
    child.translation = {position.x, position.y, position.z};
    child.rotation = rotation;
    ctx.out->nodes.push_back(std::move(child));
    return int(ctx.out->nodes.size() - 1);
}

void convertLights(Context& ctx, const std::map<std::string, int>& nodeByName) {
    bool unitsNoted = false;
    for (unsigned i = 0; i < ctx.scene->mNumLights; ++i) {
        const aiLight* src = ctx.scene->mLights[i];
        if (src == nullptr) continue;
        IrLight light;
        light.name = str(src->mName);
        const std::string what = format("light '%s'", light.name.c_str());
        switch (src->mType) {
        case aiLightSource_DIRECTIONAL: light.type = LightType::Directional; break;
        case aiLightSource_POINT: light.type = LightType::Point; break;
        case aiLightSource_SPOT: light.type = LightType::Spot; break;
        default:
            ctx.warn(what + ": ambient, area and undefined lights are not supported; dropped");
            continue;
        }
        // assimp's colour is colour x intensity; split it so the colour is at most 1.
        const aiColor3D& c = src->mColorDiffuse;
        const float peak = std::max({c.r, c.g, c.b});
        if (!std::isfinite(peak) || peak <= 0) {
            ctx.warn(what + ": black or invalid colour; imported with intensity 0");
            light.intensity = 0;
        } else {
            light.color = {c.r / peak, c.g / peak, c.b / peak};
            light.intensity = peak;
        }
        if (!unitsNoted) {
            ctx.warn("lights: the source's intensities have no physical unit; copied as "
                     "lux/candela unchanged");
            unitsNoted = true;
        }
        if (light.type != LightType::Directional) {
            // 1 / (c + l d + q d^2): the range is where that falls to 1/256 (invisible in 8-bit
            // output). No distance term → unlimited range.
            const double kc = src->mAttenuationConstant, kl = src->mAttenuationLinear,
                         kq = src->mAttenuationQuadratic, target = 256.0;
            double range = 0;
            if (kq > 0) range = (-kl + std::sqrt(kl * kl - 4 * kq * (kc - target))) / (2 * kq);
            else if (kl > 0) range = (target - kc) / kl;
            if (std::isfinite(range) && range > 0) {
                light.range = float(range);
                ctx.warn(format("%s: attenuation (constant %g, linear %g, quadratic %g) "
                                "converted to range %g; the falloff becomes inverse-square",
                                what.c_str(), kc, kl, kq, range));
            }
        }
        if (light.type == LightType::Spot) {
            // assimp's cone angles are full angles; the IR's (glTF's) are half angles.
            float outer = src->mAngleOuterCone * 0.5f, inner = src->mAngleInnerCone * 0.5f;
            const float kHalfPi = 1.5707963f;
            if (!std::isfinite(outer) || outer <= 0) outer = 0.7853982f;
            if (!std::isfinite(inner) || inner < 0) inner = 0;
            if (outer > kHalfPi) {
                ctx.warn(format("%s: cone wider than 180 degrees clamped", what.c_str()));
                outer = kHalfPi;
            }
            light.outerConeRadians = outer;
            light.innerConeRadians = std::min(inner, outer);
        }
        const bool needsDirection = light.type != LightType::Point;
        const Vec4 rotation = needsDirection ? lookRotation(src->mDirection, src->mUp)
                                             : Vec4{0, 0, 0, 1};
        const aiVector3D position = light.type == LightType::Directional ? aiVector3D(0, 0, 0)
                                                                         : src->mPosition;
        const int node = attachmentNode(ctx, nodeByName, light.name, position, rotation, true);
        ctx.out->lights.push_back(std::move(light));
        ctx.out->nodes[size_t(node)].light = int(ctx.out->lights.size() - 1);
    }
}

void convertCameras(Context& ctx, const std::map<std::string, int>& nodeByName) {
    for (unsigned i = 0; i < ctx.scene->mNumCameras; ++i) {
        const aiCamera* src = ctx.scene->mCameras[i];
        if (src == nullptr) continue;
        IrCamera camera;
        camera.name = str(src->mName);
        const std::string what = format("camera '%s'", camera.name.c_str());
        const float aspect = std::isfinite(src->mAspect) && src->mAspect > 0 ? src->mAspect : 0;
        camera.aspectRatio = aspect;
        if (std::isfinite(src->mOrthographicWidth) && src->mOrthographicWidth > 0) {
            camera.projection = Projection::Orthographic;
            camera.xmag = src->mOrthographicWidth;
            camera.ymag = aspect > 0 ? src->mOrthographicWidth / aspect : src->mOrthographicWidth;
        } else {
            // assimp documents mHorizontalFOV as the half angle, but its Collada, FBX and Blend
            // loaders store the full angle (Blender's default camera arrives as 0.8576 rad =
            // 49.1 degrees, its full horizontal FOV), so it is taken as full.
            float hfov = src->mHorizontalFOV;
            if (!std::isfinite(hfov) || hfov <= 0 || hfov >= 3.14159f) {
                ctx.warn(format("%s: invalid field of view %g; using 0.8 rad", what.c_str(), hfov));
                hfov = 0.8f;
            }
            if (aspect > 0) {
                camera.yfovRadians = 2.0f * std::atan(std::tan(hfov * 0.5f) / aspect);
            } else {
                ctx.warn(what + ": no aspect ratio; the vertical field of view is taken equal to "
                                "the horizontal one");
                camera.yfovRadians = hfov;
            }
        }
        camera.znear = std::isfinite(src->mClipPlaneNear) && src->mClipPlaneNear > 0
                           ? src->mClipPlaneNear : 0.1f;
        camera.zfar = std::isfinite(src->mClipPlaneFar) && src->mClipPlaneFar > camera.znear
                          ? src->mClipPlaneFar : 0; // 0 = infinite
        const Vec4 rotation = lookRotation(src->mLookAt, src->mUp);
        const int node =
            attachmentNode(ctx, nodeByName, camera.name, src->mPosition, rotation, false);
        ctx.out->cameras.push_back(std::move(camera));
        ctx.out->nodes[size_t(node)].camera = int(ctx.out->cameras.size() - 1);
    }
}

// [SECTION] scene and entry point

Result<IrScene, ConvertError> translate(Context& ctx) {
    const aiScene* scene = ctx.scene;
    IrScene& out = *ctx.out;
    ctx.materialOf.assign(scene->mNumMaterials, -2);

    // Each aiMesh is converted once; nodes then share IrMeshes by the list of aiMeshes they use.
    std::vector<std::optional<IrPrimitive>> primitives(scene->mNumMeshes);
    std::vector<bool> converted(scene->mNumMeshes, false);
    auto primitiveOf = [&](unsigned meshIndex) -> Result<const IrPrimitive*, ConvertError> {
        if (!converted[meshIndex]) {
            auto r = convertMesh(ctx, meshIndex);
            if (!r) return r.error();
            primitives[meshIndex] = std::move(r.value());
            converted[meshIndex] = true;
        }
        return primitives[meshIndex] ? &*primitives[meshIndex] : nullptr;
    };
    std::map<std::vector<unsigned>, int> meshByList;

    const auto rootConversion = axisConversion(ctx);
    std::map<std::string, int> nodeByName;
    struct Pending {
        const aiNode* node;
        int parent;
    };
    std::vector<Pending> stack{{scene->mRootNode, -1}};
    while (!stack.empty()) {
        const Pending pending = stack.back();
        stack.pop_back();
        const aiNode* src = pending.node;
        if (src == nullptr) continue;
        IrNode node;
        node.name = str(src->mName);
        node.parent = pending.parent;
        aiMatrix4x4 local = src->mTransformation;
        if (pending.parent < 0 && rootConversion) local = *rootConversion * local;
        if (!finite(local)) {
            return ConvertError{ConvertErrorKind::Input,
                                format("%s: node '%s' has a non-finite transform",
                                       ctx.path.c_str(), node.name.c_str())};
        }
        const Trs trs = decompose(local);
        if (!trs.exact) {
            ctx.warn(format("node '%s': transform has shear or projection; approximated by "
                            "translation/rotation/scale", node.name.c_str()));
        }
        node.translation = trs.translation;
        node.rotation = trs.rotation;
        node.scale = trs.scale;

        std::vector<unsigned> list;
        for (unsigned k = 0; k < src->mNumMeshes; ++k) {
            const unsigned meshIndex = src->mMeshes[k];
            if (meshIndex >= scene->mNumMeshes) {
                return ConvertError{ConvertErrorKind::Input,
                                    format("%s: node '%s' refers to mesh %u of %u",
                                           ctx.path.c_str(), node.name.c_str(), meshIndex,
                                           scene->mNumMeshes)};
            }
            auto prim = primitiveOf(meshIndex);
            if (!prim) return prim.error();
            if (prim.value() != nullptr) list.push_back(meshIndex);
        }
        if (!list.empty()) {
            auto [it, inserted] = meshByList.emplace(list, int(out.meshes.size()));
            if (inserted) {
                IrMesh mesh; // primitives are filled in once all lists are known
                const aiMesh* first = scene->mMeshes[list[0]];
                mesh.name = list.size() == 1 && first->mName.length > 0 ? str(first->mName)
                                                                        : node.name;
                out.meshes.push_back(std::move(mesh));
            }
            node.mesh = it->second;
        }
        out.nodes.push_back(std::move(node));
        const int index = int(out.nodes.size() - 1);
        nodeByName.emplace(str(src->mName), index); // first node of a name wins
        // Reverse order so children come out in their source order (preorder: parents first).
        for (unsigned k = src->mNumChildren; k-- > 0;) stack.push_back({src->mChildren[k], index});
    }

    // An aiMesh in several distinct lists is copied into each IrMesh; the last one takes it.
    std::vector<unsigned> uses(scene->mNumMeshes, 0);
    for (const auto& entry : meshByList) {
        for (unsigned meshIndex : entry.first) ++uses[meshIndex];
    }
    for (const auto& [list, meshIndex] : meshByList) {
        IrMesh& mesh = out.meshes[size_t(meshIndex)];
        for (unsigned m : list) {
            if (--uses[m] == 0) mesh.primitives.push_back(std::move(*primitives[m]));
            else mesh.primitives.push_back(*primitives[m]);
        }
    }

    size_t unused = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) unused += converted[m] ? 0 : 1;
    if (unused > 0) ctx.warn(format("%zu mesh(es) used by no node; dropped", unused));
    if (out.meshes.empty()) {
        return ConvertError{ConvertErrorKind::Input,
                            format("%s: no triangle meshes (%u mesh(es) in the file, none with "
                                   "triangles)", ctx.path.c_str(), scene->mNumMeshes)};
    }

    convertLights(ctx, nodeByName);
    convertCameras(ctx, nodeByName);
    if (scene->mNumAnimations > 0) {
        ctx.warn(format("%u animation(s) ignored", scene->mNumAnimations));
    }
    return std::move(out);
}

} // namespace

Result<IrScene, ConvertError> importWithAssimp(const std::string& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        return ConvertError{ConvertErrorKind::Input,
                            format("%s: no such file (or not a regular file)", path.c_str())};
    }
    // Assimp reports bad data through its error string, but a std::bad_alloc (or a loader's
    // stray exception) must not cross our module boundary either.
    try {
        const fs::path sourceDir = fs::path(path).parent_path();
        Assimp::Importer importer;
        // Formats with bones but no meshes (BVH) would otherwise get a generated skeleton mesh.
        importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
        // One node per FBX node instead of a chain of "$AssimpFbx$" pivot helpers.
        importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
        auto* io = new ResolvingIOSystem(sourceDir.empty() ? fs::path(".") : sourceDir);
        importer.SetIOHandler(io); // the importer owns and deletes it

        const unsigned flags =
            aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure;
        const aiScene* scene = importer.ReadFile(path, flags);
        if (scene == nullptr) {
            const char* message = importer.GetErrorString();
            return ConvertError{ConvertErrorKind::Input,
                                format("%s: assimp could not read it: %s", path.c_str(),
                                       message && *message ? message : "unknown error")};
        }
        if (scene->mRootNode == nullptr || scene->mNumMeshes == 0) {
            return ConvertError{ConvertErrorKind::Input,
                                format("%s: the file has no meshes", path.c_str())};
        }
        if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) {
            return ConvertError{ConvertErrorKind::Input,
                                format("%s: assimp could only read part of it (scene marked "
                                       "incomplete)", path.c_str())};
        }

        IrScene out;
        out.sourcePath = path;
        out.warnings = io->notes();
        Context ctx;
        ctx.scene = scene;
        ctx.path = path;
        ctx.sourceDir = sourceDir.empty() ? fs::path(".") : sourceDir;
        ctx.out = &out;
        return translate(ctx);
    } catch (const std::exception& e) {
        return ConvertError{ConvertErrorKind::Input,
                            format("%s: import failed: %s", path.c_str(), e.what())};
    } catch (...) {
        return ConvertError{ConvertErrorKind::Input,
                            format("%s: import failed (unknown exception)", path.c_str())};
    }
}

} // namespace pnb::converter
