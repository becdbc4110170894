// Which programs the edited materials need, chosen exactly as the converter chooses them
// (converter::planShaders over the same features), matched against the programs the file
// already has; only what is missing is added.
//
// Rules (each keeps a save as small as possible and a converted file unchanged by no-op edits):
//   - A material whose fields equal the file's keeps the file's program, whatever it is.
//   - A changed material gets the converter's variant for its features: the file's own program
//     if that is the variant, else the first file program that is, else a new one.
//   - When blended shadow casters appear or go, every material counts as changed: the lighting
//     programs' TRANSLUCENT_SHADOWS define follows them.
//   - A scene-level program (deferred lighting, shadow, shadow with alpha mask or translucent
//     casters, tonemap) is added only when the edits create the need: if the file's own
//     materials already called for it, the file has it or deliberately lacks it (a hand-built
//     file) and is left alone.
//   - Features that the fields do not show (vertex colours) are the file's (document.cpp).

#include <algorithm>

#include "document_impl.h"

namespace pnb::editor {

using converter::MaterialFeatures;
using converter::ProgramVariant;

namespace {

constexpr const char* kSlotFields[] = {"base_color_texture", "metallic_roughness_texture",
                                       "normal_texture", "occlusion_texture", "emissive_texture"};

bool sameVariant(const ProgramVariant& a, const ProgramVariant& b) {
    return a.name == b.name && a.defines == b.defines && a.stageFiles == b.stageFiles;
}

// Streams a material's texture slots read: TexCoord0/1 per slot, Tangent for a normal map.
struct StreamUse {
    VertexSemantic semantic;
    size_t slot; // the first slot that needs it, for the message
};

std::vector<StreamUse> streamsRead(const Material& m) {
    std::vector<StreamUse> uses;
    auto add = [&](VertexSemantic s, size_t slot) {
        for (const StreamUse& u : uses)
            if (u.semantic == s) return;
        uses.push_back({s, slot});
    };
    for (size_t slot = 0; slot < m.textures.size(); ++slot) {
        const TextureSlot& t = m.textures[slot];
        if (t.texture == kNone) continue;
        add(t.texCoord == 1 ? VertexSemantic::TexCoord1 : VertexSemantic::TexCoord0, slot);
        if (slot == size_t(TextureSlotKind::Normal)) add(VertexSemantic::Tangent, slot);
    }
    return uses;
}

Error convertError(const converter::ConvertError& e) {
    return makeError(FormatError::BadReference, 0, "%s", e.message.c_str());
}

} // namespace

std::vector<MaterialFeatures> Document::Impl::featuresOf(
    const std::vector<Material>& materials) const {
    std::vector<MaterialFeatures> features(materials.size());
    for (size_t i = 0; i < materials.size(); ++i) {
        const Material& m = materials[i];
        MaterialFeatures& f = features[i];
        auto has = [&](TextureSlotKind k) { return m.textures[size_t(k)].texture != kNone; };
        f.baseColorMap = has(TextureSlotKind::BaseColor);
        f.metallicRoughnessMap = has(TextureSlotKind::MetallicRoughness);
        f.normalMap = has(TextureSlotKind::Normal);
        f.occlusionMap = has(TextureSlotKind::Occlusion);
        f.emissiveMap = has(TextureSlotKind::Emissive);
        for (const TextureSlot& t : m.textures)
            if (t.texture != kNone) (t.texCoord == 1 ? f.uv1 : f.uv0) = true;
        f.alphaMask = m.alphaMode == AlphaMode::Mask;
        f.vertexColor = i < base.vertexColor.size() && base.vertexColor[i];
    }
    return features;
}

converter::SceneShaderNeeds Document::Impl::sceneNeeds(
    const std::vector<Material>& materials) const {
    // As convert.cpp: any light that casts shadows (the sun, or a point or spot light).
    bool shadowLight = false;
    for (const Light& l : scene.lights.lights) shadowLight |= l.castsShadows;
    converter::SceneShaderNeeds needs;
    for (const Material& m : materials) {
        needs.shadows |= shadowLight && m.castsShadows;
        needs.maskedCasters |= shadowLight && m.castsShadows && m.alphaMode == AlphaMode::Mask;
        needs.translucentCasters |= shadowLight && m.castsShadows && m.alphaMode == AlphaMode::Blend;
    }
    for (const Setting& s : scene.settings.entries)
        if (scene.str(s.key) == "gi.enabled" && scene.str(s.value) == "true") needs.gi = true;
    needs.ibl = scene.environment.has_value(); // as convert.cpp: lighting with IBL iff an ENVM
    return needs;
}

std::vector<ProgramVariant> Document::Impl::sceneLevelVariants(
    const std::vector<Material>& materials) const {
    auto features = featuresOf(materials);
    converter::ShaderPlan plan = converter::planShaders(materials, features, sceneNeeds(materials));
    std::vector<ProgramVariant> out;
    for (uint32_t p = 0; p < plan.programs.size(); ++p)
        if (std::find(plan.materialProgram.begin(), plan.materialProgram.end(), p) ==
            plan.materialProgram.end())
            out.push_back(plan.programs[p]);
    return out;
}

Status Document::Impl::checkStreams(const std::vector<Material>& materials) const {
    for (uint32_t i = 0; i < materials.size(); ++i) {
        if (detail::sameExceptProgram(materials[i], base.materials[i])) continue;
        // Only what the edit adds: a file that already reads a missing stream is left as it is.
        auto before = streamsRead(base.materials[i]);
        for (const StreamUse& use : streamsRead(materials[i])) {
            bool old = std::any_of(before.begin(), before.end(),
                                   [&](const StreamUse& u) { return u.semantic == use.semantic; });
            if (old) continue;
            for (uint32_t meshIndex : base.meshesOf[i]) {
                const Mesh& mesh = scene.meshes[meshIndex];
                bool present = std::any_of(mesh.streams.begin(), mesh.streams.end(),
                                           [&](const VertexStream& s) {
                                               return s.semantic == use.semantic;
                                           });
                if (present) continue;
                std::string meshName(scene.str(mesh.name));
                if (use.semantic == VertexSemantic::Tangent)
                    return makeError(
                        FormatError::BadReference, 0,
                        "material %s: %s needs tangents, but mesh '%s' (which draws it) has no "
                        "tangent stream; the converter writes tangents only for normal-mapped "
                        "materials: give the material a normal map in the source and reconvert",
                        materialLabel(i).c_str(), kSlotFields[use.slot], meshName.c_str());
                return makeError(
                    FormatError::BadReference, 0,
                    "material %s: %s reads TEXCOORD_%d, but mesh '%s' (which draws it) has no "
                    "such stream; the converter keeps texture coordinates only where a material "
                    "samples a texture: give the material a texture in the source and reconvert",
                    materialLabel(i).c_str(), kSlotFields[use.slot],
                    use.semantic == VertexSemantic::TexCoord1 ? 1 : 0, meshName.c_str());
            }
        }
    }
    return {};
}

Result<const detail::ResolvedStage*> Document::Impl::resolveStage(const std::string& file,
                                                                  ShaderStage stage) {
    auto it = stages.find(file);
    if (it == stages.end()) {
        auto resolved = converter::resolveShaderSource(file, converter::builtinShaderFiles());
        if (!resolved) return convertError(resolved.error());
        it = stages.emplace(file, detail::ResolvedStage{stage, std::move(resolved->text)}).first;
    }
    return &it->second;
}

Result<detail::ProgramPlan> Document::Impl::planPrograms(const std::vector<Material>& materials) {
    auto features = featuresOf(materials);
    converter::ShaderPlan plan = converter::planShaders(materials, features, sceneNeeds(materials));

    // A file program matches a variant when its name, sorted defines and stage files agree.
    auto matches = [&](uint32_t q, const ProgramVariant& v) {
        const Program& p = scene.programs[q];
        if (scene.str(p.name) != v.name || p.shaders.size() != v.stageFiles.size()) return false;
        for (size_t k = 0; k < p.shaders.size(); ++k) {
            const ShaderSource& sh = scene.shaders[p.shaders[k]];
            if (scene.str(sh.name) != v.stageFiles[k] || sh.stage != v.stages[k]) return false;
        }
        std::vector<std::string> defines;
        for (StringRef d : p.defines) defines.emplace_back(scene.str(d));
        std::sort(defines.begin(), defines.end());
        return defines == v.defines;
    };

    detail::ProgramPlan out;
    std::vector<uint32_t> resolved(plan.programs.size(), kNone);
    auto resolve = [&](uint32_t p) -> Status {
        if (resolved[p] != kNone) return {};
        const ProgramVariant& v = plan.programs[p];
        for (uint32_t q = 0; q < base.programs; ++q)
            if (matches(q, v)) {
                resolved[p] = q;
                return {};
            }
        // New: checked with glslang once per document, as the converter checks what it packs.
        std::string key = converter::describeVariant(v);
        for (const std::string& f : v.stageFiles) key += " " + f;
        if (!validated.count(key)) {
            converter::ShaderPlan one;
            one.programs.push_back(v);
            auto ok = converter::validateShaders(one, converter::builtinShaderFiles());
            if (!ok) return convertError(ok.error());
            validated[key] = true;
        }
        detail::AddedProgram added{v, {}};
        for (size_t k = 0; k < v.stageFiles.size(); ++k) {
            uint32_t index = kNone;
            for (uint32_t s = 0; s < base.shaders && index == kNone; ++s)
                if (scene.str(scene.shaders[s].name) == v.stageFiles[k] &&
                    scene.shaders[s].stage == v.stages[k])
                    index = s;
            for (uint32_t s = 0; s < out.addedShaders.size() && index == kNone; ++s)
                if (out.addedShaders[s] == v.stageFiles[k]) index = uint32_t(base.shaders + s);
            if (index == kNone) {
                auto stage = resolveStage(v.stageFiles[k], v.stages[k]);
                if (!stage) return stage.error();
                index = uint32_t(base.shaders + out.addedShaders.size());
                out.addedShaders.push_back(v.stageFiles[k]);
            }
            added.shaders.push_back(index);
        }
        resolved[p] = uint32_t(base.programs + out.addedPrograms.size());
        out.addedPrograms.push_back(std::move(added));
        return {};
    };

    // In plan order, so additions come in the converter's order: surface programs of changed
    // materials (by first use), then the scene-level programs the edits call for.
    // Blended casters appearing or going (casts_shadows on a BLEND material) change every
    // lighting program's defines (TRANSLUCENT_SHADOWS): each material then takes the converter's
    // variant again, as a changed one does (its own program is kept where it still matches).
    const bool translucentChanged =
        sceneNeeds(materials).translucentCasters != sceneNeeds(base.materials).translucentCasters;
    std::vector<bool> changed(materials.size());
    for (size_t i = 0; i < materials.size(); ++i)
        changed[i] = translucentChanged || !detail::sameExceptProgram(materials[i], base.materials[i]);
    for (uint32_t p = 0; p < plan.programs.size(); ++p) {
        bool surface = false, wanted = false;
        for (size_t i = 0; i < materials.size(); ++i) {
            if (plan.materialProgram[i] != p) continue;
            surface = true;
            const uint32_t own = base.materials[i].program;
            bool ownMatches = own != kNone && own < base.programs && matches(own, plan.programs[p]);
            wanted |= changed[i] && !ownMatches;
        }
        if (!surface)
            wanted = std::none_of(base.sceneLevelBefore.begin(), base.sceneLevelBefore.end(),
                                  [&](const ProgramVariant& v) {
                                      return sameVariant(v, plan.programs[p]);
                                  });
        if (wanted)
            if (Status s = resolve(p); !isOk(s)) return s;
    }
    out.materialProgram.resize(materials.size());
    for (size_t i = 0; i < materials.size(); ++i) {
        const uint32_t own = base.materials[i].program;
        const uint32_t p = plan.materialProgram[i];
        if (!changed[i] || (own != kNone && own < base.programs && matches(own, plan.programs[p])))
            out.materialProgram[i] = own;
        else
            out.materialProgram[i] = resolved[p];
    }
    return out;
}

} // namespace pnb::editor
