// Relative MSE, its noise share, error-map summaries and magma (image_error.h): analytic values.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "pnb_reference/image_error.h"

namespace pnb::reference::test {

TEST(RelativeMse, AnalyticValuesOnConstantImages) {
    const std::vector<glm::vec3> one(16, glm::vec3(1.0f)), two(16, glm::vec3(2.0f)),
        zero(16, glm::vec3(0.0f));
    EXPECT_EQ(relativeMse(one, one).mean, 0.0);
    EXPECT_NEAR(relativeMse(two, one).mean, 1.0 / 1.01, 1e-12); // (2-1)^2 / (1 + 0.01)
    EXPECT_NEAR(relativeMse(one, two).mean, 1.0 / 4.01,
                1e-12); // not symmetric: divided by the reference
    EXPECT_NEAR(relativeMse(std::vector<glm::vec3>(16, glm::vec3(0.1f)), zero).mean, 1.0,
                1e-6); // 0.01 / eps
    EXPECT_NEAR(relativeMse(two, one, 1.0).mean, 0.5, 1e-12);
    // Per channel: only red differs, the mean is over the three channels.
    const std::vector<glm::vec3> t(4, glm::vec3(2, 0, 3)), r(4, glm::vec3(1, 0, 3));
    const RelativeMse rel = relativeMse(t, r);
    EXPECT_NEAR(rel.mean, (1.0 / 1.01) / 3.0, 1e-12);
    EXPECT_EQ(rel.pixels, 4u);
    EXPECT_NEAR(rel.map[2], (1.0 / 1.01) / 3.0, 1e-7);
}

TEST(RelativeMse, SkipsNonFinitePixels) {
    std::vector<glm::vec3> t(4, glm::vec3(2.0f)), r(4, glm::vec3(1.0f));
    t[1].y = std::numeric_limits<float>::quiet_NaN();
    r[2].z = std::numeric_limits<float>::infinity();
    const RelativeMse rel = relativeMse(t, r);
    EXPECT_EQ(rel.pixels, 2u);
    EXPECT_NEAR(rel.mean, 1.0 / 1.01, 1e-12);
    EXPECT_TRUE(std::isnan(rel.map[1]));
}

// The reference-noise formula against the empirical relMSE of noisy estimates of a known image:
// estimates r + s N(0, 1) of a truth r, their relMSE against r averaged over trials, equals
// mean s^2 / (r^2 + eps) within the sampling error (~0.3 % here).
TEST(RelativeMse, NoiseShareMatchesAnEmpiricalEstimate) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> value(0.0f, 3.0f), spread(0.01f, 0.3f);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    const size_t n = 20000;
    std::vector<glm::vec3> truth(n), stderrs(n);
    for (size_t p = 0; p < n; ++p) {
        truth[p] = {value(rng), value(rng), value(rng)};
        stderrs[p] = {spread(rng), spread(rng), spread(rng)};
    }
    const double predicted = noiseRelativeMse(truth, stderrs);
    double empirical = 0.0;
    const int trials = 10;
    for (int t = 0; t < trials; ++t) {
        std::vector<glm::vec3> estimate(n);
        for (size_t p = 0; p < n; ++p)
            for (int c = 0; c < 3; ++c)
                estimate[p][c] = truth[p][c] + stderrs[p][c] * gauss(rng);
        empirical += relativeMse(estimate, truth).mean / trials;
    }
    EXPECT_GT(predicted, 0.01);
    EXPECT_NEAR(empirical / predicted, 1.0, 0.02);
}

// Weighted quantiles weigh each pixel by its error: {1, 1, 1, 1, 4} sums to 8; half of it (4) is
// reached at the fourth 1, three quarters (6) only at the 4.
TEST(ErrorSummary, WeightedQuantiles) {
    const std::vector<float> map = {1, 4, 1, 1, 1};
    EXPECT_EQ(weightedQuantile(map, 0.5), 1.0);
    EXPECT_EQ(weightedQuantile(map, 0.75), 4.0);
    EXPECT_EQ(weightedQuantile(map, 0.0), 1.0);
    const ErrorSummary s = summarizeError(map);
    EXPECT_EQ(s.pixels, 5u);
    EXPECT_DOUBLE_EQ(s.mean, 1.6);
    EXPECT_EQ(s.min, 1.0);
    EXPECT_EQ(s.max, 4.0);
    EXPECT_EQ(s.weightedQuartile3, 4.0);
    EXPECT_EQ(weightedQuantile(std::vector<float>(3, 0.0f), 0.5), 0.0);
}

TEST(ErrorSummary, MagmaRunsFromBlackPurpleToPaleYellow) {
    EXPECT_EQ(magma(0.0), (std::array<uint8_t, 3>{0, 0, 4}));
    EXPECT_EQ(magma(1.0), (std::array<uint8_t, 3>{252, 253, 191}));
    EXPECT_EQ(magma(std::nan("")), magma(0.0));
    EXPECT_EQ(magma(7.0), magma(1.0));
    double previous = -1.0;
    for (int i = 0; i <= 64; ++i) {
        const auto c = magma(i / 64.0);
        const double luma = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        EXPECT_GT(luma, previous) << i; // brighter with the error: readable in grey too
        previous = luma;
    }
    EXPECT_EQ(magmaImage(std::vector<float>{0.0f, 1.0f}).size(), 6u);
}

} // namespace pnb::reference::test
