#include <gtest/gtest.h>

#include "pnb/chunks.h"
#include "pnb_assets/box_room.h"
#include "pnb_editor/set_expression.h"

namespace {

using namespace pnb;
using namespace pnb::editor;

TEST(SetExpression, ParsesDottedNamesAtTheLastDotBeforeTheValue) {
    auto e = parseSetExpression("wall.v2*.layer_priority=3");
    ASSERT_TRUE(e.ok());
    EXPECT_EQ(e->pattern, "wall.v2*");
    EXPECT_EQ(e->field, "layer_priority");
    EXPECT_EQ(e->value, "3");
    auto withDotInValue = parseSetExpression("glass.base_color=0.5,0.5,0.5,0.25");
    ASSERT_TRUE(withDotInValue.ok());
    EXPECT_EQ(withDotInValue->field, "base_color");
    EXPECT_EQ(withDotInValue->value, "0.5,0.5,0.5,0.25");
    for (const char* bad : {"glass", "glass=1", ".roughness=1", "glass.=1", ""})
        EXPECT_FALSE(parseSetExpression(bad).ok()) << bad;
}

TEST(SetExpression, AppliesToEveryMatchAndNothingOnError) {
    SceneBuilder b;
    assets::buildBoxRoom(b);
    Scene& scene = b.scene;
    auto n = applySetExpression(scene, {"*-wall", "shading_path", "forward"});
    ASSERT_TRUE(n.ok()) << n.error().describe();
    EXPECT_EQ(*n, 3u); // white, red, green walls
    size_t forward = 0;
    for (const Material& m : scene.materials) forward += m.shadingPath == ShadingPath::Forward;
    EXPECT_EQ(forward, 4u); // the walls + the glass, which already was

    auto before = encodeChunk(scene.materials[0]);
    auto none = applySetExpression(scene, {"marble*", "roughness", "0.1"});
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().message.find("white-wall"), std::string::npos) << "lists names";
    auto badValue = applySetExpression(scene, {"*", "roughness", "2"});
    ASSERT_FALSE(badValue.ok());
    EXPECT_EQ(encodeChunk(scene.materials[0]), before) << "failed edits change nothing";
}

} // namespace
