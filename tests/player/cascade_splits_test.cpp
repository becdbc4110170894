#include <gtest/gtest.h>

#include <cmath>

#include "cascade_splits.h"

namespace {

using pnb::player::practicalSplitDistances;

TEST(CascadeSplits, PracticalSchemeMatchesReferenceVector) {
    // n = 0.1, f = 1000, m = 4, lambda = 0.5 (issue 5's reference values).
    auto s = practicalSplitDistances(0.1f, 1000.0f, 4, 0.5f);
    ASSERT_EQ(s.size(), 4u);
    EXPECT_NEAR(s[0], 125.537f, 1e-3f);
    EXPECT_NEAR(s[1], 255.025f, 1e-3f);
    EXPECT_NEAR(s[2], 425.012f, 1e-3f);
    EXPECT_EQ(s[3], 1000.0f);
}

TEST(CascadeSplits, LambdaEndsAreUniformAndLogarithmic) {
    auto uniform = practicalSplitDistances(1.0f, 101.0f, 4, 0.0f);
    auto logarithmic = practicalSplitDistances(1.0f, 10000.0f, 4, 1.0f);
    ASSERT_EQ(uniform.size(), 4u);
    EXPECT_NEAR(uniform[0], 26.0f, 1e-4f);
    EXPECT_NEAR(uniform[1], 51.0f, 1e-4f);
    EXPECT_NEAR(logarithmic[0], 10.0f, 1e-3f);
    EXPECT_NEAR(logarithmic[2], 1000.0f, 1e-1f);
}

TEST(CascadeSplits, ExtremesStayFiniteAndIncreasing) {
    for (uint32_t m : {1u, 2u, 4u, 8u, 16u})
        for (float lambda : {0.0f, 0.5f, 1.0f}) {
            // Near/far ratio 1e-5 and 1e-7.
            for (float nearDistance : {0.01f, 0.0001f}) {
                auto s = practicalSplitDistances(nearDistance, 1000.0f, m, lambda);
                ASSERT_EQ(s.size(), m);
                float previous = nearDistance;
                for (float d : s) {
                    EXPECT_TRUE(std::isfinite(d));
                    EXPECT_GT(d, previous) << "m=" << m << " lambda=" << lambda;
                    previous = d;
                }
                EXPECT_EQ(s.back(), 1000.0f);
            }
        }
}

TEST(CascadeSplits, InvalidArgumentsGiveNoSplits) {
    EXPECT_TRUE(practicalSplitDistances(0.0f, 10.0f, 4, 0.5f).empty());
    EXPECT_TRUE(practicalSplitDistances(10.0f, 1.0f, 4, 0.5f).empty());
    EXPECT_TRUE(practicalSplitDistances(0.1f, INFINITY, 4, 0.5f).empty());
    EXPECT_TRUE(practicalSplitDistances(0.1f, 10.0f, 0, 0.5f).empty());
    EXPECT_TRUE(practicalSplitDistances(0.1f, 10.0f, 4, 1.5f).empty());
    EXPECT_TRUE(practicalSplitDistances(NAN, 10.0f, 4, 0.5f).empty());
}

} // namespace
