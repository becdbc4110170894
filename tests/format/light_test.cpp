// LGHT (docs/FORMAT.md "LGHT"): how far a light reaches (pnb/light_range.h) at the extremes, and
// the reader refusing lights outside their domain, or more of them than kMaxLights, with an
// error that names LGHT and the light.

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <limits>
#include <string>

#include "format_test_util.h"
#include "pnb/light_range.h"

namespace {

using namespace pnb;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

Light pointLight(float intensity, Vec3 color = {1, 1, 1}) {
    Light l;
    l.type = LightType::Point;
    l.color = color;
    l.intensity = intensity;
    return l;
}

// [SECTION] lightCutoffRange / effectiveLightRange

TEST(LightRange, CutoffRangeIsWhereTheBrightestChannelFallsToTheCutoff) {
    // 100 cd with a brightest channel of 1: 100 / d^2 = 0.01 lux at d = 100 m.
    EXPECT_FLOAT_EQ(lightCutoffRange(pointLight(100, {0.5f, 1.0f, 0.25f})), 100.0f);
    // The blue channel alone decides it: sqrt(100 * 0.25 / 0.01) = 50.
    EXPECT_FLOAT_EQ(lightCutoffRange(pointLight(100, {0, 0, 0.25f})), 50.0f);
    // A 100x higher cut-off: a tenth of the reach.
    EXPECT_FLOAT_EQ(lightCutoffRange(pointLight(100), 1.0f), 10.0f);
    Light spot = pointLight(400);
    spot.type = LightType::Spot;
    EXPECT_FLOAT_EQ(lightCutoffRange(spot), 200.0f) << "the cone does not shorten the reach";
}

TEST(LightRange, LightsThatGiveNoLightReachNothing) {
    EXPECT_EQ(lightCutoffRange(pointLight(0)), 0.0f);
    EXPECT_EQ(lightCutoffRange(pointLight(100, {0, 0, 0})), 0.0f);
    EXPECT_EQ(lightCutoffRange(pointLight(-5)), 0.0f);
    EXPECT_EQ(lightCutoffRange(pointLight(kNaN)), 0.0f);
    // NaN in any channel, not only the first (std::max alone would skip a later NaN).
    EXPECT_EQ(lightCutoffRange(pointLight(100, {kNaN, 1, 1})), 0.0f);
    EXPECT_EQ(lightCutoffRange(pointLight(100, {1, kNaN, 1})), 0.0f);
    EXPECT_EQ(lightCutoffRange(pointLight(100, {1, 1, kNaN})), 0.0f);
    Light sun = pointLight(100000);
    sun.type = LightType::Directional;
    EXPECT_EQ(lightCutoffRange(sun), 0.0f) << "a directional light is not bounded";
    EXPECT_EQ(effectiveLightRange(sun), 0.0f);
}

TEST(LightRange, ExtremesStayFiniteAndAtMostFltMax) {
    const float huge = lightCutoffRange(pointLight(FLT_MAX));
    EXPECT_TRUE(std::isfinite(huge));
    EXPECT_NEAR(double(huge), std::sqrt(double(FLT_MAX) / 0.01), 1e-6 * double(huge));
    EXPECT_EQ(lightCutoffRange(pointLight(kInf)), FLT_MAX);
    // A tiny cut-off: sqrt(FLT_MAX / 1e-45) overflows float; clamped, not infinite.
    EXPECT_EQ(lightCutoffRange(pointLight(FLT_MAX), 1e-45f), FLT_MAX);
    EXPECT_NEAR(double(lightCutoffRange(pointLight(1), 1e-30f)), 1e15, 1e9);
    // The faintest light: a denormal intensity still gives a positive range.
    EXPECT_GT(lightCutoffRange(pointLight(std::numeric_limits<float>::denorm_min())), 0.0f);
}

TEST(LightRange, ACutoffThatIsNoNumberIsTheDefault) {
    const float expected = lightCutoffRange(pointLight(100), kDefaultLightCutoffLux);
    EXPECT_FLOAT_EQ(expected, 100.0f);
    for (float bad : {0.0f, -1.0f, kNaN, kInf, -kInf})
        EXPECT_EQ(lightCutoffRange(pointLight(100), bad), expected) << bad;
}

TEST(LightRange, EffectiveRangeIsTheLightsOwnElseTheCutoffRange) {
    Light l = pointLight(100);
    l.range = 7;
    EXPECT_EQ(effectiveLightRange(l), 7.0f);
    for (float none : {0.0f, -3.0f, kNaN, kInf}) {
        l.range = none;
        EXPECT_FLOAT_EQ(effectiveLightRange(l), 100.0f) << none;
    }
    Light dark = pointLight(0);
    dark.range = 7;
    EXPECT_EQ(effectiveLightRange(dark), 0.0f) << "no light: skipped whatever its range says";
}

// [SECTION] the reader's domain rules

// The box room (a sun and a point lamp) with `extra` as light 2, written and read back.
Result<Scene> readWithLight(const Light& extra) {
    SceneBuilder b;
    assets::buildBoxRoom(b);
    b.scene.lights.lights.push_back(extra);
    std::vector<std::byte> bytes = test::writeToMemory(b.scene);
    auto container = Container::fromMemory(bytes);
    if (!container) return container.error();
    return readScene(*container);
}

Light spotLight(float inner, float outer) {
    Light l = pointLight(10);
    l.type = LightType::Spot;
    l.innerConeRadians = inner;
    l.outerConeRadians = outer;
    return l;
}

TEST(LightValidation, ValuesOutsideTheirDomainAreRefusedNamingLghtAndTheLight) {
    struct Case {
        const char* what;
        Light light;
        const char* words;
    };
    auto with = [](Light l, auto change) {
        change(l);
        return l;
    };
    const Light base = pointLight(10);
    const Case cases[] = {
        {"NaN intensity", with(base, [](Light& l) { l.intensity = kNaN; }), "intensity"},
        {"negative intensity", with(base, [](Light& l) { l.intensity = -1; }), "intensity"},
        {"infinite intensity", with(base, [](Light& l) { l.intensity = kInf; }), "intensity"},
        {"NaN range", with(base, [](Light& l) { l.range = kNaN; }), "range"},
        {"negative range", with(base, [](Light& l) { l.range = -2; }), "range"},
        {"infinite range", with(base, [](Light& l) { l.range = kInf; }), "range"},
        {"negative colour", with(base, [](Light& l) { l.color.y = -0.5f; }), "colour"},
        {"NaN colour", with(base, [](Light& l) { l.color.z = kNaN; }), "colour"},
        // Finite, but the renderer's sums overflow: FLT_MAX x FLT_MAX filled the frame with NaN.
        {"FLT_MAX intensity and colour", pointLight(FLT_MAX, {FLT_MAX, FLT_MAX, FLT_MAX}),
         "exceeds 1e+10"},
        {"just above kMaxLightOutput", pointLight(kMaxLightOutput * 1.01f), "kMaxLightOutput"},
        {"a bright channel", pointLight(2e4f, {1, 1e6f, 1}), "brightest colour channel"},
        {"inner > outer", spotLight(0.6f, 0.5f), "cone"},
        {"outer > pi/2", spotLight(0.1f, 1.6f), "cone"},
        {"negative inner", spotLight(-0.1f, 0.5f), "cone"},
        {"NaN outer", spotLight(0.1f, kNaN), "cone"},
    };
    for (const Case& c : cases) {
        auto r = readWithLight(c.light);
        ASSERT_FALSE(r.ok()) << c.what;
        EXPECT_EQ(r.error().code, FormatError::BadPayload) << c.what;
        const std::string& m = r.error().message;
        EXPECT_NE(m.find("LGHT light 2:"), std::string::npos) << c.what << ": " << m;
        EXPECT_NE(m.find(c.words), std::string::npos) << c.what << ": " << m;
    }
}

TEST(LightValidation, AnUnknownTypeIsRefusedNamingLghtAndTheElement) {
    Light l = pointLight(10);
    l.type = static_cast<LightType>(7);
    auto r = readWithLight(l);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, FormatError::BadPayload);
    const std::string& m = r.error().message;
    EXPECT_NE(m.find("LGHT"), std::string::npos) << m;
    EXPECT_NE(m.find("element 2 of 3"), std::string::npos) << m;
    // validateScene on a scene built in memory (never decoded) says the same in its words.
    SceneBuilder b;
    assets::buildBoxRoom(b);
    b.scene.lights.lights.push_back(l);
    Status st = validateScene(b.scene);
    EXPECT_NE(st.message.find("LGHT light 2: unknown type 7"), std::string::npos) << st.message;
}

TEST(LightValidation, TheDomainsEdgesAreAccepted) {
    // Exactly pi/2 as glTF writes it (a double rounded to float), inner = outer, range 0
    // (unlimited), a dark light, zero cone: all valid.
    const float halfPi = float(M_PI / 2);
    // The brightest light allowed, and a black colour of any size on a dark light.
    for (const Light& l : {spotLight(halfPi, halfPi), spotLight(0, 0), pointLight(0, {0, 0, 0}),
                           pointLight(kMaxLightOutput), pointLight(0, {FLT_MAX, FLT_MAX, FLT_MAX}),
                           pointLight(kMaxLightOutput / 1e6f, {1e6f, 0, 0})}) {
        auto r = readWithLight(l);
        EXPECT_TRUE(r.ok()) << r.error().describe();
    }
    // Cone angles of point and directional lights are unused, so not checked.
    Light point = pointLight(10);
    point.innerConeRadians = 3;
    EXPECT_TRUE(readWithLight(point).ok());
}

TEST(LightValidation, MoreThanKMaxLightsIsRefused) {
    SceneBuilder b;
    assets::buildBoxRoom(b);
    std::vector<Light>& lights = b.scene.lights.lights;
    lights.resize(kMaxLights, pointLight(1));
    {
        std::vector<std::byte> bytes = test::writeToMemory(b.scene);
        auto container = Container::fromMemory(bytes);
        ASSERT_TRUE(container.ok());
        auto r = readScene(*container);
        EXPECT_TRUE(r.ok()) << "exactly kMaxLights: " << r.error().describe();
    }
    lights.push_back(pointLight(1));
    std::vector<std::byte> bytes = test::writeToMemory(b.scene);
    auto container = Container::fromMemory(bytes);
    ASSERT_TRUE(container.ok());
    auto r = readScene(*container);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, FormatError::LimitExceeded);
    EXPECT_NE(r.error().message.find("LGHT: 65537 lights, more than kMaxLights (65536)"),
              std::string::npos)
        << r.error().message;
}

} // namespace
