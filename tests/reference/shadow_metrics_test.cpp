// Shadow metrics on small hand-made arrays with exactly known answers.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "pnb_reference/shadow_metrics.h"

namespace pnb::reference::test {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

TEST(ShadowMetrics, CompareCountsFalseLitFalseShadowAndMeanAbsError) {
    //                              agree  agree  falseLit falseShadow  agree  (excluded ...)
    const std::vector<float> player = {1.0f, 0.0f, 0.75f, 0.25f, 0.5f, -1.0f, kNaN, 1.0f, 0.0f, kInf};
    const std::vector<float> truth = {1.0f, 0.0f, 0.0f, 1.0f, 1.0f, kNaN, kNaN, kNaN, 1.0f, 0.0f};
    // Pixel 8 (player 0, truth 1) is a false shadow too; 5, 6 have no geometry in either;
    // 7 (player has geometry, truth not) and 9 (player inf = none, truth has) are coverage
    // mismatches.
    ShadowErrorMetrics m = compareShadow(player, truth);
    EXPECT_EQ(m.pixels, 6u);
    EXPECT_DOUBLE_EQ(m.falseLitPercent, 100.0 * 1 / 6);
    EXPECT_DOUBLE_EQ(m.falseShadowPercent, 100.0 * 2 / 6);
    EXPECT_DOUBLE_EQ(m.misclassifiedPercent, 100.0 * 3 / 6);
    // |0| + |0| + 0.75 + 0.75 + 0.5 + 1 = 3.0 over 6 pixels.
    EXPECT_DOUBLE_EQ(m.meanAbsError, 0.5);
    EXPECT_EQ(m.coverageMismatch, 2u);
}

TEST(ShadowMetrics, CompareOfNothingIsZero) {
    ShadowErrorMetrics m = compareShadow({}, {});
    EXPECT_EQ(m.pixels, 0u);
    EXPECT_EQ(m.misclassifiedPercent, 0.0);
    EXPECT_EQ(m.meanAbsError, 0.0);
    const std::vector<float> none = {-1.0f, kNaN};
    m = compareShadow(none, std::vector<float>{kNaN, kNaN});
    EXPECT_EQ(m.pixels, 0u);
    EXPECT_EQ(m.coverageMismatch, 0u);
}

TEST(ShadowMetrics, ThresholdIsHalfInclusive) {
    const std::vector<float> player = {0.5f, 0.49999f};
    const std::vector<float> truth = {1.0f, 0.0f};
    EXPECT_EQ(compareShadow(player, truth).misclassifiedPercent, 0.0);
}

TEST(ShadowMetrics, FlickerCountsClassificationChangesOverPixelsValidInBothFrames) {
    const std::vector<float> previous = {1.0f, 1.0f, 0.0f, 0.0f, 0.6f, -1.0f, 1.0f, kNaN};
    const std::vector<float> current = {1.0f, 0.2f, 0.0f, 0.9f, 0.4f, 1.0f, -1.0f, 0.0f};
    // Valid in both: pixels 0..4; changed: 1, 3, 4.
    EXPECT_DOUBLE_EQ(flickerPercent(previous, current), 60.0);
    EXPECT_EQ(flickerPercent(previous, previous), 0.0);
    EXPECT_EQ(flickerPercent({}, {}), 0.0);
}

TEST(ShadowMetrics, PercentileInterpolatesLinearlyBetweenRanks) {
    std::vector<double> v = {4, 1, 3, 2}; // sorted 1 2 3 4
    EXPECT_DOUBLE_EQ(percentile(v, 50), 2.5);
    v = {4, 1, 3, 2};
    EXPECT_DOUBLE_EQ(percentile(v, 95), 3.85); // h = 2.85: 3 + 0.85
    v = {4, 1, 3, 2};
    EXPECT_DOUBLE_EQ(percentile(v, 0), 1.0);
    v = {4, 1, 3, 2};
    EXPECT_DOUBLE_EQ(percentile(v, 100), 4.0);
    v = {7};
    EXPECT_DOUBLE_EQ(percentile(v, 95), 7.0);
    EXPECT_EQ(percentile(std::span<double>(), 50), 0.0);
}

TEST(ShadowMetrics, TexelRatioGroupsByCascadeWithMedianAndP95) {
    std::vector<float> cascade, ratio;
    // Cascade 0: ratios 1..21 (median 11, p95 = 20 at h = 19 exactly).
    for (int i = 1; i <= 21; ++i) {
        cascade.push_back(0.0f);
        ratio.push_back(float(i));
    }
    // Cascade 2: 0.5, 1.5 (median 1.0, p95 1.45); stored with float noise on the index.
    cascade.insert(cascade.end(), {2.0001f, 1.9999f});
    ratio.insert(ratio.end(), {0.5f, 1.5f});
    // Skipped: no cascade, NaN cascade, and bad ratios.
    cascade.insert(cascade.end(), {-1.0f, kNaN, 1.0f, 1.0f, 1.0f});
    ratio.insert(ratio.end(), {3.0f, 3.0f, 0.0f, -2.0f, kNaN});

    auto stats = texelRatioByCascade(cascade, ratio);
    ASSERT_EQ(stats.size(), 2u);
    EXPECT_EQ(stats[0].cascade, 0);
    EXPECT_EQ(stats[0].pixels, 21u);
    EXPECT_DOUBLE_EQ(stats[0].median, 11.0);
    EXPECT_DOUBLE_EQ(stats[0].p95, 20.0);
    EXPECT_EQ(stats[1].cascade, 2);
    EXPECT_EQ(stats[1].pixels, 2u);
    EXPECT_DOUBLE_EQ(stats[1].median, 1.0);
    EXPECT_DOUBLE_EQ(stats[1].p95, 1.45);

    EXPECT_TRUE(texelRatioByCascade({}, {}).empty());
}

} // namespace

} // namespace pnb::reference::test
