// The streaming player's pure-CPU rules: which mip level a view needs (player/math/mip_need.h)
// and which levels stay resident under a budget (texture_residency.h), at ordinary and extreme
// inputs, without a GL context.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "mip_need.h"
#include "pnb/scene_builder.h"
#include "texture_residency.h"

namespace pnb::player {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(MipNeed, OneTexelPerPixelIsLevelZeroAndEachHalvingOneLevelCoarser) {
    // 1024 texels per unit, 512 pixels per unit at distance 1.
    EXPECT_EQ(neededMipLevel(1024, 0.5, 512, 11), 0u); // 1 texel per pixel
    EXPECT_EQ(neededMipLevel(1024, 1.0, 512, 11), 1u); // 2
    EXPECT_EQ(neededMipLevel(1024, 1.9, 512, 11), 1u); // 3.8: the finer of the two blended
    EXPECT_EQ(neededMipLevel(1024, 4.0, 512, 11), 3u);
    EXPECT_EQ(neededMipLevel(1024, 0.01, 512, 11), 0u);   // magnified
    EXPECT_EQ(neededMipLevel(1024, 1e9, 512, 11), 10u);   // clamped to the coarsest
}

TEST(MipNeed, ExtremeInputsGiveALevelInRange) {
    EXPECT_EQ(neededMipLevel(kNaN, 1, 512, 11), 0u);
    EXPECT_EQ(neededMipLevel(1024, kNaN, 512, 11), 0u);
    EXPECT_EQ(neededMipLevel(1024, 1, kInf, 11), 0u);  // zero field of view: full detail
    EXPECT_EQ(neededMipLevel(1024, 1, 0, 11), 10u);    // everything below a pixel
    EXPECT_EQ(neededMipLevel(1024, kInf, 512, 11), 10u);
    EXPECT_EQ(neededMipLevel(-5, 1, 512, 11), 0u);
    EXPECT_EQ(neededMipLevel(1e300, 1e300, 1e-300, 11), 10u);
    EXPECT_EQ(neededMipLevel(1024, 1, 512, 1), 0u);
    EXPECT_EQ(neededMipLevel(1024, 1, 512, 0), 0u);
}

// A unit quad in the XY plane (mesh units), UVs spanning [0, uvSpan]^2.
Mesh quad(SceneBuilder& b, float uvSpan, float size) {
    std::vector<float> pos = {0, 0, 0, size, 0, 0, size, size, 0, 0, size, 0};
    std::vector<float> uv = {0, 0, uvSpan, 0, uvSpan, uvSpan, 0, uvSpan};
    std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
    Mesh m;
    m.vertexCount = 4;
    m.indexType = IndexType::U16;
    VertexStream p;
    p.semantic = VertexSemantic::Position;
    p.componentType = ComponentType::F32;
    p.componentCount = 3;
    p.data = b.keep(pos);
    VertexStream t;
    t.semantic = VertexSemantic::TexCoord0;
    t.componentType = ComponentType::F32;
    t.componentCount = 2;
    t.data = b.keep(uv);
    m.streams = {p, t};
    m.indices = b.keep(idx);
    Submesh sm;
    sm.indexCount = 6;
    sm.bounds = {{0, 0, 0}, {size, size, 0}};
    m.submeshes = {sm};
    return m;
}

TEST(MipNeed, UvDensityIsUvUnitsPerMeshUnit) {
    SceneBuilder b;
    Mesh once = quad(b, 1.0f, 2.0f), tiled = quad(b, 8.0f, 2.0f);
    EXPECT_NEAR(uvDensity(once, once.submeshes[0]), 0.5, 1e-9);  // [0,1] over 2 units
    EXPECT_NEAR(uvDensity(tiled, tiled.submeshes[0]), 4.0, 1e-9);
    EXPECT_NEAR(uvDensityFromBounds(once.submeshes[0]), 0.5, 1e-9);
    Mesh flat = quad(b, 1.0f, 0.0f); // no area
    EXPECT_EQ(uvDensity(flat, flat.submeshes[0]), 0.0);
    EXPECT_EQ(uvDensityFromBounds(flat.submeshes[0]), 0.0);
    once.streams.pop_back(); // no TEXCOORD_0
    EXPECT_EQ(uvDensity(once, once.submeshes[0]), 0.0);
}

// A texture of 1024^2 RGBA8: 11 levels, level l holds 4 * (1024 >> l)^2 bytes.
TextureResidency texture(uint32_t allocated, uint32_t valid, uint32_t wanted) {
    TextureResidency t;
    for (uint32_t l = 0; l < 11; ++l) t.levelBytes.push_back(4ull * (1024u >> l) * (1024u >> l));
    t.allocated = allocated;
    t.valid = valid;
    t.wanted = wanted;
    return t;
}

void applyPlan(std::vector<TextureResidency>& ts, const ResidencyPlan& plan) {
    for (const ResidencyChange& c : plan.evictions) ts[c.texture].allocated = c.allocated;
    for (const ResidencyChange& c : plan.growths) ts[c.texture].allocated = c.allocated;
}

TEST(TextureResidency, WithoutABudgetEveryWantedLevelGetsStorage) {
    std::vector<TextureResidency> ts = {texture(10, 10, 0), texture(10, 10, 3)};
    ResidencyPlan plan = planResidency(ts, 0, 1);
    applyPlan(ts, plan);
    EXPECT_EQ(ts[0].allocated, 0u);
    EXPECT_EQ(ts[1].allocated, 3u);
    EXPECT_TRUE(plan.evictions.empty());
}

TEST(TextureResidency, GrowthCountsTheOldAndNewChainWhileTheyCoexist) {
    std::vector<TextureResidency> ts = {texture(10, 10, 0)};
    const uint64_t full = ts[0].bytesFrom(0), smallest = ts[0].bytesFrom(10);
    // Exactly the whole chain plus the old one: it grows all the way.
    ResidencyPlan plan = planResidency(ts, full + smallest, 1);
    ASSERT_EQ(plan.growths.size(), 1u);
    EXPECT_EQ(plan.growths[0].allocated, 0u);
    EXPECT_EQ(plan.peakBytes, full + smallest);
    // One byte less: only as far as fits (level 1), then spare room is not enough for level 0.
    ts[0].allocated = 10;
    plan = planResidency(ts, full + smallest - 1, 2);
    ASSERT_FALSE(plan.growths.empty());
    EXPECT_EQ(plan.growths[0].allocated, 1u);
    EXPECT_LE(plan.peakBytes, full + smallest - 1);
}

TEST(TextureResidency, NeedsEvictTheLeastRecentlyNeededFirst) {
    // Two textures hold level 0 but want only level 5: texture 0 was needed at frame 3,
    // texture 1 at frame 7. Texture 2 now wants level 0.
    std::vector<TextureResidency> ts = {texture(0, 0, 5), texture(0, 0, 5), texture(10, 10, 0)};
    ts[0].lastNeededFrame = 3;
    ts[1].lastNeededFrame = 7;
    const uint64_t budget = ts[0].bytesFrom(0) * 2 + ts[2].bytesFrom(10) + ts[0].bytesFrom(5) + 4096;
    ResidencyPlan plan = planResidency(ts, budget, 10);
    ASSERT_FALSE(plan.evictions.empty());
    EXPECT_EQ(plan.evictions[0].texture, 0u);
    EXPECT_EQ(plan.evictions[0].allocated, 5u);
    applyPlan(ts, plan);
    EXPECT_EQ(ts[2].allocated, 0u);
    EXPECT_EQ(ts[1].allocated, 0u); // not needed to make room: kept as cache
    EXPECT_LE(plan.peakBytes, budget);
    EXPECT_LE(residentBytes(ts), budget);
}

TEST(TextureResidency, ALoweredBudgetIsMetByCuttingBack) {
    std::vector<TextureResidency> ts = {texture(0, 0, 8), texture(0, 0, 8)};
    const uint64_t budget = ts[0].bytesFrom(1) + ts[0].bytesFrom(8) * 2;
    applyPlan(ts, planResidency(ts, budget, 1));
    EXPECT_LE(residentBytes(ts), budget);
}

TEST(TextureResidency, NeverOverBudgetAlongARandomWalk) {
    std::mt19937 rng(7);
    std::vector<TextureResidency> ts;
    for (int i = 0; i < 24; ++i) ts.push_back(texture(10, 10, 10));
    const uint64_t budget = ts[0].bytesFrom(0) * 24 / 4; // a quarter of everything
    uint64_t peak = 0;
    for (uint64_t frame = 1; frame < 500; ++frame) {
        for (TextureResidency& t : ts) t.wanted = std::uniform_int_distribution<uint32_t>(0, 10)(rng);
        ResidencyPlan plan = planResidency(ts, budget, frame);
        applyPlan(ts, plan);
        for (TextureResidency& t : ts) t.valid = std::max(t.valid, t.allocated);
        peak = std::max(peak, plan.peakBytes);
        ASSERT_LE(residentBytes(ts), budget) << "frame " << frame;
        for (const TextureResidency& t : ts) ASSERT_LT(t.allocated, t.mipCount()); // smallest kept
    }
    EXPECT_LE(peak, budget);
    EXPECT_GT(peak, budget / 2); // the budget is used, not left idle
}

TEST(TextureResidency, SpareRoomFillsTheCacheUntilTheSceneIsResident) {
    std::vector<TextureResidency> ts = {texture(10, 10, 9), texture(10, 10, 9)};
    const uint64_t budget = 2 * ts[0].bytesFrom(0) + ts[0].bytesFrom(0); // everything and a copy
    for (uint64_t frame = 1; frame < 40; ++frame) applyPlan(ts, planResidency(ts, budget, frame));
    EXPECT_EQ(ts[0].allocated, 0u);
    EXPECT_EQ(ts[1].allocated, 0u);
    EXPECT_EQ(neededBytes(ts), 2 * ts[0].bytesFrom(9));
}

TEST(TextureResidency, NewStoragePerFrameIsBoundedButAFrameAlwaysGrowsOneLevel) {
    std::vector<TextureResidency> ts = {texture(10, 10, 0), texture(10, 10, 0), texture(10, 10, 0)};
    const uint64_t level0 = ts[0].levelBytes[0];
    for (uint64_t frame = 1; frame < 30; ++frame) {
        const uint64_t before = residentBytes(ts);
        ResidencyPlan plan = planResidency(ts, 0, frame, level0 / 2);
        applyPlan(ts, plan);
        // Within the allowance, or one level alone (level 0 is larger than the allowance).
        EXPECT_TRUE(residentBytes(ts) - before <= level0 / 2 ||
                    (plan.growths.size() == 1 && residentBytes(ts) - before == level0))
            << "frame " << frame;
    }
    for (const TextureResidency& t : ts) EXPECT_EQ(t.allocated, 0u); // all the way, over frames
    // An allowance smaller than any level: one level a frame.
    ts = {texture(10, 10, 0)};
    ResidencyPlan plan = planResidency(ts, 0, 1, 1);
    ASSERT_EQ(plan.growths.size(), 1u);
    EXPECT_EQ(plan.growths[0].allocated, 9u);
}

} // namespace
} // namespace pnb::player
