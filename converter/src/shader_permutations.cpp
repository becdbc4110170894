// Program selection: one variant per distinct feature combination, plus the scene-level
// programs something in the scene uses.

#include <algorithm>
#include <map>

#include "pnb_converter/shader_permutations.h"

namespace pnb::converter {

namespace {

ProgramVariant variant(std::string name, std::vector<std::string> files,
                       std::vector<std::string> defines) {
    ProgramVariant v;
    v.name = std::move(name);
    auto endsWith = [](const std::string& f, const char* ext) {
        const size_t n = std::char_traits<char>::length(ext);
        return f.size() > n && f.compare(f.size() - n, n, ext) == 0;
    };
    for (const std::string& f : files)
        v.stages.push_back(endsWith(f, ".vert")   ? ShaderStage::Vertex
                           : endsWith(f, ".comp") ? ShaderStage::Compute
                                                  : ShaderStage::Fragment);
    v.stageFiles = std::move(files);
    std::sort(defines.begin(), defines.end());
    v.defines = std::move(defines);
    return v;
}

std::vector<std::string> surfaceDefines(const MaterialFeatures& f) {
    std::vector<std::string> d;
    if (f.baseColorMap) d.push_back("HAS_BASE_COLOR_MAP");
    if (f.metallicRoughnessMap) d.push_back("HAS_METALLIC_ROUGHNESS_MAP");
    if (f.normalMap) d.push_back("HAS_NORMAL_MAP");
    if (f.normalMap) d.push_back("HAS_TANGENT");
    if (f.occlusionMap) d.push_back("HAS_OCCLUSION_MAP");
    if (f.emissiveMap) d.push_back("HAS_EMISSIVE_MAP");
    if (f.vertexColor) d.push_back("HAS_VERTEX_COLOR");
    if (f.uv0) d.push_back("HAS_UV0");
    if (f.uv1) d.push_back("HAS_UV1");
    if (f.alphaMask) d.push_back("ALPHA_MASK");
    return d;
}

} // namespace

Result<bool, ConvertError> appendShaderPrograms(const ShaderPlan& plan, std::span<const ShaderFile> library,
                                                SceneBuilder& b) {
    std::vector<std::string> stageFiles;
    for (const ProgramVariant& v : plan.programs)
        for (size_t k = 0; k < v.stageFiles.size(); ++k)
            if (std::find(stageFiles.begin(), stageFiles.end(), v.stageFiles[k]) == stageFiles.end()) {
                stageFiles.push_back(v.stageFiles[k]);
                auto resolved = resolveShaderSource(v.stageFiles[k], library);
                if (!resolved) return resolved.error();
                b.scene.shaders.push_back({b.intern(v.stageFiles[k]), v.stages[k], b.keep(resolved->text)});
            }
    for (const ProgramVariant& v : plan.programs) {
        Program p;
        p.name = b.intern(v.name);
        for (const std::string& f : v.stageFiles)
            p.shaders.push_back(uint32_t(std::find(stageFiles.begin(), stageFiles.end(), f) - stageFiles.begin()));
        for (const std::string& d : v.defines) p.defines.push_back(b.intern(d));
        b.scene.programs.push_back(p);
    }
    return true;
}

ShaderPlan planShaders(std::span<const Material> materials,
                       std::span<const MaterialFeatures> features, const SceneShaderNeeds& needs) {
    ShaderPlan plan;
    std::map<std::pair<std::string, std::vector<std::string>>, uint32_t> index;
    auto add = [&](ProgramVariant v) {
        auto key = std::make_pair(v.name, v.defines);
        auto it = index.find(key);
        if (it != index.end()) return it->second;
        uint32_t i = uint32_t(plan.programs.size());
        plan.programs.push_back(std::move(v));
        index.emplace(key, i);
        return i;
    };
    bool anyDeferred = false;
    for (size_t i = 0; i < materials.size(); ++i) {
        bool deferred = materials[i].shadingPath == ShadingPath::Deferred;
        anyDeferred |= deferred;
        std::vector<std::string> defines = surfaceDefines(features[i]);
        // Forward shading samples the shadow maps itself; deferred receivers get them in the
        // lighting pass.
        // With GI the reflective shadow map draws every opaque or masked surface with the
        // G-buffer program of its features: forward materials get one too.
        if (!deferred && needs.gi && materials[i].alphaMode != AlphaMode::Blend)
            add(variant("gbuffer", {"surface.vert", "gbuffer.frag"}, defines));
        if (!deferred && needs.shadows && materials[i].receivesShadows) {
            defines.push_back("SHADOWS");
            if (needs.translucentCasters) defines.push_back("TRANSLUCENT_SHADOWS");
        }
        if (!deferred && needs.gi) defines.push_back("GI");
        // Image-based lighting is a lighting term: the forward program and deferred lighting
        // get it; G-buffer programs (the deferred ones and the GI twin above, which FORMAT.md
        // "PROG" defines as the forward program's defines without SHADOWS, GI and IBL) do not.
        if (!deferred && needs.ibl) defines.push_back("IBL");
        plan.materialProgram.push_back(
            add(deferred ? variant("gbuffer", {"surface.vert", "gbuffer.frag"}, std::move(defines))
                         : variant("forward", {"surface.vert", "forward.frag"}, std::move(defines))));
    }
    if (anyDeferred) {
        std::vector<std::string> defines;
        if (needs.shadows) defines.push_back("SHADOWS");
        if (needs.shadows && needs.translucentCasters) defines.push_back("TRANSLUCENT_SHADOWS");
        if (needs.gi) defines.push_back("GI");
        if (needs.ibl) defines.push_back("IBL");
        add(variant("deferred_lighting", {"fullscreen.vert", "deferred_lighting.frag"}, std::move(defines)));
    }
    if (needs.shadows) {
        add(variant("shadow", {"shadow.vert", "shadow.frag"}, {}));
        if (needs.maskedCasters)
            add(variant("shadow", {"shadow.vert", "shadow.frag"}, {"ALPHA_MASK"}));
        // Blended casters: their transmittance into the maps' colour companions.
        if (needs.translucentCasters)
            add(variant("shadow", {"shadow.vert", "shadow.frag"}, {"TRANSLUCENT"}));
    }
    // GI's own passes (RSM injection, propagation) are the player's compute shaders: they do not
    // depend on the scene's materials, so they are not scene content.
    add(variant("tonemap", {"fullscreen.vert", "tonemap.frag"}, {}));
    // The deforming pre-pass, only in a scene that deforms something: SKIN with a skinned node,
    // MORPH with morph targets (a static scene's programs are what they were without it).
    if (needs.skins || needs.morphs) {
        std::vector<std::string> defines;
        if (needs.morphs) defines.push_back("MORPH");
        if (needs.skins) defines.push_back("SKIN");
        add(variant("deform", {"deform.comp"}, std::move(defines)));
    }
    return plan;
}

std::string describeVariant(const ProgramVariant& v) {
    std::string s = v.name + "[";
    for (size_t i = 0; i < v.defines.size(); ++i) s += (i ? " " : "") + v.defines[i];
    return s + "]";
}

} // namespace pnb::converter
