// Level-of-detail selection (player/math/lod_select.h) and level pairing (pnb/mesh_levels.h): the
// rule at ordinary and extreme inputs, without a GL context.
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "pnb/mesh_levels.h"
#include "lod_select.h"

namespace pnb::player {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Errors 0, 0.01, 0.04, 0.16 mesh units: each level four times the previous.
const std::vector<float> kErrors = {0.0f, 0.01f, 0.04f, 0.16f};

TEST(LodSelect, PixelScaleIsHeightOverTwiceTanHalfFov) {
    EXPECT_NEAR(lodPixelScale(std::numbers::pi / 2, 1000), 500.0, 1e-9); // tan 45 = 1
    EXPECT_EQ(lodPixelScale(0.0, 100), kInf);
    EXPECT_EQ(lodPixelScale(-1.0, 100), kInf);
    EXPECT_EQ(lodPixelScale(kNaN, 100), kInf);
    EXPECT_EQ(lodPixelScale(std::numbers::pi, 100), 0.0);
    EXPECT_EQ(lodPixelScale(4.0, 100), 0.0);
    EXPECT_GT(lodPixelScale(1e-12, 100), 1e13);
    EXPECT_EQ(lodPixelScale(1.0, 0), 0.0);
}

// Orthographic: pixels per unit are the viewport height over the view's height, and the rule's
// distance is 1 wherever the item is: the level chosen does not change with distance.
TEST(LodSelect, OrthographicSizeOnScreenDoesNotDependOnDistance) {
    EXPECT_DOUBLE_EQ(lodPixelScaleOrthographic(2.0, 1000), 250.0);
    EXPECT_EQ(lodPixelScaleOrthographic(0.0, 100), kInf);
    EXPECT_EQ(lodPixelScaleOrthographic(kNaN, 100), kInf);
    const glm::dvec3 lo(-1, -1, -1), hi(1, 1, 1);
    const LodRule rule{1.0f, 0.2f};
    const double ortho = lodPixelScaleOrthographic(2.0, 1000); // 250 px per unit
    std::vector<uint32_t> levels;
    for (double z : {3.0, 30.0, 300.0, 3000.0}) {
        const double d = lodDistance(true, {0, 0, z}, lo, hi);
        EXPECT_EQ(d, 1.0);
        levels.push_back(selectLod(kErrors, 1.0, d, ortho, rule, 0));
    }
    // 0.01 * 250 = 2.5 px > 1: full detail at every distance.
    EXPECT_EQ(levels, std::vector<uint32_t>(4, 0u));
    // The same distances through a perspective view of the same height at z = 3 walk the chain.
    const double persp = lodPixelScale(2.0 * std::atan(2.0 / 3.0), 1000);
    EXPECT_EQ(selectLod(kErrors, 1.0, lodDistance(false, {0, 0, 3.0}, lo, hi), persp, rule, 0), 0u);
    EXPECT_EQ(selectLod(kErrors, 1.0, lodDistance(false, {0, 0, 3000.0}, lo, hi), persp, rule, 0), 3u);
    // A larger orthographic view (ymag 40: 12.5 px per unit) is coarser, again at every distance.
    for (double z : {3.0, 3000.0})
        EXPECT_EQ(selectLod(kErrors, 1.0, lodDistance(true, {0, 0, z}, lo, hi), lodPixelScaleOrthographic(40.0, 1000),
                            rule, 0),
                  2u)
            << z;
}

TEST(LodSelect, DistanceIsToTheNearestPointOfTheBox) {
    glm::dvec3 lo(-1, -1, -1), hi(1, 1, 1);
    EXPECT_EQ(distanceToBox({0, 0, 0}, lo, hi), 0.0);    // inside
    EXPECT_EQ(distanceToBox({1, 1, 1}, lo, hi), 0.0);    // on a corner
    EXPECT_DOUBLE_EQ(distanceToBox({0, 0, 5}, lo, hi), 4.0);
    EXPECT_DOUBLE_EQ(distanceToBox({4, 5, 1}, lo, hi), 5.0); // 3-4-5 to the edge
    EXPECT_EQ(distanceToBox({kNaN, 0, 0}, lo, hi), 0.0);
}

TEST(LodSelect, MaxStretchIsTheLargestSingularValue) {
    EXPECT_NEAR(maxStretch(glm::dmat3(1.0)), 1.0, 1e-12);
    EXPECT_NEAR(maxStretch(glm::dmat3(glm::dvec3(2, 0, 0), glm::dvec3(0, 7, 0), glm::dvec3(0, 0, -3))), 7.0, 1e-12);
    // Rotation by 30 degrees about z of diag(1, 5, 2): still 5 (column lengths would say 5 too,
    // a row-sum bound would not).
    double c = std::cos(0.5236), s = std::sin(0.5236);
    glm::dmat3 r(glm::dvec3(c, s, 0), glm::dvec3(-s, c, 0), glm::dvec3(0, 0, 1));
    glm::dmat3 d(glm::dvec3(1, 0, 0), glm::dvec3(0, 5, 0), glm::dvec3(0, 0, 2));
    EXPECT_NEAR(maxStretch(r * d), 5.0, 1e-9);
    // Shear: [[1, 1], [0, 1]] has singular value (1 + sqrt 5) / 2, more than either column.
    glm::dmat3 shear(glm::dvec3(1, 0, 0), glm::dvec3(1, 1, 0), glm::dvec3(0, 0, 1));
    EXPECT_NEAR(maxStretch(shear), (1 + std::sqrt(5.0)) / 2, 1e-9);
    EXPECT_EQ(maxStretch(glm::dmat3(0.0)), 0.0);
    EXPECT_EQ(maxStretch(glm::dmat3(kNaN)), kInf);
    EXPECT_EQ(maxStretch(glm::dmat3(1e300)), kInf);
}

TEST(LodSelect, FarIsCoarseNearIsFullDetail) {
    const double scale = lodPixelScale(1.0, 720); // ~655 px per unit at distance 1
    LodRule rule{1.0f, 0.0f};
    EXPECT_EQ(selectLod(kErrors, 1.0, 0.5, scale, rule, 0), 0u);
    // Level 1 projects to 0.01 * 655 / d px: within 1 px beyond d = 6.55.
    EXPECT_EQ(selectLod(kErrors, 1.0, 6.0, scale, rule, 0), 0u);
    EXPECT_EQ(selectLod(kErrors, 1.0, 7.0, scale, rule, 0), 1u);
    EXPECT_EQ(selectLod(kErrors, 1.0, 1e6, scale, rule, 0), 3u);
    // From a coarse level, a near view goes straight back to full detail.
    EXPECT_EQ(selectLod(kErrors, 1.0, 0.5, scale, rule, 3), 0u);
    // World scale multiplies the error: 10x the size switches at 10x the distance.
    EXPECT_EQ(selectLod(kErrors, 10.0, 60.0, scale, rule, 0), 0u);
    EXPECT_EQ(selectLod(kErrors, 10.0, 70.0, scale, rule, 0), 1u);
}

TEST(LodSelect, HysteresisHoldsTheLevelInsideTheBand) {
    const double scale = lodPixelScale(1.0, 720);
    const double d1 = 0.01 * scale; // level 1 is exactly 1 px here
    LodRule rule{1.0f, 0.2f};
    // At 1.1 d1 level 1 is within the threshold but not within 0.8 of it: stay at 0.
    EXPECT_EQ(selectLod(kErrors, 1.0, 1.1 * d1, scale, rule, 0), 0u);
    // Once at level 1, 0.99 d1... is over the threshold: back to 0 at once; 1.01 d1 keeps 1.
    EXPECT_EQ(selectLod(kErrors, 1.0, 1.01 * d1, scale, rule, 1), 1u);
    EXPECT_EQ(selectLod(kErrors, 1.0, 0.99 * d1, scale, rule, 1), 0u);
    // Beyond d1 / 0.8 the coarser level is taken.
    EXPECT_EQ(selectLod(kErrors, 1.0, 1.26 * d1, scale, rule, 0), 1u);
    // Back and forth across d1 by 5 %: never changes with hysteresis, every time without.
    uint32_t with = 0, without = 0, switchesWith = 0, switchesWithout = 0;
    for (int k = 0; k < 20; ++k) {
        double d = (k % 2 ? 1.05 : 0.95) * d1;
        uint32_t a = selectLod(kErrors, 1.0, d, scale, rule, with);
        uint32_t b = selectLod(kErrors, 1.0, d, scale, LodRule{1.0f, 0.0f}, without);
        switchesWith += a != with;
        switchesWithout += b != without;
        with = a;
        without = b;
    }
    EXPECT_EQ(switchesWith, 0u);
    EXPECT_EQ(switchesWithout, 19u);
}

TEST(LodSelect, ExtremesGiveALevelInRangeAndNeverNaN) {
    const double scale = lodPixelScale(1.0, 720);
    const LodRule rule;
    for (double distance : {0.0, -1.0, -kInf, kNaN, 1e-300, 1e300, kInf})
        for (double worldScale : {0.0, 1e-300, 1.0, 1e300, kInf, kNaN, -5.0})
            for (double px : {0.0, scale, kInf, kNaN, lodPixelScale(1e-9, 720), lodPixelScale(3.14159, 720)})
                for (uint32_t current : {0u, 2u, 200u}) {
                    uint32_t l = selectLod(kErrors, worldScale, distance, px, rule, current);
                    ASSERT_LT(l, kErrors.size()) << distance << " " << worldScale << " " << px;
                }
    // Unknown or non-positive distances and unbounded scales keep full detail.
    EXPECT_EQ(selectLod(kErrors, 1.0, 0.0, scale, rule, 3), 0u);
    EXPECT_EQ(selectLod(kErrors, 1.0, -3.0, scale, rule, 3), 0u);
    EXPECT_EQ(selectLod(kErrors, 1.0, kNaN, scale, rule, 3), 0u);
    EXPECT_EQ(selectLod(kErrors, kNaN, 100.0, scale, rule, 3), 0u);
    EXPECT_EQ(selectLod(kErrors, kInf, 100.0, scale, rule, 3), 0u);
    EXPECT_EQ(selectLod(kErrors, 1e300, 100.0, scale, rule, 3), 0u);
    // FOV near 0: a pixel is infinitely small, full detail; near 180 degrees: everything coarse.
    EXPECT_EQ(selectLod(kErrors, 1.0, 100.0, lodPixelScale(1e-9, 720), rule, 3), 0u);
    EXPECT_EQ(selectLod(kErrors, 1.0, 0.01, lodPixelScale(std::numbers::pi - 1e-9, 720), rule, 0), 3u);
    // An infinite distance with a finite scale: the coarsest.
    EXPECT_EQ(selectLod(kErrors, 1.0, kInf, scale, rule, 0), 3u);
    // Exact levels (error 0) are always acceptable, even at distance 0 or an infinite scale.
    const std::vector<float> exact = {0.0f, 0.0f, 0.5f};
    EXPECT_EQ(selectLod(exact, kInf, 0.0, kInf, rule, 0), 1u);
    // Threshold 0: only exact levels; NaN thresholds and hysteresis behave as 0.
    EXPECT_EQ(selectLod(kErrors, 1.0, 1e6, scale, LodRule{0.0f, 0.2f}, 0), 0u);
    EXPECT_EQ(selectLod(kErrors, 1.0, 1e6, scale, LodRule{float(kNaN), 0.2f}, 0), 0u);
    EXPECT_EQ(selectLod(kErrors, 1.0, 1e6, scale, LodRule{1.0f, float(kNaN)}, 0), 3u);
    // A NaN or decreasing error never makes a coarser level look better than a finer one.
    const std::vector<float> odd = {0.0f, float(kNaN), 0.001f};
    EXPECT_EQ(selectLod(odd, 1.0, 1e6, scale, rule, 0), 0u);
    const std::vector<float> decreasing = {0.0f, 0.5f, 0.001f};
    EXPECT_EQ(selectLod(decreasing, 1.0, 100.0, scale, rule, 0), 0u);
    // No levels or one level: 0.
    EXPECT_EQ(selectLod({}, 1.0, 100.0, scale, rule, 5), 0u);
    EXPECT_EQ(selectLod(std::vector<float>{0.0f}, 1.0, 100.0, scale, rule, 5), 0u);
}

TEST(LodSelect, ForceAndBiasAreClampedToTheLevelsThereAre) {
    EXPECT_EQ(applyLodOverrides(1, 4, 0, -1), 1u);
    EXPECT_EQ(applyLodOverrides(1, 4, 1, -1), 2u);
    EXPECT_EQ(applyLodOverrides(1, 4, 8, -1), 3u);
    EXPECT_EQ(applyLodOverrides(1, 4, -8, -1), 0u);
    EXPECT_EQ(applyLodOverrides(1, 4, 0, 0), 0u);
    EXPECT_EQ(applyLodOverrides(1, 4, 3, 2), 2u); // force wins over bias
    EXPECT_EQ(applyLodOverrides(0, 4, 0, 254), 3u);
    EXPECT_EQ(applyLodOverrides(0, 1, 5, 7), 0u);
    EXPECT_EQ(applyLodOverrides(0, 0, 5, 7), 0u);
}

Submesh submesh(uint32_t material, uint8_t lod, uint32_t first = 0) {
    Submesh s;
    s.material = material;
    s.lod = lod;
    s.firstIndex = first;
    s.indexCount = 3;
    return s;
}

TEST(LodLevels, ChainsPairTheJthLevelLSubmeshOfAMaterialWithItsJthLevel0One) {
    // Materials 0 (two submeshes), 1 and kNone; levels as the converter writes them.
    std::vector<Submesh> s = {submesh(0, 0), submesh(1, 0), submesh(0, 0), submesh(kNone, 0),
                              submesh(0, 1), submesh(1, 1), submesh(0, 1),
                              submesh(1, 2), submesh(0, 2)}; // level 2 of material 0 incomplete
    auto chains = buildLevelChains(s);
    ASSERT_EQ(chains.size(), 3u); // kNone is not drawn
    EXPECT_EQ(chains[0].material, 0u);
    EXPECT_EQ(chains[0].levels, (std::vector<uint32_t>{0, 4}));
    EXPECT_EQ(chains[1].material, 1u);
    EXPECT_EQ(chains[1].levels, (std::vector<uint32_t>{1, 5, 7}));
    EXPECT_EQ(chains[2].levels, (std::vector<uint32_t>{2, 6}));
}

TEST(LodLevels, AMissingLevelEndsTheChainAndNoLodsGiveOneLevelEach) {
    std::vector<Submesh> s = {submesh(0, 0), submesh(0, 2)}; // level 1 missing
    auto chains = buildLevelChains(s);
    ASSERT_EQ(chains.size(), 1u);
    EXPECT_EQ(chains[0].levels, (std::vector<uint32_t>{0}));
    std::vector<Submesh> plain = {submesh(2, 0), submesh(1, 0)};
    chains = buildLevelChains(plain);
    ASSERT_EQ(chains.size(), 2u);
    EXPECT_EQ(chains[0].material, 2u); // chunk order kept
    EXPECT_EQ(chains[1].levels.size(), 1u);
    EXPECT_TRUE(buildLevelChains({}).empty());
}

} // namespace
} // namespace pnb::player
