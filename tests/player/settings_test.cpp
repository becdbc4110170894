#include <gtest/gtest.h>

#include "pnb_player/settings.h"

namespace pnb::player {

TEST(Settings, ParsesEveryKindAndRoundTrips) {
    RenderSettings s;
    ASSERT_TRUE(applySetting(s, "lighting.exposure=2.5").ok());
    ASSERT_TRUE(applySetting(s, "post.fxaa", "on").ok());
    ASSERT_TRUE(applySetting(s, "cull.frustum", "0").ok());
    ASSERT_TRUE(applySetting(s, "debug.view", "overdraw").ok());
    ASSERT_TRUE(applySetting(s, "shadows.technique=sdsm").ok());
    ASSERT_TRUE(applySetting(s, "shadows.cascades=8").ok());
    ASSERT_TRUE(applySetting(s, "lod.bias=-3").ok()); // signed integers
    ASSERT_TRUE(applySetting(s, "lod.force", "2").ok());
    EXPECT_EQ(s.lodBias, -3);
    EXPECT_EQ(s.lodForce, 2);
    EXPECT_EQ(settingValue(s, "lod.bias"), "-3");
    EXPECT_EQ(settingValue(RenderSettings{}, "lod.force"), "-1");
    EXPECT_EQ(s.shadowTechnique, ShadowTechnique::Sdsm);
    EXPECT_EQ(s.shadowCascades, 8u);
    EXPECT_EQ(settingChoices("shadows.filter").size(), 3u);
    EXPECT_EQ(s.exposure, 2.5f);
    EXPECT_TRUE(s.fxaa);
    EXPECT_FALSE(s.frustumCulling);
    EXPECT_EQ(s.debugView, DebugView::Overdraw);
    // Every value printed parses back to the same settings.
    RenderSettings copy;
    for (const auto& [k, v] : settingValues(s)) ASSERT_TRUE(applySetting(copy, k, v).ok()) << k << "=" << v;
    EXPECT_EQ(settingValues(copy), settingValues(s));
    EXPECT_EQ(settingValues(s).size(), settingInfos().size());
}

TEST(Settings, RejectsWhatDoesNotParseAndNamesTheKey) {
    RenderSettings s;
    const std::pair<const char*, const char*> bad[] = {
        {"lighting.exposure", "0"},     {"lighting.exposure", "abc"}, {"lighting.exposure", "1e40"},
        {"lighting.exposure", "nan"},   {"lighting.ambient", "-1"},   {"post.fxaa", "yes please"},
        {"debug.view", "normals"},      {"camera.far", "-2"},         {"lighting.exposure", "2x"},
        {"shadows.cascades", "0"},      {"shadows.cascades", "9"},    {"shadows.cascades", "2.5"},
        {"shadows.technique", "csm"},   {"shadows.lambda", "1.5"},    {"shadows.resolution", "-1"},
        {"lod.force", "-2"},            {"lod.force", "255"},         {"lod.bias", "9"},
        {"lod.bias", "-1.5"},           {"lod.threshold_px", "-1"},   {"lod.hysteresis", "1"},
    };
    for (auto [key, value] : bad) {
        auto r = applySetting(s, key, value);
        ASSERT_FALSE(r.ok()) << key << "=" << value;
        EXPECT_EQ(r.error().kind, PlayErrorKind::Usage);
        EXPECT_NE(r.error().message.find(key), std::string::npos);
    }
    auto unknown = applySetting(s, "shadows.cascade", "4");
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("known:"), std::string::npos);
    EXPECT_FALSE(applySetting(s, "no-equals-sign").ok());
    EXPECT_FALSE(applySetting(s, "=1").ok());
    EXPECT_EQ(settingValues(s), settingValues(RenderSettings{})); // nothing half-applied
}

TEST(Settings, CommandLineWinsOverContainerWhichWinsOverDefaults) {
    std::vector<std::pair<std::string, std::string>> container = {
        {"lighting.exposure", "2"}, {"post.fxaa", "true"}, {"gi.lpv_cells", "32"}, {"shadows.cascades", "3"}, {"lighting.ambient", "-3"}};
    std::vector<std::string> warnings;
    auto s = resolveSettings(container, {"lighting.exposure=0.5"}, &warnings);
    ASSERT_TRUE(s.ok());
    EXPECT_EQ(s->exposure, 0.5f);       // command line
    EXPECT_TRUE(s->fxaa);               // container
    EXPECT_EQ(s->ambient, RenderSettings{}.ambient); // invalid container value: default kept
    EXPECT_EQ(s->shadowCascades, 3u);   // container
    ASSERT_EQ(warnings.size(), 2u);     // unknown key and bad value, both reported
    EXPECT_NE(warnings[0].find("gi.lpv_cells"), std::string::npos);
    EXPECT_FALSE(resolveSettings(container, {"lighting.exposure=-1"}).ok());
}

} // namespace pnb::player
