#include <gtest/gtest.h>

#include <cstddef>
#include <string>

#include "pnb/material_fields.h"

namespace {

using namespace pnb;


// A valid value for each field that differs from the default Material's.
std::string changedValue(const MaterialField& f) {
    switch (f.type) {
    case FieldType::Float: return "0.25";
    case FieldType::Color3: return "0.5,0.25,0.125";
    case FieldType::Color4: return "0.5,0.25,0.125,0.75";
    case FieldType::Bool: return "false"; // defaults: double_sided false, others true
    case FieldType::Choice: return "forward";
    case FieldType::Integer: return "7";
    case FieldType::TextureRef: return "3";
    }
    return {};
}

TEST(MaterialFields, EveryFieldRoundTripsAndChangesTheEncodedMaterial) {
    for (const MaterialField& f : materialFields()) {
        Material m;
        std::string value = changedValue(f);
        if (f.type == FieldType::Choice && std::string(f.name) == "alpha_mode") value = "blend";
        if (std::string(f.name) == "double_sided" || std::string(f.name) == "unlit") value = "true";
        ASSERT_TRUE(isOk(setMaterialField(m, f.name, value))) << f.name;
        EXPECT_EQ(getMaterialField(m, f.name), value) << f.name;
        // The edit must reach the serialised material, i.e. the table points at a real field.
        EXPECT_NE(encodeChunk(m), encodeChunk(Material{})) << f.name;
    }
}

TEST(MaterialFields, FieldsWriteDistinctStorage) {
    // Setting field A must not disturb field B: catches two table rows aliasing one member.
    for (const MaterialField& a : materialFields()) {
        Material m;
        std::string value = changedValue(a);
        if (std::string(a.name) == "alpha_mode") value = "blend";
        if (std::string(a.name) == "double_sided") value = "true";
        ASSERT_TRUE(isOk(setMaterialField(m, a.name, value)));
        for (const MaterialField& b : materialFields()) {
            if (&a == &b) continue;
            EXPECT_EQ(getMaterialField(m, b.name), getMaterialField(Material{}, b.name))
                << a.name << " disturbed " << b.name;
        }
    }
}

TEST(MaterialFields, InvalidInputIsRejectedWithTheValidChoicesAndNoChange) {
    Material m;
    Status s = setMaterialField(m, "rougness", "0.5");
    EXPECT_EQ(s.code, FormatError::BadReference);
    EXPECT_NE(s.message.find("roughness"), std::string::npos) << "lists valid names";
    s = setMaterialField(m, "shading_path", "sideways");
    EXPECT_NE(s.message.find("deferred|forward"), std::string::npos);
    for (const char* bad : {"1.5", "-0.1", "nan", "inf", "", "0.5x"})
        EXPECT_FALSE(isOk(setMaterialField(m, "metallic", bad))) << bad;
    EXPECT_FALSE(isOk(setMaterialField(m, "base_color", "1,1,1")));
    EXPECT_FALSE(isOk(setMaterialField(m, "base_color", "1,1,1,0.5,1")));
    EXPECT_FALSE(isOk(setMaterialField(m, "layer_priority", "70000")));
    EXPECT_FALSE(isOk(setMaterialField(m, "double_sided", "yes")));
    EXPECT_FALSE(isOk(setMaterialField(m, "normal_texture", "4294967295")));
    EXPECT_EQ(encodeChunk(m), encodeChunk(Material{})) << "failed edits change nothing";
}

TEST(MaterialFields, GlobMatch) {
    EXPECT_TRUE(globMatch("*", ""));
    EXPECT_TRUE(globMatch("glass*", "glass"));
    EXPECT_TRUE(globMatch("glass*", "glass-pane"));
    EXPECT_TRUE(globMatch("*_trunk", "oak_trunk"));
    EXPECT_TRUE(globMatch("a?c", "abc"));
    EXPECT_TRUE(globMatch("*a*b*c*", "xxaxxbxxcxx"));
    EXPECT_FALSE(globMatch("glass*", "tinted-glass"));
    EXPECT_FALSE(globMatch("a?c", "ac"));
    EXPECT_FALSE(globMatch("abc", "abcd"));
    EXPECT_FALSE(globMatch("", "a"));
    // Pathological backtracking stays fast.
    std::string text(2000, 'a');
    EXPECT_FALSE(globMatch("*a*a*a*a*a*a*b", text));
}

} // namespace

namespace {

// The one table: each row's accessor gives exactly the pointer its type uses, into the Material
// it was given.
TEST(MaterialFields, EveryRowsAccessorMatchesItsType) {
    for (const pnb::MaterialField& f : pnb::materialFields()) {
        SCOPED_TRACE(f.name);
        pnb::Material m;
        ASSERT_NE(f.slot, nullptr);
        const pnb::MaterialFieldSlot s = f.slot(m);
        const bool number = f.type == pnb::FieldType::Float || f.type == pnb::FieldType::Color3 ||
                            f.type == pnb::FieldType::Color4;
        EXPECT_EQ(s.floats != nullptr, number);
        EXPECT_EQ(s.flag != nullptr, f.type == pnb::FieldType::Bool);
        EXPECT_EQ(s.choice != nullptr, f.type == pnb::FieldType::Choice);
        EXPECT_EQ(s.integer != nullptr, f.type == pnb::FieldType::Integer);
        EXPECT_EQ(s.texture != nullptr, f.type == pnb::FieldType::TextureRef);
        const void* ptrs[] = {s.floats, s.flag, s.choice, s.integer, s.texture};
        for (const void* p : ptrs) {
            if (!p) continue;
            auto at = reinterpret_cast<const std::byte*>(p);
            auto begin = reinterpret_cast<const std::byte*>(&m);
            EXPECT_TRUE(at >= begin && at < begin + sizeof m) << "outside the Material given";
        }
    }
}

} // namespace
