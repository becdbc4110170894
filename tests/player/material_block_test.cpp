// material_block_test.cpp — the material table (pnb/material_fields.h, the one list of editable
// fields) against the MaterialBlock the shaders read (shaders/shared/material_block.h, one
// declaration for GLSL and C++): every field of the table either lands in a named block member,
// read back from the buffer the player uploads, or is named here as one the block does not carry
// (it picks programs, pipeline state or texture bindings instead). A field added to the table
// fails this test until it is placed in one of the two lists below.
#include <cstring>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "pnb/material_fields.h"
#include "pnb_player/gpu_scene.h"
#include "render_fixture.h"
#include "shared/material_block.h"

namespace pnb::player::test {
namespace {

// A field set through the converter's sidecar (which applies the table's setMaterialField) and
// where its value must appear in the uploaded block.
struct Lands {
    const char* field;
    const char* sidecarValue; // JSON
    glm::vec4 MaterialBlock::*member;
    std::vector<int> components;
    std::vector<float> expected;
};

const std::vector<Lands>& landing() {
    static const std::vector<Lands> rows = {
        {"base_color", "[0.5, 0.25, 0.125, 0.75]", &MaterialBlock::baseColorFactor, {0, 1, 2, 3},
         {0.5f, 0.25f, 0.125f, 0.75f}},
        // emissive arrives multiplied by emissive_strength (2 below)
        {"emissive", "[0.5, 0.25, 0.125]", &MaterialBlock::emissive, {0, 1, 2}, {1.0f, 0.5f, 0.25f}},
        {"emissive_strength", "2", &MaterialBlock::emissive, {0}, {1.0f}},
        {"metallic", "0.375", &MaterialBlock::params, {0}, {0.375f}},
        {"roughness", "0.625", &MaterialBlock::params, {1}, {0.625f}},
        {"normal_scale", "1.5", &MaterialBlock::params, {2}, {1.5f}},
        {"occlusion_strength", "0.875", &MaterialBlock::params, {3}, {0.875f}},
        {"alpha_cutoff", "0.3125", &MaterialBlock::alphaParams, {0}, {0.3125f}},
        {"alpha_mode", "\"blend\"", &MaterialBlock::alphaParams, {1}, {1.0f}},
        {"receives_shadows", "false", &MaterialBlock::alphaParams, {2}, {0.0f}},
        {"unlit", "true", &MaterialBlock::alphaParams, {3}, {1.0f}},
    };
    return rows;
}

// Fields the block does not carry: they choose programs (shading_path, double_sided via the
// pipeline's culling, casts_shadows via the shadow casters, the textures via permutation and
// bindings) or the draw order (layer_priority).
const std::set<std::string> kNotInBlock = {
    "shading_path",      "layer_priority",  "double_sided",
    "casts_shadows",     "base_color_texture", "metallic_roughness_texture",
    "normal_texture",    "occlusion_texture",  "emissive_texture",
};

TEST(MaterialBlock, EveryTableFieldIsPlacedInTheBlockOrNamedAsNotInIt) {
    std::set<std::string> landed;
    for (const Lands& l : landing()) landed.insert(l.field);
    for (const MaterialField& f : materialFields()) {
        EXPECT_NE(landed.count(f.name) + kNotInBlock.count(f.name), 0u)
            << f.name << ": a table field this test does not place (in the block or not)";
        EXPECT_FALSE(landed.count(f.name) && kNotInBlock.count(f.name)) << f.name;
    }
}

TEST(MaterialBlock, TableFieldsLandWhereTheShadersReadThem) {
    gltf::Document doc;
    gltf::Material probe;
    probe.name = "probe";
    doc.materials = {probe};
    addObject(doc, "box", box(1, 1, 1, 0), {0, 0, 0});
    addLights(doc);
    std::string sidecar = R"({"materials": {"probe": {)";
    for (const Lands& l : landing())
        sidecar += std::string(sidecar.back() == '{' ? "" : ", ") + "\"" + l.field + "\": " + l.sidecarValue;
    sidecar += "}}}";
    std::string path = convert(doc, "material_block", sidecar);

    auto scene = loadScene(path);
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    ASSERT_EQ((*scene)->materials.size(), 1u);
    MaterialBlock block;
    glGetNamedBufferSubData((*scene)->materialBuffer.id(), (*scene)->materials[0].uniformOffset,
                            sizeof block, &block);
    for (const Lands& l : landing()) {
        for (size_t i = 0; i < l.components.size(); ++i)
            EXPECT_FLOAT_EQ((block.*l.member)[l.components[i]], l.expected[i])
                << l.field << " component " << l.components[i];
    }
}

} // namespace
} // namespace pnb::player::test
