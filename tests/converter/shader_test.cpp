// Shader library: include resolution, permutation planning, glslang validation.

#include <gtest/gtest.h>

#include <algorithm>

#include "pnb_converter/shader_permutations.h"

namespace {

using namespace pnb;
using namespace pnb::converter;

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
    return n;
}

TEST(ShaderSources, IncludesAreInlinedOnceWithLineDirectives) {
    auto r = resolveShaderSource("forward.frag", builtinShaderFiles());
    ASSERT_TRUE(r.ok()) << r.error().message;
    // Line 2 names the files that the #line directives number, starting with the stage file.
    EXPECT_EQ(r->text.rfind("#version 450 core\n// pnb-files: forward.frag include/", 0), 0u);
    EXPECT_NE(r->text.find("\n#line 2 0\n"), std::string::npos);
    EXPECT_EQ(count(r->text, "#include"), 0u);
    // interface.glsl is reached through material.glsl and lights.glsl: inlined once.
    // (FrameBlock is declared by shared/frame_block.h, for GLSL and C++ alike.)
    EXPECT_EQ(count(r->text, "PNB_UNIFORM_BLOCK(FrameBlock,"), 1u);
    EXPECT_TRUE(std::find(r->files.begin(), r->files.end(), "shared/frame_block.h") != r->files.end());
    EXPECT_TRUE(std::find(r->files.begin(), r->files.end(), "include/brdf.glsl") != r->files.end());
    EXPECT_EQ(r->files[0], "forward.frag");
}

TEST(ShaderSources, MissingFilesAndCyclesAreErrors) {
    std::vector<ShaderFile> lib = {
        {"a.frag", "#version 450 core\n#include \"b.glsl\"\nvoid main() {}\n"},
        {"b.glsl", "#include \"c.glsl\"\n"},
        {"c.glsl", "#include \"b.glsl\"\n"},
        {"d.frag", "#version 450 core\n#include \"nope.glsl\"\n"},
        {"e.frag", "void main() {}\n"},
    };
    // b -> c -> b: "included once" semantics stop the cycle without an error, as include guards
    // would; a missing file and a missing #version are errors.
    EXPECT_TRUE(resolveShaderSource("a.frag", lib).ok());
    auto missing = resolveShaderSource("d.frag", lib);
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("nope.glsl"), std::string::npos);
    EXPECT_NE(missing.error().message.find("d.frag"), std::string::npos);
    EXPECT_FALSE(resolveShaderSource("e.frag", lib).ok());
    EXPECT_FALSE(resolveShaderSource("zzz.frag", lib).ok());
}

Material deferredOpaque() { return Material{}; }
Material forwardBlend() {
    Material m;
    m.shadingPath = ShadingPath::Forward;
    m.alphaMode = AlphaMode::Blend;
    return m;
}

TEST(ShaderPlan, OnlyTheVariantsTheMaterialsUse) {
    MaterialFeatures plain;
    MaterialFeatures textured;
    textured.baseColorMap = textured.uv0 = true;
    MaterialFeatures normalMapped = textured;
    normalMapped.normalMap = true;
    std::vector<Material> materials = {deferredOpaque(), deferredOpaque(), deferredOpaque(),
                                       deferredOpaque()};
    std::vector<MaterialFeatures> features = {plain, textured, textured, plain};
    ShaderPlan plan = planShaders(materials, features, {});
    // gbuffer[], gbuffer[HAS_BASE_COLOR_MAP HAS_UV0], deferred_lighting, tonemap.
    ASSERT_EQ(plan.programs.size(), 4u);
    EXPECT_EQ(plan.materialProgram[0], plan.materialProgram[3]);
    EXPECT_EQ(plan.materialProgram[1], plan.materialProgram[2]);
    EXPECT_NE(plan.materialProgram[0], plan.materialProgram[1]);
    for (const ProgramVariant& v : plan.programs) {
        EXPECT_NE(v.name, "forward") << "no forward material, no forward program";
        EXPECT_NE(v.name, "shadow") << "no shadows requested";
        for (const std::string& d : v.defines) EXPECT_NE(d, "HAS_NORMAL_MAP");
    }

    features[3] = normalMapped;
    materials.push_back(forwardBlend());
    features.push_back(plain);
    plan = planShaders(materials, features, {.shadows = true});
    auto has = [&](const std::string& name, const std::vector<std::string>& defines) {
        return std::any_of(plan.programs.begin(), plan.programs.end(), [&](const ProgramVariant& v) {
            return v.name == name && v.defines == defines;
        });
    };
    EXPECT_TRUE(has("gbuffer", {"HAS_BASE_COLOR_MAP", "HAS_NORMAL_MAP", "HAS_TANGENT", "HAS_UV0"}));
    // With a shadow-casting light, forward receivers and the deferred lighting pass sample the
    // shadow maps themselves (SHADOWS); a forward material that receives none does not.
    EXPECT_TRUE(has("forward", {"SHADOWS"}));
    EXPECT_FALSE(has("forward", {}));
    EXPECT_TRUE(has("deferred_lighting", {"SHADOWS"}));
    EXPECT_TRUE(has("shadow", {}));
    EXPECT_FALSE(has("shadow", {"ALPHA_MASK"})) << "no masked caster";

    materials.back().receivesShadows = false;
    plan = planShaders(materials, features, {.shadows = true});
    EXPECT_TRUE(has("forward", {}));

    std::vector<Material> forwardOnly = {forwardBlend()};
    plan = planShaders(forwardOnly, std::vector<MaterialFeatures>{plain}, {});
    EXPECT_FALSE(has("deferred_lighting", {})) << "no deferred material, no lighting pass";
}

// Issue 43: blended casters get a translucent shadow program, and lighting reads its maps
// (TRANSLUCENT_SHADOWS); without one, neither exists.
TEST(ShaderPlan, TranslucentShadowVariantOnlyWithBlendedCasters) {
    std::vector<Material> materials = {deferredOpaque(), forwardBlend()};
    std::vector<MaterialFeatures> features(2);
    ShaderPlan plan;
    auto has = [&](const std::string& name, const std::vector<std::string>& defines) {
        return std::any_of(plan.programs.begin(), plan.programs.end(), [&](const ProgramVariant& v) {
            return v.name == name && v.defines == defines;
        });
    };
    auto anyDefine = [&](const std::string& define) {
        return std::any_of(plan.programs.begin(), plan.programs.end(), [&](const ProgramVariant& v) {
            return std::find(v.defines.begin(), v.defines.end(), define) != v.defines.end();
        });
    };
    plan = planShaders(materials, features, {.shadows = true});
    EXPECT_FALSE(anyDefine("TRANSLUCENT")) << "no blended caster, no translucent shadow program";
    EXPECT_FALSE(anyDefine("TRANSLUCENT_SHADOWS"));
    plan = planShaders(materials, features, {.shadows = true, .translucentCasters = true});
    EXPECT_TRUE(has("shadow", {}));
    EXPECT_TRUE(has("shadow", {"TRANSLUCENT"}));
    EXPECT_TRUE(has("deferred_lighting", {"SHADOWS", "TRANSLUCENT_SHADOWS"}));
    EXPECT_TRUE(has("forward", {"SHADOWS", "TRANSLUCENT_SHADOWS"}));
    EXPECT_FALSE(has("deferred_lighting", {"SHADOWS"}));
    auto validated = validateShaders(plan, builtinShaderFiles());
    ASSERT_TRUE(validated.ok()) << validated.error().message;
    EXPECT_EQ(*validated, plan.programs.size());
    // A forward material that receives no shadow reads no map at all.
    materials[1].receivesShadows = false;
    plan = planShaders(materials, features, {.shadows = true, .translucentCasters = true});
    EXPECT_TRUE(has("forward", {}));
}

TEST(ShaderPlan, EveryFeatureAloneAndAllTogetherCompileAndLink) {
    std::vector<Material> materials;
    std::vector<MaterialFeatures> features;
    auto addBoth = [&](MaterialFeatures f) {
        materials.push_back(deferredOpaque());
        features.push_back(f);
        materials.push_back(forwardBlend());
        features.push_back(f);
    };
    MaterialFeatures all;
    all.baseColorMap = all.metallicRoughnessMap = all.normalMap = all.occlusionMap =
        all.emissiveMap = all.vertexColor = all.uv0 = all.uv1 = all.alphaMask = true;
    addBoth({});
    addBoth(all);
    bool MaterialFeatures::*flags[] = {
        &MaterialFeatures::baseColorMap, &MaterialFeatures::metallicRoughnessMap,
        &MaterialFeatures::normalMap,    &MaterialFeatures::occlusionMap,
        &MaterialFeatures::emissiveMap,  &MaterialFeatures::vertexColor,
        &MaterialFeatures::uv1,          &MaterialFeatures::alphaMask};
    for (auto flag : flags) {
        MaterialFeatures f;
        f.uv0 = true;
        f.*flag = true;
        addBoth(f);
    }
    ShaderPlan plan = planShaders(materials, features, {.shadows = true, .maskedCasters = true});
    auto validated = validateShaders(plan, builtinShaderFiles());
    ASSERT_TRUE(validated.ok()) << validated.error().message;
    EXPECT_EQ(*validated, plan.programs.size());
    EXPECT_GE(plan.programs.size(), 20u);
}

TEST(ShaderPlan, ABrokenShaderNamesTheVariantFileAndLine) {
    std::vector<ShaderFile> lib(builtinShaderFiles().begin(), builtinShaderFiles().end());
    std::string broken = "#version 450 core\n#include \"include/interface.glsl\"\n"
                         "layout(location = 0) out vec4 outColor;\n"
                         "void main() {\n    outColor = vec4(undefinedThing);\n}\n";
    for (ShaderFile& f : lib)
        if (f.name == "tonemap.frag") f.text = broken;
    ShaderPlan plan = planShaders(std::vector<Material>{}, std::vector<MaterialFeatures>{}, {});
    auto r = validateShaders(plan, lib);
    ASSERT_FALSE(r.ok());
    const std::string& m = r.error().message;
    EXPECT_NE(m.find("tonemap[]"), std::string::npos) << m;
    EXPECT_NE(m.find("tonemap.frag:5"), std::string::npos) << m;
    EXPECT_NE(m.find("undefinedThing"), std::string::npos) << m;
}

} // namespace
