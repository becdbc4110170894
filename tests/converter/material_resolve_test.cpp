// Material resolve: default placement, sidecar overrides, texture grouping, stream needs.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "pnb_converter/material_resolve.h"

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
