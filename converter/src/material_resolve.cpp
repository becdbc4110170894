// Material resolve: placement, sidecar overrides, texture requests, features, stream needs.

#include "pnb_converter/material_resolve.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <tuple>
#include <sstream>

#include <nlohmann/json.hpp>

#include "pnb/material_fields.h"

namespace pnb::converter {

namespace {

ConvertError inputError(std::string message) {
    return ConvertError{ConvertErrorKind::Input, std::move(message)};
}

// JSON scalar or number array → the text form setMaterialField parses.
// ordered_json keeps the file's key order, which is the documented rule order.
using Json = nlohmann::ordered_json;

bool valueText(const Json& v, std::string& out) {
    if (v.is_string()) {
        out = v.get<std::string>();
    } else if (v.is_boolean()) {
        out = v.get<bool>() ? "true" : "false";
    } else if (v.is_number()) {
        std::ostringstream s;
        s.precision(9);
        s << v.get<double>();
        out = s.str();
    } else if (v.is_array() && !v.empty()) {
        out.clear();
        for (const auto& e : v) {
            if (!e.is_number()) return false;
            std::ostringstream s;
            s.precision(9);
            s << e.get<double>();
            out += (out.empty() ? "" : ",") + s.str();
        }
    } else {
        return false;
    }
    return true;
}

bool isTextureField(const std::string& field) {
    return field.size() > 8 && field.compare(field.size() - 8, 8, "_texture") == 0;
}

ColorSpace colorSpaceOf(TextureSlotKind k) {
    return k == TextureSlotKind::BaseColor || k == TextureSlotKind::Emissive ? ColorSpace::Srgb
                                                                             : ColorSpace::Linear;
}

} // namespace

Result<MaterialOverrides, ConvertError> loadSidecar(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return inputError(path + ": cannot open the sidecar file");
    Json doc = Json::parse(in, nullptr, false);
    if (doc.is_discarded())
        return inputError(path + ": not valid JSON (expected { \"materials\": { ... } })");
    MaterialOverrides o;
    o.sourcePath = path;
    if (!doc.is_object()) return inputError(path + ": the top level must be an object");
    for (const auto& item : doc.items())
        if (item.key() != "materials" && item.key() != "environment")
            return inputError(path + ": unknown key '" + item.key() + "' (only \"materials\", \"environment\")");
    if (doc.contains("environment")) {
        const Json& e = doc["environment"];
        if (!e.is_object()) return inputError(path + ": \"environment\" must be an object");
        SidecarEnvironment env;
        for (const auto& [key, value] : e.items()) {
            if (key == "image" && value.is_string() && !value.get<std::string>().empty()) {
                std::filesystem::path image(value.get<std::string>());
                env.image = (image.is_absolute() ? image : std::filesystem::path(path).parent_path() / image).string();
            } else if (key == "sky" && value.is_boolean()) {
                env.sky = value.get<bool>();
            } else if ((key == "turbidity" || key == "ground_albedo") && value.is_number()) {
                float v = value.get<float>();
                if (!std::isfinite(v) || v < 0 || (key == "ground_albedo" && v > 1))
                    return inputError(path + ": environment." + key + ": out of range");
                (key == "turbidity" ? env.turbidity : env.groundAlbedo) = v;
            } else {
                return inputError(path + ": environment." + key +
                                  ": unknown key or wrong type (image: a path, sky: a boolean, "
                                  "turbidity, ground_albedo: numbers)");
            }
        }
        if (env.sky && !env.image.empty())
            return inputError(path + ": environment: both an image and the sky; choose one");
        o.environment = std::move(env);
    }
    if (!doc.contains("materials")) return o;
    if (!doc["materials"].is_object())
        return inputError(path + ": \"materials\" must be an object of pattern: fields");
    for (const auto& [pattern, fields] : doc["materials"].items()) {
        if (!fields.is_object())
            return inputError(path + ": materials['" + pattern + "'] must be an object of fields");
        MaterialOverride rule{pattern, {}};
        for (const auto& [field, value] : fields.items()) {
            if (isTextureField(field))
                return inputError(path + ": materials['" + pattern + "']." + field +
                                  ": texture slots cannot be overridden in a sidecar");
            std::string text;
            if (!valueText(value, text))
                return inputError(path + ": materials['" + pattern + "']." + field +
                                  ": value must be a string, number, boolean or number array");
            Material probe;
            if (Status s = setMaterialField(probe, field, text); !isOk(s))
                return inputError(path + ": materials['" + pattern + "']: " + s.message);
            rule.fields.emplace_back(field, text);
        }
        o.rules.push_back(std::move(rule));
    }
    return o;
}

namespace {

// A KHR_materials_pbrSpecularGlossiness material's metallic-roughness factors, before sidecar
// overrides apply to them: converted once when it has no texture, 1 when the conversion runs per
// texel (resolveSpecGlossTextures).
void specGlossFactors(const IrMaterial& source, Material& m) {
    const SpecGlossFactors& k = *source.specGloss;
    if (source.textures[size_t(TextureSlotKind::BaseColor)].image < 0 &&
        source.textures[size_t(TextureSlotKind::MetallicRoughness)].image < 0) {
        const MetalRough c = specGlossToMetalRough(k.diffuse, k.specular, k.glossiness);
        m.baseColorFactor = c.baseColor;
        m.metallicFactor = c.metallic;
        m.roughnessFactor = c.roughness;
    } else {
        m.baseColorFactor = {1, 1, 1, 1};
        m.metallicFactor = m.roughnessFactor = 1;
    }
}

// Its textures: with a diffuse or specular-glossiness texture the conversion runs per texel
// (TextureRequest::specGloss) into a base colour and a metallic-roughness texture of this
// material's own.
std::optional<ConvertError> resolveSpecGlossTextures(const IrScene& scene, const IrMaterial& source,
                                                     const std::string& name, Material& m,
                                                     MaterialFeatures& f, ResolvedMaterials& r) {
    const SpecGlossFactors& k = *source.specGloss;
    const IrTextureRef& diffuse = source.textures[size_t(TextureSlotKind::BaseColor)];
    const IrTextureRef& specular = source.textures[size_t(TextureSlotKind::MetallicRoughness)];
    m.textures[size_t(TextureSlotKind::BaseColor)] = TextureSlot{};
    m.textures[size_t(TextureSlotKind::MetallicRoughness)] = TextureSlot{};
    for (const IrTextureRef* ref : {&diffuse, &specular})
        if (ref->image >= 0 && size_t(ref->image) >= scene.images.size())
            return inputError(scene.sourcePath + ": material '" + name + "' refers to image " +
                              std::to_string(ref->image) + " of " +
                              std::to_string(scene.images.size()));
    if (diffuse.image < 0 && specular.image < 0) return std::nullopt;
    // The texels are converted on the grid of one texture: both must be read alike.
    const IrTextureRef& grid = diffuse.image >= 0 ? diffuse : specular;
    if (diffuse.image >= 0 && specular.image >= 0 &&
        (diffuse.texCoord != specular.texCoord || diffuse.offset.x != specular.offset.x ||
         diffuse.offset.y != specular.offset.y || diffuse.scale.x != specular.scale.x ||
         diffuse.scale.y != specular.scale.y || diffuse.rotationRadians != specular.rotationRadians))
        r.warnings.push_back("material '" + name + "': KHR_materials_pbrSpecularGlossiness's "
                             "two textures use different UV sets or transforms; converted on "
                             "the diffuse texture's");
    for (bool toMetallicRoughness : {false, true}) {
        TextureRequest req;
        req.image = diffuse.image >= 0 ? &scene.images[size_t(diffuse.image)] : nullptr;
        req.specGloss = TextureRequest::SpecGlossBake{
            specular.image >= 0 ? &scene.images[size_t(specular.image)] : nullptr, k,
            toMetallicRoughness};
        if (!req.image) req.image = req.specGloss->specularGlossiness;
        req.name = name + (toMetallicRoughness ? "-metallicRoughness" : "-baseColor");
        req.colorSpace = toMetallicRoughness ? ColorSpace::Linear : ColorSpace::Srgb;
        for (bool& c : req.channels) c = false;
        if (toMetallicRoughness) {
            req.channels[1] = req.channels[2] = true;
        } else {
            req.channels[0] = req.channels[1] = req.channels[2] = true;
            req.channels[3] = m.alphaMode != AlphaMode::Opaque;
            req.alphaMask = m.alphaMode == AlphaMode::Mask;
            req.alphaCutoff = m.alphaCutoff;
        }
        req.minFilter = grid.minFilter;
        req.magFilter = grid.magFilter;
        req.wrapU = grid.wrapU;
        req.wrapV = grid.wrapV;
        TextureSlot& out = m.textures[size_t(toMetallicRoughness ? TextureSlotKind::MetallicRoughness
                                                                 : TextureSlotKind::BaseColor)];
        out.texture = uint32_t(r.textures.size());
        out.texCoord = grid.texCoord > 1 ? 0 : grid.texCoord;
        out.offset = grid.offset;
        out.scale = grid.scale;
        out.rotationRadians = grid.rotationRadians;
        (out.texCoord == 0 ? f.uv0 : f.uv1) = true;
        r.textures.push_back(std::move(req));
    }
    f.baseColorMap = f.metallicRoughnessMap = true;
    return std::nullopt;
}

} // namespace

Result<ResolvedMaterials, ConvertError> resolveMaterials(const IrScene& scene,
                                                         const MaterialOverrides& overrides) {
    ResolvedMaterials r;
    std::vector<const IrMaterial*> sources;
    for (const IrMaterial& m : scene.materials) sources.push_back(&m);
    static const IrMaterial kDefault = [] {
        IrMaterial m;
        m.name = "default"; // glTF's default material: white, metallic 1, roughness 1
        return m;
    }();
    bool needsDefault = false;
    for (const IrMesh& mesh : scene.meshes)
        for (const IrPrimitive& p : mesh.primitives) needsDefault |= p.material < 0;
    if (needsDefault) {
        r.defaultMaterial = int(sources.size());
        sources.push_back(&kDefault);
    }

    // Placement, then overrides (which may change the alpha mode, so features come after).
    std::vector<bool> ruleMatched(overrides.rules.size(), false);
    for (size_t i = 0; i < sources.size(); ++i) {
        Material m = sources[i]->pbr;
        if (sources[i]->specGloss) specGlossFactors(*sources[i], m);
        m.name = kNone;
        m.program = kNone;
        m.shadingPath = m.alphaMode == AlphaMode::Blend ? ShadingPath::Forward : ShadingPath::Deferred;
        m.layerPriority = 0;
        for (size_t k = 0; k < overrides.rules.size(); ++k) {
            const MaterialOverride& rule = overrides.rules[k];
            if (!globMatch(rule.pattern, sources[i]->name)) continue;
            ruleMatched[k] = true;
            for (const auto& [field, value] : rule.fields)
                if (Status s = setMaterialField(m, field, value); !isOk(s))
                    return inputError(overrides.sourcePath + ": " + s.message);
        }
        r.materials.push_back(m);
        r.names.push_back(sources[i]->name.empty() ? "material" + std::to_string(i)
                                                   : sources[i]->name);
    }
    for (size_t k = 0; k < overrides.rules.size(); ++k)
        if (!ruleMatched[k])
            r.warnings.push_back(overrides.sourcePath + ": pattern '" + overrides.rules[k].pattern +
                                 "' matches no material");

    // Vertex colours: a material shows them if any primitive drawn with it has COLOR_0.
    r.features.resize(sources.size());
    for (const IrMesh& mesh : scene.meshes)
        for (const IrPrimitive& p : mesh.primitives)
            if (!p.colors.empty()) r.features[materialForPrimitive(r, p.material)].vertexColor = true;

    // Textures: one request per (image, colour space, sampler); channels are the union of the
    // slots'. The sampler is part of the key because the container keeps it on the texture
    // (TEXR): glTF textures that share an image but not a sampler (clamp here, repeat there)
    // must stay apart, at the price of storing that image's texels once per sampler.
    using TextureKey = std::tuple<int, ColorSpace, MinFilter, MagFilter, Wrap, Wrap>;
    std::map<TextureKey, uint32_t> textureIndex;
    for (size_t i = 0; i < sources.size(); ++i) {
        Material& m = r.materials[i];
        MaterialFeatures& f = r.features[i];
        f.alphaMask = m.alphaMode == AlphaMode::Mask;
        if (sources[i]->specGloss) {
            if (auto e = resolveSpecGlossTextures(scene, *sources[i], r.names[i], m, f, r)) return *e;
        }
        for (size_t slot = 0; slot < size_t(TextureSlotKind::Count); ++slot) {
            const IrTextureRef& ref = sources[i]->textures[slot];
            TextureSlot& out = m.textures[slot];
            if (sources[i]->specGloss && (TextureSlotKind(slot) == TextureSlotKind::BaseColor ||
                                          TextureSlotKind(slot) == TextureSlotKind::MetallicRoughness))
                continue; // converted above
            out = TextureSlot{};
            if (ref.image < 0) continue;
            if (size_t(ref.image) >= scene.images.size())
                return inputError(scene.sourcePath + ": material '" + r.names[i] +
                                  "' refers to image " + std::to_string(ref.image) + " of " +
                                  std::to_string(scene.images.size()));
            auto kind = TextureSlotKind(slot);
            const TextureKey key{ref.image, colorSpaceOf(kind), ref.minFilter, ref.magFilter,
                                 ref.wrapU, ref.wrapV};
            auto [it, added] = textureIndex.emplace(key, uint32_t(r.textures.size()));
            if (added) {
                TextureRequest req;
                req.image = &scene.images[size_t(ref.image)];
                req.name = req.image->name.empty() ? "image" + std::to_string(ref.image)
                                                   : req.image->name;
                req.colorSpace = std::get<1>(key);
                for (bool& c : req.channels) c = false;
                req.minFilter = ref.minFilter;
                req.magFilter = ref.magFilter;
                req.wrapU = ref.wrapU;
                req.wrapV = ref.wrapV;
                r.textures.push_back(req);
            }
            TextureRequest& req = r.textures[it->second];
            switch (kind) {
            case TextureSlotKind::BaseColor:
                req.channels[0] = req.channels[1] = req.channels[2] = true;
                if (m.alphaMode != AlphaMode::Opaque) req.channels[3] = true;
                if (m.alphaMode == AlphaMode::Mask) {
                    req.alphaMask = true;
                    req.alphaCutoff = m.alphaCutoff;
                }
                f.baseColorMap = true;
                break;
            case TextureSlotKind::MetallicRoughness:
                req.channels[1] = req.channels[2] = true; // glTF: G roughness, B metallic
                f.metallicRoughnessMap = true;
                break;
            case TextureSlotKind::Normal:
                req.channels[0] = req.channels[1] = req.channels[2] = true;
                f.normalMap = true;
                break;
            case TextureSlotKind::Occlusion:
                req.channels[0] = true;
                f.occlusionMap = true;
                break;
            case TextureSlotKind::Emissive:
                req.channels[0] = req.channels[1] = req.channels[2] = true;
                f.emissiveMap = true;
                break;
            case TextureSlotKind::Count: break;
            }
            out.texture = it->second;
            out.texCoord = ref.texCoord > 1 ? 0 : ref.texCoord;
            if (ref.texCoord > 1)
                r.warnings.push_back("material '" + r.names[i] + "': TEXCOORD_" +
                                     std::to_string(ref.texCoord) + " is not supported; using 0");
            out.offset = ref.offset;
            out.scale = ref.scale;
            out.rotationRadians = ref.rotationRadians;
            (out.texCoord == 0 ? f.uv0 : f.uv1) = true;
        }
    }

    // Streams a mesh keeps: the union of what its primitives' materials read.
    for (const IrMesh& mesh : scene.meshes) {
        StreamNeeds needs;
        for (const IrPrimitive& p : mesh.primitives) {
            const MaterialFeatures& f = r.features[materialForPrimitive(r, p.material)];
            needs.uv0 |= f.uv0;
            needs.uv1 |= f.uv1;
            needs.tangents |= f.normalMap;
            needs.colors |= f.vertexColor;
        }
        r.meshNeeds.push_back(needs);
    }
    return r;
}

} // namespace pnb::converter
