// Colour shadow metrics (light through glass, issue 43): the states rule {0, t, 1} per channel
// on hand-made pixels, the irradiance-weighted figures per channel, and, on a binary truth,
// exactly compareShadow's figures for a grey player (random pixels, fixed seed).
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "pnb_reference/local_light.h"
#include "pnb_reference/shadow_color_metrics.h"
#include "pnb_reference/shadow_metrics.h"

namespace pnb::reference::test {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
using C = ShadowColorClass;

TEST(ShadowColorMetrics, ThePlayerIsJudgedByTheNearestOfTheStatesZeroTruthAndOne) {
    // Truth 0.4 in every channel: the states are 0, 0.4 and 1; the boundaries 0.2 and 0.7, a tie
    // going to the brighter state.
    const glm::vec3 t(0.4f);
    EXPECT_EQ(classifyShadowColor(glm::vec3(0.19f), t), C::FalseShadow);
    EXPECT_EQ(classifyShadowColor(glm::vec3(0.2f), t), C::AgreeTranslucent);
    EXPECT_EQ(classifyShadowColor(glm::vec3(0.4f), t), C::AgreeTranslucent);
    EXPECT_EQ(classifyShadowColor(glm::vec3(0.69f), t), C::AgreeTranslucent);
    EXPECT_EQ(classifyShadowColor(glm::vec3(0.7f), t), C::FalseLit);
    EXPECT_EQ(classifyShadowColor(glm::vec3(1.0f), t), C::FalseLit);
    // Per channel: red glass (T = (0.5, 0, 0)) seen as grey 0.5 leaks green and blue.
    EXPECT_EQ(classifyShadowColor(glm::vec3(0.5f), {0.5f, 0, 0}), C::FalseLit);
    EXPECT_EQ(classifyShadowColor({0.3f, 0.49f, 0}, {0.5f, 0, 0}), C::AgreeTranslucent);
    EXPECT_EQ(classifyShadowColor({0.24f, 0, 0}, {0.5f, 0, 0}), C::FalseShadow);
    EXPECT_EQ(classifyShadowColor({0.5f, 0, 0.4f}, {0.5f, 0, 1}), C::FalseShadow);
    // One channel each way: the sum of the differences decides (0.7 - 0 + 0.4 - 1 > 0).
    EXPECT_EQ(classifyShadowColor({0.7f, 0.4f, 1}, {0, 1, 1}), C::FalseLit);
    EXPECT_EQ(classifyShadowColor({0.5f, 0.2f, 1}, {0, 1, 1}), C::FalseShadow);
    // Where the truth is 0 or 1, the 0.5 threshold.
    EXPECT_EQ(classifyShadowColor(glm::vec3(0.5f), glm::vec3(0)), C::FalseLit);
    EXPECT_EQ(classifyShadowColor(glm::vec3(0.5f), glm::vec3(1)), C::AgreeLit);
    EXPECT_EQ(classifyShadowColor(glm::vec3(0.49f), glm::vec3(0)), C::AgreeShadow);
    EXPECT_EQ(classifyShadowColor(glm::vec3(0.49f), glm::vec3(1)), C::FalseShadow);
    // No geometry: NaN truth, a negative or non-finite player channel.
    EXPECT_EQ(classifyShadowColor(glm::vec3(-1.0f), glm::vec3(1)), C::Unclassified);
    EXPECT_EQ(classifyShadowColor({1, 1, kNaN}, glm::vec3(1)), C::Unclassified);
    EXPECT_EQ(classifyShadowColor(glm::vec3(1.0f), {1, kNaN, 1}), C::Unclassified);
}

TEST(ShadowColorMetrics, CompareCountsWeighsPerChannelAndSplitsBrighterFromDarker) {
    const std::vector<glm::vec3> player = {{0.25f, 0, 1}, {0.5f, 0.5f, 0.5f}, glm::vec3(1), glm::vec3(-1),
                                           glm::vec3(0)};
    const std::vector<glm::vec3> truth = {{0.5f, 0, 1}, {0.5f, 0, 0}, glm::vec3(1), glm::vec3(1), glm::vec3(kNaN)};
    const std::vector<float> weights = {2, 1, 1, 5, 5};
    const ShadowColorMetrics m = compareShadowColor(player, truth, weights);
    EXPECT_EQ(m.pixels, 3u);
    EXPECT_EQ(m.translucentPixels, 2u);
    EXPECT_EQ(m.coverageMismatch, 2u);
    EXPECT_DOUBLE_EQ(m.misclassifiedPercent, 100.0 / 3);
    EXPECT_DOUBLE_EQ(m.falseLitPercent, 100.0 / 3); // pixel 1 leaks green and blue
    EXPECT_DOUBLE_EQ(m.falseShadowPercent, 0.0);    // pixel 0 is darker but in its state
    // |d| over 3 pixels x 3 channels: 0.25 + 0.5 + 0.5 = 1.25.
    EXPECT_DOUBLE_EQ(m.meanAbsError, 1.25 / 9);
    ASSERT_TRUE(m.weighted);
    // Red: truth 2 x 0.5 + 1 x 0.5 + 1 = 2.5, darker by 2 x 0.25; green: truth 1, brighter
    // by 1 x 0.5; blue: truth 2 x 1 + 1 = 3, brighter by 0.5.
    EXPECT_EQ(m.litIrradiance, glm::dvec3(2.5, 1.0, 3.0));
    EXPECT_DOUBLE_EQ(m.weightedFalseShadowPercent.x, 100.0 * 0.5 / 2.5);
    EXPECT_DOUBLE_EQ(m.weightedFalseLitPercent.x, 0.0);
    EXPECT_DOUBLE_EQ(m.weightedFalseLitPercent.y, 50.0);
    EXPECT_DOUBLE_EQ(m.weightedFalseLitPercent.z, 100.0 * 0.5 / 3.0);
    EXPECT_DOUBLE_EQ(m.weightedErrorPercent.z, 100.0 * 0.5 / 3.0);
    // Per-pixel classes are what the comparison counts.
    EXPECT_EQ(classifyShadowColor(player[0], truth[0]), C::AgreeTranslucent);
    EXPECT_EQ(classifyShadowColor(player[1], truth[1]), C::FalseLit);
    EXPECT_EQ(classifyShadowColor(player[2], truth[2]), C::AgreeLit);
    // Without weights: no weighted figures; nothing at all: zeros.
    EXPECT_FALSE(compareShadowColor(player, truth).weighted);
    EXPECT_EQ(compareShadowColor({}, {}).pixels, 0u);
    // No irradiance in a channel and an error there: 100 %.
    const std::vector<glm::vec3> dark = {glm::vec3(0)}, leak = {{1, 0, 0}};
    const std::vector<float> one = {1};
    EXPECT_EQ(compareShadowColor(leak, dark, one).weightedErrorPercent, glm::dvec3(100, 0, 0));
}

TEST(ShadowColorMetrics, OnABinaryTruthAGreyPlayerGetsCompareShadowsFiguresExactly) {
    std::mt19937 random(43);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const size_t n = 20000;
    std::vector<float> player(n), truth(n), weights(n);
    for (size_t i = 0; i < n; ++i) {
        const float kind = unit(random);
        player[i] = kind < 0.05f ? -1.0f : kind < 0.07f ? kNaN : kind < 0.1f ? 0.5f : unit(random);
        const float t = unit(random);
        truth[i] = t < 0.05f ? kNaN : t < 0.5f ? 0.0f : 1.0f;
        const float w = unit(random);
        weights[i] = w < 0.05f ? -1.0f : w < 0.07f ? kNaN : w;
    }
    std::vector<glm::vec3> playerRgb, truthRgb;
    for (size_t i = 0; i < n; ++i) {
        playerRgb.push_back(glm::vec3(player[i]));
        truthRgb.push_back(glm::vec3(truth[i]));
    }
    const ShadowErrorMetrics s = compareShadow(player, truth, weights);
    const ShadowColorMetrics c = compareShadowColor(playerRgb, truthRgb, weights);
    ASSERT_GT(s.misclassifiedPercent, 10.0); // the sample does test something
    EXPECT_EQ(c.pixels, s.pixels);
    EXPECT_EQ(c.translucentPixels, 0u);
    EXPECT_EQ(c.coverageMismatch, s.coverageMismatch);
    EXPECT_EQ(c.misclassifiedPercent, s.misclassifiedPercent);
    EXPECT_EQ(c.falseLitPercent, s.falseLitPercent);
    EXPECT_EQ(c.falseShadowPercent, s.falseShadowPercent);
    EXPECT_DOUBLE_EQ(c.meanAbsError, s.meanAbsError);
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(c.litIrradiance[k], s.litIrradiance);
        EXPECT_EQ(c.weightedErrorPercent[k], s.weightedErrorPercent);
        EXPECT_EQ(c.weightedFalseLitPercent[k], s.weightedFalseLitPercent);
        EXPECT_EQ(c.weightedFalseShadowPercent[k], s.weightedFalseShadowPercent);
    }
    for (size_t i = 0; i < n; ++i) {
        const ShadowClass a = classifyShadow(player[i], truth[i]);
        const ShadowColorClass b = classifyShadowColor(playerRgb[i], truthRgb[i]);
        ASSERT_EQ(int(a == ShadowClass::Unclassified), int(b == C::Unclassified)) << i;
        ASSERT_EQ(int(a == ShadowClass::FalseLit), int(b == C::FalseLit)) << i;
        ASSERT_EQ(int(a == ShadowClass::FalseShadow), int(b == C::FalseShadow)) << i;
        ASSERT_EQ(int(a == ShadowClass::AgreeLit), int(b == C::AgreeLit)) << i;
    }
}

TEST(ShadowColorMetrics, ALocalLightJudgesOnlyThePixelsItReaches) {
    LocalLightWeights reach;
    reach.reached = {1, 0, 1};
    reach.irradiance = {1, 0, 3};
    reach.reachedCount = 2;
    const std::vector<glm::vec3> player = {{0.5f, 0, 0}, glm::vec3(1), glm::vec3(0)};
    const std::vector<glm::vec3> truth = {{0.5f, 0, 0}, glm::vec3(0), glm::vec3(1)};
    const ShadowColorMetrics m = compareLocalShadowColor(player, truth, reach);
    EXPECT_EQ(m.pixels, 2u);
    EXPECT_EQ(m.coverageMismatch, 0u);
    EXPECT_DOUBLE_EQ(m.falseShadowPercent, 50.0);
    EXPECT_DOUBLE_EQ(m.falseLitPercent, 0.0);
    EXPECT_EQ(m.litIrradiance, glm::dvec3(0.5 + 3, 3, 3));
}

} // namespace
} // namespace pnb::reference::test
