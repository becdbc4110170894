// Material resolve: default placement, sidecar overrides, texture grouping, stream needs.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "pnb_converter/material_resolve.h"
#include "pnb_converter/spec_gloss.h"

namespace {

using namespace pnb;
using namespace pnb::converter;
namespace fs = std::filesystem;

IrScene twoMaterialScene() {
    IrScene s;
    s.sourcePath = "test.gltf";
    s.images.push_back({"albedo", "albedo.png", {}, "image/png"});
    s.images.push_back({"orm", "orm.png", {}, "image/png"});
    IrMaterial wall;
    wall.name = "brick-wall";
    wall.textures[size_t(TextureSlotKind::BaseColor)].image = 0;
    wall.textures[size_t(TextureSlotKind::Normal)].image = 1;
    IrMaterial glass;
    glass.name = "glass-window";
    glass.pbr.alphaMode = AlphaMode::Blend;
    glass.pbr.baseColorFactor = {0.5f, 0.6f, 0.9f, 0.3f};
    // ORM-packed: occlusion (R) and metallic-roughness (G, B) share one image.
    glass.textures[size_t(TextureSlotKind::Occlusion)].image = 1;
    glass.textures[size_t(TextureSlotKind::MetallicRoughness)].image = 1;
    glass.textures[size_t(TextureSlotKind::MetallicRoughness)].texCoord = 1;
    s.materials = {wall, glass};
    IrMesh a, b;
    a.name = "walls";
    a.primitives.push_back(IrPrimitive{.positions = {0, 0, 0}, .material = 0});
    b.name = "windows";
    b.primitives.push_back(IrPrimitive{.positions = {0, 0, 0}, .colors = {1, 1, 1, 1}, .material = 1});
    b.primitives.push_back(IrPrimitive{.positions = {0, 0, 0}, .material = -1});
    s.meshes = {a, b};
    return s;
}

TEST(MaterialResolve, DefaultPlacementTexturesFeaturesAndNeeds) {
    IrScene scene = twoMaterialScene();
    auto r = resolveMaterials(scene, {});
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->materials.size(), 3u) << "two + the default for the material-less primitive";
    EXPECT_EQ(r->defaultMaterial, 2);
    EXPECT_EQ(r->names[2], "default");
    EXPECT_EQ(r->materials[0].shadingPath, ShadingPath::Deferred);
    EXPECT_EQ(r->materials[1].shadingPath, ShadingPath::Forward) << "BLEND goes forward";

    // albedo (sRGB); orm used as a normal map (linear) and as ORM (linear): one linear texture.
    ASSERT_EQ(r->textures.size(), 2u);
    EXPECT_EQ(r->textures[0].colorSpace, ColorSpace::Srgb);
    EXPECT_FALSE(r->textures[0].channels[3]) << "opaque material: alpha not read";
    EXPECT_EQ(r->textures[1].colorSpace, ColorSpace::Linear);
    EXPECT_TRUE(r->textures[1].channels[0] && r->textures[1].channels[1] && r->textures[1].channels[2]);
    EXPECT_EQ(r->materials[1].textures[size_t(TextureSlotKind::Occlusion)].texture, 1u);
    EXPECT_EQ(r->materials[1].textures[size_t(TextureSlotKind::MetallicRoughness)].texture, 1u);

    EXPECT_TRUE(r->features[0].baseColorMap && r->features[0].normalMap && r->features[0].uv0);
    EXPECT_FALSE(r->features[0].vertexColor);
    EXPECT_TRUE(r->features[1].vertexColor);
    EXPECT_TRUE(r->features[1].uv1 && r->features[1].uv0);
    EXPECT_TRUE(r->meshNeeds[0].tangents && r->meshNeeds[0].uv0 && !r->meshNeeds[0].uv1);
    EXPECT_FALSE(r->meshNeeds[0].colors);
    EXPECT_TRUE(r->meshNeeds[1].colors && r->meshNeeds[1].uv1 && !r->meshNeeds[1].tangents);
}

class Sidecar : public ::testing::Test {
protected:
    fs::path path = fs::temp_directory_path() / ("pnb_sidecar_" + std::to_string(::getpid()) + ".json");
    void TearDown() override { fs::remove(path); }
    void write(const std::string& text) { std::ofstream(path) << text; }
};

TEST_F(Sidecar, OverridesApplyInFileOrderAndSurviveResolve) {
    write(R"({ "materials": {
        "glass*": { "shading_path": "deferred", "layer_priority": 2, "casts_shadows": false },
        "*": { "roughness": 0.25 },
        "glass-window": { "base_color": [1, 0, 0, 0.5] },
        "marble*": { "metallic": 1 } } })");
    auto o = loadSidecar(path.string());
    ASSERT_TRUE(o.ok()) << o.error().message;
    auto r = resolveMaterials(twoMaterialScene(), *o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Material& glass = r->materials[1];
    EXPECT_EQ(glass.shadingPath, ShadingPath::Deferred);
    EXPECT_EQ(glass.layerPriority, 2);
    EXPECT_FALSE(glass.castsShadows);
    EXPECT_FLOAT_EQ(glass.baseColorFactor.x, 1.0f);
    EXPECT_FLOAT_EQ(glass.baseColorFactor.w, 0.5f);
    for (const Material& m : r->materials) EXPECT_FLOAT_EQ(m.roughnessFactor, 0.25f);
    ASSERT_EQ(r->warnings.size(), 1u);
    EXPECT_NE(r->warnings[0].find("marble*"), std::string::npos);
}

TEST_F(Sidecar, BadSidecarsNameFilePatternAndField) {
    struct Case { const char* json; const char* expect; } cases[] = {
        {"{ not json", "not valid JSON"},
        {R"({"material": {}})", "unknown key 'material'"},
        {R"({"materials": {"glass*": {"shadingpath": "forward"}}})", "shadingpath"},
        {R"({"materials": {"glass*": {"shading_path": "sideways"}}})", "deferred|forward"},
        {R"({"materials": {"glass*": {"base_color_texture": 3}}})", "texture slots"},
        {R"({"materials": {"glass*": {"roughness": {"x": 1}}}})", "must be a string"},
        {R"({"materials": {"glass*": 5}})", "object of fields"},
    };
    for (const Case& c : cases) {
        write(c.json);
        auto o = loadSidecar(path.string());
        ASSERT_FALSE(o.ok()) << c.json;
        EXPECT_NE(o.error().message.find(path.string()), std::string::npos) << o.error().message;
        EXPECT_NE(o.error().message.find(c.expect), std::string::npos) << o.error().message;
    }
    EXPECT_FALSE(loadSidecar((path.string() + ".missing")).ok());
}

TEST(MaterialResolve, ImageIndexOutOfRangeIsAnError) {
    IrScene scene = twoMaterialScene();
    scene.materials[0].textures[0].image = 9;
    auto r = resolveMaterials(scene, {});
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("brick-wall"), std::string::npos);
}

} // namespace

namespace {

// The container keeps the sampler on the texture (TEXR), so glTF textures that share an image but
// not a sampler stay two textures (TextureSettingsTest: 9 textures over 3 images); equal ones
// share one.
TEST(MaterialResolve, OneImageThroughTwoSamplersIsTwoTextures) {
    IrScene s;
    s.sourcePath = "samplers.gltf";
    s.images.push_back({"checker", "checker.png", {}, "image/png"});
    IrMaterial clamp, repeat, repeatToo;
    clamp.name = "clamp";
    clamp.textures[size_t(TextureSlotKind::BaseColor)].image = 0;
    clamp.textures[size_t(TextureSlotKind::BaseColor)].wrapU = Wrap::ClampToEdge;
    repeat.name = "repeat";
    repeat.textures[size_t(TextureSlotKind::BaseColor)].image = 0;
    repeatToo = repeat;
    repeatToo.name = "repeat-too";
    s.materials = {clamp, repeat, repeatToo};
    IrMesh mesh;
    for (int m = 0; m < 3; ++m) mesh.primitives.push_back(IrPrimitive{.positions = {0, 0, 0}, .material = m});
    s.meshes = {mesh};
    auto r = resolveMaterials(s, {});
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->textures.size(), 2u);
    const uint32_t a = r->materials[0].textures[size_t(TextureSlotKind::BaseColor)].texture;
    const uint32_t b = r->materials[1].textures[size_t(TextureSlotKind::BaseColor)].texture;
    const uint32_t c = r->materials[2].textures[size_t(TextureSlotKind::BaseColor)].texture;
    EXPECT_NE(a, b);
    EXPECT_EQ(b, c);
    EXPECT_EQ(r->textures[a].wrapU, Wrap::ClampToEdge);
    EXPECT_EQ(r->textures[b].wrapU, Wrap::Repeat);
}

// A spec-gloss material is converted before the sidecar applies: a user's override of its
// roughness wins over the converted factor, and its gold stays gold.
TEST(MaterialResolve, SpecGlossFactorsAreConvertedBeforeOverrides) {
    IrScene s;
    s.sourcePath = "gold.gltf";
    IrMaterial gold;
    gold.name = "gold";
    gold.specGloss = SpecGlossFactors{{0, 0, 0, 1}, {1.0f, 0.766f, 0.336f}, 0.8f};
    s.materials = {gold};
    IrMesh mesh;
    mesh.primitives.push_back(IrPrimitive{.positions = {0, 0, 0}, .material = 0});
    s.meshes = {mesh};
    auto plain = resolveMaterials(s, {});
    ASSERT_TRUE(plain.ok()) << plain.error().message;
    EXPECT_GT(plain->materials[0].metallicFactor, 0.95f);
    EXPECT_NEAR(plain->materials[0].roughnessFactor, 0.2f, 1e-6f);
    EXPECT_NEAR(plain->materials[0].baseColorFactor.y, 0.766f, 0.05f);
    MaterialOverrides o;
    o.rules.push_back({"gold", {{"roughness", "0.6"}}});
    auto overridden = resolveMaterials(s, o);
    ASSERT_TRUE(overridden.ok()) << overridden.error().message;
    EXPECT_FLOAT_EQ(overridden->materials[0].roughnessFactor, 0.6f);
    EXPECT_GT(overridden->materials[0].metallicFactor, 0.95f);
}

// KHR_materials_pbrSpecularGlossiness with Khronos's published conversion: a metal (black
// diffuse, coloured specular) keeps its colour as base colour with metallic ~1, not black; a
// dielectric (4 % specular) keeps its diffuse with metallic 0.
TEST(SpecGloss, MetalsKeepTheirColourAndDielectricsTheirDiffuse) {
    const Vec3 gold{1.0f, 0.766f, 0.336f};
    MetalRough metal = specGlossToMetalRough({0, 0, 0, 1}, gold, 0.8f);
    EXPECT_GT(metal.metallic, 0.95f);
    EXPECT_NEAR(metal.baseColor.x, gold.x, 0.05f);
    EXPECT_NEAR(metal.baseColor.y, gold.y, 0.05f);
    EXPECT_NEAR(metal.baseColor.z, gold.z, 0.05f);
    EXPECT_NEAR(metal.roughness, 0.2f, 1e-6f);
    MetalRough plastic = specGlossToMetalRough({0.5f, 0.25f, 0.1f, 0.5f}, {0.04f, 0.04f, 0.04f}, 0.3f);
    EXPECT_EQ(plastic.metallic, 0.0f);
    EXPECT_NEAR(plastic.baseColor.x, 0.5f, 1e-3f);
    EXPECT_NEAR(plastic.baseColor.y, 0.25f, 1e-3f);
    EXPECT_NEAR(plastic.baseColor.z, 0.1f, 1e-3f);
    EXPECT_FLOAT_EQ(plastic.baseColor.w, 0.5f);
    EXPECT_NEAR(plastic.roughness, 0.7f, 1e-6f);
    // Extremes stay finite and inside [0, 1].
    for (const MetalRough& e : {specGlossToMetalRough({1, 1, 1, 1}, {1, 1, 1}, 1),
                                specGlossToMetalRough({0, 0, 0, 0}, {0, 0, 0}, 0),
                                specGlossToMetalRough({1e30f, -1, 0, 1}, {2, -3, 1e30f}, -4)}) {
        for (float v : {e.baseColor.x, e.baseColor.y, e.baseColor.z, e.baseColor.w, e.metallic, e.roughness}) {
            EXPECT_TRUE(v >= 0.0f && v <= 1.0f) << v;
        }
    }
}

} // namespace
