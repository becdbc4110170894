// The local-light shadow atlas's CPU math (player/src/local_shadows.h): tile sizes that follow
// the screen, packing without overlap inside the budget, shrinking before dropping, and tile
// matrices that put the light's near plane at depth 1 and its range at 0.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "shadows/local_shadows.h"

namespace pnb::player {
namespace {

struct Square {
    glm::uvec2 origin;
    uint32_t size;
};

std::vector<Square> squares(const std::vector<LocalShadowPlacement>& placements) {
    std::vector<Square> out;
    for (const LocalShadowPlacement& p : placements)
        for (uint32_t f = 0; f < p.faces; ++f) out.push_back({p.origins[f], p.size});
    return out;
}

void expectInsideAndDisjoint(const std::vector<LocalShadowPlacement>& placements, uint32_t atlas) {
    const std::vector<Square> sq = squares(placements);
    for (size_t i = 0; i < sq.size(); ++i) {
        EXPECT_LE(sq[i].origin.x + sq[i].size, atlas);
        EXPECT_LE(sq[i].origin.y + sq[i].size, atlas);
        for (size_t j = i + 1; j < sq.size(); ++j) {
            const bool apart = sq[i].origin.x + sq[i].size <= sq[j].origin.x ||
                               sq[j].origin.x + sq[j].size <= sq[i].origin.x ||
                               sq[i].origin.y + sq[i].size <= sq[j].origin.y ||
                               sq[j].origin.y + sq[j].size <= sq[i].origin.y;
            EXPECT_TRUE(apart) << "tiles " << i << " and " << j << " overlap";
        }
    }
}

TEST(LocalShadowMath, TileSizeFollowsTheScreenInPowersOfTwo) {
    EXPECT_EQ(localShadowTileSize(1.0f, 720, 32, 1024), 1024u);
    EXPECT_EQ(localShadowTileSize(0.5f, 720, 32, 1024), 512u);  // 360 px -> 512
    EXPECT_EQ(localShadowTileSize(0.01f, 720, 32, 1024), 32u);  // 7 px -> the smallest tile
    EXPECT_EQ(localShadowTileSize(1.0f, 4000, 32, 1024), 1024u); // capped
    EXPECT_EQ(localShadowTileSize(-1.0f, 720, 32, 1024), 32u);
}

TEST(LocalShadowMath, LargestOnScreenFirstAndAtMostTheLightCap) {
    RenderSettings s;
    s.shadowLocalLights = 3;
    std::vector<LocalShadowRequest> r;
    for (uint32_t i = 0; i < 6; ++i) r.push_back({i, i % 2 == 0, 0.1f * float(i + 1)});
    const auto plan = planLocalShadows(r, 512, s, 2048);
    ASSERT_EQ(plan.size(), 3u);
    std::vector<uint32_t> lights;
    for (const auto& p : plan) lights.push_back(p.light);
    std::sort(lights.begin(), lights.end());
    EXPECT_EQ(lights, (std::vector<uint32_t>{3, 4, 5}));
    for (const auto& p : plan) EXPECT_EQ(p.faces, r[p.light].cube ? 6u : 1u);
    expectInsideAndDisjoint(plan, 2048);
}

TEST(LocalShadowMath, TilesShrinkTogetherBeforeAnyLightIsDropped) {
    RenderSettings s;
    s.shadowLocalLights = 16;
    std::vector<LocalShadowRequest> r;
    for (uint32_t i = 0; i < 16; ++i) r.push_back({i, true, 1.0f}); // 16 x 6 faces of 1024 wanted
    const auto plan = planLocalShadows(r, 1080, s, 2048);
    ASSERT_EQ(plan.size(), 16u); // 96 tiles of 128 fit 2048^2 (a quarter of it at 256 would not)
    for (const auto& p : plan) EXPECT_EQ(p.size, 128u);
    expectInsideAndDisjoint(plan, 2048);
    // An atlas too small for every light at the smallest tile: the largest on screen keep theirs.
    std::vector<LocalShadowRequest> many;
    for (uint32_t i = 0; i < 16; ++i) many.push_back({i, true, 0.01f * float(i + 1)});
    const auto small = planLocalShadows(many, 1080, s, 256); // 64 tiles of 32 fit: 10 lights
    EXPECT_EQ(small.size(), 10u);
    for (const auto& p : small) EXPECT_GE(p.light, 6u);
    expectInsideAndDisjoint(small, 256);
}

TEST(LocalShadowMath, MixedSizesPackWithoutOverlap) {
    RenderSettings s;
    s.shadowLocalLights = 64;
    s.shadowLocalMaxTile = 1024;
    std::vector<LocalShadowRequest> r;
    for (uint32_t i = 0; i < 40; ++i) r.push_back({i, i % 3 == 0, std::fmod(0.37f * float(i), 1.0f)});
    const auto plan = planLocalShadows(r, 720, s, 4096);
    EXPECT_FALSE(plan.empty());
    expectInsideAndDisjoint(plan, 4096);
}

TEST(LocalShadowMath, TileMatrixMapsNearToOneAndRangeToZero) {
    const glm::vec3 light(1, 2, 3);
    const glm::mat4 m = localShadowMatrix(light, {0, 0, -1}, 1.0f, 10.0f);
    auto depth = [&](glm::vec3 p) {
        const glm::vec4 c = m * glm::vec4(p, 1.0f);
        return c.z / c.w;
    };
    EXPECT_NEAR(depth(light + glm::vec3(0, 0, -0.01f)), 1.0f, 1e-4f); // near = range / 1000
    EXPECT_NEAR(depth(light + glm::vec3(0, 0, -10.0f)), 0.0f, 1e-5f);
    EXPECT_GT(depth(light + glm::vec3(0, 0, -1.0f)), depth(light + glm::vec3(0, 0, -2.0f))); // reversed-Z
    // The edge of the face (45 degrees with tanHalf 1) lands on the tile's edge.
    const glm::vec4 edge = m * glm::vec4(light + glm::vec3(2, 0, -2), 1.0f);
    EXPECT_NEAR(edge.x / edge.w, 1.0f, 1e-5f);
    // Straight up or down is a valid direction too (no degenerate up vector).
    const glm::mat4 down = localShadowMatrix(light, {0, -1, 0}, 1.0f, 10.0f);
    for (int i = 0; i < 16; ++i) EXPECT_TRUE(std::isfinite(down[i / 4][i % 4]));
}

} // namespace
} // namespace pnb::player
