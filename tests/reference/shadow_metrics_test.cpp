// Shadow metrics on small hand-made arrays with exactly known answers.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include <glm/glm.hpp>

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

TEST(ShadowMetrics, ClassifyShadowIsWhatCompareCounts) {
    // The same arrays: per-pixel classes (pnb-play --error-maps) and the percentages agree.
    const std::vector<float> player = {1.0f, 0.0f, 0.75f, 0.25f, 0.5f, -1.0f, kNaN, 1.0f, 0.0f, kInf};
    const std::vector<float> truth = {1.0f, 0.0f, 0.0f, 1.0f, 1.0f, kNaN, kNaN, kNaN, 1.0f, 0.0f};
    using C = ShadowClass;
    const C want[] = {C::AgreeLit, C::AgreeShadow, C::FalseLit,     C::FalseShadow,  C::AgreeLit,
                      C::Unclassified, C::Unclassified, C::Unclassified, C::FalseShadow, C::Unclassified};
    uint64_t classified = 0, wrong = 0;
    for (size_t i = 0; i < player.size(); ++i) {
        const C c = classifyShadow(player[i], truth[i]);
        EXPECT_EQ(c, want[i]) << "pixel " << i;
        classified += c != C::Unclassified;
        wrong += c == C::FalseLit || c == C::FalseShadow;
    }
    // -0 is a valid (shadowed) player value; a negative one is not.
    EXPECT_EQ(classifyShadow(-0.0f, 0.0f), C::AgreeShadow);
    EXPECT_EQ(classifyShadow(-1e-6f, 1.0f), C::Unclassified);
    const ShadowErrorMetrics m = compareShadow(player, truth);
    EXPECT_EQ(m.pixels, classified);
    EXPECT_DOUBLE_EQ(m.misclassifiedPercent, 100.0 * double(wrong) / double(classified));
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

TEST(ShadowMetrics, WeightedErrorFollowsTheLightAndSplitsLeaksFromDarkening) {
    // A lit ground (w = 1) and a grazing wall (w = 0.002) seen by as many pixels each: the wall
    // is misclassified everywhere, the ground in one pixel of ten.
    std::vector<float> player, truth, weights;
    for (int i = 0; i < 10; ++i) {
        player.push_back(i == 0 ? 0.0f : 1.0f); // one false shadow on the ground
        truth.push_back(1.0f);
        weights.push_back(1.0f);
    }
    for (int i = 0; i < 10; ++i) {
        player.push_back(1.0f); // the wall: player lit, truly shadowed (a leak)
        truth.push_back(0.0f);
        weights.push_back(0.002f);
    }
    ShadowErrorMetrics m = compareShadow(player, truth, weights);
    EXPECT_DOUBLE_EQ(m.misclassifiedPercent, 100.0 * 11 / 20); // binary: the wall dominates
    ASSERT_TRUE(m.weighted);
    EXPECT_NEAR(m.litIrradiance, 10.0, 1e-12);
    EXPECT_NEAR(m.weightedFalseShadowPercent, 10.0, 1e-9);       // 1 of the ground's 10
    EXPECT_NEAR(m.weightedFalseLitPercent, 100.0 * 0.02 / 10, 1e-6); // the wall: 0.2 %
    EXPECT_NEAR(m.weightedErrorPercent, m.weightedFalseShadowPercent + m.weightedFalseLitPercent, 1e-9);
    EXPECT_LT(m.weightedErrorPercent, m.misclassifiedPercent / 5);

    // Filtered player values count by how far off they are; values above 1 are clamped; bad
    // weights count as 0.
    m = compareShadow(std::vector<float>{0.75f, 1.5f, 0.0f}, std::vector<float>{1.0f, 1.0f, 1.0f},
                      std::vector<float>{1.0f, 1.0f, kNaN});
    EXPECT_NEAR(m.weightedErrorPercent, 100.0 * 0.25 / 2, 1e-9);
    EXPECT_FALSE(compareShadow(player, truth).weighted);

    // Nothing truly lit: 0 when the player agrees, 100 when it leaks.
    EXPECT_EQ(compareShadow(std::vector<float>{0.0f}, std::vector<float>{0.0f}, std::vector<float>{1.0f})
                  .weightedErrorPercent, 0.0);
    EXPECT_EQ(compareShadow(std::vector<float>{1.0f}, std::vector<float>{0.0f}, std::vector<float>{1.0f})
                  .weightedErrorPercent, 100.0);
}

TEST(ShadowMetrics, NormalsFromPositionsFaceTheEyeAndSkipSilhouettes) {
    // A 4 x 3 image of the plane y = -1 seen from the origin (spacing 0.1), except pixel (3, 1),
    // which lies on a far wall: its neighbours on the plane must not bend the plane's normals,
    // and it has no neighbour of its own on the wall.
    const int w = 4, h = 3;
    std::vector<glm::vec3> p;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) p.push_back({0.1f * float(x), -1.0f, -1.0f - 0.1f * float(y)});
    p[1 * w + 3] = {5.0f, 3.0f, -40.0f};
    p[2 * w + 0] = {kNaN, kNaN, kNaN};
    for (float scale : {1e-6f, 1.0f, 1e6f}) {
        std::vector<glm::vec3> q;
        for (glm::vec3 v : p) q.push_back(v * scale);
        std::vector<glm::vec3> n = normalsFromPositions(q, w, h);
        for (int i : {0, 1, 2, 4, 5, 6, 9, 10}) { // 3, 11: their only y neighbour is the wall
            EXPECT_NEAR(n[size_t(i)].x, 0.0f, 1e-5f) << i << " at " << scale;
            EXPECT_NEAR(n[size_t(i)].y, 1.0f, 1e-5f) << i << " at " << scale; // towards the eye
            EXPECT_NEAR(n[size_t(i)].z, 0.0f, 1e-5f) << i << " at " << scale;
        }
        EXPECT_EQ(n[8], glm::vec3(0.0f)); // no geometry
    }
    // Weights: the shading normal wins where known, the fallback elsewhere, N.L clamped at 0.
    std::vector<glm::vec3> shading = {{0, 0, 0}, {1, 0, 0}, {0, 0, 0}};
    std::vector<glm::vec3> fallback = {{0, 2, 0}, {0, 1, 0}, {0, -1, 0}};
    std::vector<float> wts = lambertWeights(shading, fallback, glm::vec3(0, 3, 0));
    EXPECT_EQ(wts, (std::vector<float>{1.0f, 0.0f, 0.0f}));
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
