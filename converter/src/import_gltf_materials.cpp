// converter/src/import_gltf_materials.cpp — glTF materials into IR materials, with their
// textures (samplers, KHR_texture_transform) and images (external files, bufferViews, data
// URIs). A stage of the glTF importer, separate from the meshes that reference materials
// (import_gltf_internal.h).
#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "import_gltf_internal.h"

namespace pnb::converter::gltf_internal {

namespace {

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
            // KTX2 says what to do: Debian 12 packages no KTX2/Basis Universal decoder (no
            // libktx, no basisu transcoder library), so the file must be re-exported.
            const bool ktx2 = std::string_view(name) == "KHR_texture_basisu";
            return ctx.fail(strf("%s: texture %d: %s needs %s%s, which is not supported, and the "
                                 "texture has no fallback source image%s",
                                 who.c_str(), info.index, imageWho.c_str(), name,
                                 ktx2 ? " (a KTX2 / Basis Universal image)" : " (a WebP image)",
                                 ktx2 ? "; Penumbra does not decode KTX2 (no decoder is packaged "
                                        "in Debian 12): re-export the model with PNG or JPEG "
                                        "textures, e.g. `gltf-transform ktxdecompress in.glb "
                                        "out.glb`, or add a PNG fallback `source`"
                                      : "; re-export the model with PNG or JPEG textures"),
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

} // namespace

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
    pbr.unlit = extensionObject(src.extensions, "KHR_materials_unlit") != nullptr;

    struct Slot { TextureSlotKind kind; TexInfo info; const char* name; };
    Slot slots[] = {
        {TextureSlotKind::BaseColor, texInfo(mr.baseColorTexture), "baseColorTexture"},
        {TextureSlotKind::MetallicRoughness, texInfo(mr.metallicRoughnessTexture),
         "metallicRoughnessTexture"},
        {TextureSlotKind::Normal, texInfo(src.normalTexture), "normalTexture"},
        {TextureSlotKind::Occlusion, texInfo(src.occlusionTexture), "occlusionTexture"},
        {TextureSlotKind::Emissive, texInfo(src.emissiveTexture), "emissiveTexture"},
    };

    // KHR_materials_pbrSpecularGlossiness (archived): a metallic-roughness fallback in the file
    // is what we use when it is there. Otherwise the spec-gloss factors and textures are kept
    // for material resolve, which converts them with Khronos's published conversion
    // (pnb_converter/spec_gloss.h), per texel where there are textures.
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
            SpecGlossFactors f;
            float v[4];
            if (numbersOf(member(sg, "diffuseFactor"), v, 4))
                f.diffuse = {clampOr(v[0], 0, 1, 1), clampOr(v[1], 0, 1, 1),
                             clampOr(v[2], 0, 1, 1), clampOr(v[3], 0, 1, 1)};
            if (numbersOf(member(sg, "specularFactor"), v, 3))
                f.specular = {clampOr(v[0], 0, 1, 1), clampOr(v[1], 0, 1, 1),
                              clampOr(v[2], 0, 1, 1)};
            f.glossiness = clampOr(numberOf(member(sg, "glossinessFactor")).value_or(1.0), 0, 1, 1);
            out.specGloss = f;
            static const tinygltf::ExtensionMap kNoExtensions;
            auto textureOf = [&](const char* name) -> TexInfo {
                const tinygltf::Value* t = member(sg, name);
                if (!t) return {};
                const tinygltf::Value* ext = member(t, "extensions");
                return {intOf(member(t, "index")).value_or(-1),
                        intOf(member(t, "texCoord")).value_or(0),
                        ext && ext->IsObject() ? &ext->Get<tinygltf::Value::Object>()
                                               : &kNoExtensions};
            };
            slots[0].info = textureOf("diffuseTexture");
            slots[1].info = textureOf("specularGlossinessTexture");
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

} // namespace pnb::converter::gltf_internal
